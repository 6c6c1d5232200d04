"""What the training loop may know about a robot: its sensors, its commands, and a ground truth where it has one.

A real-robot adapter implements `Robot` on top of the robot's SDK (for the HB40, the
MAB Robotics API publishing joint states and IMU data and taking joint targets with
gains), is registered by name in `adapters.py` and is passed to `loop.run`. Nothing else
of the loop touches the robot.
"""

import dataclasses
from typing import Protocol

import numpy as np

from mjx_badger.robot import description as robot


@dataclasses.dataclass(frozen=True)
class Sensors:
    """One reading of everything the robot measures itself."""

    time: float
    """Robot clock (s)."""
    joint_angle: np.ndarray
    """(12,) encoder angles (rad), order FL, FR, RL, RR x hip, thigh, knee."""
    joint_velocity: np.ndarray
    """(12,) encoder velocities (rad/s)."""
    joint_torque: np.ndarray
    """(12,) motor torques from the drivers' current (N m)."""
    acceleration: np.ndarray
    """(3,) IMU specific force in the trunk frame (m/s^2; reads +9.81 on z at rest)."""
    angular_velocity: np.ndarray
    """(3,) IMU gyro in the trunk frame (rad/s)."""
    orientation: np.ndarray
    """(4,) IMU orientation, quaternion w, x, y, z, trunk to world."""


class LinkLost(RuntimeError):
    """The robot cannot be reached, or damped itself (its watchdog or safety rule): the episode ends here."""


class RobotTripped(LinkLost):
    """The robot damped itself on its own safety rule before the loop's reading showed it: a fall, not a lost link."""

    def __init__(self, reason: str):
        super().__init__(f"the robot's own safety rule: {reason}")
        self.reason = reason


class Robot(Protocol):
    """A robot the loop can train on; an adapter that subclasses it inherits `truth`'s None."""

    def start(self) -> None:
        """Bring the robot up standing in the nominal pose."""

    def read(self) -> Sensors:
        """The latest sensor reading; never blocks for long."""

    def command(self, targets: np.ndarray, kp: float, kd: float) -> None:
        """Send 12 joint targets (rad) for the motors' PD controllers with gains kp, kd."""

    def hold(self) -> None:
        """Hold the nominal pose with the robot's own controller, no commands needed (pause, standing)."""
        self.command(robot.nominal_pose(robot.HB40), *robot.HB40.pd_gains)

    def damp(self) -> None:
        """Safety mode: Kp 0, Kd 3 on every joint, the robot sinks down slowly."""

    def reset(self) -> None:
        """Block until the robot stands again in the nominal pose (an operator's manual reset)."""

    def stop(self) -> None:
        """Leave the robot in damping mode and release it."""

    def truth(self) -> dict | None:
        """The ground truth, for logs and figures only (the loop never learns from it): a dict with at least
        "linear_velocity", the trunk-frame trunk velocity (3,) in m/s; None where the robot has none (a real one)."""
        return None


def rotation_matrix(quaternion: np.ndarray) -> np.ndarray:
    """Trunk-to-world rotation (3, 3) from a unit quaternion w, x, y, z."""
    w, x, y, z = np.asarray(quaternion, dtype=np.float64) / np.linalg.norm(quaternion)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])


def roll_pitch(rotation: np.ndarray) -> tuple[float, float]:
    """Roll and pitch (rad) of a trunk-to-world rotation, by the environment's own rule (robot.roll_pitch)."""
    roll, pitch = robot.roll_pitch(rotation)
    return float(roll), float(pitch)
