"""Bad input gets one clear line and exit code 2 before anything compiles; options come from the run specs."""

import dataclasses
import json
import os
import subprocess
import sys

import pytest

from mjx_badger.cli import main, parse
from mjx_badger.realtime.config import RealtimeConfig
from mjx_badger.train import TrainConfig


def _fails(capsys, argv):
    with pytest.raises(SystemExit) as exit_info:
        main(argv)
    assert exit_info.value.code == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and err.count("\n") == 1, f"not one line: {err!r}"
    return err


def test_unknown_approach_names_the_choices(capsys):
    err = _fails(capsys, ["train", "--approach", "jt-xyz"])
    assert "unknown approach 'jt-xyz'; choose from" in err and "jt-nf" in err and "jt-lpf" in err and "jt-oef" in err


def test_unknown_algorithm_and_task(capsys):
    assert "crossq" in _fails(capsys, ["train", "--algo", "ppo"])
    assert "forward" in _fails(capsys, ["train", "--task", "backflip"])


@pytest.mark.parametrize("flag, value, says", [("--seeds", "0", "--seeds must be a positive number"),
                                               ("--steps", "-5", "total_steps must be a positive number"),
                                               ("--seeds", "two", "Error parsing --seeds")])
def test_non_positive_counts(capsys, flag, value, says):
    assert says in _fails(capsys, ["train", flag, value])


def test_warmup_longer_than_run(capsys):
    assert "warm-up (2000 steps) must be shorter" in _fails(capsys, ["train", "--steps", "1500", "--warmup-steps", "2000"])
    assert "chunk_steps (1000) must not exceed" in _fails(capsys, ["train", "--steps", "500", "--warmup-steps", "100"])


def test_unwritable_output(capsys, tmp_path):
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    assert "not writable" in _fails(capsys, ["train", "--out", str(blocker / "sub")])


def test_exit_code_2_from_the_shell_before_any_compile():
    # JAX names every program it traces or compiles when JAX_LOG_COMPILES is set: none may appear.
    done = subprocess.run([sys.executable, "-m", "mjx_badger", "train", "--approach", "nope"],
                          capture_output=True, text=True, env=dict(os.environ, JAX_LOG_COMPILES="1"))
    assert done.returncode == 2
    assert "choose from" in done.stderr and "jt-oef" in done.stderr
    assert "Compiling" not in done.stderr and "Finished tracing" not in done.stderr, done.stderr[-2000:]
    assert done.stderr.count("\n") == 1  # the one line


def test_list_names_everything(capsys):
    assert main(["list"]) == 0
    out = capsys.readouterr().out
    assert "jt-oef" in out and "crossq" in out and "forward" in out and "quick" in out
    assert "thesis-code, thesis-text" in out and "termination" in out and "robots: hb40, hb40-v1" in out
    assert "robot adapters: simulated" in out


def test_bad_protocol_names_and_fields_exit_2(capsys):
    for command in ("train", "reproduce", "figures", "claims"):
        err = _fails(capsys, [command, "--protocol", "thesis-paper"])
        assert "'thesis-paper'" in err and "thesis-code" in err and "thesis-text" in err
    err = _fails(capsys, ["train", "--set", "no_such_field=1"])
    assert "unknown protocol field(s) ['no_such_field']" in err and "episode_seconds" in err
    assert "expected NAME=VALUE, got 'action_delay'" in _fails(capsys, ["train", "--set", "action_delay"])
    assert "Unrecognized options: trian" in _fails(capsys, ["trian"])


def test_the_cpg_on_another_robot_exits_2(capsys):
    assert "hb40-v1" in _fails(capsys, ["train", "--robot", "hb40-v2"])
    err = _fails(capsys, ["train", "--robot", "hb40-v1", "--approach", "cpg-vf"])
    assert "runs on the hb40 only" in err


def test_claims_without_results_prints_both_empty_scoreboards(capsys, tmp_path):
    assert main(["claims", "--results-dir", str(tmp_path), "--json", str(tmp_path / "board.json")]) == 0
    out = capsys.readouterr().out
    assert "thesis-code protocol, quick profile: 0 of 15 hold (0 checked)" in out
    assert "wall time: 0 runs in 0.00 h" in out
    assert "thesis-text protocol" in out and "thesis: CrossQ ~2 min, DroQ ~7 min" in out
    board = json.loads((tmp_path / "board.json").read_text())
    assert sorted(board) == ["thesis-code", "thesis-text"]
    assert all(len(claims) == 15 and all(c["holds"] is None for c in claims) for claims in board.values())


def test_a_run_shared_by_two_experiments_is_found_and_reused(tmp_path):
    from mjx_badger import results
    from mjx_badger.reproduce import same_run
    from mjx_badger.experiments import EXPERIMENTS

    config = EXPERIMENTS["forward"].train_config(EXPERIMENTS["forward"].runs[0], "smoke")
    path = tmp_path / "algo-comparison" / "jt-nf_crossq_forward.json"
    results.write(path, {"schema": results.SCHEMA, "config": results.config_dict(config), "seeds": [0, 1],
                         "complete": True})
    assert same_run(tmp_path, config, [0, 1]) == path
    assert same_run(tmp_path, config, [0, 1, 2]) is None
    assert same_run(tmp_path, EXPERIMENTS["forward"].train_config(EXPERIMENTS["forward"].runs[0], "quick"),
                     [0, 1]) is None


@pytest.fixture
def no_figures(monkeypatch):
    """reproduce's bookkeeping alone: no figures, videos or scoreboard drawn after the runs."""
    monkeypatch.setattr("mjx_badger.plots.draw", lambda *args, **kwargs: [])
    monkeypatch.setattr("mjx_badger.render.draw", lambda *args, **kwargs: [])
    monkeypatch.setattr("mjx_badger.claims.score", lambda *args: [])


def test_reproduce_skips_only_complete_results_of_the_same_configuration(tmp_path, monkeypatch, capsys, no_figures):
    from mjx_badger import cli, results
    from mjx_badger.experiments import EXPERIMENTS

    experiment = EXPERIMENTS["forward"]
    ran = []

    def fake_run(config, seeds, path, **kwargs):
        ran.append(path.name)
        return {"wall_clock": {"run_s": 0.0}}

    monkeypatch.setattr("mjx_badger.runner.run", fake_run)
    folder = tmp_path / "smoke" / "thesis-code" / "forward"
    for index, run in enumerate(experiment.runs):
        config = experiment.train_config(run, "smoke")
        if index == 1:  # same file name, different configuration: must rerun
            config = config.__class__(**{**config.__dict__, "eval_steps": config.eval_steps + 1})
        results.write(folder / f"{run.approach}_{run.algo}_{run.task}.json",
                      {"schema": results.SCHEMA, "config": results.config_dict(config), "seeds": [0, 1],
                       "complete": index != 2})
    assert cli.main(["reproduce", "--profile", "smoke", "--experiments", "forward",
                     "--results-dir", str(tmp_path), "--figures-dir", str(tmp_path / "fig")]) == 0
    assert ran == ["jt-lpf_crossq_forward.json", "jt-oef_crossq_forward.json"]
    progress = [line for line in capsys.readouterr().out.splitlines() if line.startswith("run ")]
    assert progress[0] == "run 1 of 2, 0 % of the gradient updates done"  # nothing measured yet: no ETA
    assert progress[1].startswith("run 2 of 2, 50 %") and progress[1].endswith("min left")


def test_a_reused_run_brings_its_policy_and_agents(tmp_path, monkeypatch, no_figures):
    """The algorithm comparison reuses the forward experiment's CrossQ JT-NF run: the copy is evaluated and
    published like its twin, so its saved policy and agents come with it."""
    from mjx_badger import checkpoints, cli, policy, results
    from mjx_badger.experiments import EXPERIMENTS

    monkeypatch.setattr("mjx_badger.runner.run", lambda config, seeds, path, **kwargs: {"wall_clock": {"run_s": 0.0}})
    forward = EXPERIMENTS["forward"]
    twin = tmp_path / "smoke" / "thesis-code" / "forward" / "jt-nf_crossq_forward.json"
    results.write(twin, {"schema": results.SCHEMA, "config": results.config_dict(forward.train_config(
        forward.runs[0], "smoke")), "seeds": [0, 1], "complete": True})
    policy.path_for(twin).write_bytes(b"the policy")
    checkpoints.agents_folder(twin).mkdir()
    (checkpoints.agents_folder(twin) / "0.npz").write_bytes(b"an agent")
    assert cli.main(["reproduce", "--profile", "smoke", "--experiments", "algo-comparison",
                     "--results-dir", str(tmp_path), "--figures-dir", str(tmp_path / "fig")]) == 0
    copy = tmp_path / "smoke" / "thesis-code" / "algo-comparison" / "jt-nf_crossq_forward.json"
    assert results.read(copy)["complete"]
    assert policy.path_for(copy).read_bytes() == b"the policy"
    assert (checkpoints.agents_folder(copy) / "0.npz").read_bytes() == b"an agent"


def test_realtime_refuses_what_a_robot_cannot_run(capsys):
    assert "cpg-rt-avg" in _fails(capsys, ["realtime", "--approach", "cpg-rt"])
    assert "unknown robot adapter 'hb50'; choose from simulated" in _fails(capsys, ["realtime", "--robot-adapter", "hb50"])
    assert "planned contacts" in _fails(capsys, ["realtime", "--approach", "jt-oef", "--planned-contacts"])
    assert "warmup_steps (200) must be smaller" in _fails(capsys, ["realtime", "--steps", "100", "--warmup-steps", "200"])
    assert "control rate" in _fails(capsys, ["realtime", "--control-hz", "500"])


def test_reproduce_reports_overall_progress_with_an_eta_once_a_run_has_ended():
    from mjx_badger.reproduce import overall_progress

    assert overall_progress(0, 4, 0, 100, None) == "run 1 of 4, 0 % of the gradient updates done"
    assert overall_progress(1, 4, 25, 100, 5400.0).endswith("25 % of the gradient updates done, ~1.5 h left")
    assert overall_progress(3, 4, 90, 100, 750.0).endswith("~12 min left")


def test_train_takes_approach_algorithm_and_task_parameters_and_names_bad_ones(capsys):
    config = parse(["train", "--approach", "jt-lpf", "--approach-param", "cutoff_hz=2.0", "--algo-param",
                    "learning_rate=0.001", "--task-param", "target_velocity=0.3", "--set", "action_delay=False",
                    "--set", "jt_pd_gains=[60,3]"]).run
    assert config.protocol_changes == (("action_delay", False), ("jt_pd_gains", (60, 3)))
    assert config.protocol_spec.jt_pd_gains == (60, 3) and config.protocol_spec.action_delay is False
    assert config.approach_params == (("cutoff_hz", 2.0),) and config.agent_config.learning_rate == 0.001
    assert config.task_params == (("target_velocity", 0.3),)
    err = _fails(capsys, ["train", "--approach", "jt-lpf", "--approach-param", "cutof=1", "--steps", "2000"])
    assert "approach 'jt-lpf' takes cutoff_hz, not cutof" in err


@pytest.mark.parametrize("command, spec", [("train", TrainConfig), ("realtime", RealtimeConfig)])
def test_every_run_spec_field_is_an_option_with_its_docstring_as_help(capsys, command, spec):
    with pytest.raises(SystemExit) as exit_info:
        main([command, "--help"])
    assert exit_info.value.code == 0
    help_text = " ".join(capsys.readouterr().out.replace("│", " ").split())
    hidden = {"env", "agent"}  # nested configs the protocol resolves; Python callers set them
    for field in dataclasses.fields(spec):
        if field.name not in hidden:
            assert f"--{field.name.replace('_', '-')}" in help_text, field.name
    assert "One-factor swaps of protocol fields" in help_text  # a RunSpec field's docstring, in both
    own = {"train": "Environment steps per seed", "realtime": "Control steps, warm-up included"}[command]
    assert own in help_text  # and one of the command's own fields


def test_the_train_defaults_are_the_specs_own():
    assert parse(["train"]).run == TrainConfig() and parse(["realtime"]).run == RealtimeConfig()
    assert parse(["train", "--steps", "2000"]).run.total_steps == 2000
