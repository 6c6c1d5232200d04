"""Reward terms of Table 4.5 against hand-computed values."""

import jax.numpy as jnp
import numpy as np
import pytest

from mjx_badger import rewards, tasks


@pytest.mark.parametrize(
    "vx, expected",
    [
        (-0.6, 0.0),  # below -v_t
        (-0.5, 0.0),  # -v_t
        (0.0, 0.5),  # (0 + 0.5) / 1.0
        (0.25, 0.75),
        (0.5, 1.0),  # plateau starts at v_t
        (0.75, 1.0),
        (1.0, 1.0),  # plateau ends at 2 v_t
        (1.5, 0.5),  # (2.0 - 1.5) / 1.0
        (2.0, 0.0),  # 4 v_t
        (3.0, 0.0),
    ],
)
def test_velocity_tracking(vx, expected):
    assert float(rewards.velocity_tracking(jnp.float32(vx), 0.5)) == pytest.approx(expected, abs=1e-6)


def test_penalty_terms():
    assert float(rewards.yaw_rate_squared(jnp.float32(-0.3))) == pytest.approx(0.09)
    assert float(rewards.roll_pitch_squared(jnp.float32(0.1), jnp.float32(-0.2))) == pytest.approx(0.05)
    assert float(rewards.torque_squared(jnp.full(12, 2.0))) == pytest.approx(48.0)


def test_forward_reward_total_by_hand():
    task = tasks.forward()
    motion = tasks.Motion(
        linear_velocity=jnp.array([0.25, 0.1, 0.0]),
        angular_velocity=jnp.array([0.0, 0.0, 0.5]),
        roll=jnp.float32(0.1),
        pitch=jnp.float32(0.0),
        torque=jnp.full(12, 2.0),
    )
    reward, parts = task.reward(motion, task.command((), None)[1])
    # velocity 0.75 * 1; yaw 0.25 * -0.1 = -0.025; roll/pitch 0.01 * -10 = -0.1; energy 48 * -0.0003 = -0.0144
    # total = 10 * (0.75 - 0.025 - 0.1 - 0.0144) = 6.106
    assert float(reward) == pytest.approx(6.106, rel=1e-5)
    np.testing.assert_allclose([float(parts[k]) for k in ("velocity", "yaw", "roll_pitch", "energy")],
                               [0.75, -0.025, -0.1, -0.0144], rtol=1e-5)


def test_forward_reward_is_never_negative():
    task = tasks.forward()
    motion = tasks.Motion(jnp.array([-1.0, 0.0, 0.0]), jnp.array([0.0, 0.0, 3.0]), jnp.float32(0.5),
                          jnp.float32(0.5), jnp.full(12, 16.0))
    reward, parts = task.reward(motion, task.command((), None)[1])
    assert sum(float(v) for v in parts.values()) < 0
    assert float(reward) == 0.0
