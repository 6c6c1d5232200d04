"""Bad messages for the robot server's property test (test_robot_server.py): hypothesis strategies, the known
killers, a flood and oversize messages. Each is (category, frames, the id its reply must carry: an int, None where
the server cannot read it, ANY where either may be). None of them is a valid request."""

import json

import numpy as np
from hypothesis import strategies as st

from mjx_badger.realtime import link_schema
from mjx_badger.realtime.robot_server import MAX_KD, MAX_KP, TARGET_MARGIN_RAD
from mjx_badger.robot import description as robot
from mjx_badger.robot import kinematics

NOMINAL = np.asarray(robot.nominal_pose(robot.HB40), np.float64)
LOWER, UPPER = kinematics.leg(robot.HB40).lower.reshape(-1), kinematics.leg(robot.HB40).upper.reshape(-1)
ANY = object()
IDS = st.integers(0, 2**53)
JUNK = st.one_of(st.none(), st.booleans(), st.text(max_size=8), st.lists(st.integers(), max_size=3),
                 st.dictionaries(st.text(max_size=3), st.integers(), max_size=2))
GOOD_TARGETS = st.tuples(*[st.floats(float(lo), float(hi)) for lo, hi in zip(LOWER, UPPER)]).map(list)
HUGE = st.sampled_from([10**400, -10**400, 1e308, -1e308, 2**64, 1e20])
"""10**400 is an integer JSON reads and no float holds (it once stopped the server: OverflowError)."""


def raw(message: dict) -> bytes:
    return json.dumps(message).encode()


def command(**fields) -> dict:
    return {"v": 1, "id": 7, "type": "command", "targets": NOMINAL.tolist(), "kp": 60.0, "kd": 3.0, **fields}


KILLERS = [  # what once stopped the server (an exception out of its loop): always sent first
    ("bad command", [raw(command(kp=10**400))], 7),
    ("bad command", [raw(command(targets=[10**400] + NOMINAL.tolist()[1:]))], 7),
    ("nested deep", [('{"v":1,"id":7,"type":"command","targets":' + "[" * 2000 + "]" * 2000 + "}").encode()], ANY),
]
"""Sent outside hypothesis: while it runs, it raises the interpreter's recursion limit (and a JSON reader's) for
every thread, so nesting within MAX_BYTES no longer trips it."""


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
        good[index] = draw(st.one_of(st.booleans(), st.text(max_size=4), st.none(),
                                     st.lists(st.floats(-1, 1), min_size=1, max_size=3)))
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
    """A command of the schema's version and a readable id whose targets, kp or kd are bad (or missing)."""
    message = command(id=draw(IDS), targets=draw(GOOD_TARGETS))
    field = draw(st.sampled_from(["targets", "kp", "kd"]))
    if draw(st.integers(0, 9)) == 0:
        del message[field]
    else:
        message[field] = draw({"targets": bad_targets(), "kp": bad_gain(MAX_KP), "kd": bad_gain(MAX_KD)}[field])
    return "bad command", [raw(message)], message["id"]


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
    """A field nested hundreds to two thousand lists deep, within 4 KiB (see KILLERS)."""
    depth = draw(st.one_of(st.integers(500, 2020), st.sampled_from([990, 1000, 2020])))
    field = draw(st.sampled_from(["v", "type", "targets", "kp"]))
    text = f'{{"v":1,"id":1,"type":"command","{field}":' + "[" * depth + "]" * depth + "}"
    return "nested deep", [text.replace('"v":1,', "", 1).encode() if field == "v" else text.encode()], ANY


@st.composite
def wrong_version(draw):  # 1.0 and true equal 1 in JSON's reading: left out
    v = draw(st.one_of(st.integers().filter(lambda v: v != 1), st.floats(allow_nan=False).filter(lambda v: v != 1),
                       st.text(max_size=3), st.none(), st.lists(st.integers(), max_size=2)))
    return "wrong version", [raw({"v": v, "id": draw(IDS), "type": draw(st.sampled_from(link_schema.REQUESTS))})], None


@st.composite
def bad_id(draw):
    message = {"v": 1, "type": draw(st.sampled_from(link_schema.REQUESTS))}
    choice = draw(st.one_of(st.just("missing"), st.booleans(), st.text(max_size=5), st.floats(allow_nan=False),
                            st.none(), st.lists(IDS, max_size=2)))
    if choice != "missing":
        message["id"] = choice
    return "missing, bool or str id", [raw(message)], None


@st.composite
def unknown_type(draw):
    kind = draw(st.one_of(st.text(max_size=10), st.integers(), JUNK).filter(lambda t: t not in link_schema.REQUESTS))
    message = {"v": 1, "id": draw(IDS), "type": kind}
    return "unknown type", [raw(message)], message["id"]


@st.composite
def drive(draw):  # the robot holds no policy: a drive is refused whatever its command
    message = {"v": 1, "id": draw(IDS), "type": "drive",
               "command": draw(st.one_of(st.lists(st.floats(-9, 9), min_size=3, max_size=3), JUNK))}
    return "drive without a policy", [raw(message)], message["id"]


@st.composite
def multi_frame(draw):
    hello = raw({"v": 1, "id": 1, "type": "hello"})
    frames = draw(st.one_of(st.lists(st.binary(max_size=40), min_size=2, max_size=4), st.just([hello, b""]),
                            st.just([hello, hello])))
    return "multi-frame", frames, None


BAD = st.one_of(
    st.binary(max_size=600).map(lambda data: ("random bytes", [data], ANY)),
    st.one_of(st.lists(st.integers(), max_size=4), st.text(max_size=20), st.integers(), st.none()).map(
        lambda value: ("JSON, not an object", [json.dumps(value).encode()], None)),
    wrong_version(), bad_id(), unknown_type(), bad_commands(), constants(), nested(), drive(), multi_frame())


def flood(n: int, seed: int = 0) -> list[tuple[bytes, object]]:
    """n bad messages and their replies' ids: random bytes, bad commands, NaN, a stop of version 2, in turn."""
    rng, messages = np.random.default_rng(seed), []
    for i in range(n):
        targets = NOMINAL.tolist()
        targets[i % 12] = [float(UPPER[i % 12]) + 1.0, "0", None, True, [0.0]][i % 5]
        messages.append([(rng.bytes(int(rng.integers(1, 300))), ANY),
                         (raw(command(id=i, targets=targets)), i),
                         (f'{{"v":1,"id":{i},"type":"command","targets":[NaN],"kp":60,"kd":3}}'.encode(), None),
                         (raw({"v": 2, "id": i, "type": "stop"}), None)][i % 4])
    return messages


def oversize(i: int) -> bytes:
    """A valid stop, reset or command padded past link_schema.MAX_BYTES: ZeroMQ drops it unread."""
    return raw(command(id=i, type=["stop", "reset", "command"][i % 3])) + b" " * (link_schema.MAX_BYTES + 100 * i)
