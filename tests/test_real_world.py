"""The real-world tables and claims (real_world.py) follow from the numbers in the results files."""

import json

import numpy as np
import pytest

from mjx_badger import claims, plots, real_world, results
from mjx_badger.experiments import EXPERIMENTS, result_name
from mjx_badger.realtime.report import SCHEMA as LOOP_SCHEMA

CHUNKS = 20


def _document(velocity, falls, estimated=0.05, yaw_rate=0.0, conditions="office"):
    """A real-world results document of 2 seeds: final evaluation at `velocity` (true) and `estimated`, `falls`
    safety stops in all, heading turning at `yaw_rate` rad/s over a 10 s evaluation at 40 Hz."""
    per_chunk = lambda value: [[value, value] for _ in range(CHUNKS)]
    return {"schema": results.SCHEMA, "seeds": [0, 1], "complete": True,
            "config": {"eval_steps": 400, "env": {"control_hz": 40.0}, "conditions": conditions,
                       "condition_changes": [], "protocol": "thesis-code"},
            "steps": [1000 * (i + 1) for i in range(CHUNKS)], "sim_minutes": [0.4167 * (i + 1) for i in range(CHUNKS)],
            "metrics": {"eval/desired_velocity": per_chunk(velocity), "eval/estimated_desired_velocity": per_chunk(estimated),
                        "eval/yaw_rate": per_chunk(yaw_rate),
                        "train/falls_total": [[falls * (i + 1) / CHUNKS] * 2 for i in range(CHUNKS)]}}


def _write(folder, experiment, label, document):
    run = next(r for r in EXPERIMENTS[experiment].runs if EXPERIMENTS[experiment].label(r) == label)
    results.write(folder / experiment / result_name(run), document)


@pytest.mark.parametrize("degrees, category", [(5, "very good"), (10, "good"), (29.9, "good"), (45, "medium"),
                                               (61, "poor")])
def test_heading_drift_falls_in_the_thesis_categories(degrees, category):
    document = _document(0.3, 0.0, yaw_rate=np.radians(degrees) / 10.0)
    row = real_world.summary(document)
    assert row["yaw_drift_deg"] == pytest.approx(degrees) and row["yaw"] == category


def test_minutes_count_each_fall_at_the_conditions_reset_time():
    row = real_world.summary(_document(0.3, falls=30.0))
    # 20k steps at 40 Hz are 8.33 simulated minutes; each of 30 falls adds the office's 20 s reset.
    assert row["minutes"] == pytest.approx(20 * 0.4167 + 30 * 20 / 60)
    assert row["falls"] == 30.0 and row["estimated_velocity"] == pytest.approx(0.05)


def test_the_real_world_claims_follow_the_numbers(tmp_path):
    folder = tmp_path / "quick" / "thesis-code"
    for label, velocity, falls in (("jt-oef", 0.85, 10), ("jt-lpf", 0.4, 12), ("cpg-d", 0.3, 0), ("cpg-vf", 0.3, 0),
                                   ("jt-nf", 0.5, 150), ("cpg-rt", 0.2, 120)):
        _write(folder, "real-office", label, _document(velocity, falls))
    for label, velocity, falls, yaw in (("jt-oef", 0.25, 20, 20), ("jt-lpf", 0.23, 25, 20), ("cpg-d", 0.3, 39, 5),
                                        ("cpg-vf", 0.02, 81, 90), ("jt-nf", 0.2, 130, 40), ("cpg-rt", 0.1, 40, 40)):
        _write(folder, "real-outdoor", label, _document(velocity, falls, yaw_rate=np.radians(yaw) / 10.0,
                                                        conditions="outdoor"))
    board = {v.claim.id: v for v in claims.score(tmp_path / "quick", "thesis-code", real_world.real_claims())}
    assert all(v.holds is True for v in board.values()), {k: v.ours for k, v in board.items()}
    assert "office: JT-NF 150, CPG-RT 120" in board["real-excluded-fall"].ours
    assert "CPG-VF 0.02 m/s, 81 falls, yaw poor" in board["real-outdoor-cpg"].ours

    # CPG-RT below 100 falls in the office: the reason for leaving it out does not hold.
    _write(folder, "real-office", "cpg-rt", _document(0.2, 60))
    # A policy that believes its speed: no faster than 1.5 x its estimate.
    _write(folder, "real-office", "jt-oef", _document(0.85, 10, estimated=0.8))
    board = {v.claim.id: v for v in claims.score(tmp_path / "quick", "thesis-code", real_world.real_claims())}
    assert board["real-excluded-fall"].holds is False and board["real-faster-than-believed"].holds is False
    # Standing still and believing it stands stiller is no finding.
    _write(folder, "real-office", "jt-oef", _document(0.04, 10, estimated=0.006))
    board = {v.claim.id: v for v in claims.score(tmp_path / "quick", "thesis-code", real_world.real_claims())}
    assert board["real-faster-than-believed"].holds is False


def test_the_loop_table_puts_the_loop_beside_the_vmapped_runs(tmp_path):
    loop = {"schema": LOOP_SCHEMA, "steps": 20000, "complete": True, "falls": 12, "train_minutes": 8.4,
            "updates_per_learning_step": 0.97, "evaluation": {"true_velocity": 0.31, "estimated_velocity": 0.02, "seconds": 0.55,
                                                                   "fell": "pitch +0.87 rad"},
            "config": {"approach": "cpg-d", "conditions": "outdoor", "condition_changes": [], "protocol": "thesis-text"}}
    folder = tmp_path / "realtime" / "outdoor"
    folder.mkdir(parents=True)
    (folder / "cpg-d_crossq_forward.json").write_text(json.dumps(loop))
    loaded = plots.load_loop(folder)
    assert list(loaded) == ["cpg-d"]
    row = real_world.loop_summary(loaded["cpg-d"])
    assert row["minutes"] == pytest.approx(8.4 + 12 * 20 / 60)  # outdoor resets take 20 s each
    table = real_world.loop_table(loaded, {"cpg-d": _document(0.3, 39, conditions="outdoor")})
    assert "| CPG-D | 20,000, thesis-text | 12 | fell after 0.55 s | 0.31 | 0.02 | 12 | 0.97 | 2 x 20,000, thesis-code | 39 [39-39] | 0.30 |" in table
    assert "not run" in real_world.loop_table(loaded, {})
    (folder / "jt-oef_crossq_forward.json").write_text(json.dumps({"schema": "other"}))
    with pytest.raises(ValueError, match="not a mjx_badger.realtime/1 results file"):
        plots.load_loop(folder)
    assert plots.load_loop(tmp_path / "missing") == {}


def test_a_run_of_another_algorithm_is_named_algorithm_first():
    from mjx_badger.analysis import display_name

    assert display_name("jt-lpf sac-utd20") == "SAC-UTD20 JT-LPF"  # Table 5.3's first row, as the thesis names it
    assert display_name("jt-lpf") == "JT-LPF" and display_name("jt-lpf cutoff_hz=2") == "JT-LPF cutoff_hz=2"
