"""The on-robot loop on this machine: control-period timing and what the learner sustains.

1. `--sustain`: for every algorithm at 20 and 40 Hz, the loop on the simulated HB40 with the
   learner running flat out for `--seconds` of learning: gradient updates per control step
   it sustains beside the robot, and the control-period timing while it does.
2. `--run`: the evidence run of issue 5, CrossQ JT-OEF for 20k steps at 40 Hz with the
   learner at CrossQ's one update per step: velocity (estimated and true), falls, timing,
   figure. Target: p99 control-period error <= 2 ms and no missed deadline.
Writes benchmarks/results/bench_realtime.json (and the run's results under
benchmarks/results/realtime/). Run: `make benchmark` (both), or pick one.
"""

import argparse
import json
from pathlib import Path

from mjx_badger import enable_compilation_cache, plots, results
from mjx_badger.agents import ALGORITHMS
from mjx_badger.realtime import loop
from mjx_badger.realtime.simulated import SimulatedHB40

OUT = Path(__file__).parent / "results" / "bench_realtime.json"
RUN_DIR = Path(__file__).parent / "results" / "realtime"


def run_dir(seed: int) -> Path:
    """Where the evidence run of `seed` keeps its results (seed 0 at the top, as in the README)."""
    return RUN_DIR if seed == 0 else RUN_DIR / f"seed{seed}"


def _timing(document: dict) -> dict:
    timing = document["timing"]
    return {k: round(timing[k], 3) if isinstance(timing[k], float) else timing[k]
            for k in ("period_p50_ms", "period_p99_ms", "period_error_p99_ms", "period_error_max_ms",
                      "missed_deadlines", "ticks", "work_p50_ms", "work_p99_ms", "work_max_ms", "wake_p99_ms", "wake_max_ms",
                      "worst_periods", "scheduling", "memory_locked", "major_page_faults")}


def sustain(seconds: float, warmup_steps: int = 200) -> list[dict]:
    """Most updates per control step each algorithm keeps up at 20 and 40 Hz, learner flat out."""
    rows = []
    for algo in ALGORITHMS:
        for hz in (20.0, 40.0):
            config = loop.RealtimeConfig(approach="jt-oef", algo=algo, control_hz=hz, warmup_steps=warmup_steps,
                                         steps=warmup_steps + int(seconds * hz), unthrottled=True, eval_seconds=0.0)
            document = loop.run(config, SimulatedHB40(reset_seconds=0.5), RUN_DIR / "sustain", resume=False,
                                view=False)
            row = {"algo": algo, "hz": hz, "updates_per_step": round(document["updates_per_learning_step"], 2),
                   **_timing(document)}
            print(f"{algo:10s} {hz:4.0f} Hz  {row['updates_per_step']:6.2f} updates/step  period p50 "
                  f"{row['period_p50_ms']:.2f} ms  p99 error {row['period_error_p99_ms']:.2f} ms  "
                  f"late {row['missed_deadlines']}/{row['ticks']}", flush=True)
            rows.append(row)
    return rows


def evidence_run(steps: int, seed: int) -> dict:
    """CrossQ JT-OEF at 40 Hz on the simulated robot, as the thesis's office run (Table 5.3)."""
    config = loop.RealtimeConfig(approach="jt-oef", algo="crossq", steps=steps, seed=seed)
    out = run_dir(seed)
    document = loop.run(config, SimulatedHB40(seed=seed), out, resume=False)  # a measurement starts afresh
    plots.realtime_figure(document, loop.load_trace(out, config), out / f"{config.name}.png")
    rows = document["rows"]
    best = max((r for r in rows if r["true_velocity"] is not None), key=lambda r: r["true_velocity"], default=None)
    summary = {
        "steps": document["steps"], "complete": document["complete"], "falls": document["falls"],
        "train_minutes": round(document["train_minutes"], 2),
        "minutes_with_resets": round(document["minutes_with_resets"], 2),
        "updates_per_learning_step": round(document["updates_per_learning_step"], 3),
        "best_5s_true_velocity": None if best is None else round(best["true_velocity"], 3),
        "best_5s_estimated_velocity": None if best is None else round(best["estimated_velocity"], 3),
        "evaluation": document["evaluation"], **_timing(document),
        "thesis_office_run": {"eval_speed": 0.85, "falls": 15, "minutes_with_resets": 25},
    }
    print(json.dumps(summary, indent=1))
    return summary


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sustain", action="store_true", help="only the updates-per-step measurement")
    parser.add_argument("--run", action="store_true", help="only the 20k-step evidence run")
    parser.add_argument("--seconds", type=float, default=30.0, help="learning seconds per sustain measurement")
    parser.add_argument("--steps", type=int, default=20_000, help="steps of the evidence run")
    parser.add_argument("--seed", type=int, default=0, help="seed of the evidence run (a repeat: another seed)")
    args = parser.parse_args()
    both = not (args.sustain or args.run)
    enable_compilation_cache()
    found = json.loads(OUT.read_text()) if OUT.exists() else {}
    if args.sustain or both:
        found["sustain"] = {"seconds": args.seconds, "rows": sustain(args.seconds)}
    if args.run or both:
        found["run" if args.seed == 0 else f"run_seed{args.seed}"] = evidence_run(args.steps, args.seed)
    found.update(versions=results.versions(), git_commit=results.git_commit(), hardware=results.hardware(),
                 updated=results.now())
    OUT.parent.mkdir(parents=True, exist_ok=True)
    OUT.write_text(json.dumps(found, indent=1))
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
