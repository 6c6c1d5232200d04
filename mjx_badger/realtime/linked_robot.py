"""A robot behind the link: `interface.Robot` over ZeroMQ to a robot server (robot_server.py, link_schema.py).

Every call is one request and its reply, waited for at most `timeout_s`: a robot that does not answer in time,
or answers that it damped itself, raises `LinkLost`, which ends the loop's episode without a transition.
"""

import itertools
import time
from pathlib import Path

import numpy as np
import zmq

from mjx_badger.realtime import link_keys, link_schema
from mjx_badger.realtime.interface import LinkLost, Robot, RobotTripped, Sensors


class LinkedRobot(Robot):
    """The robot served at `address` (tcp://HOST:PORT), as the loop sees any robot."""

    def __init__(self, address: str, timeout_s: float = 0.05, reset_timeout_s: float = 120.0,
                 keys: Path | None = None):
        link_keys.check(address, keys, "learner")  # before anything moves
        self.address, self.timeout_s, self.reset_timeout_s, self.keys = address, timeout_s, reset_timeout_s, keys
        self._ids = itertools.count(1)
        self._socket = None
        self._truth = None
        self.robot: dict = {}
        """The robot's side as of the last reply: mode, reason, damps, time."""
        self.round_trips: list[float] = []
        """Seconds from each control-period request (read, command, hold, damp, drive) to its reply."""
        self.info = None

    # The Robot protocol.
    def start(self) -> None:
        self.info = self.request("hello", timeout_s=max(self.timeout_s, 2.0))
        # A robot its watchdog damped (the training process before this one died) stands up again by a reset.
        self.request("reset" if self.robot.get("mode") == "damped" else "start", timeout_s=self.reset_timeout_s)

    def read(self) -> Sensors:
        reply = self.request("read")
        try:
            fields = link_schema.read_sensors(reply)
            truth = reply.get("truth")
            self._truth = ({"linear_velocity": link_schema.vector(truth, "linear_velocity", 3)}
                           if isinstance(truth, dict) else None)
        except link_schema.Refused as error:
            raise LinkLost(f"the robot sent a reading that breaks the schema: {error}") from None
        return Sensors(**fields)

    def command(self, targets, kp: float, kd: float) -> None:
        self.request("command", targets=np.asarray(targets, np.float64), kp=float(kp), kd=float(kd))

    def hold(self) -> None:
        self.request("hold")

    def damp(self) -> None:
        # Best effort: a robot out of reach damps itself on its watchdog anyway.
        try:
            self.request("damp")
        except LinkLost:
            pass

    def reset(self) -> None:
        self.request("reset", timeout_s=self.reset_timeout_s)

    def stop(self) -> None:
        self.damp()
        self._close()

    def truth(self) -> dict | None:
        return self._truth

    # The link.
    def drive(self, command) -> None:
        """Test mode: the robot's own saved policy walks under `command` (vx, vy, yaw rate)."""
        self.request("drive", command=np.asarray(command, np.float64))

    def request(self, kind: str, timeout_s: float | None = None, **fields) -> dict:
        """Send one request and wait for its reply; LinkLost when none comes in time or the robot refuses it."""
        socket = self._connect()
        request_id = next(self._ids)
        sent = time.perf_counter()
        deadline = sent + (self.timeout_s if timeout_s is None else timeout_s)
        # No robot connected (or its handshake refused): the send waits at most until the deadline, like the reply.
        ready = socket.poll(max(1, int((deadline - sent) * 1000)), zmq.POLLOUT)
        if ready:
            socket.send(link_schema.encode({"v": link_schema.VERSION, "id": request_id, "type": kind, **fields}),
                        zmq.DONTWAIT)
        while True:
            left = deadline - time.perf_counter()
            if not ready or left <= 0 or not socket.poll(max(1, int(left * 1000))):
                self._close()  # drop what is queued: a late reply must not answer the next request
                lost = LinkLost(f"no reply from {self.address} to {kind} within "
                                f"{1000 * (self.timeout_s if timeout_s is None else timeout_s):.0f} ms")
                lost.since = sent  # the gap began when the unanswered request went out
                raise lost
            try:
                reply = link_schema.decode(socket.recv())
            except link_schema.Refused:
                continue
            if reply["id"] == request_id:
                break
        if timeout_s is None:  # the control period's requests, not a reset's or a hello's long waits
            self.round_trips.append(time.perf_counter() - sent)
            if len(self.round_trips) > 100_000:
                del self.round_trips[:50_000]
        self.robot = reply.get("robot") if isinstance(reply.get("robot"), dict) else {}
        if reply.get("type") == "refused":
            reason = self.robot.get("reason")
            if self.robot.get("mode") == "damped" and isinstance(reason, str) and reason.startswith("safety:"):
                raise RobotTripped(reason.removeprefix("safety:").strip())
            raise LinkLost(f"the robot refused {kind}: {reply.get('error')}")
        return reply

    def hello(self, timeout_s: float = 0.5) -> dict | None:
        """The robot's hello (joints, robot, has_truth, policy), or None if it does not answer within `timeout_s`."""
        try:
            self.info = self.request("hello", timeout_s=timeout_s)
            return self.info
        except LinkLost:
            return None

    def reachable(self, timeout_s: float = 0.5) -> bool:
        """Whether the robot answers a hello within `timeout_s`."""
        return self.hello(timeout_s) is not None

    def _connect(self):
        if self._socket is None:
            socket = zmq.Context.instance().socket(zmq.DEALER)
            socket.setsockopt(zmq.LINGER, 0)
            socket.setsockopt(zmq.IMMEDIATE, 1)  # no queueing for a robot that is not there
            socket.setsockopt(zmq.MAXMSGSIZE, 1 << 16)
            link_keys.secure_client(socket, self.address, self.keys)
            socket.connect(self.address)
            self._socket = socket
        return self._socket

    def _close(self) -> None:
        if self._socket is not None:
            self._socket.close()
            self._socket = None
