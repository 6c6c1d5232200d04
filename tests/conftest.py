"""Shared, compiled-once fixtures: MJX compiles take 10-30 s each on a CPU."""

import jax
import jax.numpy as jnp
import pytest

from mjx_badger import enable_compilation_cache
from mjx_badger.env import EnvConfig, HB40Env
from mjx_badger.train import TrainConfig, make_train

enable_compilation_cache()

# The smallest training run that still exercises warm-up, learning, episode ends and evaluation.
TINY_TRAIN = TrainConfig(approach="jt-oef", algo="crossq", task="forward", total_steps=300, chunk_steps=100,
                         warmup_steps=100, eval_steps=20)


@pytest.fixture(scope="session")
def env():
    """JT-NF on the forward task under the thesis-code protocol (no action delay: rollouts are deterministic)."""
    return HB40Env("jt-nf", "forward", EnvConfig())


@pytest.fixture(scope="session")
def env_fns(env):
    """Jitted reset and step of the shared environment."""
    return jax.jit(env.reset), jax.jit(env.step)


@pytest.fixture(scope="session")
def trainer():
    return make_train(TINY_TRAIN)


@pytest.fixture(scope="session")
def train_fns(trainer):
    """jit(vmap(init)) and jit(vmap(chunk)) of the tiny run, plus a trace counter for the chunk."""
    traces = {"chunk": 0}

    def counted_chunk(carry, start):
        traces["chunk"] += 1
        return trainer.chunk(carry, start)

    init = jax.jit(jax.vmap(trainer.init))
    chunk = jax.jit(jax.vmap(counted_chunk, in_axes=(0, None)))
    return init, chunk, traces


def seed_keys(seeds):
    return jax.vmap(jax.random.PRNGKey)(jnp.asarray(seeds))
