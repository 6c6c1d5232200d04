"""Tasks of §4.4 and §5.1 and the PDEC curriculum of §4.5.1, against hand-computed cases."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from mjx_badger import curriculum, tasks


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


def test_bins_start_backward_and_tile_the_circle():
    low, high = jax.vmap(curriculum.bin_range)(jnp.arange(10))
    degrees = lambda x: np.degrees(np.asarray(x))
    np.testing.assert_allclose(degrees(low[:5]), [144, 108, 72, 36, 0], atol=1e-4)  # left half, backward first
    np.testing.assert_allclose(degrees(high[5:]), [-144, -108, -72, -36, 0], atol=1e-4)  # right half
    np.testing.assert_allclose(degrees(high - low), 36, atol=1e-4)


def test_sampling_probabilities():
    learned = jnp.zeros(10, bool)
    p = np.asarray(curriculum.bin_probabilities(learned))
    np.testing.assert_allclose(p[[0, 5]], 0.5)  # nothing learned: the two backward bins, equally
    assert p.sum() == pytest.approx(1.0)
    learned = learned.at[0].set(True)
    p = np.asarray(curriculum.bin_probabilities(learned))
    np.testing.assert_allclose(p[[1, 5, 0]], [0.4, 0.4, 0.2])  # next left 2/5, next right 2/5, learned 1/5
    left_done = jnp.zeros(10, bool).at[:5].set(True)
    p = np.asarray(curriculum.bin_probabilities(left_done))
    # No next-left bin: 2/5 right, 1/5 over five learned bins, renormalised over 3/5.
    np.testing.assert_allclose(p[5], 2 / 3)
    np.testing.assert_allclose(p[:5], 1 / 15)


def test_samples_land_in_the_drawn_bin_at_half_speed_until_complete():
    state = curriculum.init()._replace(learned=jnp.zeros(10, bool).at[0].set(True))
    keys = jax.random.split(jax.random.PRNGKey(1), 500)
    states, commands = jax.vmap(lambda k: curriculum.sample(state, k, 0.5))(keys)
    bins, commands = np.asarray(states.bin), np.asarray(commands)
    assert set(bins) == {0, 1, 5}
    assert 0.1 < (bins == 0).mean() < 0.3
    np.testing.assert_allclose(np.linalg.norm(commands[:, :2], axis=1), 0.25, atol=1e-6)
    angles = np.arctan2(commands[:, 1], commands[:, 0])
    low, high = jax.vmap(curriculum.bin_range)(jnp.asarray(bins))
    assert np.all((angles >= np.asarray(low) - 1e-5) & (angles <= np.asarray(high) + 1e-5))
    full = curriculum.init()._replace(learned=jnp.ones(10, bool))
    _, command = curriculum.sample(full, keys[0], 0.5)
    assert float(jnp.linalg.norm(command[:2])) == pytest.approx(0.5)


def _window(state, command, velocity_xy, yaw, steps=curriculum.WINDOW_STEPS):
    def body(s, _):
        return curriculum.record(s, command, jnp.asarray(velocity_xy), jnp.float32(yaw)), None

    return jax.lax.scan(body, state, None, length=steps)[0]


@pytest.mark.parametrize("velocity_xy, yaw, learned", [
    ((-0.238, 0.0), 0.0, True),  # 95.2 % of 0.25 m/s backward
    ((-0.23, 0.0), 0.0, False),  # 92 %
    ((-0.25, 0.049), 0.0, True),  # lateral just inside 0.05
    ((-0.25, 0.06), 0.0, False),  # lateral 0.06
    ((-0.25, 0.0), -0.06, False),  # yaw 0.06
])
def test_a_bin_is_learned_by_the_400_step_window(velocity_xy, yaw, learned):
    state = curriculum.init()._replace(bin=jnp.int32(0))
    command = jnp.array([-0.25, 0.0, 0.0])
    almost = _window(state, command, velocity_xy, yaw, steps=curriculum.WINDOW_STEPS - 1)
    assert not bool(almost.learned[0]) and int(almost.window) == curriculum.WINDOW_STEPS - 1
    after = _window(state, command, velocity_xy, yaw)
    assert bool(after.learned[0]) == learned
    assert int(after.window) == 0 and np.all(np.asarray(after.sums) == 0)  # a new window starts
    assert int(jnp.sum(after.learned)) == int(learned)


def test_progress_metrics_count_bins_per_half():
    state = curriculum.init()._replace(learned=jnp.array([1, 1, 0, 0, 0, 1, 0, 0, 0, 0], bool))
    progress = curriculum.progress(state)
    assert float(progress["curriculum/learned_bins"]) == 3
    assert float(progress["curriculum/left_bins"]) == 2 and float(progress["curriculum/right_bins"]) == 1
