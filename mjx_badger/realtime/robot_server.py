"""The robot's side of the link: one process holding the robot, its sensors and its safety, serving link_schema.

Safety lives here, not with the learner: the motors are damped (Kp 0, Kd 3) when no valid command has come within
the watchdog's time while walking, when a command is out of range or not finite, and on the robot's own
roll/pitch/joint-limit rule (robot/safety.py), so a dead, stalled or confused training process cannot hurt it.
"""

import json
import logging
import threading
import time
from pathlib import Path

import numpy as np
import zmq

from mjx_badger.realtime import link_keys, link_schema, safety
from mjx_badger.realtime.interface import Robot
from mjx_badger.realtime.link_schema import Refused
from mjx_badger.realtime.test_drive import Driver
from mjx_badger.robot import kinematics
from mjx_badger.robot.description import HB40, RobotSpec

log = logging.getLogger("mjx_badger.robot_server")

MAX_KP, MAX_KD = 200.0, 20.0
"""The largest PD gains a command may ask for (the HB40 walks at 60 and 3)."""
TARGET_MARGIN_RAD = 0.1
"""A target this far beyond a joint's mechanical range is refused (the range itself is the motor's stop)."""
BATCH = 64
"""Messages served between two safety checks, so a flood cannot starve the watchdog."""


class RobotServer:
    """Serves one robot on `address` until a stop request or `halt` is set; `mode` and `reason` are its state."""

    def __init__(self, bot: Robot, spec: RobotSpec = HB40, address: str = "tcp://127.0.0.1:5555",
                 watchdog_s: float = 0.05, policy=None, keys: Path | None = None, events: Path | None = None):
        self.bot, self.spec, self.watchdog_s, self.policy = bot, spec, watchdog_s, policy
        self.mode, self.reason = "idle", None
        self.damps = self.refused = self.served = 0
        self.halt = threading.Event()
        self.driver: Driver | None = None
        self._last_command = 0.0
        limits = kinematics.leg(spec)
        self._low = limits.lower.reshape(-1) - TARGET_MARGIN_RAD
        self._high = limits.upper.reshape(-1) + TARGET_MARGIN_RAD
        self._events = open(events, "a") if events is not None else None
        self._context = zmq.Context()
        self.socket = self._context.socket(zmq.ROUTER)
        self.socket.setsockopt(zmq.MAXMSGSIZE, link_schema.MAX_BYTES)
        self.socket.setsockopt(zmq.LINGER, 0)
        self._authenticator = link_keys.secure_server(self.socket, self._context, address, keys)
        self.socket.bind(address)
        self.address = self.socket.getsockopt_string(zmq.LAST_ENDPOINT)

    def serve(self) -> None:
        """Answer requests and keep watch until stopped; the robot is left damped."""
        poller = zmq.Poller()
        poller.register(self.socket, zmq.POLLIN)
        try:
            while not self.halt.is_set():
                self._watch()
                if poller.poll(1):
                    for _ in range(BATCH):
                        try:
                            frames = self.socket.recv_multipart(zmq.NOBLOCK)
                        except zmq.Again:
                            break
                        self._answer(frames)
        finally:
            self._damp("server stopped")
            self.bot.stop()
            self.socket.close()
            if self._authenticator is not None:  # its socket lives in the context, which waits for it
                self._authenticator.stop()
            self._context.term()
            if self._events is not None:
                self._events.close()

    def _answer(self, frames: list) -> None:
        identity, payloads = frames[0], frames[1:]
        request_id = None
        try:
            if len(payloads) != 1:
                raise Refused(f"a request is one frame, not {len(payloads)}")
            message = link_schema.decode(payloads[0])
            request_id = message["id"]
            reply = self._handle(message)
        except Refused as error:
            self.refused += 1
            log.warning("refused: %s", error)
            reply = {"type": "refused", "error": str(error)}
        self.served += 1
        reply.update(v=link_schema.VERSION, id=request_id, robot=self.state())
        self.socket.send_multipart([identity, link_schema.encode(reply)])

    def _handle(self, message: dict) -> dict:
        kind = message.get("type")
        if kind not in link_schema.REQUESTS:
            raise Refused(f"unknown type {kind!r}; valid: {', '.join(link_schema.REQUESTS)}")
        if kind == "hello":
            return {"type": "ok", "joints": self.spec.num_joints, "robot": self.spec.name,
                    "has_truth": self.bot.truth() is not None, "policy": self.policy is not None}
        if kind == "read":
            return self._read()
        if kind == "damp":
            self._damp("asked by the learner")
            return {"type": "ok"}
        if kind == "stop":
            self.halt.set()
            return {"type": "ok"}
        if kind == "reset":
            self._stop_driving()
            self.bot.reset()
            return self._stand()
        if self.mode == "damped":
            raise Refused(f"damped ({self.reason}); send reset once the robot may stand again")
        if kind == "start":
            if self.mode == "idle":
                self.bot.start()
            return self._stand()
        if self.mode == "idle":
            raise Refused("the robot has not started; send start first")
        if kind == "hold":
            return self._stand()
        if kind == "command":
            return self._command(message)
        return self._drive(message)

    def _read(self) -> dict:
        reply = {"type": "sensors", **link_schema.sensors_fields(self.bot.read())}
        truth = self.bot.truth()
        if truth is not None:
            reply["truth"] = {"linear_velocity": np.asarray(truth["linear_velocity"], np.float64)}
        return reply

    def _command(self, message: dict) -> dict:
        if self.mode == "driving":
            raise Refused("in test mode the robot's own policy drives; send hold first")
        try:
            targets = link_schema.vector(message, "targets", self.spec.num_joints, self._low, self._high)
            kp = link_schema.number(message, "kp", 0.0, MAX_KP)
            kd = link_schema.number(message, "kd", 0.0, MAX_KD)
        except Refused as error:
            self._damp(f"bad command: {error}")
            raise
        self.bot.command(targets, kp, kd)
        self.mode, self._last_command = "walking", time.monotonic()
        return {"type": "ok"}

    def _drive(self, message: dict) -> dict:
        if self.policy is None:
            raise Refused("this robot holds no policy; start the server with --policy FILE.onnx")
        command = link_schema.vector(message, "command", 3)
        if self.driver is None:
            self.driver = Driver(self.bot, self.policy)
            self.driver.start()
        self.driver.command = tuple(command)
        self.mode, self._last_command = "driving", time.monotonic()
        return {"type": "ok"}

    def _stand(self) -> dict:
        self._stop_driving()
        self.bot.hold()
        self.mode, self.reason = "standing", None
        return {"type": "ok"}

    def _watch(self) -> None:
        """The watchdog and the safety rule, between every batch of messages."""
        if self.mode in ("walking", "driving") and time.monotonic() - self._last_command > self.watchdog_s:
            self._damp(f"no valid command for {1000 * self.watchdog_s:.0f} ms")
        elif self.mode in ("standing", "walking", "driving"):
            why = safety.check(self.bot.read(), self.spec)
            if why:
                self._damp(f"safety: {why}")
            elif self.driver is not None and self.driver.stopped:
                self._damp(f"test mode ended: {self.driver.stopped}")

    def _damp(self, reason: str) -> None:
        self._stop_driving()
        self.bot.damp()
        if self.mode != "damped":
            self.damps += 1
            log.warning("damped: %s", reason)
            if self._events is not None:
                self._events.write(json.dumps({"event": "damp", "reason": reason, "unix_time": time.time()}) + "\n")
                self._events.flush()
        self.mode, self.reason = "damped", reason

    def _stop_driving(self) -> None:
        if self.driver is not None:
            self.driver.stop()
            self.driver = None

    def state(self) -> dict:
        return {"mode": self.mode, "reason": self.reason, "damps": self.damps, "time": time.time()}
