"""The thesis's test mode: a saved policy (onboard.py, no JAX) walks the robot under an operator's velocity command.

The same driver runs on the robot's computer (robot_server.py, `drive` requests) and in the training process for
a robot without a link; it learns nothing and stops, damping the robot, on the safety rule.
"""

import threading
import time

from mjx_badger.realtime import scheduling
from mjx_badger.realtime.interface import Robot


class Driver(threading.Thread):
    """Walks `bot` with `policy` (an onboard.OnboardPolicy) at the rate it was trained at, under `command` (vx, vy,
    yaw rate), until `stop()`; `stopped` says why. Its safety rule is the policy's own copy (no JAX on the robot)."""

    def __init__(self, bot: Robot, policy):
        super().__init__(name="test-drive", daemon=True)
        self.bot, self.policy, self.period = bot, policy, 1.0 / policy.control_hz
        self.command = (0.0, 0.0, 0.0)
        self.steps = 0
        self.stopped: str | None = None
        self._halt = threading.Event()

    def stop(self) -> None:
        self._halt.set()
        if self.is_alive() and threading.current_thread() is not self:
            self.join()

    def run(self) -> None:
        self.policy.reset()
        deadline = time.perf_counter()
        while not self._halt.is_set():
            s = self.bot.read()
            why = self.policy.trip(s.joint_angle, s.orientation)
            if why:
                self.bot.damp()
                self.stopped = why
                return
            targets, kp, kd = self.policy.step(s.joint_angle, s.joint_velocity, s.joint_torque, s.acceleration,
                                               s.angular_velocity, s.orientation, self.command, self.period)
            self.bot.command(targets, kp, kd)
            self.steps += 1
            deadline += self.period
            if not scheduling.sleep_until(deadline):
                deadline = time.perf_counter()
        self.stopped = "stopped"
