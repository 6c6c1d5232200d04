"""Reward terms of Table 4.5 against hand-computed values."""

import jax.numpy as jnp
import numpy as np
import pytest

from mjx_badger.tasks import locomotion as tasks
from mjx_badger.tasks import rewards


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


def test_rewards_take_the_codes_forms():
    code, text = tasks.make_task("forward", "thesis-code"), tasks.make_task("forward", "thesis-text")
    cmd = jnp.array([0.5, 0.0, 0.0])
    motion = lambda vx, yaw=0.0: tasks.Motion(jnp.array([vx, 0.0, 0.0]), jnp.array([0.0, 0.0, yaw]), 0.0, 0.0,
                                              jnp.zeros(12))
    # Just above 2 v_t = 1.0 m/s: the code's term jumps to 1 - 0.6 / 1.0 = 0.4; the text's ramp is (2 - 1.1) / 1 = 0.9.
    assert float(code.reward(motion(1.1), cmd)[0]) == pytest.approx(4.0, abs=1e-5)
    assert float(text.reward(motion(1.1), cmd)[0]) == pytest.approx(9.0, abs=1e-5)
    # Yaw: 0.1 |w| in the code, 0.1 w^2 in the text; at w = 0.5: 10 (1 - 0.05) vs 10 (1 - 0.025).
    assert float(code.reward(motion(0.5, 0.5), cmd)[0]) == pytest.approx(9.5, abs=1e-5)
    assert float(text.reward(motion(0.5, 0.5), cmd)[0]) == pytest.approx(9.75, abs=1e-5)
    # max_x is unclipped in the code: walking backward earns a negative reward; its command stays (0.5, 0, 0).
    code_max, text_max = tasks.make_task("forward-max", "thesis-code"), tasks.make_task("forward-max", "thesis-text")
    assert float(code_max.reward(motion(-0.5), cmd)[0]) == pytest.approx(10 * (-0.5 / 0.5), abs=1e-5)
    assert float(text_max.reward(motion(-0.5), cmd)[0]) == 0.0
    np.testing.assert_allclose(code_max.command((), None)[1], [0.5, 0.0, 0.0])
    # track_xy: 0.5 |yaw error| and no energy term in the code.
    omni = tasks.make_task("omni-random", "thesis-code")
    heavy = tasks.Motion(jnp.array([0.5, 0.0, 0.0]), jnp.array([0.0, 0.0, 0.2]), 0.0, 0.0, jnp.full(12, 10.0))
    assert float(omni.reward(heavy, cmd)[0]) == pytest.approx(10 * (1 - 0.5 * 0.2), abs=1e-5)
