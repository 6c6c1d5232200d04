"""The figures of each experiment: learning curves with the thesis's numbers in the title, wrapped to fit."""

import matplotlib

from mjx_badger.core import safe_io
from mjx_badger.experiments.registry import EXPERIMENTS
from mjx_badger.outputs import curves


def test_an_omni_titles_thesis_note_leaves_no_empty_finding():
    assert curves.omni_thesis_note({"falls": 0, "desired_mae": 0.05}) == "MAE ~0.05 (0 falls)"
    assert curves.omni_thesis_note({"falls": "~30", "finding": "stands still"}) == "stands still (~30 falls)"


def test_a_long_thesis_note_is_wrapped_inside_the_figure(monkeypatch, tmp_path):
    """The omni experiments' thesis notes run longer than a figure is wide: no title line may be cut at its edges."""
    drawn = []
    monkeypatch.setattr(safe_io, "save_figure", lambda fig, out, dpi: drawn.append((fig, dpi)))
    experiment = EXPERIMENTS["omni-random"]
    note = "; ".join(f"{name}: moves in every direction, below the best (0 falls)" for name in "ABCDEFGH")
    curves.learning_curves(experiment, {}, tmp_path / "x.png", "quick", "steps", (("eval/desired_mae", "t", "m/s"),) * 4,
                           ("a title", note))
    (fig, dpi), = drawn
    renderer = matplotlib.backends.backend_agg.FigureCanvasAgg(fig).get_renderer()
    title = fig._suptitle
    assert title.get_text().count("\n") >= 2  # wrapped
    extent = title.get_window_extent(renderer)
    assert 0 <= extent.x0 and extent.x1 <= fig.get_figwidth() * fig.dpi
