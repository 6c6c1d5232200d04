"""The estimate's weight, measured: the real-world experiments rerun along one family of estimate quality, each
finding scored at the gain (slope of estimate against truth) the family's value produces.

The family is `kalman.contact_trust` (estimators.KalmanConfig): 0 is the thesis's robot, its filter averaging all
four feet (the sourced default); 1 weighs each foot by the contacts its motor torques imply. Between them the
estimate moves from a few per cent of the truth to most of it, while nothing else about the robot changes.
Value 0 is the real-world experiments' own runs; the others are written under <results>/estimate-gain/.
"""

import dataclasses
from pathlib import Path

import numpy as np

from mjx_badger.experiments.registry import EXPERIMENTS, PROFILES
from mjx_badger.learning import runner
from mjx_badger.learning.progress import progress_wanted
from mjx_badger.records import analysis, results
from mjx_badger.records.real_world import summary
from mjx_badger.scoring import real_world
from mjx_badger.scoring.verdicts import Results

FIELD = "kalman.contact_trust"
VALUES = (0.0, 0.25, 0.5, 1.0)
"""The family's values; 0, the default, is the real-world experiments' own runs."""
EXPERIMENT_NAMES = ("real-office", "real-outdoor")
"""Tables 5.3 and 5.4, the forward findings; Table 5.5's omnidirectional runs, 2.5x longer, are left out."""
LEFT_OUT = {("real-office", "sac-utd20")}
"""SAC-UTD20's 20 updates a step would cost more than the rest of a value together; no finding reads it."""
WALKING = 0.05
"""m/s: a run standing slower than this at evaluation has no walk ratio (its ratio would be noise over nothing)."""


def folder(results_dir: Path, profile: str, protocol: str, value: float) -> Path:
    """Where the runs of one value live (value 0: the real-world experiments' own)."""
    if value == 0.0:
        return Path(results_dir) / profile / protocol
    return Path(results_dir) / "estimate-gain" / profile / protocol / f"contact-trust-{value:g}"


def planned(results_dir: Path, profile: str, protocol: str, values: tuple = VALUES):
    """(value, config, path) of every run of the study's values other than 0."""
    for value in values:
        if value == 0.0:
            continue
        for name in EXPERIMENT_NAMES:
            experiment = EXPERIMENTS[name]
            for run in experiment.runs:
                if (name, run.algo) in LEFT_OUT:
                    continue
                config = dataclasses.replace(experiment.train_config(run, profile, protocol),
                                             condition_changes=((FIELD, value),))
                yield value, config, folder(results_dir, profile, protocol, value) / name / experiment.result_name(run)


def run(results_dir: Path, profile: str, protocol: str, values: tuple = VALUES) -> None:
    """Train every planned run without complete results (an interrupted one resumes)."""
    seeds = list(range(PROFILES[profile].seeds))
    for _, config, path in planned(results_dir, profile, protocol, values):
        if path.exists() and (results.read_or_skip(path) or {}).get("complete"):
            print(f"skip {path}: complete")
            continue
        runner.run(config, seeds, path, progress=progress_wanted())


def study_documents(where: Path):
    """(experiment, label, document) of the value's complete runs that the study plans (value 0's omni and
    SAC-UTD20 runs left out, so every value is measured over the same runs)."""
    for name in EXPERIMENT_NAMES:
        experiment = EXPERIMENTS[name]
        documents = Results(where).documents(name) if (where / name).is_dir() else {}
        for run in experiment.runs:
            document = documents.get(experiment.label(run))
            if (name, run.algo) not in LEFT_OUT and document and document.get("complete"):
                yield name, experiment.label(run), document


def gain(where: Path) -> dict | None:
    """Mean slope and correlation of estimate against truth over the value's runs (seeds pooled per run), or None
    where no run has its estimate's moments."""
    slopes, correlations = [], []
    for _, _, document in study_documents(where):
        measured = analysis.estimate_gain(document)
        if measured:
            slopes += measured["slope"]
            correlations += measured["correlation"]
    if not slopes:
        return None
    return {"slope": float(np.nanmean(slopes)), "correlation": float(np.nanmean(correlations)), "seeds": len(slopes)}


def score(results_dir: Path, profile: str, protocol: str, values: tuple = VALUES) -> list[dict]:
    """Per value: its gain and each real-world finding's verdict and numbers (None where a run is missing)."""
    rows = []
    for value in values:
        where = folder(results_dir, profile, protocol, value)
        verdicts = [claim.check(Results(where)) for claim in real_world.CLAIMS]
        measured, speeds = gain(where), runs(where)
        if measured is not None:
            measured["walk_ratio"] = walk_ratio(speeds)
        rows.append({"value": value, "gain": measured, "runs": speeds,
                     "findings": {v.claim.id: {"holds": v.holds, "ours": v.ours} for v in verdicts}})
    return rows


def walk_ratio(speeds: dict) -> float | None:
    """Mean estimated over true evaluation speed of the runs that walk: what a walking policy's reward sees.

    The slope over training weighs the large, brief speeds of falls, resets and warm-up, which the filter follows,
    by their squares; the walk's own ratio is the weight the estimate gives the steady gait (docs/real-world.md).
    """
    walks = [run for experiment in speeds.values() for run in experiment.values()]
    ratios = [run["estimated_velocity"] / run["velocity"] for run in walks
              if run["velocity"] >= WALKING and np.isfinite(run["estimated_velocity"])]
    return float(np.mean(ratios)) if ratios else None


def runs(where: Path) -> dict:
    """{experiment: {label: {velocity, estimated_velocity, falls}}} of the value's complete runs."""
    out = {}
    for name, label, document in study_documents(where):
        row = summary(document)
        out.setdefault(name, {})[label] = {k: row[k] for k in ("velocity", "estimated_velocity", "falls")}
    return out
