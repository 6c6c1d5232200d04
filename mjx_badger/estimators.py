"""The robot's own trunk-velocity estimators (thesis §2.6), pure JAX and vmappable.

Each is an `Estimator(init, step)`: `init() -> state` (standing still, and sure of it: a
reset recalibrates), `step(state, reading, dt) -> (state, velocity)` with the velocity in
the trunk frame. The state holds the velocity in the world frame, so turning does not
rotate what was integrated.

- `kinematic-kalman` (§2.6.1): a linear Kalman filter predicting with the IMU's specific
  force rotated to the world plus gravity and correcting with leg odometry, the trunk
  velocity a foot standing still on the ground implies, v = -(dp/dt + omega x p), averaged
  over the feet weighted by `reading.contacts`. The thesis's robot took all four feet to be
  on the ground (contacts all one); swinging feet then pull the mean toward zero, and the
  estimate runs low (its Fig 2.1). Contacts from a gait plan or a contact estimate are the
  contact-aware variant.
- `integration` (§2.6.2): the same world-frame acceleration integrated by the trapezoidal
  rule, with no correction: it follows the truth after a reset and drifts with every bias
  of the IMU, until the next reset recalibrates it.
"""

import dataclasses
import functools
from typing import Callable, NamedTuple

import jax
import jax.numpy as jnp

from mjx_badger import kinematics
from mjx_badger.robot import HB40, RobotSpec

GRAVITY = jnp.array([0.0, 0.0, -9.81])


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
    """(4,) weight of each foot's odometry, 1 on the ground and 0 in the air (all ones: the thesis's robot)."""


class KalmanState(NamedTuple):
    velocity: jax.Array
    """(3,) world-frame trunk velocity."""
    covariance: jax.Array
    """(3, 3) its covariance."""
    acceleration: jax.Array
    """(3,) the last world-frame acceleration (the trapezoidal rule's left end)."""


@dataclasses.dataclass(frozen=True)
class KalmanConfig:
    """Noise levels of the filters' models (assumed: the thesis gives none)."""

    acceleration_std: float = 0.5
    """m/s^2: IMU noise plus unmodelled vibration, the growth of the prediction's variance."""
    odometry_std: float = 0.1
    """m/s: foot slip and contact-timing error of one leg's odometry."""


class Estimator(NamedTuple):
    init: Callable
    step: Callable


def leg_odometry(joint_angle, joint_velocity, angular_velocity, spec: RobotSpec = HB40) -> jax.Array:
    """(4, 3) trunk-frame trunk velocity each foot implies if it stands still on the ground."""
    feet, feet_velocity = jax.jvp(functools.partial(kinematics.forward, spec=spec), (joint_angle,), (joint_velocity,))
    in_trunk = jnp.asarray(spec.hip_positions) + feet
    return -(feet_velocity + jnp.cross(angular_velocity, in_trunk))


def _standing() -> KalmanState:
    """Still, and sure of it; at rest the world-frame acceleration (specific force plus gravity) is zero."""
    return KalmanState(jnp.zeros(3), jnp.eye(3) * 1e-4, jnp.zeros(3))


def _world_acceleration(reading: Reading) -> jax.Array:
    return reading.rotation @ reading.acceleration + GRAVITY


def kinematic_kalman(config: KalmanConfig = KalmanConfig(), spec: RobotSpec = HB40) -> Estimator:
    """§2.6.1: IMU prediction, leg-odometry correction weighted by the reading's contacts."""

    def step(state: KalmanState, reading: Reading, dt):
        acceleration = _world_acceleration(reading)
        velocity = state.velocity + acceleration * dt
        covariance = state.covariance + jnp.eye(3) * (config.acceleration_std * dt) ** 2
        weights = jnp.asarray(reading.contacts, jnp.float32)
        total = jnp.sum(weights)
        odometry = leg_odometry(reading.joint_angle, reading.joint_velocity, reading.angular_velocity, spec)
        measured = reading.rotation @ (weights @ odometry / jnp.maximum(total, 1e-6))
        noise = jnp.eye(3) * config.odometry_std ** 2 / jnp.maximum(total, 1e-6)
        gain = covariance @ jnp.linalg.inv(covariance + noise)
        corrected = velocity + gain @ (measured - velocity)
        on_ground = total > 0  # no foot on the ground: nothing to correct with
        velocity = jnp.where(on_ground, corrected, velocity)
        covariance = jnp.where(on_ground, (jnp.eye(3) - gain) @ covariance, covariance)
        return KalmanState(velocity, covariance, acceleration), reading.rotation.T @ velocity

    return Estimator(_standing, step)


def integration(config: KalmanConfig = KalmanConfig()) -> Estimator:
    """§2.6.2: world-frame acceleration integrated by the trapezoidal rule; no correction, so it drifts."""

    def step(state: KalmanState, reading: Reading, dt):
        acceleration = _world_acceleration(reading)
        velocity = state.velocity + 0.5 * (state.acceleration + acceleration) * dt
        covariance = state.covariance + jnp.eye(3) * (config.acceleration_std * dt) ** 2
        return KalmanState(velocity, covariance, acceleration), reading.rotation.T @ velocity

    return Estimator(_standing, step)


ESTIMATORS = {"kinematic-kalman": kinematic_kalman, "integration": lambda config=KalmanConfig(), spec=HB40:
              integration(config)}


def make(name: str, config: KalmanConfig = KalmanConfig(), spec: RobotSpec = HB40) -> Estimator:
    """The estimator called `name`; ValueError naming the choices for any other."""
    if name not in ESTIMATORS:
        raise ValueError(f"unknown estimator {name!r}; choose from {', '.join(ESTIMATORS)}")
    return ESTIMATORS[name](config, spec)
