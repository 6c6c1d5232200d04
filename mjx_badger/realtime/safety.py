"""The safety monitor: when to stop the motors before the robot hurts itself."""


import numpy as np

from mjx_badger import kinematics, robot
from mjx_badger.realtime.interface import Sensors, roll_pitch, rotation_matrix
from mjx_badger.robot import HB40, RobotSpec

JOINT_MARGIN_RAD = 0.05
"""A joint this far outside its mechanical range trips (encoders overshoot the stops a little)."""


def trips(rotation, joint_angle, spec: RobotSpec = HB40, xp=np):
    """Whether the monitor stops the robot: a roll or pitch past the spec's fall tilt or a joint out of its range
    (`xp` numpy, or jax.numpy in the vmapped env, which applies the same rule under on-robot conditions)."""
    roll, pitch = robot.roll_pitch(rotation, xp)
    limits = kinematics.leg(spec)
    angle = xp.reshape(joint_angle, (-1,))
    outside = (angle < limits.lower.reshape(-1) - JOINT_MARGIN_RAD) | (angle > limits.upper.reshape(-1) + JOINT_MARGIN_RAD)
    return (xp.abs(roll) > spec.fall_tilt_rad) | (xp.abs(pitch) > spec.fall_tilt_rad) | xp.any(outside)


def check(sensors: Sensors, spec: RobotSpec = HB40) -> str | None:
    """Why the robot must stop now, or None if it may go on: the spec's fall tilt (the env's rule) or a joint out of range."""
    roll, pitch = roll_pitch(rotation_matrix(sensors.orientation))
    if abs(roll) > spec.fall_tilt_rad:
        return f"roll {roll:+.2f} rad"
    if abs(pitch) > spec.fall_tilt_rad:
        return f"pitch {pitch:+.2f} rad"
    angle = np.asarray(sensors.joint_angle)
    limits = kinematics.leg(spec)  # computed once per robot: this runs every control period
    lower, upper = limits.lower.reshape(-1), limits.upper.reshape(-1)
    outside = (angle < lower - JOINT_MARGIN_RAD) | (angle > upper + JOINT_MARGIN_RAD)
    if outside.any():
        joint = int(np.argmax(outside))
        return f"{spec.joint_names[joint]} at {angle[joint]:+.2f} rad, outside its range"
    return None
