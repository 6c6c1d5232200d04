"""Per algorithm on this machine: updates/s, training steps/s, and the real-time budget.

For SAC, SAC-UTD20, DroQ and CrossQ: gradient updates/s at 1 and 10 seeds, environment
steps/s with learning at 1 and 10 seeds, and the most updates per step that fit in a 20 Hz
and a 40 Hz control period next to one policy inference (the on-robot loop's budget).
Prints a table and writes benchmarks/results/bench_algorithms.json. Run: `make benchmark`, or
`python -m benchmarks.bench_algorithms [--algos ...]` from the repository root.
"""

import argparse
import json
import math
import time
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np

from benchmarks.common import RESULTS, chunk_program, timed, train_chunk, update_program, updates_per_s
from mjx_badger.agents.agent import make_agent
from mjx_badger.agents.config import ALGORITHMS
from mjx_badger.learning.config import TrainConfig
from mjx_badger.records import results

OUT = RESULTS / "bench_algorithms.json"


def training_config(algo):
    """The agent a training run of `algo` builds under the default protocol, so that updates
    timed alone are the updates the training chunk times (under thesis-code the UTD20
    algorithms update their actor once per step, CrossQ every update)."""
    return TrainConfig(algo=algo).agent_config


def act_seconds(algo):
    """One stochastic policy inference for one observation, as the on-robot loop calls it."""
    agent = make_agent(training_config(algo), 54, 12)
    state = agent.init(jax.random.PRNGKey(0))
    act = jax.jit(agent.act)
    obs = jnp.zeros(54)
    return timed(lambda: act(state, obs, jax.random.PRNGKey(1)), repeats=200)


def utd20_overhead(repeats=5):
    """Gradient updates/s while training at 20 updates per step over updates/s with no environment.

    SAC-UTD20's networks, 1 seed, 200 updates each way, timed alternately in one process so
    drifts of this shared machine's speed hit both sides alike; returns both rates and the ratio.
    """
    updates, args_u = update_program(1, "sac-utd20", updates=200, cfg=training_config("sac-utd20"))
    _, chunk, args_c = chunk_program(1, chunk_steps=10, algo="sac-utd20")
    jax.block_until_ready(updates(*args_u))
    alone, training = [], []
    for _ in range(repeats):
        for fn, args, out in ((updates, args_u, alone), (chunk, args_c, training)):
            t0 = time.perf_counter()
            jax.block_until_ready(fn(*args))
            out.append(200 / (time.perf_counter() - t0))
    alone, training = float(np.median(alone)), float(np.median(training))
    return alone, training, training / alone


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=OUT)
    parser.add_argument("--algos", nargs="+", choices=list(ALGORITHMS), default=list(ALGORITHMS),
                        help="measure only these; the others' rows are kept from an existing --out file")
    args = parser.parse_args()

    table = {}
    if args.out.exists() and set(args.algos) != set(ALGORITHMS):
        table = json.loads(args.out.read_text())["algorithms"]
    for algo in args.algos:
        cfg = ALGORITHMS[algo]()
        row = {"updates_per_step": cfg.updates_per_step, "control_hz": cfg.control_hz}
        agent = training_config(algo)
        row["updates_per_s_1_seed"], _ = updates_per_s(1, algo, cfg=agent)
        _, row["updates_per_s_total_10_seeds"] = updates_per_s(10, algo, cfg=agent)
        chunk = 500 // cfg.updates_per_step
        for seeds in (1, 10):
            _, rate = train_chunk(seeds, chunk_steps=chunk, algo=algo)
            row[f"env_steps_per_s_{seeds}_seeds"] = rate
            row[f"train_updates_per_s_{seeds}_seeds"] = rate * cfg.updates_per_step
        row["act_ms"] = act_seconds(algo) * 1000
        update_ms = 1000 / row["updates_per_s_1_seed"]
        for hz in (20, 40):
            row[f"max_updates_per_step_at_{hz}_hz"] = max(0, math.floor((1000 / hz - row["act_ms"]) / update_ms))
        table[algo] = row

    table = {algo: table[algo] for algo in ALGORITHMS}
    columns = list(next(iter(table.values())))
    print("algorithm  " + "  ".join(f"{c:>10.10s}" for c in columns))
    for algo, row in table.items():
        print(f"{algo:10s} " + "  ".join(f"{row[c]:10.1f}" for c in columns))
    alone, training, ratio = utd20_overhead()
    print(f"SAC-UTD20, 1 seed: {training:.1f} gradient updates/s while training at 20 per step, {alone:.1f} with no "
          f"environment: x{ratio:.2f} (target >= 0.9: {'met' if ratio >= 0.9 else 'MISSED'})")
    document = {"algorithms": {a: {k: round(v, 3) for k, v in r.items()} for a, r in table.items()},
                "utd20_overhead": {"updates_per_s_alone": round(alone, 1), "updates_per_s_training": round(training, 1),
                                   "ratio": round(ratio, 3)}, "measured": results.now(),
                "versions": results.versions(), "git_commit": results.git_commit(), "hardware": results.hardware()}
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(document, indent=1))
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
