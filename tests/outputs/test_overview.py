"""The overview figures: every simulation experiment's headline curve and the falls, at one budget or several."""

from mjx_badger.core.paths import REFERENCE
from mjx_badger.experiments.registry import EXPERIMENTS, GROUPS, load_experiment
from mjx_badger.outputs import overview


def _loaded(profile: str, names=GROUPS["simulation"]) -> dict:
    return {name: load_experiment(EXPERIMENTS[name], REFERENCE / profile / "thesis-code" / name) for name in names}


def test_the_overview_draws_what_is_there_and_says_which_command_fills_the_rest(tmp_path):
    out = overview.overview_figure(_loaded("quick", ("forward",)), tmp_path / "overview.png", "quick profile")
    assert out.read_bytes().startswith(b"\x89PNG") and out.stat().st_size > 30_000
    assert set(overview.HEADLINE) == set(GROUPS["simulation"])  # one panel per experiment, the sixth the falls


def test_the_budgets_figure_puts_the_committed_quick_and_full_runs_side_by_side(tmp_path):
    loaded = {"quick": _loaded("quick"), "full": _loaded("full")}
    out = overview.budgets_figure(loaded, tmp_path / "budgets.png", "thesis-code")
    assert out.read_bytes().startswith(b"\x89PNG") and out.stat().st_size > 50_000
