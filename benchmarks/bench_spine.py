"""Speed and memory of the spine on this machine: env steps/s, CrossQ updates/s, compile, memory.

Prints a table and writes benchmarks/results/bench_spine.json. Run: `make benchmark`, or
`python -m benchmarks.bench_spine` from the repository root.
The persistent compilation cache is deliberately not enabled, so compile times are real.
"""

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

import mujoco

from benchmarks.common import RESULTS, mjx_env_steps_per_s, train_chunk, updates_per_s
from mjx_badger.records import results
from mjx_badger.robot import description as robot
from mjx_badger.robot import mjcf

OUT = RESULTS / "bench_spine.json"


def native_control_steps_per_s(seconds=3.0):
    """Native MuJoCo, one thread: control steps (5 physics steps each) per second."""
    model = mjcf.load_model()
    data = mujoco.MjData(model)
    data.qpos[:] = robot.standing_qpos(model)
    data.ctrl[:] = robot.nominal_pose()
    steps, t0 = 0, time.perf_counter()
    while time.perf_counter() - t0 < seconds:
        for _ in range(5):
            mujoco.mj_step(model, data)
        steps += 1
    return steps / (time.perf_counter() - t0)


def memory_of_run(seeds, steps):
    """Peak resident memory (MiB) of a fresh process holding a `seeds` x `steps` CrossQ run."""
    code = (
        "import jax, resource\n"
        "from mjx_badger.learning.config import TrainConfig\n"
        "from mjx_badger.learning.train import make_train\n"
        f"c = TrainConfig(approach='jt-oef', total_steps={steps}, chunk_steps=100, warmup_steps=50, eval_steps=20)\n"
        "t = make_train(c)\n"
        f"carry = jax.jit(jax.vmap(t.init))(jax.random.split(jax.random.PRNGKey(0), {seeds}))\n"
        "from mjx_badger.learning.programs import seeds_chunk\n"
        f"chunk = jax.jit(seeds_chunk(t, {seeds}), donate_argnums=0)\n"
        "carry, m = jax.block_until_ready(chunk(carry, 0))\n"
        "carry, m = jax.block_until_ready(chunk(carry, 100))\n"
        "print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return float(done.stdout.strip().splitlines()[-1])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=OUT)
    args = parser.parse_args()

    figures = {}
    figures["native_mujoco_control_steps_per_s"] = native_control_steps_per_s()
    for batch in (1, 10, 64):
        figures[f"mjx_env_steps_per_s_batch_{batch}"] = mjx_env_steps_per_s(batch)
    for seeds in (1, 10):
        per_seed, total = updates_per_s(seeds)
        figures[f"crossq_updates_per_s_per_seed_{seeds}_seeds"] = per_seed
        figures[f"crossq_updates_per_s_total_{seeds}_seeds"] = total
    for seeds in (1, 10):
        compile_s, rate = train_chunk(seeds)
        figures[f"train_chunk_compile_s_{seeds}_seeds"] = compile_s
        figures[f"train_seed_steps_per_s_{seeds}_seeds"] = rate
    figures["peak_memory_mib_10_seeds_50k_steps"] = memory_of_run(10, 50_000)

    targets = {
        "train_chunk_compile_s_1_seeds": ("<=", 60.0),
        "crossq_updates_per_s_per_seed_1_seeds": (">=", 200.0),
        "peak_memory_mib_10_seeds_50k_steps": ("<", 4096.0),
    }
    print(f"{'figure':48s} {'value':>12s}  target")
    for name, value in figures.items():
        target = targets.get(name)
        verdict = ""
        if target:
            ok = value <= target[1] if target[0] == "<=" else value >= target[1] if target[0] == ">=" else value < target[1]
            verdict = f"{target[0]} {target[1]:g}  {'met' if ok else 'MISSED'}"
        print(f"{name:48s} {value:12.1f}  {verdict}")
    document = {"figures": {k: round(v, 2) for k, v in figures.items()}, "targets": targets,
                "measured": results.now(), "versions": results.versions(), "git_commit": results.git_commit(),
                "hardware": results.hardware()}
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(document, indent=1))
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
