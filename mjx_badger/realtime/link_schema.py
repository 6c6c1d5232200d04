"""The robot link's messages, version 1: JSON objects over ZeroMQ, checked field by field on arrival.

Every request is {"v": 1, "id": n, "type": T, ...} and gets one reply {"v": 1, "id": n, "type": R, "robot": {...}}:

    T        fields                                   reply R     what the robot does
    hello    -                                        ok          nothing; the reply says what the robot is
    start    -                                        ok          stands up in the nominal pose and holds it
    read     -                                        sensors     nothing; the latest reading
    command  targets [12] rad, kp, kd                 ok          PD targets; arms the watchdog
    hold     -                                        ok          holds the nominal pose on its own; disarms it
    damp     -                                        ok          Kp 0, Kd 3 on every joint
    reset    -                                        ok          blocks until the robot stands again
    drive    command [vx, vy, yaw]                    ok          test mode: its own saved policy walks
    stop     -                                        ok          damps and ends the server

A refused request gets {"type": "refused", "error": "..."}. "robot" is the robot's side of things: mode (standing,
walking, driving, damped), reason (why it is damped, or null), damps (how often it damped itself) and time.
A "sensors" reply carries time (the robot's clock, s), joint_angle, joint_velocity, joint_torque [12],
acceleration, angular_velocity [3], orientation [4] (w, x, y, z) and, where the robot has one, truth
{"linear_velocity": [3]}. No pickle: a lab's robot computer answers these in any language with a JSON library.
"""

import json
import math

import numpy as np

VERSION = 1
MAX_BYTES = 4096
"""A longer message is dropped by ZeroMQ before it is read (the socket's MAXMSGSIZE)."""
REQUESTS = ("hello", "start", "read", "command", "hold", "damp", "reset", "drive", "stop")
SENSOR_FIELDS = {"joint_angle": 12, "joint_velocity": 12, "joint_torque": 12, "acceleration": 3,
                 "angular_velocity": 3, "orientation": 4}


class Refused(ValueError):
    """A message that breaks the schema; its text says what is wrong and what is valid."""


def encode(message: dict) -> bytes:
    """A message as UTF-8 JSON, NumPy arrays as lists; NaN is not JSON and is refused here too."""
    return json.dumps(message, default=_plain, allow_nan=False, separators=(",", ":")).encode()


def _plain(value):
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    raise TypeError(f"{type(value).__name__} is not part of the link's schema")


def decode(raw: bytes) -> dict:
    """A message of this version as a dict, or Refused naming what is wrong."""
    if len(raw) > MAX_BYTES:
        raise Refused(f"a message is at most {MAX_BYTES} bytes, this one {len(raw)}")
    try:
        message = json.loads(raw.decode(), parse_constant=_no_constant)
    except (UnicodeDecodeError, ValueError, RecursionError) as error:  # RecursionError: nested too deep
        raise Refused(f"not JSON text ({type(error).__name__}); messages are UTF-8 JSON objects") from None
    if not isinstance(message, dict):
        raise Refused("a message is a JSON object")
    if type(message.get("v")) is not int or message["v"] != VERSION:  # true and 1.0 equal 1 in Python, not here
        raise Refused(f"schema version {message.get('v')!r}; this robot speaks version {VERSION}")
    if not isinstance(message.get("id"), int) or isinstance(message.get("id"), bool):
        raise Refused("a message has an integer id")
    return message


def _no_constant(name: str):
    raise ValueError(f"{name} is not a number a message may hold")


def vector(message: dict, name: str, size: int, low=None, high=None) -> np.ndarray:
    """Field `name` as `size` finite floats within [low, high] (scalars or arrays), or Refused."""
    values = message.get(name)
    if not isinstance(values, list) or len(values) != size or not all(_is_number(v) for v in values):
        raise Refused(f"{name} must be a list of {size} numbers")
    array = np.asarray(values, dtype=np.float64)
    if not np.isfinite(array).all():
        raise Refused(f"{name} must be finite")
    if low is not None and ((array < low) | (array > high)).any():
        index = int(np.argmax((array < low) | (array > high)))
        raise Refused(f"{name}[{index}] = {array[index]:.3f} is outside its range "
                      f"[{np.broadcast_to(low, size)[index]:.3f}, {np.broadcast_to(high, size)[index]:.3f}]")
    return array


def number(message: dict, name: str, low: float, high: float) -> float:
    """Field `name` as a finite float within [low, high], or Refused."""
    value = message.get(name)
    if not _is_number(value) or not math.isfinite(value) or not low <= value <= high:
        raise Refused(f"{name} must be a number in [{low}, {high}]")
    return float(value)


def _is_number(value) -> bool:
    if not isinstance(value, (int, float)) or isinstance(value, bool):
        return False
    try:
        float(value)  # an integer beyond a float's range (10**400) is no number a message may hold
    except OverflowError:
        return False
    return True


def sensors_fields(sensors) -> dict:
    """A Sensors reading as the fields of a "sensors" reply."""
    return {"time": float(sensors.time), **{name: np.asarray(getattr(sensors, name), np.float64)
                                            for name in SENSOR_FIELDS}}


def read_sensors(reply: dict) -> dict:
    """The arrays of a "sensors" reply, checked, as keyword arguments of interface.Sensors."""
    fields = {name: vector(reply, name, size) for name, size in SENSOR_FIELDS.items()}
    fields["time"] = number(reply, "time", 0.0, 1e9)
    return fields
