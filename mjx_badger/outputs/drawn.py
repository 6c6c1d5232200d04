"""What each figure was drawn from, so that redrawing from fewer results keeps it instead.

A figures folder (one protocol's) holds `drawn_from_<profile>.json`: for each file drawn there,
how many complete runs it was drawn from. A redraw from fewer complete runs than that keeps the
file and says why; a file with no record (a committed reference) counts as drawn from all of its
runs. So a partial rerun never replaces a fuller figure, while a run that goes on redraws its own.
"""

import json
from pathlib import Path

from mjx_badger.core import safe_io


def complete_runs(experiment, documents: dict) -> tuple[int, int]:
    """(runs of `experiment` with complete results among `documents`, runs it has)."""
    return sum(bool(d.get("complete")) for d in documents.values()), len({experiment.label(r) for r in experiment.runs})


class Drawn:
    """The record of one figures folder at one profile: `keeps(...)` before drawing, `note(...)` after."""

    def __init__(self, folder: Path, profile: str):
        self.path = Path(folder) / f"drawn_from_{profile}.json"
        try:
            self.counts = json.loads(self.path.read_text()) if self.path.exists() else {}
        except (OSError, ValueError):
            self.counts = {}
        if not isinstance(self.counts, dict):
            self.counts = {}

    def keeps(self, paths: list[Path], done: int, needed: int, why: str, kept: list | None) -> bool:
        """Whether any of `paths` was drawn from more than the `done` complete runs now (of `needed`); those
        are appended to `kept` with `why`."""
        fuller = [p for p in paths if p.exists() and done < self.counts.get(p.name, needed)]
        if kept is not None:
            kept.extend((path, why) for path in fuller)
        return bool(fuller)

    def note(self, paths: list[Path], done: int) -> None:
        """`paths` were just drawn from `done` complete runs."""
        self.counts.update({Path(p).name: done for p in paths})
        safe_io.write_text(self.path, json.dumps(self.counts, indent=1, sort_keys=True) + "\n")
