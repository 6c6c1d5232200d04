"""What an estimator reads at one control step, and what an estimator is: the types every estimator shares."""

from typing import Callable, NamedTuple

import jax


class Reading(NamedTuple):
    """What an estimator reads at one control step, as the robot measures it."""

    joint_angle: jax.Array
    """(12,) encoder angles (rad), FL, FR, RL, RR x hip, thigh, knee."""
    joint_velocity: jax.Array
    """(12,) encoder velocities (rad/s)."""
    acceleration: jax.Array
    """(3,) IMU specific force in the trunk frame (m/s^2; +9.81 on z at rest)."""
    angular_velocity: jax.Array
    """(3,) IMU gyro in the trunk frame (rad/s)."""
    rotation: jax.Array
    """(3, 3) trunk-to-world rotation from the IMU's orientation."""
    contacts: jax.Array
    """(4,) how surely each foot is on the ground, 1 on it and 0 in the air (a plan, or estimated_contacts)."""
    joint_torque: jax.Array
    """(12,) motor torques from the drivers' current (N m)."""


class Estimator(NamedTuple):
    init: Callable
    step: Callable
