"""Per algorithm on this machine: updates/s, training steps/s, and the real-time budget.

For SAC, SAC-UTD20, DroQ and CrossQ: gradient updates/s at 1 and 10 seeds, environment
steps/s with learning at 1 and 10 seeds, and the most updates per step that fit in a 20 Hz
and a 40 Hz control period next to one policy inference (the on-robot loop's budget).
Prints a table and writes benchmarks/results/bench_algorithms.json. Run: `make benchmark`.
"""

import argparse
import json
import math
from pathlib import Path

import jax
import jax.numpy as jnp

from bench_spine import timed, train_chunk, updates_per_s
from mjx_badger import results
from mjx_badger.agents import ALGORITHMS, make_agent

OUT = Path(__file__).parent / "results" / "bench_algorithms.json"


def act_seconds(algo):
    """One stochastic policy inference for one observation, as the on-robot loop calls it."""
    agent = make_agent(ALGORITHMS[algo](), 54, 12)
    state = agent.init(jax.random.PRNGKey(0))
    act = jax.jit(agent.act)
    obs = jnp.zeros(54)
    return timed(lambda: act(state, obs, jax.random.PRNGKey(1)), repeats=200)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=OUT)
    args = parser.parse_args()

    table = {}
    for algo, make in ALGORITHMS.items():
        cfg = make()
        row = {"updates_per_step": cfg.updates_per_step, "control_hz": cfg.control_hz}
        row["updates_per_s_1_seed"], _ = updates_per_s(1, algo)
        _, row["updates_per_s_total_10_seeds"] = updates_per_s(10, algo)
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

    columns = list(next(iter(table.values())))
    print("algorithm  " + "  ".join(f"{c:>10.10s}" for c in columns))
    for algo, row in table.items():
        print(f"{algo:10s} " + "  ".join(f"{row[c]:10.1f}" for c in columns))
    sac, utd20 = table["sac"], table["sac-utd20"]
    ratio = utd20["train_updates_per_s_1_seeds"] / sac["train_updates_per_s_1_seeds"]
    print(f"gradient updates/s in training at 20 per step vs 1 per step (SAC, 1 seed): x{ratio:.2f} "
          f"(target >= 0.9: {'met' if ratio >= 0.9 else 'MISSED'})")
    document = {"algorithms": {a: {k: round(v, 3) for k, v in r.items()} for a, r in table.items()},
                "utd20_vs_utd1_update_rate": round(ratio, 3), "measured": results.now(),
                "versions": results.versions(), "git_commit": results.git_commit(), "hardware": results.hardware()}
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(document, indent=1))
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
