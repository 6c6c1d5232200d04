"""Speed and memory of the spine on this machine: env steps/s, CrossQ updates/s, compile, memory.

Prints a table and writes benchmarks/results/bench_spine.json. Run: `make benchmark`.
The persistent compilation cache is deliberately not enabled, so compile times are real.
"""

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

import jax
import jax.numpy as jnp
import mujoco
import numpy as np

from mjx_badger import mjcf, replay_buffer, results, robot, runner
from mjx_badger.agents import ALGORITHMS, make_agent
from mjx_badger.agents.losses import Transition
from mjx_badger.env import EnvConfig, HB40Env
from mjx_badger.train import TrainConfig, make_train

OUT = Path(__file__).parent / "results" / "bench_spine.json"


def timed(fn, *args, repeats=3):
    """Median wall time of fn(*args) after one warm call (which compiles)."""
    jax.block_until_ready(fn(*args))
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        jax.block_until_ready(fn(*args))
        times.append(time.perf_counter() - t0)
    return float(np.median(times))


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


def mjx_env_steps_per_s(batch, steps=200):
    """Full environment steps (JT-OEF, delay on) per second at a given batch size."""
    env = HB40Env("jt-oef", "forward", EnvConfig())

    def rollout(keys):
        def body(state, key):
            action = jax.random.uniform(key, (batch, env.action_size), minval=-1, maxval=1)
            return jax.vmap(env.step)(state, action), None

        state = jax.vmap(env.reset)(keys)
        return jax.lax.scan(body, state, jax.random.split(keys[0], steps))[0].obs

    fn = jax.jit(rollout)
    return batch * steps / timed(fn, jax.random.split(jax.random.PRNGKey(0), batch))


def update_program(seeds, algo="crossq", updates=200, cfg=None):
    """A jitted scan of `updates` gradient updates on a filled replay buffer, and its arguments.

    One seed runs the unbatched program, as the runner does (see runner.seeds_chunk). `cfg`
    (an AgentConfig) replaces the algorithm's default configuration.
    """
    cfg = ALGORITHMS[algo]() if cfg is None else cfg
    agent = make_agent(cfg, 54, 12)
    buffer = replay_buffer.init(10_000, 54, 12)
    buffer = buffer.replace(
        data=Transition(*(jax.random.normal(jax.random.PRNGKey(i), x.shape) for i, x in enumerate(buffer.data))),
        size=jnp.int32(10_000))

    def run(key, buffer):
        def body(state, i):
            batch_key, update_key = jax.random.split(jax.random.fold_in(key, i))
            return agent.update(state, replay_buffer.sample(buffer, batch_key, cfg.batch_size), update_key, i)[0], None

        return jax.lax.scan(body, agent.init(key), jnp.arange(updates))[0].log_alpha

    keys = jax.random.split(jax.random.PRNGKey(0), seeds)
    if seeds == 1:
        return jax.jit(run), (keys[0], buffer)
    buffers = jax.tree.map(lambda x: jnp.broadcast_to(x, (seeds,) + x.shape), buffer)
    return jax.jit(jax.vmap(run)), (keys, buffers)


def updates_per_s(seeds, algo="crossq", updates=200, cfg=None):
    """Gradient updates per second per seed and in total, on a filled replay buffer."""
    fn, args = update_program(seeds, algo, updates, cfg)
    seconds = timed(fn, *args)
    return updates / seconds, seeds * updates / seconds


def chunk_program(seeds, chunk_steps=500, algo="crossq"):
    """Compile time, the compiled training chunk and its arguments (JT-OEF, forward, no warm-up).

    The chunk's deterministic evaluation is cut to one step: these figures are the
    learning loop's throughput (env step, replay, updates), not the evaluation's.
    """
    config = TrainConfig(approach="jt-oef", algo=algo, total_steps=20_000, chunk_steps=chunk_steps, warmup_steps=0,
                         eval_steps=1)
    trainer = make_train(config)
    carry = jax.jit(jax.vmap(trainer.init))(jax.random.split(jax.random.PRNGKey(0), seeds))
    t0 = time.perf_counter()
    chunk = jax.jit(runner.seeds_chunk(trainer, seeds)).lower(carry, 0).compile()
    compile_s = time.perf_counter() - t0
    carry, _ = jax.block_until_ready(chunk(carry, 0))
    return compile_s, chunk, (carry, chunk_steps)


def train_chunk(seeds, chunk_steps=500, algo="crossq"):
    """Compile time and seed-steps/s of a full training chunk (env step + updates per step)."""
    compile_s, chunk, args = chunk_program(seeds, chunk_steps, algo)
    return compile_s, seeds * chunk_steps / timed(chunk, *args, repeats=2)


def memory_of_run(seeds, steps):
    """Peak resident memory (MiB) of a fresh process holding a `seeds` x `steps` CrossQ run."""
    code = (
        "import jax, resource\n"
        "from mjx_badger.train import TrainConfig, make_train\n"
        f"c = TrainConfig(approach='jt-oef', total_steps={steps}, chunk_steps=100, warmup_steps=50, eval_steps=20)\n"
        "t = make_train(c)\n"
        f"carry = jax.jit(jax.vmap(t.init))(jax.random.split(jax.random.PRNGKey(0), {seeds}))\n"
        "from mjx_badger.runner import seeds_chunk\n"
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
