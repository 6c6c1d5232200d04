"""The robot's senses: the sensor model, the env's readings and estimate, and the learned estimator's files."""

import dataclasses

import jax
import jax.numpy as jnp
import mujoco
import numpy as np
import pytest
from mujoco import mjx

from mjx_badger.estimation import sensors
from mjx_badger.robot import description as robot
from mjx_badger.robot import mjcf

DT = 0.025


def _truth(acceleration=(0.0, 0.0, 9.81)):
    pose = jnp.asarray(robot.nominal_pose())
    return sensors.Truth(pose, jnp.zeros(12), jnp.zeros(12), jnp.asarray(acceleration), jnp.zeros(3), jnp.eye(3),
                         jnp.ones(4))


def test_the_exact_model_reads_the_truth_and_the_default_one_quantises_the_encoders():
    truth = _truth()
    _, exact = sensors.read(sensors.EXACT, sensors.init(sensors.EXACT), truth, sensors.draw(jax.random.PRNGKey(0)), DT)
    for got, want in zip(exact[:5], (truth.joint_angle, truth.joint_velocity, truth.acceleration,
                                     truth.angular_velocity, truth.rotation)):
        np.testing.assert_allclose(got, want, atol=1e-6)
    model = sensors.SensorModel()
    _, noisy = sensors.read(model, sensors.init(model), truth, sensors.no_draws(), DT)
    steps = np.asarray(noisy.joint_angle) / model.encoder_resolution
    np.testing.assert_allclose(steps, np.round(steps), atol=1e-3)  # whole encoder counts
    assert np.max(np.abs(np.asarray(noisy.joint_angle) - np.asarray(truth.joint_angle))) <= model.encoder_resolution / 2


def test_white_noise_has_its_density_and_the_bias_walks_as_the_square_root_of_time():
    """Per reading over dt the accelerometer's white noise has std density / sqrt(2 dt): 1.7e-3 / sqrt(0.05) = 0.0076;
    a bias walk of 1e-3 m/s^2/sqrt(s) is off by std 1e-3 sqrt(100) = 0.01 after 100 s (4000 readings)."""
    model = dataclasses.replace(sensors.EXACT, accelerometer_noise_density=1.7e-3, accelerometer_bias_walk=1e-3)
    keys = jax.random.split(jax.random.PRNGKey(1), 2000)
    one = jax.vmap(lambda k: sensors.read(model, sensors.init(sensors.EXACT), _truth(), sensors.draw(k), DT))
    state, reading = one(keys)
    assert np.std(np.asarray(reading.acceleration[:, 0])) == pytest.approx(1.7e-3 / np.sqrt(2 * DT), rel=0.1)

    def walk(key):
        def step(state, k):
            return sensors.read(model, state, _truth(), sensors.draw(k), DT)[0], None
        return jax.lax.scan(step, sensors.init(sensors.EXACT), jax.random.split(key, 4000))[0].accelerometer_bias
    biases = jax.jit(jax.vmap(walk))(jax.random.split(jax.random.PRNGKey(2), 400))
    assert np.std(np.asarray(biases)) == pytest.approx(1e-3 * np.sqrt(4000 * DT), rel=0.15)


def test_numpy_and_jax_read_alike_from_the_same_draws():
    model = sensors.SensorModel()
    draws = sensors.draw_numpy(np.random.default_rng(0))
    state = sensors.init(model, rng=np.random.default_rng(1))
    truth = jax.tree.map(np.asarray, _truth((0.3, -0.1, 9.7)))
    _, with_numpy = sensors.read(model, state, truth, draws, DT, xp=np)
    _, with_jax = sensors.read(model, jax.tree.map(jnp.asarray, state), jax.tree.map(jnp.asarray, truth),
                               jax.tree.map(jnp.asarray, draws), DT)
    for a, b in zip(with_numpy, with_jax):
        np.testing.assert_allclose(a, b, atol=1e-5)


def test_mjx_and_native_mujoco_read_the_same_imu():
    """Ten physics steps of a robot dropped onto its feet with random joint targets, both engines."""
    model = mjcf.load_model()
    data = mujoco.MjData(model)
    data.qpos[:] = robot.standing_qpos(model)
    rng = np.random.default_rng(0)
    data.ctrl[:] = robot.nominal_pose() + rng.uniform(-0.2, 0.2, 12)
    mujoco.mj_forward(model, data)
    mx, dx = mjx.put_model(model), mjx.put_data(model, data)
    step = jax.jit(mjx.step)
    for _ in range(10):
        mujoco.mj_step(model, data)
        dx = step(mx, dx)
    for name, tolerance in (("accelerometer", 0.05), ("gyro", 1e-3), ("orientation", 1e-4)):
        where = mjcf.sensor_slice(model, name)
        np.testing.assert_allclose(np.asarray(dx.sensordata[where]), data.sensordata[where], atol=tolerance,
                                   err_msg=name)


