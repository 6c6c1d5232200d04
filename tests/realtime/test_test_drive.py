"""Test mode's driver: a saved policy commands the robot at its own rate, under the operator's command, until it is
stopped or its safety rule trips (the robot then damped)."""

import time

import numpy as np

from mjx_badger.realtime.simulated import SimulatedHB40
from mjx_badger.realtime.test_drive import Driver
from mjx_badger.robot import description as robot
from tests.realtime.test_robot_server import Recorder, until

SPEC = robot.HB40
NOMINAL = np.asarray(robot.nominal_pose(SPEC), np.float64)


class Policy:
    """A stand-in for onboard.OnboardPolicy: the nominal pose plus a step count, and a trip at `trip_at` steps."""

    control_hz = 50.0

    def __init__(self, trip_at=None):
        self.trip_at, self.resets, self.steps, self.seen = trip_at, 0, 0, []

    def reset(self):
        self.resets += 1

    def step(self, joint_angle, joint_velocity, joint_torque, acceleration, angular_velocity, orientation, command, dt):
        assert joint_angle.shape == joint_velocity.shape == joint_torque.shape == (12,) and orientation.shape == (4,)
        self.steps += 1
        self.seen.append((command, dt))
        return NOMINAL + 0.001 * self.steps, 60.0, 3.0

    def trip(self, joint_angle, orientation):
        return "roll +0.90 rad" if self.steps == self.trip_at else None


class Timed(Recorder):
    """The recording robot, with the time of each command."""

    def __init__(self):
        super().__init__()
        self.times = []

    def command(self, targets, kp, kd):
        self.times.append(time.perf_counter())
        super().command(targets, kp, kd)


def test_the_driver_commands_the_robot_at_the_policys_rate_under_the_operators_command():
    bot, policy = Timed(), Policy()
    bot.start()
    driver = Driver(bot, policy)
    driver.command = (0.3, 0.0, -0.5)
    driver.start()
    try:
        time.sleep(0.5)
        driver.command = (0.0, 0.2, 0.0)
        time.sleep(0.3)
    finally:
        driver.stop()
        bot.stop()
    assert not driver.is_alive() and driver.stopped == "stopped" and policy.resets == 1
    assert driver.steps == policy.steps == len(bot.calls) and 30 <= driver.steps <= 45  # 0.8 s at 50 Hz
    assert 0.018 <= np.median(np.diff(bot.times)) <= 0.022
    assert {dt for _, dt in policy.seen} == {1 / 50.0}
    assert policy.seen[0][0] == (0.3, 0.0, -0.5) and policy.seen[-1][0] == (0.0, 0.2, 0.0)
    targets, kp, kd = bot.calls[-1]
    np.testing.assert_allclose(targets, NOMINAL + 0.001 * driver.steps)
    assert (kp, kd) == (60.0, 3.0)
    calls = len(bot.calls)
    time.sleep(0.1)
    assert len(bot.calls) == calls  # nothing after stop


def test_a_trip_damps_the_robot_and_ends_the_drive_by_itself():
    bot, policy = Timed(), Policy(trip_at=5)
    driver = Driver(bot, policy)
    driver.start()
    until(lambda: not driver.is_alive())
    assert driver.stopped == "roll +0.90 rad" and driver.steps == 5 and len(bot.calls) == 5
    assert bot.gains == SPEC.damping_gains and bot.damp_calls == 1
    driver.stop()  # stopping a driver that stopped itself is harmless
    assert driver.stopped == "roll +0.90 rad"


def test_a_driver_stopped_at_once_commands_at_most_once():
    bot = SimulatedHB40(noise=None)
    driver = Driver(bot, Policy())
    driver.start()
    driver.stop()
    assert not driver.is_alive() and driver.stopped == "stopped" and driver.steps <= 1
