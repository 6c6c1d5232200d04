"""What the loop knows of a robot: its sensors' reading, and the trunk's attitude from the IMU's quaternion."""

import math

import numpy as np
import pytest

from mjx_badger.realtime.interface import Robot, Sensors, roll_pitch, rotation_matrix


def test_a_quaternion_turns_into_its_rotation_and_the_envs_roll_and_pitch():
    np.testing.assert_allclose(rotation_matrix(np.array([2.0, 0.0, 0.0, 0.0])), np.eye(3))  # normalised first
    half = math.pi / 8  # 45 degrees about x: roll 0.785 rad, no pitch
    rotation = rotation_matrix(np.array([math.cos(half), math.sin(half), 0.0, 0.0]))
    np.testing.assert_allclose(rotation @ [0.0, 1.0, 0.0], [0.0, math.sqrt(0.5), math.sqrt(0.5)], atol=1e-12)
    roll, pitch = roll_pitch(rotation)
    assert roll == pytest.approx(math.pi / 4) and pitch == pytest.approx(0.0, abs=1e-12)


def test_a_robot_without_a_ground_truth_says_so():
    class Blind(Robot):
        pass

    assert Blind().truth() is None
    reading = Sensors(0.0, np.zeros(12), np.zeros(12), np.zeros(12), np.array([0, 0, 9.81]), np.zeros(3),
                      np.array([1.0, 0, 0, 0]))
    assert reading.acceleration[2] == 9.81
