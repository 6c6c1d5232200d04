"""The robot's own trunk-velocity estimators (thesis §2.6), pure JAX and vmappable.

Each is an `Estimator(init, step)`: `init() -> state` (standing still, and sure of it: a
reset recalibrates), `step(state, reading, dt) -> (state, velocity)` with the velocity in
the trunk frame. The state holds the velocity in the world frame, so turning does not
rotate what was integrated.

- `kinematic-kalman` (§2.6.1): a linear Kalman filter predicting with the IMU's specific
  force rotated to the world plus gravity and correcting with leg odometry, the trunk
  velocity a foot standing still on the ground implies, v = -(dp/dt + omega x p), averaged
  over all four feet, as the thesis's robot did (its policy gives no gait plan): swinging
  feet pull the mean toward zero, and the estimate runs low (its Fig 2.1).
- `kinematic-kalman-contact`: the same filter with each foot weighted by `reading.contacts`
  (a gait plan, or `estimated_contacts` from the motor torques).
- `integration` (§2.6.2): the same world-frame acceleration integrated by the trapezoidal
  rule, with no correction: it follows the truth after a reset and drifts with every bias
  of the IMU, until the next reset recalibrates it.
- a learned estimator (§2.6.3) from a file written by `estimator fit` (learned.py).
"""

import dataclasses
import functools
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from mjx_badger.estimation import learned
from mjx_badger.estimation.reading import Estimator, Reading
from mjx_badger.robot import kinematics
from mjx_badger.robot.description import HB40, RobotSpec

GRAVITY = np.array([0.0, 0.0, -9.81], np.float32)  # NumPy: a JAX array here would run a device op at import


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
    contact_trust: float = 0.0
    """How far `kinematic-kalman` weighs each foot by the reading's contacts rather than all four alike: 0 the thesis's
    robot (no gait plan, §2.6.1), 1 the same as `kinematic-kalman-contact`. Not a setting of the thesis: the family
    along which the estimate-gain study (docs/real-world.md) moves the estimate from a few per cent of the truth to
    most of it."""


def leg_odometry(joint_angle, joint_velocity, angular_velocity, spec: RobotSpec = HB40) -> jax.Array:
    """(4, 3) trunk-frame trunk velocity each foot implies if it stands still on the ground."""
    feet, feet_velocity = jax.jvp(functools.partial(kinematics.forward, spec=spec), (joint_angle,), (joint_velocity,))
    in_trunk = jnp.asarray(spec.hip_positions) + feet
    return -(feet_velocity + jnp.cross(angular_velocity, in_trunk))


def foot_forces(joint_angle, joint_torque, rotation, spec: RobotSpec = HB40) -> jax.Array:
    """(4,) the ground's vertical push on each foot (N) that the motor torques imply, tau = J^T f per leg (the legs'
    own weight and inertia neglected)."""
    jacobian = jax.jacfwd(functools.partial(kinematics.forward, spec=spec))(joint_angle)  # (legs, 3, 12)
    legs = len(spec.legs)
    per_leg = jnp.stack([jacobian[i, :, 3 * i:3 * i + 3] for i in range(legs)])  # (legs, 3, 3)
    force = jnp.linalg.solve(jnp.swapaxes(per_leg, 1, 2), joint_torque.reshape(legs, 3, 1))[..., 0]
    return -(force @ rotation.T)[:, 2]  # the motors push the foot down: the ground pushes it up


def estimated_contacts(joint_angle, joint_torque, rotation, spec: RobotSpec = HB40, low: float = 10.0,
                       high: float = 30.0) -> jax.Array:
    """(4,) contact weights from the motor torques: 0 below `low` N of ground force on a foot, 1 above `high`
    (a force threshold, the usual contact estimate without foot sensors; the robot weighs about 120 N)."""
    return jnp.clip((foot_forces(joint_angle, joint_torque, rotation, spec) - low) / (high - low), 0.0, 1.0)


def _standing() -> KalmanState:
    """Still, and sure of it; at rest the world-frame acceleration (specific force plus gravity) is zero."""
    return KalmanState(jnp.zeros(3), jnp.eye(3) * 1e-4, jnp.zeros(3))


def _world_acceleration(reading: Reading) -> jax.Array:
    return reading.rotation @ reading.acceleration + GRAVITY


def kinematic_kalman(config: KalmanConfig = KalmanConfig(), spec: RobotSpec = HB40, contacts: bool = False) -> Estimator:
    """§2.6.1: IMU prediction, leg-odometry correction over all four feet, or weighted by the reading's `contacts`."""

    def step(state: KalmanState, reading: Reading, dt):
        acceleration = _world_acceleration(reading)
        velocity = state.velocity + acceleration * dt
        covariance = state.covariance + jnp.eye(3) * (config.acceleration_std * dt) ** 2
        trust = 1.0 if contacts else config.contact_trust
        weights = (1.0 - trust) + trust * jnp.asarray(reading.contacts, jnp.float32)  # trust 0: every foot alike
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


ESTIMATORS = {
    "kinematic-kalman": lambda config, spec: kinematic_kalman(config, spec),
    "kinematic-kalman-contact": lambda config, spec: kinematic_kalman(config, spec, contacts=True),
    "integration": lambda config, spec: integration(config),
}
"""The estimators built from the robot's figures alone; a learned one also needs its file (`make(..., path=)`)."""


LEARNED = "learned"


def names() -> tuple:
    """Every estimator name `make` takes."""
    return (*ESTIMATORS, LEARNED)


def make(name: str, config: KalmanConfig = KalmanConfig(), spec: RobotSpec = HB40, path=None) -> Estimator:
    """The estimator called `name` (`learned` reads the fitted estimator at `path`); ValueError naming the choices
    for any other name."""
    if name == LEARNED:
        if path is None:
            raise ValueError("the learned estimator needs its file (written by `estimator fit`)")
        return learned.load(path, spec).estimator()
    if name not in ESTIMATORS:
        raise ValueError(f"unknown estimator {name!r}; choose from {', '.join(names())}")
    return ESTIMATORS[name](config, spec)
