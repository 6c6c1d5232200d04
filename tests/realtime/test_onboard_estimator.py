"""The NumPy estimator of the robot's computer is the JAX one: leg kinematics, odometry and the Kalman filter."""

import functools

import jax
import mujoco
import numpy as np
import pytest

from mjx_badger.estimation import estimators
from mjx_badger.outputs.onnx_export import leg_figures
from mjx_badger.realtime import estimation
from mjx_badger.realtime.interface import rotation_matrix as interface_rotation
from mjx_badger.realtime.onboard_estimator import KalmanEstimator, Legs, rotation_matrix
from mjx_badger.realtime.simulated import SimulatedHB40
from mjx_badger.robot import description as robot
from mjx_badger.robot import kinematics

DT = 0.025


@pytest.mark.parametrize("spec", [robot.HB40, robot.HB40_FIRST_VERSION], ids=lambda spec: spec.name)
def test_the_legs_move_as_the_jax_kinematics_say(spec):
    legs = Legs(leg_figures(spec))
    rng = np.random.default_rng(0)
    angles = robot.nominal_pose(spec) + rng.uniform(-0.4, 0.4, (8, 12))
    velocities = rng.normal(0.0, 3.0, (8, 12))
    for q, qd in zip(angles.astype(np.float32), velocities.astype(np.float32)):
        feet, feet_velocity = jax.jvp(functools.partial(kinematics.forward, spec=spec), (q,), (qd,))
        ours, ours_velocity = legs.forward(q, qd)
        np.testing.assert_allclose(ours, feet, atol=1e-6)
        np.testing.assert_allclose(ours_velocity, feet_velocity, atol=1e-5)
        np.testing.assert_allclose(legs.inverse(ours), kinematics.inverse(feet, spec), atol=1e-5)
        gyro = rng.normal(0.0, 1.0, 3).astype(np.float32)
        np.testing.assert_allclose(legs.odometry(q, qd, gyro), estimators.leg_odometry(q, qd, gyro, spec), atol=1e-5)
    unreachable = legs.forward(robot.nominal_pose(spec))[0] * 3.0  # the IK's nearest stretched leg, clipped
    np.testing.assert_allclose(legs.inverse(unreachable), kinematics.inverse(unreachable, spec), atol=1e-5)


def test_a_quaternion_turns_into_the_interfaces_rotation():
    for quaternion in np.random.default_rng(1).normal(size=(5, 4)):
        np.testing.assert_allclose(rotation_matrix(quaternion), interface_rotation(quaternion), atol=1e-12)


@pytest.fixture(scope="module")
def trace():
    """2 s of a simulated robot's noisy readings (40 Hz) under a joint wave, as test_estimation.py records them."""
    bot = SimulatedHB40(seed=3)
    readings = []
    for i in range(80):
        bot.data.ctrl[:] = robot.nominal_pose() + 0.15 * np.sin(0.3 * i + np.arange(12))
        for _ in range(5):
            mujoco.mj_step(bot.model, bot.data)
        readings.append(bot._measure())
    return readings


def test_the_all_feet_filter_is_the_on_robot_loops(trace):
    """All four feet, as the loop's VelocityEstimator: the same velocities to float32 rounding."""
    loop = estimation.VelocityEstimator()
    ours = KalmanEstimator(Legs(leg_figures(robot.HB40)))
    for s in trace:
        expected = loop.update(s, DT)
        got = ours.update(s.joint_angle, s.joint_velocity, s.acceleration, s.angular_velocity,
                          rotation_matrix(s.orientation), DT)
        np.testing.assert_allclose(got, expected, atol=1e-5)
    assert np.abs(got).max() > 1e-3  # it moved
    ours.reset()
    np.testing.assert_array_equal(ours.velocity, np.zeros(3))


def test_the_weighted_filter_is_the_contact_estimators_and_skips_a_reading_without_feet(trace):
    """Contact weights (a trot's, and none at all for two readings: prediction alone) as kinematic-kalman-contact."""
    loop = estimation.VelocityEstimator(name="kinematic-kalman-contact")
    ours = KalmanEstimator(Legs(leg_figures(robot.HB40)), acceleration_std=0.5, odometry_std=0.1)
    for i, s in enumerate(trace):
        contacts = np.zeros(4) if i in (10, 11) else np.array([1.0, 0, 0, 1]) if i % 2 else np.array([0, 1, 1, 0.5])
        expected = loop.update(s, DT, contacts)
        got = ours.update(s.joint_angle, s.joint_velocity, s.acceleration, s.angular_velocity,
                          rotation_matrix(s.orientation), DT, contacts)
        np.testing.assert_allclose(got, expected, atol=1e-5)
