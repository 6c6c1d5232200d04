"""The GPU check, one short command (about 8 minutes on one GPU): compile seconds and seed-steps/s of the quick JT-OEF CrossQ run at 10, 64 and 1,024 seeds, of one full-profile run of each task, and what pinning the matmul precision costs.

    python -m benchmarks.bench_gpu_check --out $OUT/gpu_check.json            # on a GPU
    python -m benchmarks.bench_gpu_check --allow-cpu --seeds 2 --tasks forward --steps 20 --out /tmp/g.json  # a try

Each measurement is a short run of the configuration (`programs.measure_speed`: two chunks of `--steps` learning
steps with their share of evaluation, the second timed) and is written as soon as it is taken, so a check cut
short keeps what it measured; a measurement that would start after `--budget-s` is left out and named. A full
run's hours follow from its rate: 50k steps x 10 seeds / seed-steps/s, plus its compile.
"""

import argparse
import json
import time
from pathlib import Path

import jax

from mjx_badger.experiments.registry import EXPERIMENTS, PROFILES
from mjx_badger.learning import programs
from mjx_badger.records import results

TASK_RUNS = {"forward": ("forward", "jt-nf"), "forward-max": ("forward-max", "jt-nf"),
             "omni-random": ("omni-random", "jt-nf"), "omni-pdec": ("omni-pdec", "cpg-d")}
"""One run of each task at the full profile: (experiment, approach)."""


def config_of(experiment: str, approach: str, profile: str):
    chosen = EXPERIMENTS[experiment]
    return chosen.train_config(next(r for r in chosen.runs if r.approach == approach), profile)


def plan(args) -> list[tuple]:
    """(name, config, seeds, matmul precision) of every measurement, in the order taken."""
    quick = config_of("forward", "jt-oef", "quick")
    rows = [(f"quick jt-oef crossq x{n}", quick, n, "highest") for n in args.seeds]
    rows.append((f"quick jt-oef crossq x{args.seeds[len(args.seeds) // 2]} at default precision", quick,
                 args.seeds[len(args.seeds) // 2], "default"))
    full = PROFILES["full"].seeds
    rows += [(f"full {task} x{full}", config_of(*TASK_RUNS[task], "full"), full, "highest") for task in args.tasks]
    return rows


def measure(name: str, config, seeds: int, precision: str, steps: int) -> dict:
    with jax.default_matmul_precision(precision):  # traced under it, so the program is compiled with it
        speed = programs.measure_speed(config, list(range(seeds)), steps, evaluation=True)
    row = {"name": name, "seeds": seeds, "matmul_precision": precision, "compile_s": round(speed["compile_s"], 1),
           "seed_steps_per_s": round(speed["seed_steps_per_s"], 1)}
    if name.startswith("full"):
        row["full_run_h"] = round((config.total_steps * seeds / speed["seed_steps_per_s"] + speed["compile_s"])
                                  / 3600, 2)
    return row


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seeds", type=int, nargs="+", default=[10, 64, 1024])
    parser.add_argument("--tasks", nargs="+", choices=tuple(TASK_RUNS), default=list(TASK_RUNS))
    parser.add_argument("--steps", type=int, default=200, help="learning steps per timed chunk")
    parser.add_argument("--budget-s", type=float, default=440.0, help="start no measurement after this many seconds")
    parser.add_argument("--allow-cpu", action="store_true", help="run where JAX finds no GPU (a try of the script)")
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args(argv)
    device = jax.devices()[0]
    if device.platform != "gpu" and not args.allow_cpu:
        parser.exit(2, f"error: JAX finds no GPU here ({device.platform} {device.device_kind}); the check measures "
                       "a GPU (--allow-cpu tries it here)\n")
    started = time.perf_counter()
    document = {"what": results.what(__doc__), "device": f"{device.platform} {device.device_kind}",
                "device_count": jax.device_count(), "steps_per_chunk": args.steps, "rows": [], "left_out": [],
                "measured": results.now(), "versions": results.versions(), "git_commit": results.git_commit()}
    print(f"device: {document['device']}", flush=True)
    for name, config, seeds, precision in plan(args):
        if time.perf_counter() - started > args.budget_s:
            document["left_out"].append(name)
            print(f"{name}: left out (past the {args.budget_s:.0f} s budget)", flush=True)
        else:
            row = measure(name, config, seeds, precision, args.steps)
            document["rows"].append(row)
            print(json.dumps(row), flush=True)
        document["wall_s"] = round(time.perf_counter() - started, 1)
        document["hardware"] = results.hardware()
        args.out.parent.mkdir(parents=True, exist_ok=True)
        args.out.write_text(json.dumps(document, indent=1) + "\n")  # after each row: a cut-short check keeps it
    print(f"wrote {args.out} in {document['wall_s']:.0f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
