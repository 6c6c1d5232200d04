"""The on-robot loop on this machine: control-period timing and what the learner sustains.

1. `--sustain`: for every algorithm at 20 and 40 Hz, the loop on the simulated HB40 with the
   learner running flat out for `--seconds` of learning: gradient updates per control step
   it sustains beside the robot, and the control-period timing while it does.
2. `--run`: the evidence run of issue 5, CrossQ JT-OEF for 20k steps at 40 Hz with the
   learner at CrossQ's one update per step: velocity (estimated and true), falls, timing,
   figure. Target: p99 control-period error <= 2 ms and no missed deadline.
3. `--floor`: the machine's own floor, a bare 40 Hz sleep loop in SCHED_FIFO (where allowed)
   in a process of its own, alone on the machine, for as many periods as the run: what no
   loop on this machine can do better than.
Writes benchmarks/results/bench_realtime.json (and the run's results under
benchmarks/results/realtime/). Run: `make benchmark` (all three), or pick one:
`python -m benchmarks.bench_realtime --sustain`, `--run` or `--floor` from the repository root.
"""

import argparse
import contextlib
import json
import subprocess
import sys
from pathlib import Path

import numpy as np

from benchmarks.common import RESULTS
from mjx_badger.agents.config import ALGORITHMS
from mjx_badger.core.cache import enable_compilation_cache
from mjx_badger.realtime import figure, loop
from mjx_badger.realtime.config import RealtimeConfig
from mjx_badger.realtime.report import load_trace
from mjx_badger.realtime.simulated import SimulatedHB40
from mjx_badger.records import results

OUT = RESULTS / "bench_realtime.json"
RUN_DIR = RESULTS / "realtime"


# A second process samples the machine's steal time (CPU time the hypervisor gave to someone
# else while this VM wanted it) from /proc/stat, so that a long control period can be told
# apart: the loop's own doing, or the virtual CPU not running at all.
STEAL_SAMPLER = """
import sys, time
with open(sys.argv[1], "w") as out:
    last = None
    while True:
        with open("/proc/stat") as stat:
            steal = int(stat.readline().split()[8])
        if steal != last:
            out.write(f"{time.time():.4f} {steal}\\n")
            out.flush()
            last = steal
        time.sleep(0.005)
"""
# The floor: the loop's deadline logic with nothing in the period, in a fresh process.
FLOOR_LOOP = """
import json, sys, time
from mjx_badger.realtime import scheduling
fifo = scheduling.raise_to_realtime()
periods, period = int(sys.argv[1]), 1 / float(sys.argv[2])
starts, late = [], 0
deadline = time.perf_counter()
for _ in range(periods):
    starts.append(time.perf_counter())
    deadline += period
    if not scheduling.sleep_until(deadline):
        late += 1
        deadline = time.perf_counter()
print(json.dumps({"fifo": fifo, "starts": starts, "late": late}))
"""
USER_HZ = 100
"""/proc/stat counts in 10 ms ticks."""


@contextlib.contextmanager
def steal_sampled(log: Path):
    """Sample steal time into `log` while the block runs; yields a list that receives the samples."""
    samples = []
    log.parent.mkdir(parents=True, exist_ok=True)
    sampler = subprocess.Popen([sys.executable, "-c", STEAL_SAMPLER, str(log)]) if Path("/proc/stat").exists() else None
    try:
        yield samples
    finally:
        if sampler is not None:
            sampler.terminate()
            sampler.wait()
        if log.exists() and log.stat().st_size:
            samples.extend(np.loadtxt(log, ndmin=2).tolist())


def _steal_seconds(samples: list) -> float | None:
    return (samples[-1][1] - samples[0][1]) / USER_HZ if samples else None


def _steal_ms(samples: np.ndarray, start: float, end: float) -> float:
    """Steal time (ms) the sampler saw between two epoch times."""
    before = samples[samples[:, 0] <= start]
    after = samples[samples[:, 0] <= end]
    if not len(before) or not len(after):
        return float("nan")
    return float(after[-1, 1] - before[-1, 1]) * 1000 / USER_HZ


def run_name(seed: int, lock_memory: bool = True) -> str:
    """The evidence run's key in the results (plain "run": seed 0 with memory locked, as in docs/realtime.md)."""
    return "run" + ("" if seed == 0 else f"_seed{seed}") + ("" if lock_memory else "_unlocked")


def run_dir(seed: int, lock_memory: bool = True) -> Path:
    """Where that run keeps its results."""
    name = run_name(seed, lock_memory)
    return RUN_DIR if name == "run" else RUN_DIR / name.removeprefix("run_")


def _timing(document: dict) -> dict:
    timing = document["timing"]
    return {k: round(timing[k], 3) if isinstance(timing[k], float) else timing[k]
            for k in ("period_p50_ms", "period_p99_ms", "period_error_p99_ms", "period_error_max_ms",
                      "missed_deadlines", "ticks", "work_p50_ms", "work_p99_ms", "work_max_ms", "wake_p99_ms",
                      "wake_max_ms", "worst_periods", "scheduling", "memory_locked", "major_page_faults")}


def sustain(seconds: float, warmup_steps: int = 200) -> list[dict]:
    """Most updates per control step each algorithm keeps up at 20 and 40 Hz, learner flat out."""
    rows = []
    for algo in ALGORITHMS:
        for hz in (20.0, 40.0):
            config = RealtimeConfig(approach="jt-oef", algo=algo, control_hz=hz, warmup_steps=warmup_steps,
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


def evidence_run(steps: int, seed: int, lock_memory: bool = True) -> dict:
    """CrossQ JT-OEF at 40 Hz on the simulated robot, as the thesis's office run (Table 5.3)."""
    config = RealtimeConfig(approach="jt-oef", algo="crossq", steps=steps, seed=seed)
    out = run_dir(seed, lock_memory)
    with steal_sampled(out / "steal.log") as samples:
        document = loop.run(config, SimulatedHB40(seed=seed), out, resume=False,  # a measurement starts afresh
                            lock_memory=lock_memory)
    steal = np.asarray(samples).reshape(-1, 2)
    for worst in document["timing"]["worst_periods"]:
        # The late tick started at unix_time; the stall lay somewhere in the period before it.
        worst["steal_ms"] = _steal_ms(steal, worst["unix_time"] - worst["period_ms"] / 1000 - 0.02,
                                      worst["unix_time"] + 0.02)
    figure.draw(document, load_trace(out, config), out / f"{config.name}.png")
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
        "steal_seconds": _steal_seconds(samples),
        "thesis_office_run": {"eval_speed": 0.85, "falls": 15, "minutes_with_resets": 25},
    }
    print(json.dumps(summary, indent=1))
    return summary


def floor(periods: int, hz: float = 40.0) -> dict:
    """Period error of a bare sleep loop on this machine (nothing else of ours running)."""
    with steal_sampled(RUN_DIR / "floor" / "steal.log") as samples:
        found = json.loads(subprocess.run([sys.executable, "-c", FLOOR_LOOP, str(periods), str(hz)], check=True,
                                          capture_output=True, text=True).stdout)
    error = np.abs(np.diff(found["starts"]) * 1000 - 1000 / hz)
    summary = {"periods": periods, "hz": hz, "scheduling": "SCHED_FIFO" if found["fifo"] else "ordinary",
               "period_error_p99_ms": round(float(np.percentile(error, 99)), 3),
               "period_error_max_ms": round(float(error.max()), 3),
               **{f"errors_over_{ms}_ms": int(np.sum(error > ms)) for ms in (2, 5, 10)},
               "missed_deadlines": found["late"], "steal_seconds": _steal_seconds(samples)}
    print(json.dumps(summary), flush=True)
    return summary


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sustain", action="store_true", help="only the updates-per-step measurement")
    parser.add_argument("--run", action="store_true", help="only the 20k-step evidence run")
    parser.add_argument("--floor", action="store_true", help="only the bare sleep loop (the machine's floor)")
    parser.add_argument("--seconds", type=float, default=30.0, help="learning seconds per sustain measurement")
    parser.add_argument("--steps", type=int, default=20_000, help="steps of the evidence run")
    parser.add_argument("--seed", type=int, default=0, help="seed of the evidence run (a repeat: another seed)")
    parser.add_argument("--unlocked", action="store_true",
                        help="evidence run without locking memory (what mlockall buys)")
    args = parser.parse_args()
    both = not (args.sustain or args.run or args.floor)
    enable_compilation_cache()
    found = json.loads(OUT.read_text()) if OUT.exists() else {}
    if args.sustain or both:
        found["sustain"] = {"seconds": args.seconds, "rows": sustain(args.seconds)}
    if args.run or both:
        found[run_name(args.seed, not args.unlocked)] = evidence_run(args.steps, args.seed, not args.unlocked)
    if args.floor or both:
        found.setdefault("floor", []).append({**floor(args.steps), "measured": results.now()})
    found.update(versions=results.versions(), git_commit=results.git_commit(), hardware=results.hardware(),
                 updated=results.now())
    OUT.parent.mkdir(parents=True, exist_ok=True)
    OUT.write_text(json.dumps(found, indent=1))
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
