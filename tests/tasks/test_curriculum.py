"""The PDEC curriculum: its parts, their probabilities, when a bin is learned, and its progress metrics."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from mjx_badger.tasks import curriculum
from mjx_badger.tasks import locomotion as tasks

TEXT, CODE = curriculum.RULES["thesis-text"], curriculum.RULES["thesis-code"]


def _state(left, right, **changes):
    return curriculum.init()._replace(learned=jnp.array([left, right], jnp.int32), **changes)


def test_parts_start_backward_and_grow_towards_forward():
    degrees = lambda part, left, right: np.degrees(np.asarray(curriculum.part_range(jnp.array([left, right]), part)))
    np.testing.assert_allclose(degrees(curriculum.NEXT_LEFT, 0, 0), [144, 180], atol=1e-4)
    np.testing.assert_allclose(degrees(curriculum.NEXT_RIGHT, 0, 0), [-180, -144], atol=1e-4)
    np.testing.assert_allclose(degrees(curriculum.NEXT_LEFT, 4, 1), [0, 36], atol=1e-4)  # the forward bin
    np.testing.assert_allclose(degrees(curriculum.LEARNED, 2, 1), [108, 216], atol=1e-4)  # 216 deg = -144 deg


@pytest.mark.parametrize("rules, learned, expected", [
    (TEXT, (0, 0), (0.5, 0.5, 0.0)),  # nothing learned: the two backward bins, equally
    (CODE, (0, 0), (0.5, 0.5, 0.0)),
    (TEXT, (1, 0), (0.4, 0.4, 0.2)),  # text: the learned region as soon as one bin is learned
    (CODE, (1, 0), (0.5, 0.5, 0.0)),  # code: 50/50 until each half has a bin
    (CODE, (1, 1), (0.4, 0.4, 0.2)),
    (TEXT, (5, 2), (0.0, 2 / 3, 1 / 3)),  # text: a half stops at forward, its share goes to the others
    (CODE, (5, 2), (0.4, 0.4, 0.2)),  # code: the left half grows past forward
    (TEXT, (5, 5), (0.0, 0.0, 1.0)),
    (CODE, (7, 3), (0.0, 0.0, 1.0)),
])
def test_part_probabilities(rules, learned, expected):
    p = curriculum.part_probabilities(jnp.array(learned, jnp.int32), rules)
    np.testing.assert_allclose(np.asarray(p), expected, atol=1e-6)


def _samples(state, rules, n=2000):
    keys = jax.random.split(jax.random.PRNGKey(1), n)
    states, commands = jax.vmap(lambda k: curriculum.sample(state, k, 0.5, rules))(keys)
    return np.asarray(states.part), np.asarray(commands)


def test_text_samples_land_in_the_drawn_part_at_half_speed_until_complete():
    parts, commands = _samples(_state(1, 1), TEXT)
    assert 0.15 < (parts == curriculum.LEARNED).mean() < 0.25
    np.testing.assert_allclose(np.linalg.norm(commands[:, :2], axis=1), 0.25, atol=1e-6)
    angles = np.arctan2(commands[:, 1], commands[:, 0])
    for part in range(3):
        low, high = np.asarray(curriculum.part_range(jnp.array([1, 1]), part))
        wrapped = np.mod(angles[parts == part] - low, 2 * np.pi)
        assert np.all(wrapped <= high - low + 1e-5), part
    _, commands = _samples(_state(5, 5), TEXT, n=50)
    np.testing.assert_allclose(np.linalg.norm(commands[:, :2], axis=1), 0.5, atol=1e-6)


def test_code_learned_region_speeds_are_random_or_zero():
    parts, commands = _samples(_state(2, 2), CODE)
    speeds = np.linalg.norm(commands[:, :2], axis=1)
    np.testing.assert_allclose(speeds[parts != curriculum.LEARNED], 0.25, atol=1e-6)  # the 0.25 m/s cap
    learned = speeds[parts == curriculum.LEARNED]
    assert 0.05 < (learned == 0).mean() < 0.15  # stop with probability 0.1
    moving = learned[learned > 0]
    assert moving.min() >= 0.1 - 1e-6 and moving.max() <= 0.25 + 1e-6 and moving.std() > 0.03
    _, commands = _samples(_state(6, 4), CODE)  # complete: the whole circle, U(0.1, 0.5)
    assert np.linalg.norm(commands[:, :2], axis=1).max() > 0.45


def _run(state, command, velocity_xy, yaw, rules, steps=curriculum.WINDOW_STEPS):
    def body(s, _):
        return curriculum.record(s, command, jnp.asarray(velocity_xy), jnp.float32(yaw), rules), None

    return jax.lax.scan(body, state, None, length=steps)[0]


@pytest.mark.parametrize("rules", [TEXT, CODE], ids=["text", "code"])
@pytest.mark.parametrize("velocity_xy, yaw, learned", [
    ((-0.238, 0.0), 0.0, True),  # 95.2 % of 0.25 m/s backward
    ((-0.23, 0.0), 0.0, False),  # 92 %
    ((-0.25, 0.049), 0.0, True),  # lateral just inside 0.05
    ((-0.25, 0.06), 0.0, False),  # lateral 0.06
    ((-0.25, 0.0), -0.06, False),  # yaw 0.06
])
def test_a_bin_is_learned_by_the_400_step_mean(rules, velocity_xy, yaw, learned):
    state = _state(0, 0, part=jnp.int32(curriculum.NEXT_LEFT))
    command = jnp.array([-0.25, 0.0, 0.0])
    if rules is TEXT:  # judged only once the window is full
        almost = _run(state, command, velocity_xy, yaw, rules, steps=curriculum.WINDOW_STEPS - 1)
        assert int(almost.learned[0]) == 0
    after = _run(state, command, velocity_xy, yaw, rules)
    assert tuple(np.asarray(after.learned)) == (int(learned), 0)
    twice = _run(state, command, velocity_xy, yaw, rules, steps=3 * curriculum.WINDOW_STEPS)
    assert tuple(np.asarray(twice.learned)) == (int(learned), 0)  # at most one bin per episode


def test_text_judges_whole_windows_and_code_a_rolling_mean():
    """Stand still for 200 steps, then walk at the command: only the rolling mean catches up."""
    state = _state(1, 1, part=jnp.int32(curriculum.NEXT_RIGHT))
    command = jnp.array([-0.25, 0.0, 0.0])
    for rules, expected in ((TEXT, 1), (CODE, 2)):
        s = _run(state, command, (0.0, 0.0), 0.0, rules, steps=200)
        s = _run(s, command, (-0.25, 0.0), 0.0, rules, steps=500)
        assert int(s.learned[1]) == expected


def test_the_learned_region_never_levels_up():
    state = _state(1, 1, part=jnp.int32(curriculum.LEARNED))
    after = _run(state, jnp.array([-0.25, 0.0, 0.0]), (-0.3, 0.0), 0.0, CODE)
    assert tuple(np.asarray(after.learned)) == (1, 1)


def test_progress_metrics_count_bins_per_half():
    progress = curriculum.progress(_state(2, 1))
    assert float(progress["curriculum/learned_bins"]) == 3
    assert float(progress["curriculum/left_bins"]) == 2 and float(progress["curriculum/right_bins"]) == 1


def test_the_protocols_choose_the_curriculum_rules():
    # The rules argument, not the reward form, picks the rules.
    code, text = (tasks.make_task("omni-pdec", "thesis-text", "thesis-code"),
                  tasks.make_task("omni-pdec", "thesis-code", "thesis-text"))
    state = _state(2, 2)
    key = jax.random.PRNGKey(3)
    speeds = [float(jnp.linalg.norm(t.command(state, k)[1][:2])) for t in (code, text)
              for k in jax.random.split(key, 20)]
    code_speeds, text_speeds = set(np.round(speeds[:20], 4)), set(np.round(speeds[20:], 4))
    assert len(code_speeds) > 2  # the code's learned-region speeds: U(0.1, 0.25) or 0
    assert text_speeds == {0.25}  # the text's: half speed until every bin is learned
