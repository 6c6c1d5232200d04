"""The robot server: its watchdog, bad commands and its own safety rule damp the robot; and a property test of
1,520 generated bad messages (1,000 drawn by hypothesis one at a time, a flood of 500, 20 oversize), each refused
without moving a joint, the server serving on."""

import collections
import contextlib
import json
import threading
import time

import numpy as np
import pytest
import zmq
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from mjx_badger.realtime import link_schema
from mjx_badger.realtime.interface import LinkLost
from mjx_badger.realtime.linked_robot import LinkedRobot
from mjx_badger.realtime.robot_server import MAX_KD, MAX_KP, TARGET_MARGIN_RAD, RobotServer
from mjx_badger.realtime.simulated import SimulatedHB40
from mjx_badger.robot import description as robot
from mjx_badger.robot import kinematics

SPEC = robot.HB40
NOMINAL = np.asarray(robot.nominal_pose(SPEC), np.float64)
LOWER, UPPER = kinematics.leg(SPEC).lower.reshape(-1), kinematics.leg(SPEC).upper.reshape(-1)
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


def walking(watchdog_s=WATCHDOG_S):
    """(recording bot, its server, a link to it); serve it with `serving(server)`."""
    bot = Recorder()
    server = RobotServer(bot, address="tcp://127.0.0.1:0", watchdog_s=watchdog_s)
    return bot, server, LinkedRobot(server.address, timeout_s=1.0)


def test_the_watchdog_damps_a_walking_robot_whose_commands_stop_and_only_reset_lifts_it():
    bot, server, link = walking()
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
        with pytest.raises(LinkLost, match="refused command: damped"):
            link.command(NOMINAL, *SPEC.pd_gains)
        assert len(bot.calls) == calls and link.robot["mode"] == "damped" and bot.gains == SPEC.damping_gains
        link.reset()
        assert link.robot["mode"] == "standing" and link.robot["reason"] is None and bot.gains == SPEC.pd_gains
        link.command(NOMINAL + 0.05, *SPEC.pd_gains)
        assert link.robot["mode"] == "walking" and np.array_equal(bot.held, NOMINAL + 0.05)
        link.hold()  # standing again: the robot holds on its own, no stream needed
        time.sleep(3 * WATCHDOG_S)
        assert server.mode == "standing" and server.damps == 1 and bot.gains == SPEC.pd_gains


def test_a_started_robot_stands_without_a_stream_of_commands():
    bot, server, link = walking()
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
    bot, server, link = walking()
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
    bot, server, link = walking()
    with serving(server):
        link.start()
        link.command(NOMINAL, *SPEC.pd_gains)
        bot.tip(roll=1.2)
        assert until(lambda: server.mode == "damped", 1.0) < WATCHDOG_S  # before the watchdog could have
        assert server.reason.startswith("safety: roll") and bot.gains == SPEC.damping_gains


# The property test's bad messages: (category, frames, the reply's id: an int, None where the id cannot be read,
# ANY where either may be). None of them is a valid request.
ANY = object()
IDS = st.integers(0, 2**53)
JUNK = st.one_of(st.none(), st.booleans(), st.text(max_size=8), st.lists(st.integers(), max_size=3),
                 st.dictionaries(st.text(max_size=3), st.integers(), max_size=2))
GOOD_TARGETS = st.tuples(*[st.floats(float(lo), float(hi)) for lo, hi in zip(LOWER, UPPER)]).map(list)
HUGE = st.sampled_from([10**400, -10**400, 1e308, -1e308, 2**64, 1e20])


def _raw(message: dict) -> bytes:
    return json.dumps(message).encode()


@st.composite
def bad_targets(draw):
    """Targets that are no 12 joint targets in range: wrong length, wrong type, bad element, out of range, huge."""
    good = draw(GOOD_TARGETS)
    kind = draw(st.sampled_from(["length", "not a list", "element", "range", "huge"]))
    if kind == "length":
        return draw(st.lists(st.floats(-1.0, 1.0), max_size=30).filter(lambda t: len(t) != 12))
    if kind == "not a list":
        return draw(st.one_of(st.text(max_size=12), st.floats(-1, 1), st.none(), st.dictionaries(st.text(), IDS)))
    index = draw(st.integers(0, 11))
    if kind == "element":
        good[index] = draw(st.one_of(st.booleans(), st.text(max_size=4), st.none(), st.lists(st.floats(-1, 1), 1, 3)))
    elif kind == "range":
        excess = draw(st.floats(1e-3, 1e6))
        good[index] = (float(UPPER[index]) + TARGET_MARGIN_RAD + excess if draw(st.booleans())
                       else float(LOWER[index]) - TARGET_MARGIN_RAD - excess)
    else:
        good[index] = draw(HUGE)
    return good


def bad_gain(high):
    return st.one_of(st.floats(high + 1e-6, 1e12), st.floats(-1e12, -1e-6), HUGE, JUNK)


@st.composite
def bad_commands(draw):
    """A command of the schema's version and a readable id whose targets, kp or kd are bad."""
    message = {"v": 1, "id": draw(IDS), "type": "command", "targets": draw(GOOD_TARGETS), "kp": 60.0, "kd": 3.0}
    field = draw(st.sampled_from(["targets", "kp", "kd"]))
    if draw(st.integers(0, 9)) == 0:
        del message[field]
    else:
        message[field] = draw({"targets": bad_targets(), "kp": bad_gain(MAX_KP), "kd": bad_gain(MAX_KD)}[field])
    return "bad command", [_raw(message)], message["id"]


@st.composite
def constants(draw):
    """A command whose text holds NaN, Infinity or -Infinity (no JSON numbers), or 1e400 (infinite once read)."""
    targets, index = [repr(t) for t in draw(GOOD_TARGETS)], draw(st.integers(0, 13))
    numbers = targets + ["60.0", "3.0"]
    numbers[index] = draw(st.sampled_from(["NaN", "Infinity", "-Infinity", "1e400", "-1e999"]))
    text = (f'{{"v":1,"id":{draw(IDS)},"type":"command","targets":[{",".join(numbers[:12])}],'
            f'"kp":{numbers[12]},"kd":{numbers[13]}}}')
    return "NaN, Infinity, 1e400 as text", [text.encode()], ANY


@st.composite
def nested(draw):
    """A field nested hundreds to two thousand lists deep (past the JSON reader's recursion limit), within 4 KiB."""
    depth, field = draw(st.integers(500, 2020)), draw(st.sampled_from(["v", "type", "targets", "kp"]))
    text = f'{{"v":1,"id":1,"type":"command","{field}":' + "[" * depth + "]" * depth + "}"
    return "nested deep", [text.replace('"v":1,', "", 1).encode() if field == "v" else text.encode()], ANY


def _wrong_version(draw):
    v = draw(st.one_of(st.integers().filter(lambda v: v != 1), st.floats(allow_nan=False).filter(lambda v: v != 1),
                       st.text(max_size=3), st.none(), st.lists(st.integers(), max_size=2)))
    return "wrong version", [_raw({"v": v, "id": draw(IDS), "type": draw(st.sampled_from(link_schema.REQUESTS))})], None


def _bad_id(draw):
    message = {"v": 1, "type": draw(st.sampled_from(link_schema.REQUESTS))}
    choice = draw(st.one_of(st.just("missing"), st.booleans(), st.text(max_size=5), st.floats(allow_nan=False),
                            st.none(), st.lists(IDS, max_size=2)))
    if choice != "missing":
        message["id"] = choice
    return "missing, bool or str id", [_raw(message)], None


def _unknown_type(draw):
    kind = draw(st.one_of(st.text(max_size=10), st.integers(), JUNK).filter(lambda t: t not in link_schema.REQUESTS))
    message = {"v": 1, "id": draw(IDS), "type": kind}
    return "unknown type", [_raw(message)], message["id"]


def _drive(draw):  # this robot holds no policy: a drive is refused whatever its command
    message = {"v": 1, "id": draw(IDS), "type": "drive", "command": draw(st.one_of(st.lists(st.floats(), 3, 3), JUNK))}
    return "drive without a policy", [_raw(message)], message["id"]


def _multi(draw):
    hello = _raw({"v": 1, "id": 1, "type": "hello"})
    frames = draw(st.one_of(st.lists(st.binary(max_size=40), min_size=2, max_size=4), st.just([hello, b""]),
                            st.just([hello, hello])))
    return "multi-frame", frames, None


BAD = st.one_of(
    st.binary(max_size=600).map(lambda raw: ("random bytes", [raw], ANY)),
    st.one_of(st.lists(st.integers(), max_size=4), st.text(max_size=20), st.integers(), st.none()).map(
        lambda value: ("JSON, not an object", [json.dumps(value).encode()], None)),
    st.composite(_wrong_version)(), st.composite(_bad_id)(), st.composite(_unknown_type)(), bad_commands(),
    constants(), nested(), st.composite(_drive)(), st.composite(_multi)())


class Client:
    """A raw DEALER socket on the server, and the checks every bad message must pass."""

    def __init__(self, server, bot, thread):
        self.server, self.bot, self.thread = server, bot, thread
        self.socket = zmq.Context.instance().socket(zmq.DEALER)
        self.socket.setsockopt(zmq.LINGER, 0)
        self.socket.connect(server.address)
        self.sent = collections.Counter()

    def reply(self) -> dict:
        assert self.socket.poll(5000), "no reply within 5 s"
        return json.loads(self.socket.recv())

    def ask(self, kind: str) -> dict:
        self.socket.send(_raw({"v": 1, "id": 0, "type": kind}))
        return self.reply()

    def refused(self, reply: dict, expected_id) -> None:
        assert reply["type"] == "refused" and reply["error"], reply
        assert expected_id is ANY or reply["id"] == expected_id, (reply, expected_id)

    def unmoved(self) -> None:
        assert self.thread.is_alive()
        np.testing.assert_array_equal(self.bot.held, NOMINAL)
        assert self.bot.gains in (SPEC.pd_gains, SPEC.damping_gains)


def test_a_thousand_generated_bad_messages_are_each_refused_and_move_no_joint():
    """Sends 1,520 bad messages: 1,000 drawn one at a time, 500 as one flood, 20 over MAX_BYTES (dropped by ZeroMQ)."""
    bot = Recorder()
    server = RobotServer(bot, address="tcp://127.0.0.1:0", watchdog_s=WATCHDOG_S)
    with serving(server) as thread:
        client = Client(server, bot, thread)
        assert client.ask("start")["type"] == "ok"
        valid_calls = len(bot.calls)  # start's hold, and each reset's below: none from a bad message

        @settings(max_examples=1000, deadline=None, database=None, suppress_health_check=[HealthCheck.too_slow])
        @given(BAD)
        def one_by_one(bad):
            nonlocal valid_calls
            category, frames, expected_id = bad
            before = len(bot.calls)
            client.socket.send_multipart(frames)
            client.sent[category] += 1
            client.refused(client.reply(), expected_id)
            assert len(bot.calls) == before, f"{category}: {frames}"
            client.unmoved()
            if server.mode == "damped":  # a bad command damped it: stand it up, so the next one is checked in full
                assert client.ask("reset")["robot"]["mode"] == "standing"
                valid_calls += 1

        one_by_one()
        drawn = sum(client.sent.values())

        # The flood, on a walking robot: 500 sent before any reply is read, answered in order.
        assert client.ask("hold")["type"] == "ok"
        client.socket.send(_raw({"v": 1, "id": 0, "type": "command", "targets": NOMINAL.tolist(), "kp": 60, "kd": 3}))
        assert client.reply()["robot"]["mode"] == "walking"
        valid_calls += 2
        rng, flood = np.random.default_rng(0), []
        for i in range(500):
            targets = NOMINAL.tolist()
            targets[i % 12] = [float(UPPER[i % 12]) + 1.0, "0", None, True, [0.0]][i % 5]
            flood.append([(rng.bytes(int(rng.integers(1, 300))), ANY),
                          (_raw({"v": 1, "id": i, "type": "command", "targets": targets, "kp": 60, "kd": 3}), i),
                          (f'{{"v":1,"id":{i},"type":"command","targets":[NaN],"kp":60,"kd":3}}'.encode(), None),
                          (_raw({"v": 2, "id": i, "type": "stop"}), None)][i % 4])
        served = server.served
        for raw, _ in flood:
            client.socket.send(raw)
        for _, expected_id in flood:
            client.refused(client.reply(), expected_id)
        client.sent["flood"] = len(flood)
        assert server.served - served == len(flood) and server.mode == "damped"
        client.unmoved()

        # Over MAX_BYTES, valid requests among them: ZeroMQ drops each (and its connection) before it is read.
        served, sockets = server.served, []
        for i in range(20):
            message = {"v": 1, "id": i, "type": ["stop", "reset", "command"][i % 3], "targets": NOMINAL.tolist(),
                       "kp": 60, "kd": 3}
            sockets.append(zmq.Context.instance().socket(zmq.DEALER))
            sockets[-1].setsockopt(zmq.LINGER, 0)
            sockets[-1].connect(server.address)
            sockets[-1].send(_raw(message) + b" " * (link_schema.MAX_BYTES + 100 * i))
        time.sleep(0.5)
        assert not any(s.poll(0) for s in sockets) and server.served == served
        for s in sockets:
            s.close()
        oversize = len(sockets)

        assert len(bot.calls) == valid_calls  # no command() from any bad message
        client.unmoved()
        hello = LinkedRobot(server.address, timeout_s=2.0).hello(2.0)
        assert hello is not None and hello["joints"] == 12 and thread.is_alive()
        client.socket.close()
    total = sum(client.sent.values()) + oversize
    print(f"\nbad messages: {total} in all; drawn one at a time {drawn}: "
          + ", ".join(f"{name} {n}" for name, n in client.sent.most_common() if name != "flood")
          + f"; flood {client.sent['flood']}; oversize (dropped by ZeroMQ) {oversize}")
    assert total >= 1000, f"only {total} bad messages (1,520 expected: 1,000 drawn, 500 flooded, 20 oversize)"
