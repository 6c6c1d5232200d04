"""Trunk velocity from what the robot measures (thesis §2.6.1): a Kalman filter fusing leg
odometry with the IMU.

State: the trunk's linear velocity in the world frame. Predict with the IMU's specific
force rotated to the world plus gravity; correct with leg odometry, the velocity a foot
standing still on the ground implies for the trunk, v = -(dp/dt + omega x p), averaged over
the feet taken to be in contact. The thesis assumes all four are; the CPG's planned stance
legs are the option. Swinging feet break the assumption and bias the estimate low, as the
thesis found on the robot (Fig 2.1).
"""

import dataclasses
import functools

import jax
import numpy as np

from mjx_badger import kinematics
from mjx_badger.robot import HB40, RobotSpec
from mjx_badger.realtime.interface import Sensors, rotation_matrix

GRAVITY = np.array([0.0, 0.0, -9.81])


@functools.partial(jax.jit, static_argnums=2)
def _feet_motion(joint_angle, joint_velocity, spec: RobotSpec):
    """Foot positions and velocities (4, 3) in the hip frames."""
    return jax.jvp(functools.partial(kinematics.forward, spec=spec), (joint_angle,), (joint_velocity,))


@dataclasses.dataclass(frozen=True)
class KalmanConfig:
    """Noise levels of the filter's two models."""

    acceleration_std: float = 0.5
    """m/s^2: IMU noise plus unmodelled vibration, drives the prediction's growth in variance."""
    odometry_std: float = 0.1
    """m/s: foot slip and contact-timing error of the leg odometry."""


def leg_odometry(sensors: Sensors, spec: RobotSpec = HB40) -> np.ndarray:
    """Trunk-frame trunk velocity (4, 3) each foot implies if it stands still on the ground."""
    feet, feet_velocity = (np.asarray(x) for x in _feet_motion(sensors.joint_angle, sensors.joint_velocity, spec))
    in_trunk = spec.hip_positions + feet
    return -(feet_velocity + np.cross(sensors.angular_velocity, in_trunk))


class VelocityEstimator:
    """The Kalman filter; `update` once per control step returns the trunk-frame velocity."""

    def __init__(self, config: KalmanConfig = KalmanConfig(), spec: RobotSpec = HB40):
        self.config = config
        self.spec = spec
        self.reset()

    def reset(self):
        """Standing still, and sure of it."""
        self.velocity = np.zeros(3)
        self.covariance = np.eye(3) * 1e-4

    def update(self, sensors: Sensors, dt: float, contacts=None) -> np.ndarray:
        """Predict over `dt` from the IMU, correct with the legs in `contacts` (4,) bools (all if None)."""
        rotation = rotation_matrix(sensors.orientation)
        self.velocity = self.velocity + (rotation @ sensors.acceleration + GRAVITY) * dt
        self.covariance = self.covariance + np.eye(3) * (self.config.acceleration_std * dt) ** 2
        stance = np.ones(len(self.spec.legs), bool) if contacts is None else np.asarray(contacts, bool)
        if stance.any():
            measured = rotation @ leg_odometry(sensors, self.spec)[stance].mean(axis=0)
            noise = np.eye(3) * self.config.odometry_std ** 2 / stance.sum()
            gain = self.covariance @ np.linalg.inv(self.covariance + noise)
            self.velocity = self.velocity + gain @ (measured - self.velocity)
            self.covariance = (np.eye(3) - gain) @ self.covariance
        return rotation.T @ self.velocity
