"""Tasks of §4.4 and §5.1 and the PDEC curriculum of §4.5.1, against hand-computed cases."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from mjx_badger.learning.config import TrainConfig
from mjx_badger.tasks import locomotion as tasks


def motion(vx=0.0, vy=0.0, yaw=0.0, roll=0.0, pitch=0.0, torque=0.0):
    return tasks.Motion(jnp.array([vx, vy, 0.0]), jnp.array([0.0, 0.0, yaw]), jnp.float32(roll), jnp.float32(pitch),
                        jnp.full(12, torque))


def test_forward_max_reward_table_4_6():
    task = tasks.make_task("forward-max")
    reward, terms = task.reward(motion(vx=1.0, vy=-0.2, yaw=-0.5, roll=0.1), jnp.zeros(3))
    # 10 x (2 (1.0 - 0.2) - 0.1 x 0.5 - 10 x 0.01) = 10 x (1.6 - 0.05 - 0.1) = 14.5
    assert float(reward) == pytest.approx(14.5, rel=1e-5)
    assert set(terms) == {"velocity", "yaw", "roll_pitch"}
    backward, _ = task.reward(motion(vx=-0.3), jnp.zeros(3))
    assert float(backward) == 0.0  # non-negative


def test_a_reward_weight_is_a_task_parameter_named_by_its_term():
    """forward-max without its roll/pitch penalty: 10 x (1.6 - 0.05) = 15.5; under thesis-code omni has no energy."""
    task = tasks.make_task("forward-max", roll_pitch_weight=0.0)
    reward, _ = task.reward(motion(vx=1.0, vy=-0.2, yaw=-0.5, roll=0.1), jnp.zeros(3))
    assert float(reward) == pytest.approx(15.5, rel=1e-5) and task.weights["roll_pitch"] == 0.0
    assert "energy_weight" in tasks.task_params("omni-pdec", "thesis-text")
    assert "energy_weight" not in tasks.task_params("omni-pdec", "thesis-code")
    with pytest.raises(ValueError, match="task 'omni-pdec' takes speed, velocity_weight, .*not energy_weight"):
        tasks.make_task("omni-pdec", "thesis-code", energy_weight=0.1)

    config = TrainConfig(task="omni-pdec", protocol="thesis-text", task_params=(("energy_weight", 0.0),))
    assert config.make_task().weights["energy"] == 0.0


def test_omni_joint_2d_reward():
    task = tasks.make_task("omni-random")
    command = jnp.array([0.0, 0.5, 0.0])  # left at 0.5 m/s
    on_target, _ = task.reward(motion(vx=0.0, vy=0.5), command)
    assert float(on_target) == pytest.approx(10.0)
    # ||(0.3, 0.5) - (0, 0.5)|| = 0.3 -> 1 - 0.3 / 0.5 = 0.4; energy 12 x 1^2 x -0.0003; x 10
    off, terms = task.reward(motion(vx=0.3, vy=0.5, torque=1.0), command)
    assert float(terms["velocity"]) == pytest.approx(0.4)
    assert float(off) == pytest.approx(10 * (0.4 - 0.0036), rel=1e-5)
    standing, _ = task.reward(motion(), command)
    assert float(standing) == 0.0


def test_omni_rotated_reward_with_lateral_penalty():
    task = tasks.make_task("omni-random-rotated")
    # Command left; velocity 0.5 along it and 0.1 to its right: along 0.5 -> tracking 1, lateral |-0.1|
    reward, terms = task.reward(motion(vx=0.1, vy=0.5), jnp.array([0.0, 0.5, 0.0]))
    assert float(terms["lateral"]) == pytest.approx(-0.1)
    assert float(reward) == pytest.approx(10 * (1.0 - 0.1), rel=1e-5)


def test_omni_random_commands_cover_the_circle_at_target_speed():
    task = tasks.make_task("omni-random")
    commands = jax.vmap(lambda k: task.command((), k)[1])(jax.random.split(jax.random.PRNGKey(0), 4000))
    commands = np.asarray(commands)
    np.testing.assert_allclose(np.linalg.norm(commands[:, :2], axis=1), 0.5, atol=1e-6)
    angles = np.arctan2(commands[:, 1], commands[:, 0])
    counts = np.histogram(angles, bins=8, range=(-np.pi, np.pi))[0]
    assert counts.min() > 400  # uniform: 500 per bin expected
    assert np.all(commands[:, 2] == 0)


def test_omni_evaluation_commands_are_four_directions_at_two_speeds():
    commands = tasks.make_task("omni-pdec").eval_commands
    assert len(commands) == 8
    assert commands["backward_full"] == pytest.approx((-0.5, 0.0, 0.0))
    assert commands["right_half"] == pytest.approx((0.0, -0.25, 0.0))


