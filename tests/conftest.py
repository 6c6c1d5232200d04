"""Shared, compiled-once fixtures: MJX compiles take 10-30 s each on a CPU."""

import collections
import json
import os
import tempfile
from pathlib import Path

import jax
import jax.monitoring
import jax.numpy as jnp
import pytest

from mjx_badger import enable_compilation_cache
from mjx_badger.env import EnvConfig, HB40Env
from mjx_badger.train import TrainConfig, make_train

# One compilation cache per test run, shared by the xdist workers and the commands tests start in
# subprocesses (they read MJX_BADGER_CACHE): a program compiled by one test is loaded by the others,
# and a run's time does not depend on what an earlier run left on the disk.
_RUN = os.environ.get("PYTEST_XDIST_TESTRUNUID") or f"single-{os.getpid()}"
os.environ.setdefault("MJX_BADGER_CACHE", str(Path(tempfile.gettempdir()) / "mjx_badger-tests" / _RUN))
enable_compilation_cache()

COMPILE_EVENTS = {"/jax/core/compile/jaxpr_trace_duration": "trace_s",
                  "/jax/core/compile/jaxpr_to_mlir_module_duration": "lower_s",
                  "/jax/core/compile/backend_compile_duration": "xla_compile_s"}
_compile_seconds = collections.Counter()


def _count_compile(event: str, duration: float, **_) -> None:
    if event in COMPILE_EVENTS:
        _compile_seconds[COMPILE_EVENTS[event]] += duration


jax.monitoring.register_event_duration_secs_listener(_count_compile)


def pytest_sessionfinish(session):
    """With MJX_BADGER_COMPILE_LOG=DIR, each process writes the seconds it spent compiling (bench_compile.py reads them)."""
    folder = os.environ.get("MJX_BADGER_COMPILE_LOG")
    if folder:
        Path(folder).mkdir(parents=True, exist_ok=True)
        worker = os.environ.get("PYTEST_XDIST_WORKER", "main")
        (Path(folder) / f"{worker}.json").write_text(json.dumps(dict(_compile_seconds)))

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
