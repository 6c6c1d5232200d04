"""The safety monitor: why the robot must stop now, in words, from one sensor reading (robot/safety.py's rule)."""

import numpy as np

from mjx_badger.realtime.interface import Sensors, roll_pitch, rotation_matrix
from mjx_badger.robot import kinematics
from mjx_badger.robot.description import HB40, RobotSpec
from mjx_badger.robot.safety import JOINT_MARGIN_RAD


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
