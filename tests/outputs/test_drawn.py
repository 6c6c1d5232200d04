"""What each figure was drawn from: a redraw from fewer results keeps the fuller figure."""

import shutil
from pathlib import Path

from mjx_badger.cli.main import main
from mjx_badger.outputs import drawn

REPO = Path(__file__).resolve().parents[2]


REFERENCE = REPO / "figures" / "data" / "quick" / "thesis-code"


def test_figures_from_fewer_results_keep_the_figures_already_there(tmp_path, capsys):
    results_dir = tmp_path / "results"
    folder = results_dir / "quick" / "thesis-code" / "forward"
    folder.mkdir(parents=True)
    for name in ("jt-nf_crossq_forward.json", "cpg-vf_crossq_forward.json"):
        shutil.copy(REFERENCE / "forward" / name, folder / name)
    figure = results_dir / "figures" / "thesis-code" / "forward_quick.png"
    figure.parent.mkdir(parents=True)
    figure.write_bytes(b"drawn from all six runs")
    assert main(["figures", "--results-dir", str(results_dir)]) == 0
    out = capsys.readouterr().out
    assert figure.read_bytes() == b"drawn from all six runs"
    assert f"kept {figure}: 2 of 6 runs complete under {folder}" in out
    assert not (figure.parent / "forward_quick.md").exists()  # the experiment is left alone, table included
    figure.unlink()
    assert main(["figures", "--results-dir", str(results_dir)]) == 0  # nothing to keep: drawn from what there is
    assert figure.stat().st_size > 10_000
    figure.write_bytes(b"drawn from two")
    shutil.copy(REFERENCE / "forward" / "jt-oef_crossq_forward.json", folder)
    assert main(["figures", "--results-dir", str(results_dir)]) == 0  # a run that goes on redraws its own
    assert figure.read_bytes() != b"drawn from two"
    (folder / "jt-nf_crossq_forward.json").unlink()
    capsys.readouterr()
    assert main(["figures", "--results-dir", str(results_dir)]) == 0
    assert f"kept {figure}: 2 of 6 runs complete" in capsys.readouterr().out


def test_a_file_drawn_from_more_complete_runs_is_kept_and_one_without_a_record_counts_as_whole(tmp_path):
    figure = tmp_path / "forward_quick.png"
    figure.write_bytes(b"drawn before")
    record = drawn.Drawn(tmp_path, "quick")
    kept = []
    assert record.keeps([figure], done=5, needed=6, why="5 of 6 runs complete", kept=kept)  # a committed figure
    assert kept == [(figure, "5 of 6 runs complete")]
    assert not record.keeps([figure], done=6, needed=6, why="-", kept=None)
    record.note([figure], done=2)
    assert drawn.Drawn(tmp_path, "quick").counts == {"forward_quick.png": 2}  # written beside the figures
    assert not drawn.Drawn(tmp_path, "quick").keeps([figure], done=3, needed=6, why="-", kept=None)
    (tmp_path / "drawn_from_quick.json").write_text("[damaged")
    assert drawn.Drawn(tmp_path, "quick").counts == {}
