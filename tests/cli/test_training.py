"""`train` and `sweep`: names, counts, protocol fields and parameters checked in one line before compiling."""

import json

import pytest

from mjx_badger.cli import training
from mjx_badger.cli.main import parse
from mjx_badger.learning.config import TrainConfig
from mjx_badger.realtime.config import RealtimeConfig
from tests.commands import refused


def test_unknown_approach_names_the_choices(capsys):
    err = refused(capsys, ["train", "--approach", "jt-xyz"])
    assert "unknown approach 'jt-xyz'; choose from" in err and "jt-nf" in err and "jt-lpf" in err and "jt-oef" in err


def test_unknown_algorithm_and_task(capsys):
    assert "crossq" in refused(capsys, ["train", "--algo", "ppo"])
    assert "forward" in refused(capsys, ["train", "--task", "backflip"])


@pytest.mark.parametrize("flag, value, says", [("--seeds", "0", "--seeds must be a positive number"),
                                               ("--steps", "-5", "total_steps must be a positive number"),
                                               ("--seeds", "two", "Error parsing --seeds")])
def test_non_positive_counts(capsys, flag, value, says):
    assert says in refused(capsys, ["train", flag, value])


def test_warmup_longer_than_run(capsys):
    assert "warm-up (2000 steps) must be shorter" in refused(capsys, ["train", "--steps", "1500", "--warmup-steps", "2000"])
    assert "chunk_steps (1000) must not exceed" in refused(capsys, ["train", "--steps", "500", "--warmup-steps", "100"])


def test_unwritable_output(capsys, tmp_path):
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    assert "not writable" in refused(capsys, ["train", "--out", str(blocker / "sub")])


def test_bad_protocol_names_and_fields_exit_2(capsys):
    for command in ("train", "reproduce", "figures", "claims"):
        err = refused(capsys, [command, "--protocol", "thesis-paper"])
        assert "'thesis-paper'" in err and "thesis-code" in err and "thesis-text" in err
    err = refused(capsys, ["train", "--set", "no_such_field=1"])
    assert "unknown protocol field(s) ['no_such_field']" in err and "episode_seconds" in err
    assert "expected NAME=VALUE, got 'action_delay'" in refused(capsys, ["train", "--set", "action_delay"])
    assert "Unrecognized options: trian" in refused(capsys, ["trian"])


def test_the_cpg_on_another_robot_exits_2(capsys):
    assert "hb40-v1" in refused(capsys, ["train", "--robot", "hb40-v2"])
    err = refused(capsys, ["train", "--robot", "hb40-v1", "--approach", "cpg-vf"])
    assert "runs on the hb40 only" in err


def test_train_takes_approach_algorithm_and_task_parameters_and_names_bad_ones(capsys):
    config = parse(["train", "--approach", "jt-lpf", "--approach-param", "cutoff_hz=2.0", "--algo-param",
                    "learning_rate=0.001", "--task-param", "target_velocity=0.3", "--set", "action_delay=False",
                    "--set", "jt_pd_gains=[60,3]"]).run
    assert config.protocol_changes == (("action_delay", False), ("jt_pd_gains", (60, 3)))
    assert config.protocol_spec.jt_pd_gains == (60, 3) and config.protocol_spec.action_delay is False
    assert config.approach_params == (("cutoff_hz", 2.0),) and config.agent_config.learning_rate == 0.001
    assert config.task_params == (("target_velocity", 0.3),)
    err = refused(capsys, ["train", "--approach", "jt-lpf", "--approach-param", "cutof=1", "--steps", "2000"])
    assert "approach 'jt-lpf' takes cutoff_hz, not cutof" in err


def test_the_train_defaults_are_the_specs_own():
    assert parse(["train"]).run == TrainConfig() and parse(["realtime"]).run == RealtimeConfig()
    assert parse(["train", "--steps", "2000"]).run.total_steps == 2000


def test_a_sweeps_axes_come_from_its_grid_file_and_options_and_a_word_is_refused(tmp_path):
    grid = tmp_path / "grid.json"
    grid.write_text('{"algo_params.learning_rate": [0.001, 0.0003]}')
    command = training.Sweep(vary=("approach_params.min_cutoff=0.5,2.0",), grid=grid, out=tmp_path)
    assert command.axes() == (("algo_params.learning_rate", (0.001, 0.0003)), ("approach_params.min_cutoff", (0.5, 2.0)))
    with pytest.raises(ValueError, match="sweep values of approach_params.min_cutoff must be numbers, not 'fast'"):
        training.Sweep(vary=("approach_params.min_cutoff=fast",), out=tmp_path).axes()


def test_a_sweep_on_several_processes_makes_each_group_of_vmapped_members_a_run_of_its_own(tmp_path, monkeypatch):
    for name in ("XLA_PYTHON_CLIENT_PREALLOCATE", "MJX_BADGER_PREALLOCATE_BEFORE"):  # the waiting process's
        monkeypatch.delenv(name, raising=False)
    launched = []
    monkeypatch.setattr("mjx_badger.cli.common.Launch.run", lambda self, jobs, shared: launched.extend(jobs))
    command = parse(["sweep", "--approach", "jt-nf", "--vary", "algo_params.learning_rate=0.001,0.002,0.003,0.004",
                     "--vmapped", "2", "--runs-per-device", "2", "--out", str(tmp_path)])
    assert command() == 0
    assert [job.name for job in launched] == ["members 0-1", "members 2-3"]
    assert [job.args[-2] for job in launched] == [(0, 1), (2, 3)]  # each job trains its own members
    assert [job.args[-1] for job in launched] == ["", ""]  # and returns at once where they landed
    assert all(job.args[5] is False and job.args[6] is True for job in launched)  # no bar; resumes when requeued
    # The waiting process reads a group's progress from its first member's file, which the group saves each chunk.
    assert launched[1].progress() == ""  # nothing saved yet
    first = tmp_path / "jt-nf_crossq_forward_learning_rate=0.003.json"
    first.write_text(json.dumps({"steps": [1000, 2000], "wall_clock": {"run_s": 100.0}}))
    total = launched[1].progress.args[1]
    assert launched[1].progress() == f"2,000 of {total:,} steps (20.0 steps/s, ~{(total - 2000) / 20 / 60:.0f} min left)"
    assert launched[0].progress() == ""  # the other group's own file
