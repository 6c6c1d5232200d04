"""Shared, compiled-once fixtures: MJX compiles take 10-30 s each on a CPU."""

import collections
import json
import logging
import os
import re
import tempfile
from pathlib import Path

import jax
import jax.monitoring
import jax.numpy as jnp
import pytest

from mjx_badger.core.cache import enable_compilation_cache
from mjx_badger.learning import programs
from mjx_badger.learning.config import TrainConfig
from mjx_badger.learning.train import make_train
from mjx_badger.protocol import conditions
from mjx_badger.sim.env import EnvConfig, HB40Env
from mjx_badger.tasks import locomotion as tasks

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
COMPILES = []
"""[test, phase, program, seconds] for every trace, lowering and XLA compile of this process, and
[test, "cache_hit", program, 0.0] for every program loaded from the persistent cache."""
_current_test = ["(collection)"]


def _count_compile(event: str, duration: float, fun_name: str = "?", **_) -> None:
    if event in COMPILE_EVENTS:
        _compile_seconds[COMPILE_EVENTS[event]] += duration
        COMPILES.append([_current_test[0], COMPILE_EVENTS[event], fun_name, duration])


jax.monitoring.register_event_duration_secs_listener(_count_compile)


class _CacheHits(logging.Handler):
    """Which programs came from the persistent cache (JAX names them only in a DEBUG record)."""

    HIT = re.compile(r"Persistent compilation cache hit for '([^']+)'")

    def emit(self, record):
        found = self.HIT.search(record.getMessage())
        if found:
            COMPILES.append([_current_test[0], "cache_hit", found[1], 0.0])


_compiler_log = logging.getLogger("jax._src.compiler")
_compiler_log.setLevel(logging.DEBUG)
_compiler_log.propagate = False  # its DEBUG records are counted here, not printed in pytest's reports
_compiler_log.addHandler(_CacheHits())


def traced(since: int, name: str) -> int:
    """How many times a program whose name holds `name` was traced after COMPILES[since]."""
    return sum(1 for _, phase, program, _ in COMPILES[since:] if phase == "trace_s" and name in program)


def pytest_runtest_logstart(nodeid, location):
    _current_test[0] = nodeid  # before setup, so a session fixture's compile counts for the test that built it


def pytest_sessionfinish(session):
    """With MJX_BADGER_COMPILE_LOG=DIR, each process writes the seconds it spent compiling, per phase and per
    program and test (bench_compile.py reads them)."""
    folder = os.environ.get("MJX_BADGER_COMPILE_LOG")
    if folder:
        Path(folder).mkdir(parents=True, exist_ok=True)
        worker = os.environ.get("PYTEST_XDIST_WORKER", "main")
        (Path(folder) / f"{worker}.json").write_text(json.dumps(dict(_compile_seconds)))
        (Path(folder) / f"{worker}.programs.json").write_text(json.dumps(COMPILES))

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
def cpg_code_env():
    """CPG-D on the forward task under the thesis-code protocol, with its jitted reset and step: one program
    for the tests of several files (in another process, the compile cache has it)."""
    env = HB40Env("cpg-d", "forward", EnvConfig())
    return env, jax.jit(env.reset), jax.jit(env.step)


@pytest.fixture(scope="session")
def office():
    """JT-OEF under the office conditions with a probe task whose reward is the (sensed) forward velocity it is given,
    to see which velocity reaches the reward."""
    probe = tasks.forward()._replace(reward=lambda motion, command: (motion.linear_velocity[0], {}))
    return HB40Env("jt-oef", probe, EnvConfig(conditions=conditions.OFFICE))


@pytest.fixture(scope="session")
def trainer():
    return make_train(TINY_TRAIN)


@pytest.fixture(scope="session")
def train_fns(trainer):
    """jit(vmap(init)) and the compiled chunk of the tiny run for two seeds: the very program `runner.run` of
    TINY_TRAIN with two seeds uses in this process, so tests that train it compile it once."""
    built, _ = programs.program(trainer, 2)
    return built.init, built.chunk


def seed_keys(seeds):
    return jax.vmap(jax.random.PRNGKey)(jnp.asarray(seeds))


def run_all_chunks(train_fns, seeds):
    init, chunk = train_fns
    carry = init(seed_keys(seeds))
    history = []
    for index in range(TINY_TRAIN.num_chunks):
        carry, metrics = chunk(carry, index * TINY_TRAIN.chunk_steps)
        history.append(jax.device_get(metrics))
    return carry, history
