"""The robot's own senses: what its IMU and joint encoders read, with their noise, one model for every engine.

The MJCF puts an IMU site at the trunk's origin (the released code's model has none; the
HB40's IMU sits in the trunk, where exactly is not published) with an accelerometer, a gyro
and an orientation sensor that MJX and native MuJoCo both compute. MuJoCo does not apply the
MJCF `noise` attribute, so the noise is here: white noise and a bias random walk per IMU axis,
a small attitude error, encoder quantisation and noise. The model is a pure function of
standard-normal draws, `read(model, state, truth, draws, dt, xp)`, so the MJX env (draws from
its key), native MuJoCo and the on-robot loop's simulated robot (draws from NumPy) share it.

The HB40's IMU part is not documented where we looked; the defaults are a typical MEMS IMU's
datasheet figures (Bosch BMI088 class), each field saying which.
"""

import dataclasses
import math
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from mjx_badger.estimation.estimators import KalmanConfig, Reading


@dataclasses.dataclass(frozen=True)
class SensorModel:
    """Noise of the robot's IMU and encoders; every field zero is the exact sensor."""

    accelerometer_noise_density: float = 1.7e-3
    """m/s^2/sqrt(Hz); white noise (BMI088: 175 ug/sqrt(Hz)). A reading averages it over the read period."""
    accelerometer_bias: float = 0.02
    """m/s^2 per axis, std of the bias at start (about 2 mg left after a still calibration)."""
    accelerometer_bias_walk: float = 1e-3
    """m/s^2/sqrt(s); the bias's random walk (typical MEMS bias instability)."""
    gyro_noise_density: float = 2.4e-4
    """rad/s/sqrt(Hz); white noise (BMI088: 0.014 deg/s/sqrt(Hz))."""
    gyro_bias: float = 0.002
    """rad/s per axis, std of the bias at start."""
    gyro_bias_walk: float = 1e-4
    """rad/s/sqrt(s); the bias's random walk."""
    orientation_noise: float = 0.005
    """rad per axis, the attitude filter's error (an AHRS's ~0.3 deg)."""
    encoder_resolution: float = 2 * math.pi / 2 ** 14
    """rad; a 14-bit absolute encoder on the joint."""
    encoder_noise: float = 0.0
    """rad, beyond the quantisation."""
    joint_velocity_noise: float = 0.05
    """rad/s; velocities differentiated from encoder counts."""
    joint_torque_noise: float = 0.1
    """N m; torques from the drivers' current."""

    @property
    def exact(self) -> bool:
        return not any(dataclasses.asdict(self).values())


EXACT = SensorModel(*(0.0 for _ in dataclasses.fields(SensorModel)))
"""Every reading as the simulator computes it (the learned estimator's dataset: no noise, as in the thesis)."""


class Truth(NamedTuple):
    """What the sensors measure, exactly, at one control step."""

    joint_angle: jax.Array
    """(12,) rad."""
    joint_velocity: jax.Array
    """(12,) rad/s."""
    joint_torque: jax.Array
    """(12,) N m."""
    acceleration: jax.Array
    """(3,) specific force at the IMU in the trunk frame, averaged over the read period (m/s^2)."""
    angular_velocity: jax.Array
    """(3,) trunk-frame angular velocity at the IMU (rad/s)."""
    rotation: jax.Array
    """(3, 3) trunk-to-world rotation."""
    contacts: jax.Array
    """(4,) foot contact weights the reading passes on (estimators.estimated_contacts, a plan, or foot sensors)."""


class SensorState(NamedTuple):
    """The IMU's biases, which persist from one reading to the next (and across episodes)."""

    accelerometer_bias: jax.Array
    gyro_bias: jax.Array


class Draws(NamedTuple):
    """Standard-normal draws for one reading."""

    accelerometer: jax.Array
    gyro: jax.Array
    orientation: jax.Array
    encoder: jax.Array
    joint_velocity: jax.Array
    joint_torque: jax.Array
    accelerometer_walk: jax.Array
    gyro_walk: jax.Array


SHAPES = Draws((3,), (3,), (3,), (12,), (12,), (12,), (3,), (3,))


def draw(key: jax.Array) -> Draws:
    """One reading's draws from a JAX key."""
    keys = jax.random.split(key, len(SHAPES))
    return Draws(*(jax.random.normal(k, shape) for k, shape in zip(keys, SHAPES)))


def no_draws() -> Draws:
    """Draws of zero: the reading without white noise."""
    return Draws(*(jnp.zeros(shape) for shape in SHAPES))


def draw_numpy(rng: np.random.Generator) -> Draws:
    """One reading's draws from a NumPy generator (the on-robot loop's simulated robot)."""
    return Draws(*(rng.standard_normal(shape) for shape in SHAPES))


def init(model: SensorModel, key: jax.Array | None = None, rng: np.random.Generator | None = None) -> SensorState:
    """The biases at start, drawn from `key` (JAX) or `rng` (NumPy); zero for neither."""
    if key is not None:
        a, g = jax.random.normal(key, (2, 3))
    elif rng is not None:
        a, g = rng.standard_normal((2, 3))
    else:
        a = g = np.zeros(3)
    return SensorState(model.accelerometer_bias * a, model.gyro_bias * g)


def small_rotation(angles, xp=jnp):
    """Rotation (3, 3) by the rotation vector `angles` (Rodrigues)."""
    theta = xp.sqrt(xp.sum(angles ** 2) + 1e-18)
    k = angles / theta
    skew = xp.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return xp.eye(3) + xp.sin(theta) * skew + (1 - xp.cos(theta)) * (skew @ skew)


def read(model: SensorModel, state: SensorState, truth: Truth, draws: Draws, dt, xp=jnp):
    """The sensors' reading of `truth` over a read period `dt` (s): (new state, estimators.Reading)."""
    # White noise of a given density, averaged over the period, has this std.
    average = 1.0 / xp.sqrt(2.0 * dt)
    accelerometer_bias = state.accelerometer_bias + model.accelerometer_bias_walk * xp.sqrt(dt) * draws.accelerometer_walk
    gyro_bias = state.gyro_bias + model.gyro_bias_walk * xp.sqrt(dt) * draws.gyro_walk
    acceleration = truth.acceleration + accelerometer_bias + model.accelerometer_noise_density * average * draws.accelerometer
    angular_velocity = truth.angular_velocity + gyro_bias + model.gyro_noise_density * average * draws.gyro
    rotation = truth.rotation @ small_rotation(model.orientation_noise * draws.orientation, xp)
    angle = truth.joint_angle + model.encoder_noise * draws.encoder
    if model.encoder_resolution:
        angle = xp.round(angle / model.encoder_resolution) * model.encoder_resolution
    reading = Reading(angle, truth.joint_velocity + model.joint_velocity_noise * draws.joint_velocity,
                      acceleration, angular_velocity, rotation, truth.contacts,
                      truth.joint_torque + model.joint_torque_noise * draws.joint_torque)
    return SensorState(accelerometer_bias, gyro_bias), reading


@dataclasses.dataclass(frozen=True)
class Sensing:
    """What a simulated robot senses and estimates: its sensors' noise and its trunk-velocity estimator."""

    sensors: SensorModel = SensorModel()
    """The IMU's and encoders' noise (EXACT: none)."""
    estimator: str = "kinematic-kalman"
    """estimators.names(): the thesis's robot ran kinematic-kalman (§2.6.1)."""
    estimator_file: str | None = None
    """The fitted estimator's file, for estimator `learned`."""
    kalman: KalmanConfig = KalmanConfig()
    """The Kalman filters' noise levels."""


def truth(data, trunk: int, acceleration, angular_velocity, torque) -> Truth:
    """What the sensors measure in `data` (mjx.Data, or native MuJoCo's view of the same fields): `acceleration` the
    accelerometer's mean over the read period, `angular_velocity` the gyro's; contacts all ones (the reader's to set)."""
    return Truth(data.qpos[7:], data.qvel[6:], torque, acceleration, angular_velocity, data.xmat[trunk], jnp.ones(4))
