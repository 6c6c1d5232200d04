"""The simulated HB40: paced to the wall clock, standing, on the ground of its conditions."""

import time

import mujoco

from mjx_badger.protocol import conditions
from mjx_badger.realtime import safety
from mjx_badger.realtime.simulated import SimulatedHB40
from mjx_badger.robot import description as robot


def test_the_on_robot_loops_simulated_robot_walks_on_the_same_ground():
    bot = SimulatedHB40(noise=None, conditions=conditions.OUTDOOR, seed=0)
    assert bot.model.geom_type[bot.model.geom("floor").id] == mujoco.mjtGeom.mjGEOM_HFIELD
    frictions = []
    for _ in range(4):  # the operator stands it up on another spot
        bot._stand()
        frictions.append(float(bot.model.pair_friction[0, 0]))
    low, high = conditions.OUTDOOR.ground.friction
    assert len(set(frictions)) == 4 and all(low <= f <= high for f in frictions)
    assert SimulatedHB40(noise=None).model.geom_type[0] == mujoco.mjtGeom.mjGEOM_PLANE


def test_simulated_robot_is_paced_to_the_wall_clock_and_stands():
    bot = SimulatedHB40(noise=None)
    started = time.perf_counter()
    bot.start()
    try:
        time.sleep(1.0)
        reading = bot.read()
        elapsed = time.perf_counter() - started
    finally:
        bot.stop()
    # Free-running, native MuJoCo would simulate ~40 s in this second; paced, it never runs ahead of the
    # wall clock, and it keeps moving (a loaded machine may hold it back, hence the loose lower bound).
    assert 0.1 * elapsed < reading.time <= elapsed + 0.05
    assert safety.check(reading) is None and abs(bot.truth()["height"] - 0.26) < 0.05
    assert bot.gains == robot.HB40.damping_gains  # stop() leaves it damped
