"""The progress bar of a run and the seed means beside it."""

import json

import numpy as np

from mjx_badger.learning import progress
from mjx_badger.learning.config import TrainConfig


def test_the_figures_are_seed_means_with_the_frozen_seeds_left_out():
    metrics = {"train/desired_velocity": np.array([0.2, 0.4, np.nan]), "eval/desired_velocity": np.array([0.5, 0.7, np.nan]),
               "train/falls": np.array([1.0, 3.0, np.nan]), "train/blowups": np.array([0.0, 0.0, 0.0])}
    assert progress.progress_figures(metrics) == {"v": "0.30", "eval_v": "0.60", "falls": "2.00"}
    omni = dict(metrics, **{"eval/forward_full/desired_velocity": np.zeros(3), "eval/desired_mae": np.array([0.1, 0.3, 0.2]),
                            "curriculum/learned_bins": np.array([2.0, 4.0, 6.0]), "train/blowups": np.array([0, 1, 0.0])})
    assert progress.progress_figures(omni) == {"v": "0.30", "eval_mae": "0.20", "bins": "4.00", "falls": "2.00",
                                               "blowups": "0.33"}


def test_the_bar_counts_steps_from_the_chunk_a_run_resumes_at(monkeypatch, capsys):
    config = TrainConfig(total_steps=5000, chunk_steps=1000, warmup_steps=100)
    bar = progress.progress_bar(config, first_chunk=2, seeds=3, shown=True)
    assert bar.total == 5000 and bar.n == 2000 and bar.desc == "jt-oef crossq forward x3" and not bar.disable
    bar.close()
    assert "jt-oef crossq forward x3:  40%" in capsys.readouterr().err
    hidden = progress.progress_bar(config, first_chunk=0, seeds=3, shown=False)
    assert hidden.disable
    hidden.close()
    monkeypatch.setenv("CI", "true")
    assert progress.progress_wanted() is False  # pytest's stderr is not a terminal
    monkeypatch.delenv("CI")
    assert progress.progress_wanted() is True


def test_a_runs_progress_is_read_from_what_it_saved(tmp_path):
    path = tmp_path / "run.json"
    assert progress.run_progress(path, 20_000) == ""  # nothing saved yet: nothing to say
    path.write_text(json.dumps({"steps": [1000, 2000, 4000], "wall_clock": {"run_s": 100.0}, "complete": False}))
    # 4,000 steps in 100 s: 40 steps/s, 16,000 left in 400 s
    assert progress.run_progress(path, 20_000) == "4,000 of 20,000 steps (40.0 steps/s, ~7 min left)"
    path.write_text(json.dumps({"steps": [20_000], "wall_clock": {"run_s": 500.0}, "complete": False}))
    assert progress.run_progress(path, 20_000) == "20,000 of 20,000 steps (40.0 steps/s), finishing"
    path.write_text(json.dumps({"steps": [20_000], "wall_clock": {"run_s": 100.0}, "complete": True}))
    assert progress.run_progress(path, 20_000) == ""  # complete: its landing is said instead
    path.write_text('{"steps": [10')  # caught mid-write
    assert progress.run_progress(path, 20_000) == ""


def test_time_left_reads_in_minutes_under_an_hour_and_hours_above():
    assert progress.time_left(59 * 60) == "~59 min left"
    assert progress.time_left(5400) == "~1.5 h left"
