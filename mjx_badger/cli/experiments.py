"""The thesis's experiments: `reproduce` a profile, draw its `figures`, score its `claims`, `publish` its results
into a reference folder, and `attribute` its claims to the departures of the text from the code."""

import dataclasses
import json
import sys
from pathlib import Path
from typing import Annotated, Optional

from mjx_badger.cli.common import Cluster, ExperimentName, Flat, Launch, Profile, ProtocolName, check_seed_devices
from mjx_badger.core import safe_io
from mjx_badger.core.validation import number, writable_dir, writable_file
from mjx_badger.experiments.registry import EXPERIMENTS, GROUPS, PROFILES, expand
from mjx_badger.learning import memory
from mjx_badger.outputs import estimate_gain as gain_figure
from mjx_badger.outputs import plots, publish
from mjx_badger.pipelines import reproduce, scoreboards
from mjx_badger.scoring import attribution, estimate_gain


@dataclasses.dataclass(frozen=True)
class Reproduce:
    """Run the thesis experiments of a profile (complete runs are kept), then draw figures and score the claims."""

    profile: Profile = "quick"
    """quick: a CPU in hours; full: the thesis's budgets, a GPU."""
    protocol: ProtocolName = "thesis-code"
    """thesis-code: as the thesis's released code ran it; thesis-text: as the thesis reads."""
    experiments: tuple[ExperimentName, ...] = ("simulation",)
    """Experiments, or groups of them: 'simulation' (the five simulation experiments), 'real' (the real-world
    ones under on-robot conditions, §5.2) or 'agents' (the thesis's agents beside four newer ones, docs/agents.md)."""
    results_dir: Path = Path("results")
    """Where the runs are written (<results-dir>/<profile>/<protocol>/<experiment>/)."""
    figures_dir: Optional[Path] = None
    """Where figures, tables and the scoreboard go (default: <results-dir>/figures; the committed ones: figures)."""
    force: bool = False
    """Rerun runs whose complete results exist, and start interrupted ones over instead of resuming them."""
    tensorboard: bool = True
    """Also write TensorBoard event files beside the results (<name>.tb/seed_<k>/)."""
    draw: bool = True
    """Draw the figures and score the claims once the runs have landed (--no-draw: the runs only; `figures` and
    `claims` draw them later)."""
    cluster: Annotated[Cluster, Flat] = Cluster()
    launch: Annotated[Launch, Flat] = Launch()

    @property
    def figures(self) -> Path:
        return self.figures_dir if self.figures_dir is not None else self.results_dir / "figures"

    def check(self) -> None:
        if not self.experiments:
            raise ValueError(f"--experiments needs at least one name; choose from {', '.join((*EXPERIMENTS, *GROUPS))}")
        if len(set(self.experiments)) != len(self.experiments):
            raise ValueError(f"--experiments names an experiment twice: {' '.join(self.experiments)}")
        writable_dir(self.results_dir, "results folder")
        writable_dir(self.figures, "figures folder")
        self.launch.check(distributed=self.cluster.coordinator is not None or self.cluster.distributed)
        self.cluster.start()  # before JAX touches a device, which the estimate does
        if self.launch.launcher == "slurm":  # the runs' devices and memory are the cluster's, not this machine's
            return
        seeds = PROFILES[self.profile].seeds
        check_seed_devices(seeds)
        for name in expand(self.experiments):  # one run at a time: the largest decides
            experiment = EXPERIMENTS[name]
            for run in experiment.runs:
                memory.check(experiment.train_config(run, self.profile, self.protocol), seeds)

    def __call__(self) -> int:
        return reproduce.command(self)


@dataclasses.dataclass(frozen=True)
class Figures:
    """Draw the figures and tables of existing results."""

    profile: Profile = "quick"
    """The profile whose results are read (smoke, quick or full)."""
    protocol: ProtocolName = "thesis-code"
    """The protocol whose results are read (thesis-code or thesis-text)."""
    results_dir: Path = Path("results")
    """Where the results are read from (<results-dir>/<profile>/<protocol>/<experiment>/; the committed ones:
    figures/data)."""
    figures_dir: Optional[Path] = None
    """Where they go (default: <results-dir>/figures; the committed ones: figures)."""

    @property
    def figures(self) -> Path:
        return self.figures_dir if self.figures_dir is not None else self.results_dir / "figures"

    def check(self) -> None:
        writable_dir(self.figures, "figures folder")

    def __call__(self) -> int:
        folder = self.results_dir / self.profile / self.protocol
        kept = []
        written = plots.draw(folder, self.figures, self.profile, protocol=self.protocol, kept=kept)
        for path, why in kept:
            print(f"kept {path}: {why}")
        if not written and not kept:
            print(f"no results under {folder}", file=sys.stderr)
            return 1
        for path in written:
            print(f"wrote {path}")
        return 0


@dataclasses.dataclass(frozen=True)
class Claims:
    """Score the thesis's simulation claims against existing results."""

    profile: Profile = "quick"
    """The profile whose results are scored (smoke, quick or full; --budgets compares several)."""
    protocol: Optional[ProtocolName] = None
    """One protocol (default: both)."""
    results_dir: Path = Path("results")
    """Where the results are read from (the committed ones: figures/data)."""
    json: Optional[Path] = None
    """Also write the scoreboard here."""
    markdown: Optional[Path] = None
    """Also write the protocols' scoreboards side by side as a Markdown table here."""
    budgets: tuple[Profile, ...] = ()
    """Score these profiles side by side instead (e.g. --budgets quick full), one protocol (thesis-code unless
    --protocol): one table, thesis | ours at each budget."""
    plot: Optional[Path] = None
    """With --budgets: also draw every experiment's headline curve and the falls at each budget into this image."""

    def check(self) -> None:
        if len(set(self.budgets)) != len(self.budgets):
            raise ValueError(f"--budgets names a profile twice: {' '.join(self.budgets)}")
        if self.plot is not None and len(self.budgets) < 2:
            raise ValueError("--plot draws the budgets side by side: give --budgets with two profiles or more")
        outputs = (("--json", self.json), ("--markdown", self.markdown), ("--plot", self.plot))
        for option, path in outputs:
            if path is not None:
                writable_file(path, option)
        named = [(option, path.resolve()) for option, path in outputs if path is not None]
        for i, (option, path) in enumerate(named):
            for other, other_path in named[i + 1:]:
                if path == other_path:
                    raise ValueError(f"{option} and {other} name the same file")
        if self.markdown is not None and not self.budgets and self.json is not None and \
                self.json.resolve() == self.markdown.with_suffix(".json").resolve():
            raise ValueError(f"--json {self.json} is where --markdown keeps its verdicts; name another file")

    def __call__(self) -> int:
        if self.budgets:
            scoreboards.by_budget(self.results_dir, self.budgets, self.protocol, self.markdown, self.json, self.plot)
        else:
            scoreboards.by_protocol(self.results_dir, self.profile, self.protocol, self.markdown, self.json)
        return 0


@dataclasses.dataclass(frozen=True)
class Publish:
    """Copy a profile's complete results into a reference folder, each with its best seed's policy only."""

    profile: Profile = "quick"
    """The profile whose results are read (smoke, quick or full)."""
    protocol: ProtocolName = "thesis-code"
    """The protocol whose results are read (thesis-code or thesis-text)."""
    results_dir: Path = Path("results")
    """Where the results are read from (<results-dir>/<profile>/<protocol>/)."""
    to: Optional[Path] = None
    """The reference folder, named explicitly (results land in <to>/<profile>/<protocol>/<experiment>/; the
    committed one is figures/data)."""

    def check(self) -> None:
        source = self.results_dir / self.profile / self.protocol
        if not source.is_dir():
            raise ValueError(f"no results folder {str(source)!r}")
        if self.to is None:
            raise ValueError("--to names the reference folder to publish into (the committed one: figures/data)")
        if (self.to / self.profile / self.protocol).resolve() == source.resolve():
            raise ValueError(f"--to {str(self.to)!r} is where the results already are; name another folder")
        writable_dir(self.to, "reference folder")

    def __call__(self) -> int:
        for path, what in publish.publish(self.results_dir / self.profile / self.protocol,
                                          self.to / self.profile / self.protocol):
            print(f"{path}: {what}")
        return 0


@dataclasses.dataclass(frozen=True)
class Attribute:
    """One-factor protocol swaps beside their baselines (2 seeds x 10k steps each)."""

    results_dir: Path = Path("results")
    """Where the swaps' runs are written."""
    only: Optional[tuple[str, ...]] = None
    """Run only these swaps (names as `list` prints them)."""
    launch: Annotated[Launch, Flat] = Launch()

    def check(self) -> None:
        self.launch.check()
        if self.only is not None and not self.only:
            raise ValueError(f"--only needs at least one swap; choose from: {', '.join(attribution.SWAPS_BY_NAME)}")
        unknown = sorted(set(self.only or ()) - set(attribution.SWAPS_BY_NAME))
        if unknown:
            raise ValueError(f"unknown swap(s) {unknown}; choose from: {', '.join(attribution.SWAPS_BY_NAME)}")
        writable_dir(self.results_dir, "results folder")

    def __call__(self) -> int:
        for table in attribution.run(self.results_dir, self.only, self.launch):
            print(table)
        return 0


@dataclasses.dataclass(frozen=True)
class EstimateGain:
    """The real-world experiments along one family of estimate quality (kalman.contact_trust), each finding scored
    at the gain it produces (docs/real-world.md)."""

    profile: Profile = "quick"
    """The profile of the runs (the family's value 0 is that profile's own real-world runs)."""
    protocol: ProtocolName = "thesis-code"
    """The protocol the runs follow (thesis-code or thesis-text)."""
    results_dir: Path = Path("results")
    """Where the runs are written (<results-dir>/estimate-gain/<profile>/<protocol>/contact-trust-<v>/)."""
    values: tuple[float, ...] = estimate_gain.VALUES
    """The family's values, each in [0, 1]."""
    train: bool = True
    """Train what is missing first (--no-train: score what is there)."""
    json: Optional[Path] = None
    """Also write the per-value gains, findings and speeds here."""
    figure: Optional[Path] = None
    """Also draw each finding against the gain, with the band that agrees with the thesis, here (.png)."""

    def check(self) -> None:
        for value in self.values:
            number("--values entry", value, 0.0, 1.0)
        writable_dir(self.results_dir, "results folder")
        for option, path in (("--json", self.json), ("--figure", self.figure)):
            if path is not None:
                writable_file(path, option)

    def __call__(self) -> int:
        if self.train:
            estimate_gain.run(self.results_dir, self.profile, self.protocol, self.values)
        rows = estimate_gain.score(self.results_dir, self.profile, self.protocol, self.values)
        for row in rows:
            gain = ("no moments" if row["gain"] is None
                    else f"slope {row['gain']['slope']:.2f}, {gain_figure.walk_label(row)}")
            held = [k for k, f in row["findings"].items() if f["holds"]]
            print(f"contact_trust {row['value']:g}: {gain}; holds: {', '.join(held) or 'none'}")
        print(gain_figure.band_line(rows))
        if self.json:
            safe_io.write_text(self.json, json.dumps(rows, indent=1) + "\n")
        if self.figure:
            gain_figure.figure(rows, self.figure, f"{self.profile} profile, {self.protocol}")
            print(f"wrote {self.figure}")
        return 0
