"""The safety monitor trips on tilt and on a joint out of range, and says why."""

import numpy as np

from mjx_badger.realtime import safety
from mjx_badger.realtime.interface import Sensors
from mjx_badger.realtime.simulated import SimulatedHB40
from mjx_badger.robot import description as robot

LEVEL = np.array([1.0, 0.0, 0.0, 0.0])


def test_safety_trips_on_tilt_and_joint_limits():
    bot = SimulatedHB40(noise=None)
    assert safety.check(bot.read()) is None
    bot.tip(roll=1.0)
    assert safety.check(bot.read()).startswith("roll")
    bent = bot.read()
    angles = np.asarray(robot.nominal_pose()).copy()
    angles[2] = -0.2  # the FL knee folded past its stop at 0 rad (it opens positively)
    over = Sensors(bent.time, angles, bent.joint_velocity, bent.joint_torque, bent.acceleration,
                   bent.angular_velocity, LEVEL)
    assert "FL_knee" in safety.check(over)
