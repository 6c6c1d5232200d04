"""What the robot commands start: a training run on a robot (in this process or behind a link, with or without the
operator's console), and the robot's side of the link (the robot server)."""

import dataclasses
import logging
import signal
import sys
from pathlib import Path

from mjx_badger.realtime import adapters, figure, link_keys, loop, report
from mjx_badger.realtime.config import RealtimeConfig
from mjx_badger.realtime.linked_robot import LinkedRobot
from mjx_badger.realtime.operator import Operator
from mjx_badger.realtime.robot_server import RobotServer


@dataclasses.dataclass(frozen=True)
class Robot:
    """Where the robot is: an adapter in this process, or a robot server's address (with its keys)."""

    adapter: str = "simulated"
    address: str | None = None
    keys: Path | None = None
    timeout_s: float = 0.05
    reset_seconds: float = 2.0
    sensor_noise: bool = True

    def check(self) -> None:
        adapters.check(self.adapter)
        if self.address is not None:
            if not self.address.startswith(("tcp://", "ipc://")):
                raise ValueError(f"--link takes tcp://HOST:PORT (or ipc://PATH), not {self.address!r}")
            link_keys.check(self.address, self.keys, "learner")

    def make(self, config: RealtimeConfig):
        if self.address is not None:
            return LinkedRobot(self.address, self.timeout_s, keys=self.keys)
        return adapters.make(self.adapter, config, reset_seconds=self.reset_seconds, sensor_noise=self.sensor_noise)


@dataclasses.dataclass(frozen=True)
class Console:
    """The operator's console: served or not, where, with which token."""

    serve: bool = False
    host: str = "127.0.0.1"
    port: int = 8040
    token: str | None = None
    operator_resets: bool = False


def train(config: RealtimeConfig, robot: Robot, console: Console, out_dir: Path, resume: bool = True,
          view: bool = True, test_policy: Path | None = None, checkpoint_every_s: float = 60.0
          ) -> tuple[dict, Path | None]:
    """A training run on the robot, the console served beside it; (document, figure or None)."""
    bot = robot.make(config)
    operator = Operator("idle" if console.serve else "learning", operator_resets=console.operator_resets)
    policy = None
    if test_policy is not None:
        from mjx_badger.realtime.onboard import OnboardPolicy  # onnxruntime only where a test policy is asked for
        policy = OnboardPolicy(test_policy)
    if policy is not None or (isinstance(bot, LinkedRobot) and (bot.hello(2.0) or {}).get("policy")):
        operator.test_refusal = None
    served = None
    if console.serve:
        from mjx_badger.realtime import console as web  # aiohttp only where a console is asked for
        served = web.serve(operator, console.host, console.port, console.token)
        print(f"console: {served.url}", file=sys.stderr, flush=True)
    try:
        document = loop.run(config, bot, out_dir, resume=resume, view=view, operator=operator, test_policy=policy,
                            checkpoint_every_s=checkpoint_every_s)
    finally:
        if served is not None:
            served.stop()
    if not document["steps"]:
        return document, None
    return document, figure.draw(document, report.load_trace(out_dir, config), Path(out_dir) / f"{config.name}.png")


def serve_robot(config: RealtimeConfig, adapter: str, address: str, watchdog_periods: float = 2.0,
                policy: Path | None = None, keys: Path | None = None, events: Path | None = None,
                reset_seconds: float = 2.0, sensor_noise: bool = True) -> int:
    """The robot server on `address` until stopped (SIGINT, SIGTERM or a stop request); the robot left damped."""
    logging.basicConfig(level=logging.INFO, format="%(asctime)s %(name)s %(levelname)s %(message)s")
    bot = adapters.make(adapter, config, reset_seconds=reset_seconds, sensor_noise=sensor_noise)
    onboard = None
    if policy is not None:
        from mjx_badger.realtime.onboard import OnboardPolicy
        onboard = OnboardPolicy(policy)
    server = RobotServer(bot, config.robot_spec, address, watchdog_periods / config.hz, onboard, keys, events)
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, lambda *_: server.halt.set())
    print(f"robot server: {adapter} on {server.address}, watchdog {1000 * server.watchdog_s:.0f} ms"
          + (f", test policy {policy}" if policy else ""), file=sys.stderr, flush=True)
    server.serve()
    return 0
