"""Trot central pattern generator of thesis §4.3: one phase, diagonal leg pairs in anti-phase.

The phase p in [0, 1) advances by frequency x dt. Each leg runs the same cycle shifted by
its offset: swing while its own phase is in [0, 0.5), stance after. The swing height is the
thesis's spline, read as two cubic smoothsteps (lift, then lower) each in its own
normalised half of the swing, apex 0.15 m at mid-swing; the stance height is 0, as docs/readings.md (CPG) says.
"""

from typing import NamedTuple

import jax.numpy as jnp
import numpy as np

from mjx_badger.robot.description import HB40, RobotSpec

APEX_HEIGHT = 0.15
SWING_FRACTION = 0.5


def leg_phase_offsets(spec: RobotSpec = HB40) -> np.ndarray:
    """Per leg, 0 or half a cycle: the diagonal pairs (FL with RR, FR with RL) alternate, the trot."""
    return np.where(spec.front_sign * spec.left_sign > 0, 0.0, 0.5)


class CPGState(NamedTuple):
    phase: jnp.ndarray  # () in [0, 1)


def init() -> CPGState:
    return CPGState(phase=jnp.float32(0.0))


def advance(state: CPGState, frequency, dt: float) -> CPGState:
    """Move the phase on by one control period at `frequency` Hz."""
    return CPGState(phase=jnp.mod(state.phase + frequency * dt, 1.0))


def smoothstep(t):
    """-2 t^3 + 3 t^2: 0 -> 1 on [0, 1] with zero slope at both ends."""
    return -2.0 * t**3 + 3.0 * t**2


def swing_height(t, apex: float = APEX_HEIGHT):
    """Foot height at normalised swing time t in [0, 1]: lift on [0, 0.5], lower on [0.5, 1]."""
    lift = apex * smoothstep(jnp.clip(2.0 * t, 0.0, 1.0))
    lower = apex * (1.0 - smoothstep(jnp.clip(2.0 * t - 1.0, 0.0, 1.0)))
    return jnp.where(t < 0.5, lift, lower)


def leg_phases(phase, spec: RobotSpec = HB40):
    """Each leg's own phase (4,) in [0, 1)."""
    return jnp.mod(phase + leg_phase_offsets(spec), 1.0)


def foot_heights(phase, apex: float = APEX_HEIGHT, spec: RobotSpec = HB40):
    """Foot height above the stance height (4,) for every leg at CPG phase `phase`."""
    own = leg_phases(phase, spec)
    return jnp.where(own < SWING_FRACTION, swing_height(own / SWING_FRACTION, apex), 0.0)


def progress(phase):
    """The two CPG-progress observations (Table 4.1) in [0, 1]: the phase on a circle, no jump at wrap."""
    angle = 2.0 * jnp.pi * phase
    return jnp.stack([0.5 * (1.0 + jnp.sin(angle)), 0.5 * (1.0 + jnp.cos(angle))])
