"""How figures look: a seed-mean curve with its min/max band, the seeds named, a figure saved whole."""

import numpy as np

from mjx_badger.outputs import style


def _document(seeds=(0, 1), left_out=()):
    return {"seeds": list(seeds), "steps": [1000, 2000], "sim_minutes": [0.3, 0.6],
            "metrics": {"train/forward_velocity": [[0.1, 0.3], [0.2, np.nan]]}, "left_out": list(left_out)}


def test_a_panel_draws_the_seed_mean_and_its_band_and_names_the_seeds(tmp_path):
    fig, ax = style.plt.subplots()
    style.curve_panel(ax, {"jt-oef": _document()}, "train/forward_velocity", "title", "m/s", "minutes", target=0.5)
    line = ax.get_lines()[0]
    np.testing.assert_allclose(line.get_xdata(), [0.3, 0.6])  # simulated minutes on the x axis
    np.testing.assert_allclose(line.get_ydata(), [0.2, 0.2])  # the NaN seed left out of the second mean
    assert line.get_label() == "JT-OEF" and ax.get_lines()[1].get_label() == "target 0.5 m/s"
    assert style.x_values(_document(), "steps").tolist() == [1.0, 2.0]
    out = style.save(fig, tmp_path / "panel.png")
    assert out.read_bytes().startswith(b"\x89PNG") and [p.name for p in tmp_path.iterdir()] == ["panel.png"]


def test_the_seeds_note_counts_seeds_and_names_those_left_out():
    gone = _document(left_out=[{"seed": 2, "diverged_at_step": 12000}])
    assert style.seeds_note({"jt-oef": _document()}) == "2 seeds, mean and min/max band"
    assert style.seeds_note({"jt-oef": gone, "cpg-d": _document((0, 1, 2))}) == (
        "2/3 seeds, mean and min/max band; JT-OEF seed 2 left out: diverged at step 12000")
