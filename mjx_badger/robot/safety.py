"""The robot's safety rule: when its monitor stops the motors, from a trunk attitude and the joint angles.

One rule for the on-robot loop's monitor (NumPy, realtime/safety.py) and for the vmapped env under
on-robot conditions (jax.numpy, sim/termination.py), so that both stop the robot at the same readings.
"""

import numpy as np

from mjx_badger.robot import kinematics
from mjx_badger.robot.description import HB40, RobotSpec, roll_pitch

JOINT_MARGIN_RAD = 0.05
"""A joint this far outside its mechanical range trips (encoders overshoot the stops a little)."""


def trips(rotation, joint_angle, spec: RobotSpec = HB40, xp=np):
    """Whether the monitor stops the robot: a roll or pitch past the spec's fall tilt or a joint out of its range
    (`xp` numpy, or jax.numpy in the vmapped env, which applies the same rule under on-robot conditions)."""
    roll, pitch = roll_pitch(rotation, xp)
    limits = kinematics.leg(spec)
    angle = xp.reshape(joint_angle, (-1,))
    outside = (angle < limits.lower.reshape(-1) - JOINT_MARGIN_RAD) | (angle > limits.upper.reshape(-1) + JOINT_MARGIN_RAD)
    return (xp.abs(roll) > spec.fall_tilt_rad) | (xp.abs(pitch) > spec.fall_tilt_rad) | xp.any(outside)
