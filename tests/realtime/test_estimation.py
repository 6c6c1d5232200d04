"""The on-robot loop's velocity estimate: leg odometry and the Kalman filter on the robot's readings."""

import jax
import mujoco
import numpy as np

from mjx_badger.estimation import estimators
from mjx_badger.outputs.estimator_figures import replay
from mjx_badger.realtime import estimation
from mjx_badger.realtime.estimation import VelocityEstimator, leg_odometry
from mjx_badger.realtime.interface import Sensors
from mjx_badger.realtime.simulated import SimulatedHB40
from mjx_badger.robot import description as robot
from mjx_badger.robot import kinematics

DT = 0.025


def test_the_on_robot_loops_estimates_are_the_shared_estimators_on_a_recorded_trace():
    """A simulated robot's noisy readings over 2 s of a joint wave, fed to the loop's VelocityEstimator and, as
    Readings, to the shared estimator's scan: the same velocities."""

    bot = SimulatedHB40(seed=3)
    trace = []
    for i in range(80):  # 40 Hz: 5 physics steps per reading
        bot.data.ctrl[:] = robot.nominal_pose() + 0.15 * np.sin(0.3 * i + np.arange(12))
        for _ in range(5):
            mujoco.mj_step(bot.model, bot.data)
        trace.append(bot._measure())
    loop = estimation.VelocityEstimator()
    by_loop = np.array([loop.update(s, DT) for s in trace])
    readings = jax.tree.map(lambda *x: np.stack(x), *[estimation.reading(s) for s in trace])
    shared = replay(estimators.make("kinematic-kalman"), readings, np.zeros(len(trace), bool), DT)
    np.testing.assert_allclose(by_loop, shared, atol=1e-5)
    assert np.abs(by_loop).max() > 1e-3  # it moved


LEVEL = np.array([1.0, 0.0, 0.0, 0.0])


def standing_trajectory(velocity, dt, seconds, swinging_leg=None, noise=0.0, seed=0):
    """Sensor readings of a level trunk moving at velocity(t) (3,) over feet fixed on the ground.

    `swinging_leg` moves that foot forward at 0.3 m/s in the world instead (a swing the
    all-feet contact assumption does not know about).
    """
    rng = np.random.default_rng(seed)
    times = np.arange(0.0, seconds, dt)
    fine = 20  # integrate the trunk position more finely than the control period
    feet_world = robot.HB40.hip_positions + kinematics.nominal_feet()
    readings, truth, position = [], [], np.zeros(3)

    def angles_at(position, t):
        feet = feet_world - position
        if swinging_leg is not None:
            feet[swinging_leg, 0] += 0.3 * t
        return np.asarray(kinematics.inverse(feet - robot.HB40.hip_positions)).reshape(-1)

    for t in times:
        v = velocity(t)
        eps = 1e-4
        acceleration = (velocity(t + eps) - velocity(t - eps)) / (2 * eps)
        q = angles_at(position, t)
        q_next = angles_at(position + v * eps, t + eps)
        q_prev = angles_at(position - v * eps, t - eps)
        qd = (q_next - q_prev) / (2 * eps)
        readings.append(Sensors(
            time=t, joint_angle=q, joint_velocity=qd + rng.normal(0, noise, 12), joint_torque=np.zeros(12),
            acceleration=acceleration + [0.0, 0.0, 9.81] + rng.normal(0, 10 * noise, 3),
            angular_velocity=np.zeros(3), orientation=LEVEL))
        truth.append(v)
        for k in range(fine):
            position = position + velocity(t + k * dt / fine) * dt / fine
    return readings, np.asarray(truth)


def test_leg_odometry_of_a_still_robot_is_zero():
    sensors = Sensors(0.0, np.asarray(robot.nominal_pose()), np.zeros(12), np.zeros(12), np.array([0, 0, 9.81]),
                      np.zeros(3), LEVEL)
    np.testing.assert_allclose(leg_odometry(sensors), 0.0, atol=1e-7)


def test_estimator_tracks_a_known_velocity():
    # Swaying 0.3 m/s forward and back, 0.1 m/s sideways (the feet stay within reach); 40 Hz,
    # noisy encoders and IMU.
    velocity = lambda t: np.array([0.3 * np.cos(3 * t), 0.1 * np.cos(2 * t), 0.0])
    readings, truth = standing_trajectory(velocity, 0.025, 4.0, noise=0.02)
    estimator = VelocityEstimator()
    estimates = np.array([estimator.update(s, 0.025) for s in readings])
    settled = slice(20, None)  # after 0.5 s
    error = estimates[settled] - truth[settled]
    assert np.sqrt(np.mean(error**2)) < 0.03
    assert np.max(np.abs(error)) < 0.1


def test_all_feet_contact_assumption_biases_low_and_planned_contacts_fix_it():
    # At 0.2 m/s, one foot swings forward at 0.3 m/s: assumed on the ground it implies -0.1 m/s,
    # so the four-feet mean reads (3 x 0.2 - 0.1) / 4 = 0.125; told it swings, the estimator ignores it.
    velocity = lambda t: np.array([0.2, 0.0, 0.0])
    readings, truth = standing_trajectory(velocity, 0.025, 1.0, swinging_leg=0)
    assumed, planned = VelocityEstimator(), VelocityEstimator(name="kinematic-kalman-contact")
    stance = np.array([False, True, True, True])
    all_feet = np.array([assumed.update(s, 0.025) for s in readings])[20:, 0]
    known = np.array([planned.update(s, 0.025, stance) for s in readings])[20:, 0]
    assert abs(np.mean(all_feet) - 0.125) < 0.02
    np.testing.assert_allclose(known, 0.2, atol=0.02)
