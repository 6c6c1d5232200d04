"""`reproduce`, `figures`, `claims`, `publish`, `attribute`: their arguments checked before anything runs."""

import json

import pytest

from mjx_badger.cli import experiments
from mjx_badger.cli.main import main
from tests.commands import refused


def test_the_budgets_plot_needs_two_budgets_and_a_file_of_its_own(tmp_path, capsys):


    plot = tmp_path / "budgets.png"
    for argv, says in ((["--plot", str(plot)], "give --budgets with two profiles"),
                       (["--budgets", "full", "--plot", str(plot)], "give --budgets with two profiles"),
                       (["--budgets", "quick", "full", "--markdown", str(plot), "--plot", str(plot)],
                        "--markdown and --plot name the same file")):
        with pytest.raises(SystemExit) as exit_info:
            main(["claims", *argv])
        err = capsys.readouterr().err
        assert exit_info.value.code == 2 and says in err and err.count("\n") == 1, err
    assert not plot.exists()


def test_claims_without_results_prints_both_empty_scoreboards(capsys, tmp_path):
    assert main(["claims", "--results-dir", str(tmp_path), "--json", str(tmp_path / "board.json")]) == 0
    out = capsys.readouterr().out
    assert "thesis-code protocol, quick profile: 0 of 20 hold (0 checked)" in out
    assert "wall time: 0 runs in 0.00 h" in out
    assert "thesis-text protocol" in out and "thesis: CrossQ ~2 min, DroQ ~7 min" in out
    board = json.loads((tmp_path / "board.json").read_text())
    assert sorted(board) == ["thesis-code", "thesis-text"]
    assert all(len(claims) == 20 and all(c["holds"] is None for c in claims) for claims in board.values())


def test_the_commands_refuse_empty_or_repeated_experiments_and_default_their_figures_folder(tmp_path):
    with pytest.raises(ValueError, match="--experiments needs at least one name"):
        experiments.Reproduce(experiments=(), results_dir=tmp_path).check()
    with pytest.raises(ValueError, match="--experiments names an experiment twice: forward forward"):
        experiments.Reproduce(experiments=("forward", "forward"), results_dir=tmp_path).check()
    assert experiments.Figures(results_dir=tmp_path).figures == tmp_path / "figures"
    with pytest.raises(ValueError, match="unknown swap"):
        experiments.Attribute(only=("no such swap",), results_dir=tmp_path).check()


def test_claims_refuses_a_json_where_its_markdown_keeps_its_verdicts(capsys, tmp_path):
    refused(capsys, ["claims", "--markdown", str(tmp_path / "board.md"), "--json", str(tmp_path / "board.json")],
            "is where --markdown keeps its verdicts")
    assert list(tmp_path.iterdir()) == []
