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


def _walked(step_turn: float, step_forward: float, step_sideways: float = 0.0, steps: int = 800):
    """A track of `steps` control steps, each moving the trunk `step_forward`, `step_sideways` m in its heading frame
    and turning it `step_turn` rad."""
    track, yaw, position = native._Track(), 0.0, np.zeros(2)
    pose = lambda p, y: np.array([p[0], p[1], 0.3, np.cos(y / 2), 0.0, 0.0, np.sin(y / 2)])
    for _ in range(steps):
        middle = yaw + step_turn / 2
        after = position + step_forward * np.array([np.cos(middle), np.sin(middle)]) \
            + step_sideways * np.array([-np.sin(middle), np.cos(middle)])
        track.step(pose(position, yaw), pose(after, yaw + step_turn), fell=False)
        position, yaw = after, yaw + step_turn
    return track.summary(np.array([1.0, 0.0, 0.0]), steps * 0.025, 0.005)


def test_an_evaluation_names_a_policy_that_walks_in_circles_and_measures_it_in_its_own_frame_too():
    """The committed JT-NF max-velocity policy's case: 1.25 m/s in its own frame, turning 0.2 rad/s, over 20 s."""
    circling = _walked(0.2 * 0.025, 1.25 * 0.025)
    assert circling["path"] == "circling" and "circling" in circling["path_note"]
    assert circling["forward_velocity"] == pytest.approx(1.25, rel=1e-6)
    assert circling["heading_velocity_along_command"] == pytest.approx(1.25, rel=1e-6)
    assert abs(circling["velocity_along_command"]) < 0.5  # in the world it got nowhere near 25 m
    assert circling["heading_change_deg"] == pytest.approx(np.degrees(4.0), rel=1e-6)
    straight = _walked(0.0, 0.5 * 0.025)
    assert straight["path"] == "straight" and straight["velocity_along_command"] == pytest.approx(0.5)
    assert _walked(0.001, 0.5 * 0.025)["path"] == "turning"  # 46 deg over 20 s
    crab = _walked(0.0, 0.4 * 0.025, 0.2 * 0.025)
    assert crab["path"] == "drifting" and crab["lateral_velocity"] == pytest.approx(0.2)
    assert _walked(0.0, 0.001 * 0.025)["path"] == "standing"
    # A turn that was asked for is no circling: 0.2 rad/s commanded, 0.2 walked.
    assert native.path_verdict([1.0, 0.0, 0.2], (1.0, 0.0), (0.1, 0.1), 4.0, 20.0)[0] == "straight"
