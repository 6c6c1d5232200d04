"""`python -m mjx_badger estimator {collect,fit,figures}`: the learned estimator's dataset and fit, and the
thesis's Figures 2.1 and 2.2 (experiments/estimator_data.py, estimation/fit.py and outputs/estimator_figures.py do the
work)."""

import dataclasses
import json
from pathlib import Path
from typing import Annotated, Literal, Union

import tyro

from mjx_badger.core.paths import REFERENCE
from mjx_badger.core.validation import writable_dir
from mjx_badger.estimation import fit, learned
from mjx_badger.experiments import estimator_data
from mjx_badger.outputs import estimator_figures
from mjx_badger.records import results
from mjx_badger.tasks.locomotion import TASKS

OMNI_POLICY = REFERENCE / "estimators" / "policy" / "cpg-vf_crossq_omni-pdec.json"
"""The committed omnidirectional policy (CPG-VF, CrossQ, curriculum, thesis-code, 3 seeds x 20k steps; its best seed)."""


def _positive(name: str, value) -> None:
    if not value > 0:
        raise ValueError(f"--{name} must be a positive number, not {value}")


def _results_with_policy(path: Path) -> None:
    if not path.exists():
        raise ValueError(f"no results file {str(path)!r}")
    document = results.read(path)
    if "policy" not in document or not (path.parent / document["policy"]).exists():
        raise ValueError(f"{path} has no saved policy beside it")


def _writable(path: Path, suffix: str) -> None:
    if path.suffix != suffix:
        raise ValueError(f"--out {path.name}: must end in {suffix}")
    writable_dir(path.parent, "output folder")


@dataclasses.dataclass(frozen=True)
class Collect:
    """Write a dataset: a trained policy's sensor readings (exact, as the thesis's) beside the true velocity."""

    results: Path = OMNI_POLICY
    """A run's results file with its saved policy (default: the committed omnidirectional CPG-VF policy)."""
    steps: int = 1_000_000
    """Control steps in all, over every env (the thesis: 2M; see docs/estimators.md for ours)."""
    envs: int = 128
    """Trajectories walked side by side; 20 % of them are held out for validation."""
    task: str = "omni-random"
    """Whose commands the policy follows: omni-random commands every direction."""
    action_noise: float = 0.0
    """Std of Gaussian noise on the policy's actions (in [-1, 1]), as a policy still exploring acts; 0: its own."""
    seed: int = 0
    """Seeds the walks' starts, commands and action noise."""
    out: Path = Path("results/estimators/dataset.npz")
    """The dataset file (.npz)."""

    def check(self) -> None:
        _positive("steps", self.steps)
        if not 0 <= self.action_noise <= 2:
            raise ValueError(f"--action-noise {self.action_noise}: choose within 0..2")
        _positive("envs", self.envs)
        if self.steps < self.envs * 500:
            raise ValueError(f"--steps {self.steps}: at least 500 per env ({self.envs * 500} for --envs {self.envs})")
        if self.task not in TASKS:
            raise ValueError(f"unknown task {self.task!r}; choose from {', '.join(TASKS)}")
        _results_with_policy(self.results)
        _writable(self.out, ".npz")

    def __call__(self) -> int:
        from tqdm import tqdm

        per_env = self.steps // self.envs
        with tqdm(total=per_env * self.envs, unit="step", desc="collect") as bar:
            estimator_data.write(self.results, self.steps, self.envs, self.task, self.seed, self.action_noise, self.out,
                                 progress=lambda done: bar.update(done * self.envs - bar.n))
        print(f"wrote {self.out}: {per_env * self.envs:,} steps ({self.envs} trajectories x {per_env})")
        return 0


@dataclasses.dataclass(frozen=True)
class Fit:
    """Fit the thesis's MLP estimator (one 256-256-1 network per velocity component) on a dataset."""

    dataset: Path = Path("results/estimators/dataset.npz")
    inputs: Literal[tuple(learned.INPUTS)] = "thesis"
    """thesis: joint angles and IMU acceleration; rich: the fix the thesis names (velocities, torques, contacts,
    gyro, gravity, a window of past steps)."""
    epochs: int = 100
    """Passes over the training trajectories (the thesis: 100)."""
    batch_size: int = 256
    """Samples per gradient step (ours: the thesis gives none)."""
    out: Path | None = None
    """Default: <dataset folder>/<inputs>.estimator.npz."""

    def check(self) -> None:
        _positive("epochs", self.epochs)
        _positive("batch-size", self.batch_size)
        if not self.dataset.exists():
            raise ValueError(f"no dataset {str(self.dataset)!r} (write one with `estimator collect`)")
        fit.load_dataset(self.dataset)  # the format, robot and field layout
        _writable(self.destination, ".npz")

    @property
    def destination(self) -> Path:
        return self.out or self.dataset.parent / f"{self.inputs}.estimator.npz"

    def __call__(self) -> int:
        from tqdm import tqdm

        with tqdm(total=self.epochs, unit="epoch", desc=f"fit {self.inputs}") as bar:
            def progress(epoch, train, validation):
                bar.set_postfix(train_mae=f"{sum(train) / len(train):.3f}",
                                validation_mae=f"{sum(validation) / len(validation):.3f}")
                bar.update(1)

            fitted = fit.fit_file(self.dataset, self.inputs, self.epochs, self.batch_size, self.destination, progress)
        last = fitted["meta"]["curves"]["validation_mae"][-1]
        print(f"wrote {self.destination}: validation MAE " + ", ".join(
            f"{name} {value:.3f} m/s" for name, value in zip(learned.OUTPUTS, last)))
        return 0


@dataclasses.dataclass(frozen=True)
class Figures:
    """Figures 2.1 and 2.2: the estimators against the truth over a 20 s walk, and the learned ones' MAE per epoch."""

    policies: tuple[Path, ...] = (REFERENCE / "quick" / "thesis-code" / "forward" / "jt-oef_crossq_forward.json",
                                  REFERENCE / "quick" / "thesis-code" / "forward" / "cpg-d_crossq_forward.json")
    """Results files with saved policies, walked on native MuJoCo with sensor noise."""
    learned: tuple[Path, ...] = (REFERENCE / "estimators" / "thesis.estimator.npz",
                                 REFERENCE / "estimators" / "rich.estimator.npz",
                                 REFERENCE / "estimators" / "noise-0.3" / "thesis.estimator.npz",
                                 REFERENCE / "estimators" / "noise-1.0" / "thesis.estimator.npz")
    """Fitted estimators to compare (missing files are left out, and said so)."""
    seconds: float = 20.0
    """Simulated seconds of each walk (Figure 2.1: 20)."""
    seed: int = 0
    """The walks' random seed."""
    out: Path = Path("results/estimators/figures")
    """Folder for estimators_walk.png, estimators_fit.png and estimators.md/.json (the committed ones: figures/estimators)."""

    def check(self) -> None:
        _positive("seconds", self.seconds)
        for path in self.policies:
            _results_with_policy(path)
        for path in self.learned:
            if path.exists():
                learned.load(path)
        writable_dir(self.out, "output folder")

    def __call__(self) -> int:
        learned = [path for path in self.learned if path.exists()]
        for path in sorted(set(self.learned) - set(learned)):
            print(f"left out {path}: no such file (write it with `estimator fit`)")
        report = estimator_figures.draw(self.policies, learned, self.seconds, self.seed, self.out)
        print(estimator_figures.table(report))
        print(json.dumps({"wrote": report["files"]}))
        return 0


Command = Union[Annotated[Collect, tyro.conf.subcommand("collect")], Annotated[Fit, tyro.conf.subcommand("fit")],
                Annotated[Figures, tyro.conf.subcommand("figures")]]


@dataclasses.dataclass(frozen=True)
class Estimator:
    """The learned velocity estimator (collect a dataset, fit it) and the estimators' figures (thesis §2.6)."""

    job: Annotated[Command, tyro.conf.arg(name=""), tyro.conf.OmitSubcommandPrefixes]

    def check(self) -> None:
        self.job.check()

    def __call__(self) -> int:
        return self.job()
