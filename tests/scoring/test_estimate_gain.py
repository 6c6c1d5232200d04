"""The estimate-gain study: its runs along the family, and its gain and findings per value."""

import numpy as np

from mjx_badger.scoring import estimate_gain
from tests.commands import refused
from tests.documents import real_world_document, write_run


def test_the_study_plans_each_value_but_the_default_on_the_forward_real_world_runs(tmp_path):
    plan = list(estimate_gain.planned(tmp_path, "quick", "thesis-code"))
    assert len(plan) == 3 * (6 + 6)  # 0.25, 0.5, 1 x office (no SAC-UTD20) and outdoor
    assert all(config.condition_changes == (("kalman.contact_trust", value),) for value, config, _ in plan)
    assert not any(config.algo == "sac-utd20" for _, config, _ in plan)
    assert {path.parent.parent.name for _, _, path in plan} == {"contact-trust-0.25", "contact-trust-0.5",
                                                              "contact-trust-1"}
    assert estimate_gain.folder(tmp_path, "quick", "thesis-code", 0.0) == tmp_path / "quick" / "thesis-code"


def with_estimate(document: dict, ratio: float) -> dict:
    """`document` whose training estimate reads `ratio` x the truth exactly (slope `ratio`, correlation 1)."""
    chunks = len(document["steps"])
    true = np.full((chunks, 2), 0.3)  # constant speeds: no spread
    spread = np.tile([[0.01, 0.02]], (chunks, 1))  # variance of the truth, per seed
    document["metrics"].update({
        "train/desired_velocity": true.tolist(), "train/estimated_desired_velocity": (ratio * true).tolist(),
        "train/true_squared": (true ** 2 + spread).tolist(),
        "train/estimate_squared": (ratio ** 2 * (true ** 2 + spread)).tolist(),
        "train/true_times_estimate": (ratio * (true ** 2 + spread)).tolist()})
    return document


def test_each_value_is_scored_at_the_gain_its_runs_measured(tmp_path):
    where = estimate_gain.folder(tmp_path, "quick", "thesis-code", 0.5)
    write_run(where, "real-office", "jt-oef", with_estimate(real_world_document(0.3, falls=5.0), 0.5))
    row = estimate_gain.score(tmp_path, "quick", "thesis-code", (0.5,))[0]
    assert abs(row["gain"]["slope"] - 0.5) < 1e-9
    assert abs(row["gain"]["correlation"] - 1.0) < 1e-9
    assert abs(row["gain"]["walk_ratio"] - 0.05 / 0.3) < 1e-6  # at evaluation the walk is believed far less
    assert row["runs"]["real-office"]["jt-oef"]["velocity"] == 0.3
    assert row["findings"]["real-faster-than-believed"]["holds"] is True  # 0.3 true against 0.05 believed
    assert row["findings"]["real-office-speeds"]["holds"] is None  # the other runs are not there


def test_value_0_is_measured_over_the_runs_the_other_values_rerun(tmp_path):
    where = estimate_gain.folder(tmp_path, "quick", "thesis-code", 0.0)
    write_run(where, "real-office", "jt-oef", with_estimate(real_world_document(0.3, falls=5.0), 0.5))
    write_run(where, "real-office", "jt-lpf sac-utd20", with_estimate(real_world_document(0.3, falls=5.0), 1.0))
    write_run(where, "real-outdoor-omni", "jt-oef", with_estimate(real_world_document(0.3, falls=5.0), 1.0))
    row = estimate_gain.score(tmp_path, "quick", "thesis-code", (0.0,))[0]
    assert abs(row["gain"]["slope"] - 0.5) < 1e-9  # SAC-UTD20's and the omni run's slope of 1 left out
    assert row["gain"]["seeds"] == 2
    assert list(row["runs"]) == ["real-office"] and list(row["runs"]["real-office"]) == ["jt-oef"]


def test_the_walk_ratio_averages_the_walking_runs_own_estimated_over_true_speed():
    speeds = {"real-office": {"jt-oef": {"velocity": 0.4, "estimated_velocity": 0.1},
                              "cpg-d": {"velocity": 0.02, "estimated_velocity": 0.01}},  # standing: left out
              "real-outdoor": {"jt-oef": {"velocity": 0.2, "estimated_velocity": 0.01},
                               "cpg-vf": {"velocity": 0.3, "estimated_velocity": float("nan")}}}  # no estimate
    assert abs(estimate_gain.walk_ratio(speeds) - (0.25 + 0.05) / 2) < 1e-12
    assert estimate_gain.walk_ratio({"real-office": {"cpg-d": {"velocity": 0.0, "estimated_velocity": 0.0}}}) is None


def test_a_value_out_of_the_family_is_refused_before_anything_runs(tmp_path, capsys):
    refused(capsys, ["estimate-gain", "--values", "0", "1.5", "--results-dir", str(tmp_path)],
            "--values entry must be a finite number in [0, 1], not 1.5")
    assert not any(tmp_path.iterdir())
