"""Results files: older schemas read into today's, and the wall time a folder's runs cost."""

import json

import numpy as np

from mjx_badger.records import results
from tests.documents import simulation_document, write_run


def test_results_of_the_older_evaluation_schema_are_read_into_todays():
    one = {"schema": results.SCHEMA, "metrics": {"eval/forward_velocity": [[0.1, 0.3]], "eval/return": [[1.0, 2.0]]}}
    two = {"schema": results.SCHEMA, "metrics": {"eval/forward_full/desired_velocity": [[0.4, None]],
                                                 "eval/backward_full/desired_velocity": [[0.2, 0.5]]}}
    upgraded = [results.upgrade(json.loads(json.dumps(d)))["metrics"] for d in (one, two)]
    assert upgraded[0]["eval/desired_velocity"] == [[0.1, 0.3]] and "eval/forward_velocity" not in upgraded[0]
    np.testing.assert_allclose(np.array(upgraded[1]["eval/desired_velocity"][0][:1]), [0.3])
    assert upgraded[1]["eval/desired_velocity"][0][1] is None  # a missing run leaves the mean undefined


def test_schema_1_would_be_falls_are_read_without_its_blowups():
    """Schema 1 counted a blow-up as a would-be fall: 5 would-be with 4 blow-ups is 1 rule firing."""
    old = {"schema": "mjx_badger.results/1",
           "metrics": {"train/would_falls": [[0, 2], [5, 3]], "train/blowups": [[0, 1], [4, 1]]}}
    upgraded = results.upgrade(json.loads(json.dumps(old)))
    assert upgraded["metrics"]["train/would_falls"] == [[0, 1], [1, 2]] and upgraded["schema"] == results.SCHEMA
    today = {"schema": results.SCHEMA, "metrics": {"train/would_falls": [[5]], "train/blowups": [[4]]}}
    assert results.upgrade(today)["metrics"]["train/would_falls"] == [[5]]


def test_wall_time_passes_over_the_checkpoints_of_a_running_run(tmp_path):
    folder = tmp_path / "quick" / "thesis-code"
    document = dict(simulation_document(0.5, 1.0), wall_clock={"compile_s": 60.0, "run_s": 3540.0})
    write_run(folder, "forward", "jt-nf", document)
    stamp = folder / "forward" / "jt-oef_crossq_forward.ckpt" / "run.json"
    stamp.parent.mkdir(parents=True)
    stamp.write_text('{"config": {}, "seeds": [0]}')
    assert results.wall_time_words(folder) == "1 run in 1.00 h (compile 1.0 min of it)"
    # The simulation claims' wall time leaves the real-world runs out, and theirs the simulation's.
    real = dict(simulation_document(0.5, 1.0), wall_clock={"compile_s": 0.0, "run_s": 1800.0})
    results.write(folder / "real-office" / "jt-oef_crossq_forward.json", real)
    assert results.wall_time_words(folder) == "2 runs in 1.50 h (compile 1.0 min of it)"
    assert results.wall_time_words(folder, ("forward", "omni-pdec")) == "1 run in 1.00 h (compile 1.0 min of it)"
    assert results.wall_time_words(folder, ("real-office",)) == "1 run in 0.50 h (compile 0.0 min of it)"
    # A run reproduce copied for a second experiment costs nothing of its own.
    results.write(folder / "algo-comparison" / "jt-nf_crossq_forward.json", document)
    assert results.wall_time_words(folder, ("forward", "algo-comparison")) == (
        "1 run in 1.00 h (compile 1.0 min of it; 1 more a copy of one of them)")


def test_a_thesis_agents_settings_read_as_before_the_newer_agents_and_a_newer_ones_name_theirs():
    from mjx_badger.agents.config import ADDED_LATER
    from mjx_badger.learning.config import TrainConfig

    crossq = results.config_dict(TrainConfig(algo="crossq"))["agent"]
    assert not set(ADDED_LATER) & set(crossq) and crossq["batch_renorm"] is True
    bro = results.config_dict(TrainConfig(algo="bro"))["agent"]
    assert (bro["trunk"], bro["critic_output"], bro["optimism"], bro["resets"]) == ("bro", "quantile", True, (15_000,))
    assert "joint_pass" not in bro  # at its default
