"""The safety monitor: when to stop the motors before the robot hurts itself."""

import dataclasses

import numpy as np

from mjx_badger import kinematics, robot
from mjx_badger.realtime.interface import Sensors, roll_pitch, rotation_matrix


@dataclasses.dataclass(frozen=True)
class SafetyLimits:
    """Trip points of the monitor."""

    tilt_rad: float = robot.HB40.fall_tilt_rad
    """Roll or pitch beyond this trips: the robot's fall rule, as the simulated environment's."""
    joint_margin_rad: float = 0.05
    """A joint this far outside its mechanical range trips (encoders overshoot the stops a little)."""


def check(sensors: Sensors, limits: SafetyLimits = SafetyLimits()) -> str | None:
    """Why the robot must stop now, or None if it may go on."""
    roll, pitch = roll_pitch(rotation_matrix(sensors.orientation))
    if abs(roll) > limits.tilt_rad:
        return f"roll {roll:+.2f} rad"
    if abs(pitch) > limits.tilt_rad:
        return f"pitch {pitch:+.2f} rad"
    angle = np.asarray(sensors.joint_angle)
    outside = (angle < kinematics.JOINT_LOWER.reshape(-1) - limits.joint_margin_rad) | (
        angle > kinematics.JOINT_UPPER.reshape(-1) + limits.joint_margin_rad)
    if outside.any():
        joint = int(np.argmax(outside))
        return f"{robot.JOINT_NAMES[joint]} at {angle[joint]:+.2f} rad, outside its range"
    return None
