"""Scoreboards of verdicts: plain text for the terminal, Markdown for the README and the docs, and the files
`reproduce` and `claims --markdown` write, which keep a verdict decided before while its runs are missing."""

import json
from pathlib import Path

from mjx_badger.core import safe_io
from mjx_badger.experiments.registry import GROUPS
from mjx_badger.records import results
from mjx_badger.scoring.verdicts import Verdict


def _mark(v: Verdict) -> str:
    """HOLDS, FAILS, '-' (not run yet, or partly) or '?' (undecided), five characters wide."""
    if v.holds is None:
        return "  -  " if _waits(v.ours) else "  ?  "
    return "HOLDS" if v.holds else "FAILS"


def scoreboard_text(verdicts: list[Verdict], profile: str, protocol: str) -> str:
    """A plain-text scoreboard: one line per claim, our numbers beside the thesis's."""
    held = sum(v.holds is True for v in verdicts)
    checked = sum(v.holds is not None for v in verdicts)
    lines = []
    for v in verdicts:
        lines.append(f"  {_mark(v)}  {v.claim.finding} [{v.claim.figure}]")
        lines.append(f"         thesis: {v.claim.thesis} | ours: {v.ours}")
    return (f"thesis claims, {protocol} protocol, {profile} profile: {held} of {len(verdicts)} hold "
            f"({checked} checked)\n" + "\n".join(lines))


def _waits(ours: str) -> bool:
    """Whether a verdict's words (or a board's cell) say its results are not all in yet."""
    return ours.startswith(("no results", "not run yet", "partly run"))


def _cell(v: Verdict) -> str:
    if v.holds is None:
        if v.ours.startswith("no results"):
            return "not run yet"
        return v.ours if _waits(v.ours) else f"undecided: {v.ours}"
    return f"{'**holds**' if v.holds else 'fails'}: {v.ours}"


def budgets_text(boards: dict, protocol: str) -> str:
    """Plain text of one protocol's scoreboards at several profiles (budgets), claim by claim."""
    totals = ", ".join(f"{sum(v.holds is True for v in board)} of {len(board)} at {name}" for name, board in boards.items())
    lines = [f"thesis claims, {protocol} protocol: {totals} hold"]
    width = max(len("thesis"), *map(len, boards))
    for row in zip(*boards.values()):
        lines.append(f"  {row[0].claim.finding} [{row[0].claim.figure}]")
        lines.append(f"    {'thesis':<{width}}  {row[0].claim.thesis}")
        for name, v in zip(boards, row):
            lines.append(f"    {name:<{width}}  {_mark(v)}  {v.ours}")
    return "\n".join(lines)


def scoreboard_markdown(boards: dict, column: str = "{}: ours") -> str:
    """The side-by-side scoreboard of the README and docs/results.md: one row per claim, one verdict column per board (protocol or profile)."""
    names = list(boards)
    lines = ["| thesis finding | thesis | " + " | ".join(column.format(n) for n in names) + " |",
             "|---|---|" + "---|" * len(names)]
    for row in zip(*boards.values()):
        claim = row[0].claim
        cells = [_cell(v) for v in row]
        lines.append(f"| {claim.finding} ({claim.figure}) | {claim.thesis} | " + " | ".join(cells) + " |")
    totals = [f"{sum(v.holds is True for v in board)} of {len(board)}" for board in boards.values()]
    lines.append("| **claims that hold** | | " + " | ".join(totals) + " |")
    return "\n".join(lines) + "\n"


def _decided(holds, ours: str) -> bool:
    """Whether a verdict has its results: it holds, fails or is undecided, rather than waiting for runs."""
    return holds is not None or not _waits(ours)


def keep_decided(boards: dict, previous: dict) -> tuple[dict, list[str]]:
    """`boards` (column -> verdicts) with each verdict still waiting for its runs replaced by the one `previous`
    (column -> `Verdict.as_dict()`s, as `write_markdown` keeps them) had decided: fewer results never take a
    verdict away. Returns (boards, 'finding [column]' of every verdict kept)."""
    kept, out = [], {}
    for column, verdicts in boards.items():
        before = {v.get("id"): v for v in previous.get(column, []) if isinstance(v, dict)}
        out[column] = []
        for verdict in verdicts:
            old = before.get(verdict.claim.id)
            if not _decided(verdict.holds, verdict.ours) and old is not None and _decided(old.get("holds"),
                                                                                              old.get("ours", "")):
                verdict = Verdict(verdict.claim, old["ours"], old["holds"])
                kept.append(f"{verdict.claim.finding} ({verdict.claim.figure}) [{column}]")
            out[column].append(verdict)
    return out, kept


def write_markdown(path: Path, boards: dict, profile_folder: Path) -> None:
    """The side-by-side scoreboard docs/results.md quotes, with each protocol's wall time under it, and its verdicts
    beside it as data (<path>.json) for the next write to keep what it had decided (`keep_decided`)."""
    data = path.with_suffix(".json")
    try:
        previous = json.loads(data.read_text()) if data.is_file() else {}
    except (OSError, ValueError):
        previous = {}
    boards, kept = keep_decided(boards, previous if isinstance(previous, dict) else {})
    times = "; ".join(f"{name}: {results.wall_time_words(profile_folder / name, GROUPS['simulation'])}" for name in boards)
    note = f" ({len(kept)} verdicts kept from the scoreboard there before: no results for them now)" if kept else ""
    safe_io.write_text(path, scoreboard_markdown(boards) + f"\nWall time on this machine: {times}.{note}\n")
    safe_io.write_text(data, json.dumps({name: [v.as_dict() for v in board] for name, board in boards.items()},
                                        indent=1) + "\n")
    print(f"wrote {path}")
    for cell in kept:
        print(f"kept {cell}: no results for it under {profile_folder}")
