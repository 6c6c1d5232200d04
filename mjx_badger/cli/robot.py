"""`realtime`: train on one robot at wall-clock rate, the learner beside the control loop."""

import dataclasses
import sys
from pathlib import Path
from typing import Annotated

from mjx_badger.cli.common import Flat
from mjx_badger.core.validation import number, writable_dir
from mjx_badger.realtime import adapters, loop, memory
from mjx_badger.realtime.config import RealtimeConfig


@dataclasses.dataclass(frozen=True)
class Realtime:
    """Train on one robot at wall-clock rate, learner beside the control loop (by default a simulated HB40)."""

    run: Annotated[RealtimeConfig, Flat] = RealtimeConfig()
    robot_adapter: str = "simulated"
    """The robot to train on, by its adapter's name (realtime/adapters.py): 'simulated', the HB40 in native MuJoCo."""
    reset_seconds: float = 2.0
    """Simulated manual reset after a safety stop (not counted as training time)."""
    no_sensor_noise: bool = False
    """Simulated robot: perfect sensors."""
    out: Path = Path("results/realtime")
    """Folder for results."""
    restart: bool = False
    """Ignore a saved checkpoint and start over."""
    quiet: bool = False
    """No live view."""

    def check(self) -> None:
        adapters.check(self.robot_adapter)
        if self.reset_seconds < 0:
            raise ValueError("--reset-seconds must not be negative")
        number("--reset-seconds", self.reset_seconds, 0.0, 3600.0)
        writable_dir(self.out, "output folder")
        memory.check(self.run)

    def __call__(self) -> int:
        try:
            _, figure = loop.run_adapter(self.robot_adapter, self.run, self.out, self.reset_seconds,
                                         not self.no_sensor_noise, resume=not self.restart, view=not self.quiet)
        except ValueError as error:  # a saved run of another configuration in the folder
            print(f"error: {error}", file=sys.stderr)
            return 2
        if figure is not None:
            print(f"figure: {figure}")
        return 0
