"""Progressive Directional Expansion Curriculum (thesis §4.5.1) as pure functions.

The circle of walking directions is two half circles of five 36-degree bins each. Left bin
i covers directions [180 - 36 (i + 1), 180 - 36 i] degrees and right bin i the mirror
image, so bin 0 of either half borders backward (180 degrees) and bin 4 forward; the
curriculum starts backward and grows each half towards forward. A command is drawn from
the next unlearned left bin with probability 2/5, the next unlearned right bin 2/5, and a
learned bin 1/5 (probabilities of sides already complete, or of "learned" before any bin
is, go to the other choices), uniformly within the bin. A bin is learned when, over a window
of 400 steps of one episode, the mean velocity along the command reaches 95 % of the
commanded speed and the mean lateral velocity and yaw rate stay within 0.05 (m/s, rad/s);
we read "averaged over 400 steps" as the absolute value of the window's mean. The speed is
half the target until all ten bins are learned.

State is a NamedTuple of arrays, so one curriculum per seed runs under vmap.
"""

from typing import NamedTuple

import jax
import jax.numpy as jnp

BINS_PER_SIDE = 5
NUM_BINS = 2 * BINS_PER_SIDE
BIN_WIDTH = jnp.pi / BINS_PER_SIDE
WINDOW_STEPS = 400
SPEED_FRACTION = 0.95
LATERAL_LIMIT = 0.05
YAW_LIMIT = 0.05
PROBABILITY_NEXT = 2 / 5
PROBABILITY_LEARNED = 1 / 5


class CurriculumState(NamedTuple):
    learned: jnp.ndarray  # (10,) bool: left bins 0-4, then right bins 0-4
    bin: jnp.ndarray  # () int32, bin of the current command
    window: jnp.ndarray  # () int32, steps in the current window
    sums: jnp.ndarray  # (3,) along-command velocity, lateral velocity, yaw rate summed over the window


def init() -> CurriculumState:
    return CurriculumState(learned=jnp.zeros(NUM_BINS, bool), bin=jnp.int32(0), window=jnp.int32(0),
                           sums=jnp.zeros(3))


def bin_range(index):
    """Direction interval [low, high] (radians, 0 = forward, +pi/2 = left) of bin `index`."""
    side = index // BINS_PER_SIDE
    i = index % BINS_PER_SIDE
    left = (jnp.pi - BIN_WIDTH * (i + 1), jnp.pi - BIN_WIDTH * i)
    right = (-jnp.pi + BIN_WIDTH * i, -jnp.pi + BIN_WIDTH * (i + 1))
    return jnp.where(side == 0, left[0], right[0]), jnp.where(side == 0, left[1], right[1])


def next_bins(learned):
    """Index of the next unlearned bin of each half (left, right), -1 where a half is complete."""

    def first_unlearned(half, offset):
        todo = ~half
        return jnp.where(jnp.any(todo), offset + jnp.argmax(todo), -1)

    return (first_unlearned(learned[:BINS_PER_SIDE], 0),
            first_unlearned(learned[BINS_PER_SIDE:], BINS_PER_SIDE))


def bin_probabilities(learned):
    """Probability (10,) of drawing each bin next."""
    left, right = next_bins(learned)
    bins = jnp.arange(NUM_BINS)
    p = PROBABILITY_NEXT * ((bins == left) + (bins == right))
    p = p + PROBABILITY_LEARNED * learned / jnp.maximum(jnp.sum(learned), 1)
    return p / jnp.sum(p)


def complete(learned):
    return jnp.all(learned)


def speed(learned, target_speed: float):
    """Commanded speed: half the target until the whole circle is learned."""
    return jnp.where(complete(learned), target_speed, 0.5 * target_speed)


def sample(state: CurriculumState, key, target_speed: float):
    """A new episode's command [vx, vy, 0] and the state with an empty window."""
    bin_key, angle_key = jax.random.split(key)
    index = jax.random.choice(bin_key, NUM_BINS, p=bin_probabilities(state.learned))
    low, high = bin_range(index)
    angle = jax.random.uniform(angle_key, minval=low, maxval=high)
    v = speed(state.learned, target_speed)
    command = jnp.array([v * jnp.cos(angle), v * jnp.sin(angle), 0.0])
    return state._replace(bin=index.astype(jnp.int32), window=jnp.int32(0), sums=jnp.zeros(3)), command


def record(state: CurriculumState, command, velocity_xy, yaw_rate):
    """Add one step to the window; when it is full, judge the current bin and start a new window."""
    commanded = jnp.linalg.norm(command[:2])
    direction = command[:2] / jnp.maximum(commanded, 1e-6)
    along = velocity_xy @ direction
    lateral = direction[0] * velocity_xy[1] - direction[1] * velocity_xy[0]
    sums = state.sums + jnp.stack([along, lateral, yaw_rate])
    window = state.window + 1
    full = window >= WINDOW_STEPS
    mean = sums / WINDOW_STEPS
    passed = (mean[0] >= SPEED_FRACTION * commanded) & (jnp.abs(mean[1]) < LATERAL_LIMIT) & (
        jnp.abs(mean[2]) < YAW_LIMIT)
    learned = state.learned.at[state.bin].set(state.learned[state.bin] | (full & passed))
    return state._replace(learned=learned, window=jnp.where(full, 0, window),
                          sums=jnp.where(full, jnp.zeros(3), sums))


def progress(state: CurriculumState) -> dict:
    """Learned bins per half and in all, as metrics."""
    return {
        "curriculum/learned_bins": jnp.sum(state.learned).astype(jnp.float32),
        "curriculum/left_bins": jnp.sum(state.learned[:BINS_PER_SIDE]).astype(jnp.float32),
        "curriculum/right_bins": jnp.sum(state.learned[BINS_PER_SIDE:]).astype(jnp.float32),
    }
