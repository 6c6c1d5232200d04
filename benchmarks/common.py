"""What the benchmarks share: where their results go, timing, and the env, update and training-chunk programs
they time (the persistent compilation cache is not enabled here, so compile times are real)."""

import time
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np

from mjx_badger.agents import replay_buffer
from mjx_badger.agents.agent import make_agent
from mjx_badger.agents.config import ALGORITHMS
from mjx_badger.agents.losses import Transition
from mjx_badger.learning import programs
from mjx_badger.learning.config import TrainConfig
from mjx_badger.learning.train import make_train
from mjx_badger.sim import evaluation
from mjx_badger.sim.env import EnvConfig, HB40Env

ROOT = Path(__file__).resolve().parent.parent
RESULTS = Path(__file__).parent / "results"
"""benchmarks/results/: every file there is the output of a bench_* script."""


def timed(fn, *args, repeats=3):
    """Median wall time of fn(*args) after one warm call (which compiles)."""
    jax.block_until_ready(fn(*args))
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        jax.block_until_ready(fn(*args))
        times.append(time.perf_counter() - t0)
    return float(np.median(times))


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


def env_steps_per_s(sensing, batch: int, on_robot=None, steps: int = 40) -> float:
    """Control steps per second of jit(vmap(scan of env.step)) over `batch` robots (JT-OEF, forward), with
    `sensing` (sensors.Sensing, or None for none) and `on_robot` (conditions, or None for the simulation's)."""
    env = HB40Env("jt-oef", "forward", EnvConfig(sensing=sensing, conditions=on_robot))
    actions = 0.3 * jnp.sin(jnp.arange(steps)[:, None] * 0.2 + jnp.arange(env.action_size))

    def rollout(key):
        # Every leaf made to depend on the key: vmap would otherwise step the key-free physics once for the batch.
        state = evaluation.batched_like(env.reset(key), key)
        return jax.lax.scan(lambda s, a: (env.step(s, a), None), state, actions)[0].obs

    run = jax.jit(jax.vmap(rollout))
    keys = jax.random.split(jax.random.PRNGKey(0), batch)
    return batch * steps / timed(run, keys)


def update_program(seeds, algo="crossq", updates=200, cfg=None):
    """A jitted scan of `updates` gradient updates on a filled replay buffer, and its arguments.

    One seed runs the unbatched program, as the runner does (see programs.seeds_chunk). `cfg`
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
    chunk = jax.jit(programs.seeds_chunk(trainer, seeds)).lower(carry, 0).compile()
    compile_s = time.perf_counter() - t0
    carry, _ = jax.block_until_ready(chunk(carry, 0))
    return compile_s, chunk, (carry, chunk_steps)


def train_chunk(seeds, chunk_steps=500, algo="crossq"):
    """Compile time and seed-steps/s of a full training chunk (env step + updates per step)."""
    compile_s, chunk, args = chunk_program(seeds, chunk_steps, algo)
    return compile_s, seeds * chunk_steps / timed(chunk, *args, repeats=2)
