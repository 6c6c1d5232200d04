"""Reward terms of thesis Tables 4.5 and 4.6 as small pure functions of raw quantities."""

import jax.numpy as jnp


def velocity_tracking(vx, target):
    """Table 4.5 tracking term: plateau 1 on [v_t, 2 v_t], 0 at <= -v_t and >= 4 v_t.

    The printed formula jumps at 2 v_t; we read it as linear ramps -v_t -> v_t and
    2 v_t -> 4 v_t, as docs/readings.md (Velocity reward) says.
    """
    rise = (vx + target) / (2 * target)
    fall = (4 * target - vx) / (2 * target)
    return jnp.clip(jnp.minimum(rise, fall), 0.0, 1.0)


def velocity_tracking_code(vx, target):
    """The released code's track_x term (docs/thesis-code.md §5): 1 on [v_t, 2 v_t], 0 at <= -v_t and >= 4 v_t,
    else 1 - |v - v_t| / (2 v_t). It jumps to 0.5 just above 2 v_t and is negative on (3 v_t, 4 v_t)."""
    inside = (vx > -target) & (vx < 4 * target)
    plateau = (vx >= target) & (vx <= 2 * target)
    return jnp.where(plateau, 1.0, jnp.where(inside, 1.0 - jnp.abs(vx - target) / (2 * target), 0.0))


def yaw_rate_squared(yaw_rate):
    """Table 4.5 yaw penalty: omega_z^2."""
    return yaw_rate**2


def roll_pitch_squared(roll, pitch):
    """Tables 4.5/4.6 trunk-rotation penalty: roll^2 + pitch^2."""
    return roll**2 + pitch**2


def torque_squared(torque):
    """Table 4.5 energy penalty: ||tau||^2 over all motors."""
    return jnp.sum(torque**2, axis=-1)


def combine(terms: dict, weights: dict, scale: float, clip: bool = True):
    """Weighted sum of terms times `scale`, clipped at 0 (Table 4.5 'non-negative reward') if `clip`.

    Returns (reward, contributions) where contributions are weight * term, the figures a
    user compares with the reward table.
    """
    contributions = {name: weights[name] * value for name, value in terms.items()}
    total = scale * sum(contributions.values())
    return (jnp.maximum(total, 0.0) if clip else total), contributions


def planar_velocity_tracking(velocity_xy, target_xy, width: float = 0.5):
    """§4.4.2 approach 2: clip(1 - ||v_xy - v_d|| / 0.5, 0, 1), one joint 2-D tracking term."""
    return jnp.clip(1.0 - jnp.linalg.norm(velocity_xy - target_xy, axis=-1) / width, 0.0, 1.0)


def along_and_lateral(velocity_xy, target_xy):
    """§4.4.2 approach 1 (Fig 4.5): velocity rotated into the command's frame, (along, lateral).

    A zero command counts as forward.
    """
    norm = jnp.linalg.norm(target_xy, axis=-1, keepdims=True)
    direction = jnp.where(norm > 1e-6, target_xy / jnp.maximum(norm, 1e-6), jnp.array([1.0, 0.0]))
    along = jnp.sum(velocity_xy * direction, axis=-1)
    lateral = direction[..., 0] * velocity_xy[..., 1] - direction[..., 1] * velocity_xy[..., 0]
    return along, lateral


def forward_minus_lateral(velocity_xy):
    """Table 4.6 velocity term read as v_x - |v_y|, as docs/readings.md (Tasks) says."""
    return velocity_xy[..., 0] - jnp.abs(velocity_xy[..., 1])


def yaw_rate_abs(yaw_rate):
    """Table 4.6 yaw penalty: |omega_z|."""
    return jnp.abs(yaw_rate)
