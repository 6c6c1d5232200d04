"""A thesis finding as a named predicate over results files (`Claim`), and what checking it gives (`Verdict`).

A claim names the thesis figure it comes from and the thesis's number; `check` reads one
protocol's results (`results/<profile>/<protocol>/<experiment>/*.json`, through `Results`) and
returns our number in words and a verdict: True (holds), False (does not) or None (results missing,
or undecided). A claim's tolerance is written in its `rule`, so a reader sees what 'holds' meant.
"""

import dataclasses
from pathlib import Path
from typing import Callable

import numpy as np

from mjx_badger.experiments.registry import EXPERIMENTS, load_experiment
from mjx_badger.records import analysis
from mjx_badger.records import results as results_io


class Missing(Exception):
    """A results file a claim needs is not there (yet)."""

    def __init__(self, experiment: str, name: str):
        super().__init__(f"{experiment}/{name}")
        self.experiment = experiment


class Results:
    """One protocol's results at one profile, loaded lazily per experiment."""

    def __init__(self, folder: Path):
        self.folder = Path(folder)
        self._loaded = {}
        self.used = []
        """(experiment, name) of every document a claim read since its check began, to name seeds left out."""

    def documents(self, experiment: str) -> dict:
        if experiment not in self._loaded:
            self._loaded[experiment] = load_experiment(EXPERIMENTS[experiment], self.folder / experiment)
        return self._loaded[experiment]

    def document(self, experiment: str, name: str) -> dict:
        found = self.documents(experiment).get(name)
        if found is None:
            raise Missing(experiment, name)
        self.used.append((experiment, name))
        return found

    def left_out(self) -> str:
        """'' or which seeds of the documents read since the last check were left out for diverging."""
        notes = {f"{e}/{n} {words}" for e, n in self.used
                 if (words := results_io.left_out_words(self.documents(e)[n]))}
        return "; ".join(sorted(notes))

    def crossed(self) -> str:
        """'' or which documents read since the last check evaluated past an episode's end under a drawn command."""
        return ", ".join(sorted({f"{e}/{n}" for e, n in self.used
                                 if analysis.evaluation_crossed_episode(self.documents(e)[n])}))

    def summary(self, experiment: str, name: str) -> dict:
        return analysis.summarize(self.document(experiment, name), EXPERIMENTS[experiment].target_velocity)

    def final_mean(self, experiment: str, name: str, metric: str) -> float:
        return float(np.nanmean(analysis.final(self.document(experiment, name), metric)))

    def would_falls(self, experiment: str, name: str) -> float:
        document = self.document(experiment, name)
        if "train/would_falls" not in document["metrics"]:
            return float("nan")
        return float(np.mean(analysis.series(document, "train/would_falls")[-1]))


@dataclasses.dataclass(frozen=True)
class Verdict:
    claim: "Claim"
    ours: str
    holds: bool | None

    def as_dict(self) -> dict:
        return {"id": self.claim.id, "finding": self.claim.finding, "thesis_figure": self.claim.figure,
                "thesis": self.claim.thesis, "rule": self.claim.rule, "ours": self.ours, "holds": self.holds}


@dataclasses.dataclass(frozen=True)
class Claim:
    id: str
    finding: str
    figure: str
    thesis: str
    """The thesis's own numbers."""
    rule: str
    """What 'holds' means for our numbers."""
    measure: Callable
    """Results -> (our numbers in words, holds)."""

    def check(self, results: Results) -> Verdict:
        results.used.clear()
        try:
            ours, holds = self.measure(results)
        except Missing as missing:
            have, runs = len(results.documents(missing.experiment)), len(EXPERIMENTS[missing.experiment].runs)
            if have:  # say how far a partly run experiment is, so the board does not read 'not run yet'
                return Verdict(self, f"partly run: {have} of {runs} runs of {missing.experiment} in, waits for {missing}",
                               None)
            return Verdict(self, f"no results ({missing})", None)
        left_out = results.left_out()
        ours += f" ({left_out})" if left_out else ""
        crossed = results.crossed()
        if crossed:  # its numbers mix in a command the run was not asked: no verdict until it is rerun
            return Verdict(self, f"{ours} (undecided: {crossed} evaluated past an episode's end under a drawn "
                                 "command, before the fix)", None)
        return Verdict(self, ours, None if holds is None else bool(holds))
