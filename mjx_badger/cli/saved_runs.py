"""`evaluate`, `render` and `export`: a training run's saved policy, one seed of it, under one command on native MuJoCo."""

import dataclasses
import json
from pathlib import Path
from typing import Literal, Optional

import tyro

from mjx_badger.core import safe_io
from mjx_badger.core.validation import writable_file
from mjx_badger.learning import saved_run
from mjx_badger.outputs import onnx_export, videos
from mjx_badger.robot import mjcf
from mjx_badger.sim.render import check_gl


@dataclasses.dataclass(frozen=True)
class SavedRun:
    """A training run's saved policy, one seed of it, under one command for some seconds."""

    results: tyro.conf.Positional[Path]
    """A training run's results file; its saved policy lies beside it."""
    seed: Optional[int] = None
    """Which seed's policy (default: the first the saved policy holds; a committed result holds its best seed's)."""
    command: Optional[str] = None
    """VX,VY,YAW (m/s, m/s, rad/s); default: the task's first evaluation command."""
    max_seconds = 3600.0  # the longest --seconds a command takes (a render keeps every frame in memory: less)
    seconds: float = 20.0
    """Simulated seconds to run the policy for, up to 3600."""
    conditions: Optional[str] = None
    """Run it under other conditions than it trained in (sim, office, outdoor): the thesis tested its office policy
    in simulation (§5.2.1). Default: the run's own."""

    def check(self) -> None:
        saved_run.check(self.results, self.seed, self.seconds, self.max_seconds, self.command, self.conditions)


@dataclasses.dataclass(frozen=True)
class Evaluate(SavedRun):
    """Run a run's saved policy on native MuJoCo (or MJX): velocity from the trunk's positions, falls, gait frequency."""

    engine: Literal["native", "mjx"] = "native"
    """native: mujoco.mj_step, as a robot's computer could; mjx: the training env, for comparison."""
    json: Optional[Path] = None
    """Also write the report here."""

    def check(self) -> None:
        super().check()
        if self.json is not None:
            writable_file(self.json, "--json")

    def __call__(self) -> int:
        report = saved_run.evaluate(self.results, self.seed, self.seconds, self.command, self.conditions, self.engine)
        print(json.dumps(report, indent=1))
        if self.json:
            safe_io.write_text(self.json, json.dumps(report, indent=1))
        return 0


@dataclasses.dataclass(frozen=True)
class Render(SavedRun):
    """A GIF of a run's saved policy walking on native MuJoCo, rendered offscreen (EGL or OSMesa)."""

    max_seconds = 60.0
    seconds: float = 5.0
    """Simulated seconds of video, up to 60."""
    out: Path = Path("gait.gif")
    """The video file (.gif)."""

    def check(self) -> None:
        super().check()
        if self.out.suffix.lower() != ".gif":
            raise ValueError(f"--out {self.out.name}: videos are written as .gif (an .mp4 needs ffmpeg, not installed)")
        writable_file(self.out, "--out")
        try:
            check_gl(mjcf.load_model())
        except RuntimeError as error:
            raise ValueError(str(error)) from None

    def __call__(self) -> int:
        report = videos.render_saved(self.results, self.seed, self.seconds, self.command, self.conditions, self.out)
        print(f"wrote {self.out} ({report['frames']} frames; {report['velocity_along_command']:.2f} m/s along "
              f"the command, {report['falls']} falls)")
        return 0


@dataclasses.dataclass(frozen=True)
class Export:
    """A run's saved policy as ONNX for the robot's computer (no JAX there): the actor, its settings beside it, and
    its check against the JAX policy on 1,000 observations."""

    results: tyro.conf.Positional[Path]
    """A training run's results file; its saved policy lies beside it."""
    seed: Optional[int] = None
    """Which seed's policy (default: the first the saved policy holds)."""
    out: Path = Path("policy.onnx")
    """The ONNX file; its settings go beside it as <stem>.onboard.json."""

    def check(self) -> None:
        if self.out.suffix != ".onnx":
            raise ValueError(f"--out {self.out.name}: the exported policy's file ends in .onnx")
        writable_file(self.out, "--out")
        _, config, _ = onnx_export.saved(self.results, self.seed)
        refusal = onnx_export.refusal(config)
        if refusal:
            raise ValueError(refusal)

    def __call__(self) -> int:
        onnx_export.export(self.results, self.seed, self.out)
        difference = onnx_export.check(self.results, self.seed, self.out)
        print(f"wrote {self.out} and {self.out.with_suffix('.onboard.json').name}; onnxruntime vs JAX on 1,000 "
              f"observations: max difference {difference:.1e} (limit {onnx_export.MAX_DIFFERENCE:.0e})")
        return 0 if difference <= onnx_export.MAX_DIFFERENCE else 1
