"""Numbers from results files: how figures and tables name a run, the onboard estimate's gain."""

import numpy as np
import pytest

from mjx_badger.records.analysis import display_name, estimate_gain


def test_a_run_of_another_algorithm_is_named_algorithm_first():
    assert display_name("jt-lpf sac-utd20") == "SAC-UTD20 JT-LPF"  # Table 5.3's first row, as the thesis names it
    assert display_name("jt-lpf") == "JT-LPF" and display_name("jt-lpf cutoff_hz=2") == "JT-LPF cutoff_hz=2"


def test_the_estimates_gain_is_the_least_squares_slope_and_correlation_pooled_over_the_run():
    """Per-chunk moments of two seeds' steps, pooled: seed 0 reads a tenth of the truth exactly, seed 1 a noisy half."""
    rng = np.random.default_rng(0)
    true = rng.uniform(0.0, 1.0, (4, 50, 2))  # chunks, steps, seeds
    estimate = true * [0.1, 0.5] + np.stack([np.zeros((4, 50)), rng.normal(0.0, 0.2, (4, 50))], axis=-1)
    moments = {"train/desired_velocity": true, "train/estimated_desired_velocity": estimate,
               "train/true_squared": true * true, "train/estimate_squared": estimate * estimate,
               "train/true_times_estimate": true * estimate}
    gain = estimate_gain({"metrics": {k: v.mean(axis=1).tolist() for k, v in moments.items()}})
    flat_true, flat_estimate = true.reshape(-1, 2), estimate.reshape(-1, 2)
    for seed in (0, 1):
        slope, _ = np.polyfit(flat_true[:, seed], flat_estimate[:, seed], 1)
        assert gain["slope"][seed] == pytest.approx(slope, rel=1e-9)
        correlation = np.corrcoef(flat_true[:, seed], flat_estimate[:, seed])[0, 1]
        assert gain["correlation"][seed] == pytest.approx(correlation, rel=1e-9)
    assert gain["slope"][0] == pytest.approx(0.1) and gain["correlation"][0] == pytest.approx(1.0)
    assert estimate_gain({"metrics": {"train/desired_velocity": [[1.0]]}}) is None  # no sensing, or an older file
