"""A policy on native MuJoCo walks as it does on MJX: same model, action pipeline, observation and fall rule."""

from types import SimpleNamespace
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from mjx_badger.learning.config import TrainConfig
from mjx_badger.sim import native

SECONDS = 10.0
VELOCITY_TOLERANCE = 0.03
"""m/s: MJX and native MuJoCo integrate the same contacts a little differently, and a walk amplifies it."""
YAW_TOLERANCE = 0.1
GAIT_TOLERANCE = 0.25
"""Relative: touchdowns over 10 s of a chaotic walk differ with the CPU's float32 code (AMD EPYC: 2.69 vs 3.17 Hz)."""


@pytest.mark.parametrize("approach", ["cpg-d", "jt-nf"])
def test_native_and_mjx_evaluations_agree(approach):
    env = native.evaluation_env(TrainConfig(approach=approach, task="forward"), SECONDS)
    # A fixed random linear policy: it moves the legs enough to walk off (JT) or to steer the trot (CPG).
    weights = np.random.default_rng(0).normal(0, 0.3 / np.sqrt(env.observation_size),
                                              (env.observation_size, env.action_size))
    act = lambda obs: np.tanh(obs @ weights)
    on_mjx = native.run_mjx(env, act, [0.5, 0.0, 0.0], SECONDS)
    on_native = native.run_native(env, act, [0.5, 0.0, 0.0], SECONDS)
    assert on_mjx["falls"] == on_native["falls"] == 0
    for name in ("velocity_along_command", "velocity_across_command"):
        assert abs(on_mjx[name] - on_native[name]) < VELOCITY_TOLERANCE, (name, on_mjx, on_native)
    assert abs(on_mjx["yaw_rate"] - on_native["yaw_rate"]) < YAW_TOLERANCE, (on_mjx, on_native)
    print(approach, on_mjx, on_native)
    faster = max(on_mjx["gait_hz"], on_native["gait_hz"])
    assert abs(on_mjx["gait_hz"] - on_native["gait_hz"]) < GAIT_TOLERANCE * faster, (on_mjx, on_native)
    # It is a walk, not a stand: the trunk moves and the feet step.
    assert abs(on_native["velocity_along_command"]) > 0.02 and on_native["gait_hz"] > 1.0


class _Pipeline(NamedTuple):
    qpos: jax.Array


class _State(NamedTuple):
    pipeline_state: _Pipeline
    obs: jax.Array
    info: dict


class _FallingEnv:
    """A stand-in for HB40Env whose trunk walks 1 cm per step along x and falls every 5th step; its own
    reset draws a random command, as a task's does, unless it is given one."""

    control_dt = 0.025
    spec = SimpleNamespace(physics_dt=0.005)

    def reset(self, key, command=None):
        command = jax.random.uniform(key, (3,)) if command is None else command
        return _State(_Pipeline(jnp.zeros(7).at[3].set(1.0)), command, {"terminated": jnp.array(False), "steps": 0})

    def traced_step(self, state, action):
        steps = state.info["steps"] + 1
        fell = steps % 5 == 0
        qpos = state.pipeline_state.qpos.at[0].add(0.01)
        reset = self.reset(jax.random.PRNGKey(steps))  # the env's auto-reset: the task's own command
        obs = jnp.where(fell, reset.obs, state.obs)
        return _State(_Pipeline(qpos), obs, {"terminated": fell, "steps": steps}), (jnp.ones((5, 4)), None)


def test_an_mjx_evaluation_restarts_under_its_own_command_after_a_fall():
    seen = []

    def act(obs):
        seen.append(np.asarray(obs))
        return np.zeros(12)

    report = native.run_mjx(_FallingEnv(), act, [0.3, 0.0, 0.1], seconds=1.0)
    assert report["falls"] == 40 // 5
    # Every observation carries the evaluation's command, never one the env's auto-reset drew.
    np.testing.assert_allclose(np.array(seen), np.tile([0.3, 0.0, 0.1], (40, 1)), atol=1e-7)
    # The steps that fell are not counted as displacement: 32 of 40 steps moved 1 cm in 1 s.
    assert report["velocity_along_command"] == pytest.approx(0.32, abs=1e-6)


def test_native_evaluation_reports_the_estimate_beside_the_true_speed():
    env = native.evaluation_env(TrainConfig(approach="cpg-d", conditions="office"), 1.0)
    report = native.run_native(env, lambda obs: np.zeros(env.action_size), [0.25, 0.0, 0.0], 1.0)
    assert "estimated_velocity_along_command" in report and np.isfinite(report["estimated_velocity_along_command"])
    assert "estimated_velocity_along_command" not in native.run_native(
        native.evaluation_env(TrainConfig(approach="cpg-d"), 1.0), lambda obs: np.zeros(env.action_size),
        [0.25, 0.0, 0.0], 1.0)
