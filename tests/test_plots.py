"""Figures' own arithmetic: the gait frequency read off contact records, the thesis notes in titles."""

import numpy as np
import pytest

from mjx_badger import analysis

DT = 0.005
T = np.arange(400) * DT  # a 2 s gait record at the physics rate


def trot(hz, duty=0.5, offsets=(0.0, 0.5, 0.5, 0.0)):
    """Contacts (T, 4) of a gait at `hz`: each foot in stance for `duty` of its cycle."""
    return np.stack([((T * hz + o) % 1.0) >= (1.0 - duty) for o in offsets], axis=1).astype(int)


@pytest.mark.parametrize("hz", [2.0, 2.5, 4.0, 6.0])
def test_gait_frequency_of_a_trot(hz):
    assert analysis.gait_frequency(trot(hz), DT) == pytest.approx(hz, abs=0.05)


def test_a_foot_brushing_the_floor_mid_swing_does_not_double_the_frequency():
    contacts = trot(2.0)
    brush = ((T * 2.0) % 1.0 > 0.2) & ((T * 2.0) % 1.0 < 0.25)  # FL touches briefly during its swing
    contacts[brush, 0] = 1
    assert analysis.gait_frequency(contacts, DT) == pytest.approx(2.0, abs=0.05)


def test_standing_still_has_no_gait_frequency():
    assert np.isnan(analysis.gait_frequency(np.ones((400, 4), int), DT))


@pytest.mark.parametrize("first, second", [((0.4, 0.65), (0.8, 1.0)), ((0.5, 0.65), (0.85, 1.0))])
def test_two_touchdowns_per_cycle_still_count_one_cycle(first, second):
    """Stance split by a hop: the 2nd (or 3rd) harmonic is the strongest line, the cycle is still 2 Hz."""
    phase = (T[:, None] * 2.0 + np.array([0.0, 0.5, 0.5, 0.0])) % 1.0
    contacts = (((phase >= first[0]) & (phase < first[1])) | ((phase >= second[0]) & (phase < second[1]))).astype(int)
    assert analysis.gait_frequency(contacts, DT) == pytest.approx(2.0, abs=0.05)


def test_every_experiment_declares_figures_and_a_table_that_exist():
    from mjx_badger import plots, tables
    from mjx_badger.experiments import EXPERIMENTS

    for experiment in EXPERIMENTS.values():
        assert set(experiment.figures) <= set(plots.FIGURES), experiment.name
        assert experiment.table in tables.TABLES and experiment.x_axis in ("steps", "minutes"), experiment.name
        assert ("versus" in experiment.figures) == (experiment.baseline in EXPERIMENTS), experiment.name


def test_an_omni_titles_thesis_note_leaves_no_empty_finding():
    from mjx_badger.plots import omni_thesis_note

    assert omni_thesis_note({"falls": 0, "desired_mae": 0.05}) == "MAE ~0.05 (0 falls)"
    assert omni_thesis_note({"falls": "~30", "finding": "stands still"}) == "stands still (~30 falls)"


def test_our_seeds_are_read_as_the_released_codes_and_counted_inside_its_range():
    from mjx_badger import tables

    # Two seeds, 1000-step chunks; warm-up ends at 1000 with one fall already counted for seed 1.
    document = {"config": {"warmup_steps": 1000}, "seeds": [0, 1], "steps": [1000, 2000, 3000, 4000, 5000],
                "metrics": {"train/forward_velocity": [[0.1, 0.1], [0.5, 0.2], [0.6, 0.3], [0.5, 0.3], [0.4, 0.3]],
                            "train/falls": [[0, 1], [0, 3], [2, 5], [3, 5], [4, 6]]}}
    measured = analysis.per_seed_released_measures(document)
    assert measured["steps_to_0.45"] == [2000, None]  # seed 1 never reaches 0.45 m/s
    np.testing.assert_allclose(measured["velocity_last_3k"], [0.5, 0.3])  # mean of the last three chunks
    assert measured["falls"] == [4.0, 5.0]  # the fall in warm-up does not count
    released = {"approaches": {"jt-nf": {"steps_to_0.45": [1000, 3000], "velocity_last_3k": [0.45, 0.55],
                                         "falls": [4, 9]}}}
    row = tables.released_code_table({"jt-nf": document}, released, "quick").splitlines()[-1]
    assert row == "| JT-NF | 1k, 3k / 2k, never (1 of 2) | 0.45, 0.55 / 0.50, 0.30 (1 of 2) | 4, 9 / 4, 5 (2 of 2) |"


def test_a_long_thesis_note_is_wrapped_inside_the_figure(monkeypatch, tmp_path):
    """The omni experiments' thesis notes run longer than a figure is wide: no title line may be cut at its edges."""
    import matplotlib

    from mjx_badger import plots, safe_io
    from mjx_badger.experiments import EXPERIMENTS

    drawn = []
    monkeypatch.setattr(safe_io, "save_figure", lambda fig, out, dpi: drawn.append((fig, dpi)))
    experiment = EXPERIMENTS["omni-random"]
    note = "; ".join(f"{name}: moves in every direction, below the best (0 falls)" for name in "ABCDEFGH")
    plots.learning_curves(experiment, {}, tmp_path / "x.png", "quick", "steps", (("eval/desired_mae", "t", "m/s"),) * 4,
                          ("a title", note))
    (fig, dpi), = drawn
    renderer = matplotlib.backends.backend_agg.FigureCanvasAgg(fig).get_renderer()
    title = fig._suptitle
    assert title.get_text().count("\n") >= 2  # wrapped
    extent = title.get_window_extent(renderer)
    assert 0 <= extent.x0 and extent.x1 <= fig.get_figwidth() * fig.dpi
