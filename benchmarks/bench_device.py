"""What an accelerator shows and a 2-core CPU cannot: env steps/s of the vmapped MJX env from batch 1 to 4096,
learner updates/s and seed-steps/s of a training chunk at 1, 10 and 100 vmapped seeds, each with its compile
time, on the device JAX finds (the GPU where there is one).

    python -m benchmarks.bench_device --out $OUT/device.json              # the sizes meant for a GPU
    python -m benchmarks.bench_device --batches 1 4 --seeds 1 2 --steps 50 --out /tmp/device.json  # a try on a CPU

The training chunk is the forward experiment's JT-NF CrossQ run at the full profile (thesis-code), cut to
`--steps` learning steps per chunk (programs.short_run); `device_check.sh` runs this and one whole full-profile
forward run in one sitting.
"""

import argparse
import json
import time
from pathlib import Path

import jax

from benchmarks.common import mjx_env_steps_per_s, updates_per_s
from mjx_badger.experiments.registry import EXPERIMENTS
from mjx_badger.learning import programs
from mjx_badger.records import results


def with_compile(measure, *args):
    """`measure(*args)` and the wall seconds of the whole call (its programs' compile included)."""
    t0 = time.perf_counter()
    value = measure(*args)
    return value, time.perf_counter() - t0


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--batches", type=int, nargs="+", default=[1, 16, 64, 256, 1024, 4096])
    parser.add_argument("--seeds", type=int, nargs="+", default=[1, 10, 100])
    parser.add_argument("--steps", type=int, default=500, help="learning steps per timed training chunk")
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()

    device = jax.devices()[0]
    print(f"device: {device.platform} {device.device_kind} ({jax.device_count()} of them)", flush=True)
    rows = {"env": [], "learner": [], "training": []}
    for batch in args.batches:
        rate, call_s = with_compile(mjx_env_steps_per_s, batch)
        rows["env"].append({"batch": batch, "env_steps_per_s": round(rate, 1), "first_and_timed_calls_s": round(call_s, 1)})
        print(f"env batch {batch:5d}: {rate:12.0f} env steps/s ({call_s:.0f} s with its compile)", flush=True)
    forward = EXPERIMENTS["forward"]
    config = forward.train_config(next(r for r in forward.runs if r.approach == "jt-nf"), "full")
    for seeds in args.seeds:
        (per_seed, total), call_s = with_compile(updates_per_s, seeds)
        rows["learner"].append({"seeds": seeds, "updates_per_s_per_seed": round(per_seed, 1),
                                "updates_per_s_total": round(total, 1), "first_and_timed_calls_s": round(call_s, 1)})
        speed = programs.measure_speed(config, list(range(seeds)), args.steps)
        rows["training"].append({"seeds": seeds, "seed_steps_per_s": round(speed["seed_steps_per_s"], 1),
                                 "compile_s": round(speed["compile_s"], 1)})
        print(f"{seeds:3d} seeds: learner {total:9.0f} updates/s in all, training {speed['seed_steps_per_s']:9.0f} "
              f"seed-steps/s (chunk compile {speed['compile_s']:.0f} s)", flush=True)
    document = {"what": results.what(__doc__), "device": f"{device.platform} {device.device_kind}",
                "device_count": jax.device_count(), "training_config": "forward JT-NF CrossQ, full profile, thesis-code, "
                f"{args.steps}-step chunks", **rows, "measured": results.now(), "versions": results.versions(),
                "git_commit": results.git_commit(), "hardware": results.hardware()}
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(document, indent=1) + "\n")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
