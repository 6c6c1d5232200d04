"""`claims`: the thesis's findings scored on existing results, printed and written as the scoreboards of the
README and docs/results.md, by protocol at one profile or by budget (profiles side by side) with their figure."""

import json
from pathlib import Path

from mjx_badger.core import safe_io
from mjx_badger.experiments.registry import EXPERIMENTS, GROUPS, load_experiment
from mjx_badger.outputs.overview import budgets_figure
from mjx_badger.protocol.protocols import PROTOCOLS
from mjx_badger.records import results
from mjx_badger.scoring import claims, real_world, scoreboard


def by_protocol(results_dir: Path, profile: str, protocol: str | None, markdown: Path | None,
                json_path: Path | None) -> None:
    """Both protocols' scoreboards (or `protocol`'s) at `profile`, the simulation claims and then the real-world
    findings, with their wall times; `markdown`: the side-by-side table (scoreboard.write_markdown)."""
    names = [protocol] if protocol else list(PROTOCOLS)
    boards = {name: claims.score(results_dir / profile, name) for name in names}
    for name, board in boards.items():
        print(scoreboard.scoreboard_text(board, profile, name))
        print(f"  wall time: {results.wall_time_words(results_dir / profile / name, GROUPS['simulation'])}")
        print()
    for name in names:  # the real-world findings, in their own section
        real = claims.score(results_dir / profile, name, real_world.CLAIMS)
        print(scoreboard.scoreboard_text(real, profile, name).replace("thesis claims", "real-world findings", 1))
        print(f"  wall time: {results.wall_time_words(results_dir / profile / name, GROUPS['real'])}")
        print()
    if markdown:
        scoreboard.write_markdown(markdown, boards, results_dir / profile)
    _write_json(json_path, boards)


def by_budget(results_dir: Path, budgets: tuple, protocol: str | None, markdown: Path | None, json_path: Path | None,
              plot: Path | None) -> None:
    """One protocol's scoreboard at several profiles side by side (thesis | ours at each); `plot`: every
    experiment's headline curve and the falls at each budget in one figure."""
    protocol = protocol or "thesis-code"
    boards = {name: claims.score(results_dir / name, protocol) for name in budgets}
    print(scoreboard.budgets_text(boards, protocol))
    times = {name: results.wall_time_words(results_dir / name / protocol, GROUPS["simulation"]) for name in boards}
    for name, words in times.items():
        print(f"  wall time at {name}: {words}")
    if markdown:
        safe_io.write_text(markdown, f"Protocol: {protocol}\n\n" + scoreboard.scoreboard_markdown(boards, "ours at {}")
                           + f"\nWall time on this machine: {'; '.join(f'{n}: {w}' for n, w in times.items())}.\n")
        print(f"wrote {markdown}")
    if plot:
        loaded = {budget: {name: load_experiment(EXPERIMENTS[name], results_dir / budget / protocol / name)
                           for name in GROUPS["simulation"]} for budget in budgets}
        print(f"wrote {budgets_figure(loaded, plot, protocol)}")
    _write_json(json_path, boards)


def _write_json(path: Path | None, boards: dict) -> None:
    if path:
        safe_io.write_text(path, json.dumps({name: [v.as_dict() for v in board] for name, board in boards.items()},
                                            indent=1))
