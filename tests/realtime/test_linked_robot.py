"""The learner's side of the link: readings and truth from the robot, LinkLost in time for a robot that is not
there, and a late reply never taken for the next request's."""

import socket
import time

import numpy as np
import pytest

from mjx_badger.realtime.interface import LinkLost, Sensors
from mjx_badger.realtime.linked_robot import LinkedRobot
from mjx_badger.realtime.robot_server import RobotServer
from mjx_badger.realtime.simulated import SimulatedHB40
from tests.realtime.test_robot_server import serving


class Blind(SimulatedHB40):
    """A robot without a ground truth, as a real one."""

    def truth(self):
        return None


def test_read_gives_the_robots_sensors_and_truth_and_its_clock_runs_once_started():
    bot = SimulatedHB40(noise=None)
    server = RobotServer(bot, address="tcp://127.0.0.1:0")
    with serving(server):
        link = LinkedRobot(server.address, timeout_s=1.0)
        assert link.truth() is None  # nothing read yet
        first = link.read()  # before start nothing runs: the robot's reading and truth, exactly
        assert isinstance(first, Sensors) and first.time == 0.0 and first.joint_angle.shape == (12,)
        assert first.orientation.shape == (4,) and first.acceleration.shape == (3,)
        np.testing.assert_array_equal(first.joint_angle, bot.read().joint_angle)
        np.testing.assert_array_equal(link.truth()["linear_velocity"], bot.truth()["linear_velocity"])
        assert link.read().time == 0.0
        link.start()
        assert link.info["joints"] == 12 and link.info["has_truth"] and not link.info["policy"]
        times = []
        for _ in range(3):
            time.sleep(0.05)
            times.append(link.read().time)
        assert 0.0 < times[0] < times[1] < times[2]  # the physics runs on the robot's side
        assert link.truth()["linear_velocity"].shape == (3,) and np.isfinite(link.truth()["linear_velocity"]).all()
        assert len(link.round_trips) == 2 + 3  # two reads before, three after (hello and start wait longer: not counted)
        assert all(0.0 < trip < 1.0 for trip in link.round_trips)
        assert link.robot["mode"] == "standing" and link.robot["damps"] == 0
        link.stop()
        assert server.mode == "damped" and server.reason == "asked by the learner"


def test_a_robot_without_truth_reads_none():
    server = RobotServer(Blind(), address="tcp://127.0.0.1:0")
    with serving(server):
        link = LinkedRobot(server.address, timeout_s=1.0)
        assert link.read().joint_angle.shape == (12,) and link.truth() is None
        assert not link.hello()["has_truth"]


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_a_robot_that_is_not_there_is_lost_within_the_timeout():
    link = LinkedRobot(f"tcp://127.0.0.1:{_free_port()}", timeout_s=0.1)
    for request in (link.read, link.hold, lambda: link.command(np.zeros(12), 60.0, 3.0)):
        sent = time.perf_counter()
        with pytest.raises(LinkLost, match="no reply from tcp://127.0.0.1:.* within 100 ms") as lost:
            request()
        waited = time.perf_counter() - sent
        assert 0.09 <= waited <= 0.3, waited
        assert sent <= lost.value.since <= sent + 0.01  # the gap began when the request went out
    link.damp()  # best effort: no answer is no error
    assert link.round_trips == [] and not link.reachable(0.05)


class Late(RobotServer):
    """A robot server that answers its first read `late_s` late, then on time."""

    def __init__(self, *args, late_s=0.3, **kwargs):
        super().__init__(*args, **kwargs)
        self.late_s, self.reads = late_s, 0

    def _read(self):
        self.reads += 1
        if self.reads == 1:
            time.sleep(self.late_s)
        return super()._read()


def test_a_late_reply_is_never_taken_for_the_next_requests():
    server = Late(SimulatedHB40(), address="tcp://127.0.0.1:0")
    with serving(server):
        link = LinkedRobot(server.address, timeout_s=0.1)
        assert link.hello(2.0)["type"] == "ok"
        with pytest.raises(LinkLost, match="no reply .* to read within 100 ms"):
            link.read()
        # Asked while the late "sensors" reply is still on its way: the reply must be hello's own.
        sent = time.perf_counter()
        reply = link.request("hello", timeout_s=2.0)
        assert reply["type"] == "ok" and reply["id"] == 3 and reply["joints"] == 12
        assert time.perf_counter() - sent >= 0.1  # it waited behind the late read
        assert server.reads == 1 and link.round_trips == []  # the lost read is no round trip, hellos wait longer
        assert link.read().joint_angle.shape == (12,) and server.reads == 2


def test_a_new_training_process_stands_up_a_robot_its_predecessor_left_damped():
    server = RobotServer(SimulatedHB40(reset_seconds=0.0), address="tcp://127.0.0.1:0", watchdog_s=0.05)
    with serving(server):
        first = LinkedRobot(server.address, timeout_s=0.5)
        first.start()
        first.command(first.read().joint_angle, 60.0, 3.0)
        time.sleep(0.3)  # the first process is gone: no command within the watchdog's time
        assert server.mode == "damped" and server.reason.startswith("no valid command")
        second = LinkedRobot(server.address, timeout_s=0.5)
        second.start()  # a reset, not a start: the robot lay damped
        assert server.mode == "standing" and second.robot["mode"] == "standing"
