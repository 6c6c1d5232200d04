"""The on-robot loop's velocity estimate: the shared §2.6.1 estimator (mjx_badger/estimation/estimators.py)
fed from the robot's Sensors, one reading per control step. No second implementation lives here."""

import jax
import numpy as np

from mjx_badger.estimation import estimators
from mjx_badger.estimation.estimators import KalmanConfig
from mjx_badger.realtime.interface import Sensors, rotation_matrix
from mjx_badger.robot.description import HB40, RobotSpec

__all__ = ["KalmanConfig", "VelocityEstimator", "estimator_name", "leg_odometry", "reading"]


def estimator_name(config) -> str:
    """The estimator a realtime run uses: the thesis's all-four-feet filter, or the plan's contacts (CPG)."""
    return "kinematic-kalman-contact" if config.planned_contacts else "kinematic-kalman"


def reading(sensors: Sensors, contacts=None, legs: int = 4) -> estimators.Reading:
    """The estimator's Reading of one Sensors; `contacts` (4,) bools or weights, all feet if None."""
    weights = np.ones(legs, np.float32) if contacts is None else np.asarray(contacts, np.float32)
    f32 = lambda x: np.asarray(x, np.float32)
    return estimators.Reading(f32(sensors.joint_angle), f32(sensors.joint_velocity), f32(sensors.acceleration),
                              f32(sensors.angular_velocity), f32(rotation_matrix(sensors.orientation)), weights,
                              f32(sensors.joint_torque))


def leg_odometry(sensors: Sensors, spec: RobotSpec = HB40) -> np.ndarray:
    """(4, 3) trunk-frame trunk velocity each foot implies if it stands still on the ground."""
    return np.asarray(_odometry(sensors.joint_angle, sensors.joint_velocity, sensors.angular_velocity, spec))


_odometry = jax.jit(estimators.leg_odometry, static_argnums=3)


class VelocityEstimator:
    """The Kalman filter of §2.6.1 on the host; `update` once per control step returns the trunk-frame velocity."""

    def __init__(self, config: KalmanConfig = KalmanConfig(), spec: RobotSpec = HB40, name: str = "kinematic-kalman"):
        self.spec = spec
        self.estimator = estimators.make(name, config, spec)
        self.reset()
        # Compiled here, before the loop starts: a compile inside a control tick would miss its deadline.
        legs = len(spec.legs)
        like = estimators.Reading(np.zeros(12, np.float32), np.zeros(12, np.float32), np.zeros(3, np.float32),
                                  np.zeros(3, np.float32), np.eye(3, dtype=np.float32), np.ones(legs, np.float32),
                                  np.zeros(12, np.float32))
        self._step = jax.jit(self.estimator.step).lower(self.state, like, np.float32(0.0)).compile()

    def reset(self):
        """Standing still, and sure of it."""
        self.state = self.estimator.init()

    def update(self, sensors: Sensors, dt: float, contacts=None) -> np.ndarray:
        """Predict over `dt` from the IMU, correct with the legs in `contacts` (4,) bools (all if None)."""
        self.state, velocity = self._step(self.state, reading(sensors, contacts, len(self.spec.legs)), np.float32(dt))
        return np.asarray(velocity, np.float64)
