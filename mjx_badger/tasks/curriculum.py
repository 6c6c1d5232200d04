"""Progressive Directional Expansion Curriculum (thesis §4.5.1) as pure functions, in two rule sets.

The circle of walking directions is cut into ten 36-degree bins that are learned outward from
backward (180 degrees) along two halves, left (positive angles) and right. Left bin k covers
[180 - 36 (k + 1), 180 - 36 k] degrees and right bin k its mirror image. Each episode draws
one of three parts: the next left bin, the next right bin, or the learned region (every bin
learned so far), and a direction uniformly within it. A part's next bin is learned when, in
one episode, the mean over 400 steps of the velocity along the command reaches 95 % of the
commanded speed while the mean lateral velocity and yaw rate stay within 0.05 (m/s, rad/s),
at most once per episode. We read "averaged over 400 steps" as the absolute value of the mean.

`Rules` holds the choices on which the thesis text and the released code
(`honey_badger_*/command_functions/curriculum.py`, docs/thesis-code.md §7) differ; `RULES` names the
two sets. State is a NamedTuple of arrays, so one curriculum per seed runs under vmap.
"""

from typing import NamedTuple

import jax
import jax.numpy as jnp

NUM_BINS = 10
BIN_WIDTH = 2 * jnp.pi / NUM_BINS
WINDOW_STEPS = 400
SPEED_FRACTION = 0.95
LATERAL_LIMIT = 0.05
YAW_LIMIT = 0.05
PROBABILITY_NEXT = 2 / 5
PROBABILITY_LEARNED = 1 / 5
NEXT_LEFT, NEXT_RIGHT, LEARNED = 0, 1, 2


class Rules(NamedTuple):
    """Static choices of a curriculum (text vs released code)."""

    bins_per_half: int | None
    """Text: 5, each half grows to forward. Code: None, a half grows until it meets the other."""
    both_halves_first: bool
    """Code: True, next-left or next-right 50/50 until each half has a learned bin. Text: False, the
    learned region is drawn (1/5) as soon as any bin is learned."""
    speed_cap: float | None
    """Speed until the circle is complete. Code: 0.25 m/s (min with the target). Text: None, half the target."""
    random_learned_speed: bool
    """Code: True, learned-region commands have speed U(0.1, cap) with probability 0.9, else 0.
    Text: False, every command has the curriculum's speed."""
    rolling_window: bool
    """Code: True, a zero-filled rolling 400-step mean judged every step. Text: False, judged at the
    end of each 400-step window, after which a new window starts."""


RULES = {
    "thesis-text": Rules(bins_per_half=5, both_halves_first=False, speed_cap=None, random_learned_speed=False,
                         rolling_window=False),
    "thesis-code": Rules(bins_per_half=None, both_halves_first=True, speed_cap=0.25, random_learned_speed=True,
                         rolling_window=True),
}
LEARNED_SPEED_FLOOR = 0.1
STOP_PROBABILITY = 0.1


class CurriculumState(NamedTuple):
    learned: jnp.ndarray  # (2,) int32: bins learned on the left and on the right half
    part: jnp.ndarray  # () int32: part of the current command (NEXT_LEFT, NEXT_RIGHT or LEARNED)
    window: jnp.ndarray  # () int32: steps recorded since the window started
    history: jnp.ndarray  # (WINDOW_STEPS, 3) along, lateral, yaw rate of the window's steps (ring)
    sums: jnp.ndarray  # (3,) sum of `history`
    leveled: jnp.ndarray  # () bool: this episode already learned a bin


def init() -> CurriculumState:
    return CurriculumState(learned=jnp.zeros(2, jnp.int32), part=jnp.int32(LEARNED), window=jnp.int32(0),
                           history=jnp.zeros((WINDOW_STEPS, 3)), sums=jnp.zeros(3), leveled=jnp.bool_(False))


def complete(learned):
    return jnp.sum(learned) >= NUM_BINS


def part_range(learned, part):
    """Direction interval [low, high] (radians, 0 = forward, +pi/2 = left; may exceed pi) of a part."""
    left, right = learned[0] * BIN_WIDTH, learned[1] * BIN_WIDTH
    lows = jnp.stack([jnp.pi - left - BIN_WIDTH, -jnp.pi + right, jnp.pi - left])
    highs = jnp.stack([jnp.pi - left, -jnp.pi + right + BIN_WIDTH, jnp.pi + right])
    return lows[part], highs[part]


def part_probabilities(learned, rules: Rules):
    """Probability (3,) of drawing next-left, next-right and the learned region."""
    total = jnp.sum(learned)
    if rules.bins_per_half is None:
        open_halves = jnp.full(2, total < NUM_BINS)
    else:
        open_halves = learned < rules.bins_per_half
    may_draw_learned = jnp.all(learned > 0) if rules.both_halves_first else total > 0
    next_weight = jnp.where(rules.both_halves_first & jnp.any(learned == 0), 0.5, PROBABILITY_NEXT)
    weights = jnp.concatenate([next_weight * open_halves, jnp.array([PROBABILITY_LEARNED]) * may_draw_learned])
    return weights / jnp.sum(weights)


def speed(learned, target_speed: float, rules: Rules):
    """Commanded speed: capped until the whole circle is learned."""
    cap = 0.5 * target_speed if rules.speed_cap is None else min(target_speed, rules.speed_cap)
    return jnp.where(complete(learned), target_speed, cap)


def sample(state: CurriculumState, key, target_speed: float, rules: Rules):
    """A new episode's command [vx, vy, 0] and the state with an empty window."""
    part_key, angle_key, speed_key, stop_key = jax.random.split(key, 4)
    part = jax.random.choice(part_key, 3, p=part_probabilities(state.learned, rules))
    low, high = part_range(state.learned, part)
    angle = jax.random.uniform(angle_key, minval=low, maxval=high)
    v = speed(state.learned, target_speed, rules)
    if rules.random_learned_speed:
        drawn = jax.random.uniform(speed_key, minval=LEARNED_SPEED_FLOOR, maxval=v)
        drawn = jnp.where(jax.random.uniform(stop_key) < STOP_PROBABILITY, 0.0, drawn)
        v = jnp.where(part == LEARNED, drawn, v)
    command = jnp.array([v * jnp.cos(angle), v * jnp.sin(angle), 0.0])
    fresh = init()
    return fresh._replace(learned=state.learned, part=part.astype(jnp.int32)), command


def record(state: CurriculumState, command, velocity_xy, yaw_rate, rules: Rules):
    """Add one step to the window and judge the current part's next bin when the rules say so."""
    commanded = jnp.linalg.norm(command[:2])
    direction = command[:2] / jnp.maximum(commanded, 1e-6)
    along = velocity_xy @ direction
    lateral = direction[0] * velocity_xy[1] - direction[1] * velocity_xy[0]
    step = jnp.stack([along, lateral, yaw_rate])
    slot = state.window % WINDOW_STEPS
    sums = state.sums + step - state.history[slot]
    history = state.history.at[slot].set(step)
    window = state.window + 1
    mean = sums / WINDOW_STEPS  # zero-filled before the window is full
    passed = (mean[0] >= SPEED_FRACTION * commanded) & (jnp.abs(mean[1]) < LATERAL_LIMIT) & (
        jnp.abs(mean[2]) < YAW_LIMIT)
    full = window >= WINDOW_STEPS
    judged = jnp.bool_(True) if rules.rolling_window else full
    level_up = judged & passed & (state.part != LEARNED) & ~state.leveled
    learned = state.learned + level_up * (jnp.arange(2) == state.part)
    new = state._replace(learned=learned, window=window, history=history, sums=sums,
                         leveled=state.leveled | level_up)
    if rules.rolling_window:
        return new
    restart = init()._replace(learned=learned, part=state.part, leveled=new.leveled)
    return jax.tree.map(lambda a, b: jnp.where(full, a, b), restart, new)


def progress(state: CurriculumState) -> dict:
    """Learned bins per half and in all, as metrics."""
    return {
        "curriculum/learned_bins": jnp.sum(state.learned).astype(jnp.float32),
        "curriculum/left_bins": state.learned[0].astype(jnp.float32),
        "curriculum/right_bins": state.learned[1].astype(jnp.float32),
    }
