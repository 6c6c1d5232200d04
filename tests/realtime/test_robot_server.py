"""The robot server: its watchdog, bad commands and its own safety rule damp the robot; and a property test of
1,523 bad messages (1,003 one at a time: 1,000 drawn by hypothesis and 3 known killers; a flood of 500; 20 oversize),
each refused without moving a joint, the server serving on."""

import collections
import contextlib
import json
import threading
import time

import numpy as np
import pytest
import zmq
from hypothesis import HealthCheck, given, settings
from zmq.utils.monitor import recv_monitor_message

from mjx_badger.realtime.interface import LinkLost, RobotTripped
from mjx_badger.realtime.linked_robot import LinkedRobot
from mjx_badger.realtime.robot_server import MAX_KD, MAX_KP, TARGET_MARGIN_RAD, RobotServer
from mjx_badger.realtime.simulated import SimulatedHB40
from mjx_badger.robot import description as robot
from tests.realtime.bad_link_messages import ANY, BAD, KILLERS, LOWER, NOMINAL, UPPER, flood, oversize, raw

SPEC = robot.HB40
WATCHDOG_S = 0.1


class Recorder(SimulatedHB40):
    """The simulated HB40 (exact sensors, an instant reset) recording every call to command(), hold's included."""

    def __init__(self, **kwargs):
        super().__init__(noise=None, reset_seconds=0.0, **kwargs)
        self.calls = []

    def command(self, targets, kp, kd):
        self.calls.append((np.array(targets, np.float64), kp, kd))
        super().command(targets, kp, kd)

    @property
    def held(self) -> np.ndarray:
        """The joint targets its PD controllers hold now."""
        with self._lock:
            return self._targets.copy()


@contextlib.contextmanager
def serving(server):
    """`server` answering in a thread until the block ends."""
    thread = threading.Thread(target=server.serve, daemon=True)
    thread.start()
    try:
        yield thread
    finally:
        server.halt.set()
        thread.join(10)


def until(condition, timeout_s=5.0) -> float:
    """Seconds until `condition()` holds, polled every 0.5 ms; fails after `timeout_s`."""
    start = time.perf_counter()
    while not condition():
        assert time.perf_counter() - start < timeout_s, "timed out"
        time.sleep(0.0005)
    return time.perf_counter() - start


def linked():
    """(recording bot, its server, a link to it); serve it with `serving(server)`."""
    bot = Recorder()
    server = RobotServer(bot, address="tcp://127.0.0.1:0", watchdog_s=WATCHDOG_S)
    return bot, server, LinkedRobot(server.address, timeout_s=1.0)


def test_the_watchdog_damps_a_walking_robot_whose_commands_stop_and_only_reset_lifts_it():
    bot, server, link = linked()
    with serving(server):
        link.start()
        for i in range(20):  # 0.5 s at 40 Hz
            link.command(NOMINAL, *SPEC.pd_gains)
            assert link.robot["mode"] == "walking"
            if i < 19:
                time.sleep(0.025)
        silent = time.perf_counter()
        assert server.damps == 0
        until(lambda: server.mode == "damped")
        waited = time.perf_counter() - silent
        print(f"damped {1000 * waited:.1f} ms after the last command (watchdog {1000 * WATCHDOG_S:.0f} ms)")
        assert WATCHDOG_S - 0.01 <= waited <= WATCHDOG_S + 0.03
        assert server.reason.startswith("no valid command") and bot.gains == SPEC.damping_gains
        calls = len(bot.calls)
        with pytest.raises(LinkLost, match="refused command: damped") as lost:
            link.command(NOMINAL, *SPEC.pd_gains)
        assert not isinstance(lost.value, RobotTripped)  # a lost link, not a fall
        assert len(bot.calls) == calls and link.robot["mode"] == "damped" and bot.gains == SPEC.damping_gains
        link.reset()
        assert link.robot["mode"] == "standing" and link.robot["reason"] is None and bot.gains == SPEC.pd_gains
        link.command(NOMINAL + 0.05, *SPEC.pd_gains)
        assert link.robot["mode"] == "walking" and np.array_equal(bot.held, NOMINAL + 0.05)
        link.hold()  # standing again: the robot holds on its own, no stream needed
        time.sleep(3 * WATCHDOG_S)
        assert server.mode == "standing" and server.damps == 1 and bot.gains == SPEC.pd_gains


def test_a_started_robot_stands_without_a_stream_of_commands():
    bot, server, link = linked()
    with serving(server):
        link.start()
        time.sleep(3 * WATCHDOG_S)
        assert server.mode == "standing" and server.damps == 0 and bot.gains == SPEC.pd_gains
        assert link.reachable() and link.robot["mode"] == "standing"


def _beyond(index, value):
    targets = NOMINAL.copy()
    targets[index] = value
    return targets


BAD_COMMANDS = {
    "a target beyond its range": (_beyond(2, UPPER[2] + TARGET_MARGIN_RAD + 0.01), *SPEC.pd_gains, r"targets\[2\]"),
    "a target below its range": (_beyond(0, LOWER[0] - TARGET_MARGIN_RAD - 0.01), *SPEC.pd_gains, r"targets\[0\]"),
    "kp over MAX_KP": (NOMINAL, MAX_KP + 1.0, 3.0, "kp must be"),
    "kd over MAX_KD": (NOMINAL, 60.0, MAX_KD + 1.0, "kd must be"),
    "a list of 11": (NOMINAL[:11], *SPEC.pd_gains, "list of 12"),
}


@pytest.mark.parametrize("case", BAD_COMMANDS)
def test_a_command_out_of_range_damps_the_robot_and_moves_nothing(case):
    targets, kp, kd, why = BAD_COMMANDS[case]
    bot, server, link = linked()
    with serving(server):
        link.start()
        link.command(NOMINAL + 0.05, *SPEC.pd_gains)
        calls = len(bot.calls)
        with pytest.raises(LinkLost, match=why):
            link.request("command", targets=targets, kp=kp, kd=kd)
        assert server.mode == "damped" and server.reason.startswith("bad command: ") and server.damps == 1
        assert len(bot.calls) == calls and bot.gains == SPEC.damping_gains
        np.testing.assert_array_equal(bot.held, NOMINAL + 0.05)  # still the last valid command's


def test_the_robots_own_safety_rule_damps_it_while_walking():
    bot, server, link = linked()
    with serving(server):
        link.start()
        link.command(NOMINAL, *SPEC.pd_gains)
        bot.tip(roll=1.2)
        assert until(lambda: server.mode == "damped", 1.0) < WATCHDOG_S  # before the watchdog could have
        assert server.reason.startswith("safety: roll") and bot.gains == SPEC.damping_gains
        with pytest.raises(RobotTripped) as tripped:  # the learner hears a fall, not a lost link
            link.command(NOMINAL, *SPEC.pd_gains)
        assert tripped.value.reason.startswith("roll")


class Client:
    """A raw DEALER socket on the server, and the checks every bad message must pass."""

    def __init__(self, server, bot, thread):
        self.server, self.bot, self.thread = server, bot, thread
        self.socket = zmq.Context.instance().socket(zmq.DEALER)
        self.socket.setsockopt(zmq.LINGER, 0)
        self.socket.connect(server.address)
        self.sent, self.last = collections.Counter(), None

    def send(self, frames: list) -> None:
        assert self.thread.is_alive(), f"the server stopped on {self.last!r}"
        self.last = frames
        self.socket.send_multipart(frames)

    def reply(self) -> dict:
        assert self.socket.poll(2000), f"no reply within 2 s to {self.last!r}"
        return json.loads(self.socket.recv())

    def ask(self, kind: str) -> dict:
        self.send([raw({"v": 1, "id": 0, "type": kind})])
        return self.reply()

    def refused(self, reply: dict, expected_id) -> None:
        assert reply["type"] == "refused" and reply["error"], reply
        assert expected_id is ANY or reply["id"] == expected_id, (reply, expected_id)

    def unmoved(self) -> None:
        assert self.thread.is_alive()
        np.testing.assert_array_equal(self.bot.held, NOMINAL)
        assert self.bot.gains in (SPEC.pd_gains, SPEC.damping_gains)


def test_a_thousand_generated_bad_messages_are_each_refused_and_move_no_joint():
    """1,523 bad messages: 1,003 one at a time, 500 as one flood, 20 over MAX_BYTES (dropped by ZeroMQ unread)."""
    bot = Recorder()
    server = RobotServer(bot, address="tcp://127.0.0.1:0", watchdog_s=WATCHDOG_S)
    with serving(server) as thread:
        client = Client(server, bot, thread)
        assert client.ask("start")["type"] == "ok"
        valid_calls = len(bot.calls)  # start's hold, and each reset's below: none from a bad message

        def one_at_a_time(bad):
            nonlocal valid_calls
            category, frames, expected_id = bad
            before = len(bot.calls)
            client.send(frames)
            client.sent[category] += 1
            client.refused(client.reply(), expected_id)
            assert len(bot.calls) == before, f"{category}: {frames}"
            client.unmoved()
            if server.mode == "damped":  # a bad command damped it: stand it up, so the next one is checked in full
                assert client.ask("reset")["robot"]["mode"] == "standing"
                valid_calls += 1

        for killer in KILLERS:  # outside hypothesis, which raises the recursion limit while it runs
            one_at_a_time(killer)
        settings(max_examples=1000, deadline=None, database=None, suppress_health_check=[HealthCheck.too_slow])(
            given(BAD)(one_at_a_time))()
        drawn = sum(client.sent.values())

        # The flood, on a walking robot: 500 sent before any reply is read, each answered, in order.
        assert client.ask("hold")["type"] == "ok"
        client.send([raw({"v": 1, "id": 0, "type": "command", "targets": NOMINAL.tolist(), "kp": 60, "kd": 3})])
        assert client.reply()["robot"]["mode"] == "walking"
        valid_calls += 2
        messages, served = flood(500), server.served
        for message, _ in messages:
            client.socket.send(message)
        for _, expected_id in messages:
            client.refused(client.reply(), expected_id)
        client.sent["flood"] = len(messages)
        assert server.served - served == len(messages) and server.mode == "damped"
        client.unmoved()

        # Over MAX_BYTES (valid stops, resets and commands padded): ZeroMQ drops each and its connection unread.
        served, sockets, monitors = server.served, [], []
        for i in range(20):
            sockets.append(zmq.Context.instance().socket(zmq.DEALER))
            sockets[-1].setsockopt(zmq.LINGER, 0)
            monitors.append(sockets[-1].get_monitor_socket(zmq.EVENT_DISCONNECTED))
            sockets[-1].connect(server.address)
            sockets[-1].send(oversize(i))
        for monitor in monitors:
            assert monitor.poll(2000) and recv_monitor_message(monitor)["event"] == zmq.EVENT_DISCONNECTED
        assert not any(s.poll(0) for s in sockets) and server.served == served
        for s in sockets:
            s.disable_monitor()
            s.close()
        for monitor in monitors:
            monitor.close()

        assert len(bot.calls) == valid_calls  # no command() from any bad message
        client.unmoved()
        hello = LinkedRobot(server.address, timeout_s=2.0).hello(2.0)
        assert hello is not None and hello["joints"] == 12 and thread.is_alive()
        client.socket.close()
    total = sum(client.sent.values()) + len(sockets)
    print(f"\nbad messages: {total} in all; one at a time {drawn}: "
          + ", ".join(f"{name} {n}" for name, n in client.sent.most_common() if name != "flood")
          + f"; flood {client.sent['flood']}; oversize (dropped by ZeroMQ) {len(sockets)}")
    assert total >= 1000, f"only {total} bad messages (1,523 expected: 1,003 one at a time, 500 flooded, 20 oversize)"
