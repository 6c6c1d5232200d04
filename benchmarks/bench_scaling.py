"""Seed-steps/s and compile time against the number of vmapped seeds, on this machine.

For each seed count, `programs.measure_speed` compiles a JT-NF CrossQ chunk (thesis-code, 200 learning
steps, updates from the first step) for that many seeds and times one chunk after an untimed
first one. Writes benchmarks/results/scaling.json and scaling.png. Run on an idle machine:
`python -m benchmarks.bench_scaling [--seeds 1 2 4 8 16 32 64]`.

With `--members 1 2 4 8` it measures the sweep axis instead (scaling_sweep.json/.png): that
many learning rates of the same run, one seed each, as one sweep program (sweep.py), with all
members vmapped together and with members one after another inside the program.
"""

import argparse
import json
import os
from pathlib import Path

import jax

from benchmarks.common import RESULTS
from mjx_badger.learning import programs, sweep
from mjx_badger.learning.config import TrainConfig
from mjx_badger.records import results

OUT = RESULTS / "scaling.json"


def plot(rows: list, path: Path, device: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    seeds = [r["seeds"] for r in rows]
    fig, (left, right) = plt.subplots(1, 2, figsize=(9, 3.6))
    left.plot(seeds, [r["seed_steps_per_s"] for r in rows], "o-", label="measured")
    left.plot(seeds, [rows[0]["seed_steps_per_s"]] * len(rows), "--", color="grey", label="one seed at a time")
    left.set(xscale="log", xlabel="vmapped seeds", ylabel="seed-steps/s (env step + update)", title=device)
    left.set_xticks(seeds, [str(s) for s in seeds])
    left.legend(fontsize=8)
    right.plot(seeds, [r["compile_s"] for r in rows], "o-", color="C1")
    right.set(xscale="log", xlabel="vmapped seeds", ylabel="chunk compile (s)", title="compile time")
    right.set_xticks(seeds, [str(s) for s in seeds])
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def measure_sweep(config: TrainConfig, members: int, vmapped: int, steps: int = 200) -> dict:
    """Seed-steps/s and compile seconds of a sweep of `members` learning rates, one seed each."""
    rate = config.agent_config.learning_rate
    axes = (("algo_params.learning_rate", tuple(rate * (1 + k / 10) for k in range(members))),)
    program = sweep.Sweep(programs.short_run(config, steps), axes, [0], vmapped)
    carry, chunk, compile_s = program.compiled()
    return programs.timed_chunk(carry, chunk, steps, members, compile_s)


def plot_sweep(rows: list, path: Path, device: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (left, right) = plt.subplots(1, 2, figsize=(9, 3.6))
    for mode, style in (("vmapped", "o-"), ("one after another", "s--")):
        own = [r for r in rows if r["mode"] == mode]
        members = [r["members"] for r in own]
        left.plot(members, [r["seed_steps_per_s"] for r in own], style, label=mode)
        right.plot(members, [r["compile_s"] for r in own], style, label=mode)
    for axis, label in ((left, "seed-steps/s (env step + update)"), (right, "chunk compile (s)")):
        axis.set(xscale="log", xlabel="sweep members (1 seed each)", ylabel=label)
        ticks = sorted({r["members"] for r in rows})
        axis.set_xticks(ticks, [str(t) for t in ticks])
        axis.minorticks_off()
        axis.legend(fontsize=8)
    left.set_title(device)
    right.set_title("compile time")
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 4, 8, 16, 32, 64])
    parser.add_argument("--members", type=int, nargs="+", help="measure the sweep axis with these member counts")
    parser.add_argument("--out", type=Path, default=None)
    args = parser.parse_args()
    config = TrainConfig(approach="jt-nf", algo="crossq", task="forward", protocol="thesis-code")
    device = f"{jax.devices()[0].device_kind} x{jax.device_count()} ({os.cpu_count()} CPU cores)"
    about = {"device": device, "machine": results.hardware(), "versions": results.versions(),
             "git_commit": results.git_commit(), "config": "jt-nf crossq forward, thesis-code, 200-step chunks"}
    if args.members:
        out = args.out or OUT.with_name("scaling_sweep.json")
        rows = []
        for count in args.members:
            for mode, vmapped in (("vmapped", count), ("one after another", 1)):
                measured = measure_sweep(config, count, vmapped)
                rows.append({"members": count, "mode": mode, **measured})
                print(f"{count:3d} members {mode}: {measured['seed_steps_per_s']:7.1f} seed-steps/s, "
                      f"compile {measured['compile_s']:.1f} s", flush=True)
        out.write_text(json.dumps({**about, "swept": "algo_params.learning_rate", "rows": rows}, indent=1))
        plot_sweep(rows, out.with_suffix(".png"), device)
        return
    args.out = args.out or OUT
    rows = []
    for count in args.seeds:
        measured = programs.measure_speed(config, list(range(count)))
        rows.append({"seeds": count, **measured})
        print(f"{count:3d} seeds: {measured['seed_steps_per_s']:7.1f} seed-steps/s, compile {measured['compile_s']:.1f} s",
              flush=True)
    report = {**about, "rows": rows}
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(report, indent=1))
    plot(rows, args.out.with_suffix(".png"), device)


if __name__ == "__main__":
    main()
