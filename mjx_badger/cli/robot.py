"""`realtime`, `robot-server` and `link-keys`: train on one robot at wall-clock rate, serve a robot over the link."""

import dataclasses
import ipaddress
import sys
from pathlib import Path
from typing import Annotated, Optional

import tyro

from mjx_badger.cli.common import Flat
from mjx_badger.core.validation import integer, number, writable_dir, writable_file
from mjx_badger.realtime import adapters, launch, link_keys, memory
from mjx_badger.realtime.config import RealtimeConfig
from mjx_badger.realtime.interface import LinkLost


def _existing(path: Optional[Path], what: str) -> None:
    if path is not None and not Path(path).is_file():
        raise ValueError(f"{what} {path} is not a file")


@dataclasses.dataclass(frozen=True)
class Realtime:
    """Train on one robot at wall-clock rate, learner beside the control loop (by default a simulated HB40)."""

    run: Annotated[RealtimeConfig, Flat] = RealtimeConfig()
    robot_adapter: str = "simulated"
    """The robot to train on in this process, by its adapter's name (realtime/adapters.py): 'simulated', the HB40 in
    native MuJoCo."""
    link: Optional[str] = None
    """tcp://HOST:PORT of a robot server (`robot-server`) to train on over the link, instead of --robot-adapter."""
    keys: Optional[Path] = None
    """The link's key folder (`link-keys`): required where --link leaves this machine."""
    link_timeout_s: float = 0.05
    """How long a request over the link waits for its reply before the episode ends as a lost link."""
    console: bool = False
    """Serve the operator's console (a web page): the run starts idle and waits for its buttons."""
    console_host: str = "127.0.0.1"
    """Where the console listens; beyond this machine it needs the token printed at start."""
    console_port: int = 8040
    console_token: Optional[str] = None
    """The console's token (default: a new one when --console-host is not loopback, none on loopback)."""
    operator_resets: bool = False
    """After a fall, wait for the console's Reset done (else the robot's own reset, as a simulated robot has)."""
    test_policy: Optional[Path] = None
    """An exported policy (`export`, .onnx) that the console's test mode walks the robot with."""
    reset_seconds: float = 2.0
    """Simulated manual reset after a safety stop (not counted as training time)."""
    no_sensor_noise: bool = False
    """Simulated robot: perfect sensors."""
    out: Path = Path("results/realtime")
    """Folder for results."""
    restart: bool = False
    """Ignore a saved checkpoint and start over."""
    checkpoint_every_s: float = 60.0
    """Write the session checkpoint beside the run this often (at an episode's end), so a killed run resumes."""
    quiet: bool = False
    """No live view."""

    @property
    def where(self) -> launch.Robot:
        return launch.Robot(self.robot_adapter, self.link, self.keys, self.link_timeout_s, self.reset_seconds,
                            not self.no_sensor_noise)

    def check(self) -> None:
        self.where.check()
        number("--reset-seconds", self.reset_seconds, 0.0, 3600.0)
        number("--link-timeout-s", self.link_timeout_s, 0.001, 10.0)
        number("--checkpoint-every-s", self.checkpoint_every_s, 0.0, 86400.0)
        integer("--console-port", self.console_port, 0, 65535)
        try:
            ipaddress.ip_address(self.console_host)
        except ValueError:
            raise ValueError(f"--console-host takes an IP address (127.0.0.1, 0.0.0.0), not {self.console_host!r}")
        _existing(self.test_policy, "--test-policy")
        writable_dir(self.out, "output folder")
        memory.check(self.run)

    def __call__(self) -> int:
        console = launch.Console(self.console, self.console_host, self.console_port, self.console_token,
                                 self.operator_resets)
        try:
            _, figure = launch.train(self.run, self.where, console, self.out, resume=not self.restart,
                                     view=not self.quiet, test_policy=self.test_policy,
                                     checkpoint_every_s=self.checkpoint_every_s)
        except ValueError as error:  # a saved run of another configuration in the folder
            print(f"error: {error}", file=sys.stderr)
            return 2
        except LinkLost as error:  # the robot out of reach before the run began; its checkpoint is kept
            print(f"error: the robot at {self.link}: {error}", file=sys.stderr)
            return 1
        if figure is not None:
            print(f"figure: {figure}")
        return 0


@dataclasses.dataclass(frozen=True)
class RobotServer:
    """The robot's side of the link: holds the robot, its sensors and its safety, and serves the link's messages."""

    robot: Annotated[RealtimeConfig, Flat] = RealtimeConfig()
    adapter: str = "simulated"
    """The robot, by its adapter's name (realtime/adapters.py)."""
    address: str = "tcp://127.0.0.1:5555"
    """Where to listen: tcp://127.0.0.1:PORT on this machine; beyond it (tcp://0.0.0.0:PORT) only with --keys."""
    keys: Optional[Path] = None
    """The link's key folder (`link-keys`): CURVE authentication and encryption."""
    watchdog_periods: float = 2.0
    """Damp the motors when no valid command has come for this many control periods while walking."""
    policy: Optional[Path] = None
    """An exported policy (.onnx, `export`) the robot walks with in test mode, without JAX."""
    events: Optional[Path] = None
    """Append the server's damps, with their reasons and times, to this JSON-lines file."""
    reset_seconds: float = 2.0
    """Simulated manual reset after a safety stop."""
    no_sensor_noise: bool = False
    """Simulated robot: perfect sensors."""

    def check(self) -> None:
        adapters.check(self.adapter)
        self.robot.validate()
        if not self.address.startswith(("tcp://", "ipc://")):
            raise ValueError(f"--address takes tcp://HOST:PORT (or ipc://PATH), not {self.address!r}")
        link_keys.check(self.address, self.keys, "robot server")
        number("--watchdog-periods", self.watchdog_periods, 0.5, 100.0)
        number("--reset-seconds", self.reset_seconds, 0.0, 3600.0)
        _existing(self.policy, "--policy")
        if self.events is not None:
            writable_file(self.events, "events file")

    def __call__(self) -> int:
        return launch.serve_robot(self.robot, self.adapter, self.address, self.watchdog_periods, self.policy,
                                  self.keys, self.events, self.reset_seconds, not self.no_sensor_noise)


@dataclasses.dataclass(frozen=True)
class LinkKeys:
    """Make the link's CURVE keys into a new folder: copy it to the robot's computer and the learner's."""

    folder: tyro.conf.Positional[Path]
    """A new folder for the keys."""

    def check(self) -> None:
        if (Path(self.folder) / "server.key").exists():
            raise ValueError(f"{self.folder} already holds keys; choose another folder (keys in use are not overwritten)")
        writable_dir(self.folder, "key folder")

    def __call__(self) -> int:
        print(f"keys: {link_keys.make(self.folder)}")
        return 0
