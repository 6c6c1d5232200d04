"""The robot's clock for every agent: can its learner keep up with one robot on this CPU?

For each registered agent, as the on-robot loop runs it (one environment, one seed, the agent's own batch and
updates per step): gradient updates/s, one policy inference, parameters, and the process's peak memory; then
whether the updates it makes per step fit in a control period at the agent's rate beside one inference, and the
most updates per step that would. Each agent is measured in its own process, so its peak memory is its own.
Prints a table and writes benchmarks/results/bench_agents.json. Run: `python -m benchmarks.bench_agents
[--algos ...]` from the repository root (about 10 minutes here; pause other work, it times the CPU).
"""

import argparse
import json
import math
import resource
import subprocess
import sys
from pathlib import Path

from benchmarks.common import RESULTS

OUT = RESULTS / "bench_agents.json"
UPDATES = 60


def measure(algo: str) -> dict:
    """One agent's row, measured in this process."""
    import jax
    import jax.numpy as jnp

    from benchmarks.common import timed, update_program
    from mjx_badger.agents.agent import make_agent
    from mjx_badger.learning.config import TrainConfig

    cfg = TrainConfig(algo=algo, protocol="thesis-text").agent_config  # the on-robot loop's protocol
    agent = make_agent(cfg, 54, 12)
    state = jax.jit(agent.init)(jax.random.PRNGKey(0))
    act = jax.jit(agent.act)
    act_s = timed(lambda: act(state, jnp.zeros(54), jax.random.PRNGKey(1)), repeats=200)
    program, args = update_program(1, algo, updates=UPDATES, cfg=cfg)
    update_s = timed(program, *args) / UPDATES
    period_ms = 1000 / cfg.control_hz
    fits = max(0, math.floor((period_ms - act_s * 1000) / (update_s * 1000)))
    return {"control_hz": cfg.control_hz, "batch_size": cfg.batch_size, "updates_per_step": cfg.updates_per_step,
            "parameters": int(sum(x.size for x in jax.tree.leaves((state.actor_params, state.critic_params,
                                                                   state.optimism)))),
            "updates_per_s": round(1 / update_s, 1), "act_ms": round(act_s * 1000, 3),
            "step_ms": round(cfg.updates_per_step * update_s * 1000 + act_s * 1000, 1),
            "keeps_up": cfg.updates_per_step <= fits, "max_updates_per_step": fits,
            "peak_rss_mib": round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, 1)}


def main():
    from mjx_badger.agents.config import ALGORITHMS
    from mjx_badger.records import results

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=OUT)
    parser.add_argument("--algos", nargs="+", choices=list(ALGORITHMS), default=list(ALGORITHMS))
    parser.add_argument("--one", choices=list(ALGORITHMS), help=argparse.SUPPRESS)  # the child process's job
    args = parser.parse_args()
    if args.one:
        print(json.dumps(measure(args.one)))
        return
    table = json.loads(args.out.read_text())["agents"] if args.out.exists() else {}
    for algo in args.algos:
        child = subprocess.run([sys.executable, "-m", "benchmarks.bench_agents", "--one", algo], capture_output=True,
                               text=True, check=True)
        table[algo] = json.loads(child.stdout.strip().splitlines()[-1])
        print(algo, table[algo], flush=True)
    table = {algo: table[algo] for algo in ALGORITHMS if algo in table}
    print(f"{'agent':10s} {'Hz':>4s} {'batch':>5s} {'UTD':>4s} {'params':>9s} {'upd/s':>7s} {'act ms':>7s} "
          f"{'step ms':>8s} {'keeps up':>8s} {'max UTD':>7s} {'peak MiB':>8s}")
    for algo, r in table.items():
        print(f"{algo:10s} {r['control_hz']:4.0f} {r['batch_size']:5d} {r['updates_per_step']:4d} {r['parameters']:9d} "
              f"{r['updates_per_s']:7.1f} {r['act_ms']:7.2f} {r['step_ms']:8.1f} {str(r['keeps_up']):>8s} "
              f"{r['max_updates_per_step']:7d} {r['peak_rss_mib']:8.0f}")
    document = {"agents": table, "updates_timed": UPDATES, "measured": results.now(), "versions": results.versions(),
                "git_commit": results.git_commit(), "hardware": results.hardware()}
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(document, indent=1))
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
