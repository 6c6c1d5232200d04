"""`reproduce`: complete runs are skipped or reused, the rest run, with an ETA once a run has ended."""

import pytest

from mjx_badger.cli import main as cli
from mjx_badger.experiments.registry import EXPERIMENTS
from mjx_badger.learning import checkpoints, programs
from mjx_badger.pipelines import reproduce
from mjx_badger.pipelines.reproduce import overall_progress, same_run
from mjx_badger.records import policy, results


def test_a_run_shared_by_two_experiments_is_found_and_reused(tmp_path):
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
    monkeypatch.setattr("mjx_badger.outputs.plots.draw", lambda *args, **kwargs: [])
    monkeypatch.setattr("mjx_badger.outputs.videos.draw", lambda *args, **kwargs: [])
    monkeypatch.setattr("mjx_badger.scoring.claims.score", lambda *args: [])


def test_reproduce_skips_only_complete_results_of_the_same_configuration(tmp_path, monkeypatch, capsys, no_figures):
    experiment = EXPERIMENTS["forward"]
    ran = []

    def fake_run(config, seeds, path, **kwargs):
        ran.append(path.name)
        return {"wall_clock": {"run_s": 0.0}}

    monkeypatch.setattr("mjx_badger.learning.runner.run", fake_run)
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

    monkeypatch.setattr("mjx_badger.learning.runner.run", lambda config, seeds, path, **kwargs: {"wall_clock": {"run_s": 0.0}})
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


def test_reproduce_reports_overall_progress_with_an_eta_once_a_run_has_ended():
    assert overall_progress(0, 4, 0, 100, None) == "run 1 of 4, 0 % of the gradient updates done"
    assert overall_progress(1, 4, 25, 100, 5400.0).endswith("25 % of the gradient updates done, ~1.5 h left")
    assert overall_progress(3, 4, 90, 100, 750.0).endswith("~12 min left")


def test_the_full_profile_estimate_is_measured_once_per_algorithm_and_evaluation_size(monkeypatch):
    timed = []

    def fake_measure(config, seeds, evaluation=False):
        timed.append((config.algo, config.task, len(seeds), evaluation))
        rate = 100.0 if config.algo == "crossq" else 10.0
        return {"seed_steps_per_s": rate / 2 if config.task.startswith("omni") else rate, "compile_s": 60.0}

    monkeypatch.setattr(programs, "measure_speed", fake_measure)
    todo = [(EXPERIMENTS[name], run, None) for name in ("algo-comparison", "forward-max", "omni-random")
            for run in EXPERIMENTS[name].runs]
    line = reproduce.measured_estimate(todo, cli.Reproduce(profile="full"), seeds=10)
    # One chunk per algorithm and evaluation size (forward-max shares forward's one command), with evaluation.
    assert sorted(timed) == sorted([(algo, "forward", 10, True) for algo in ("sac", "sac-utd20", "droq", "crossq")]
                                   + [("crossq", "omni-random", 10, True)])
    assert "crossq forward 100 seed-steps/s" in line and "crossq omni-random 50 seed-steps/s" in line
    expected_s = sum(experiment.steps(run, "full") * 10 / fake_measure(experiment.train_config(run, "full"), [])
                     ["seed_steps_per_s"] + 60.0 for experiment, run, _ in todo)
    assert f"about {expected_s / 3600:.1f} h for these {len(todo)} runs" in line
    assert reproduce.measured_estimate(todo[:1], cli.Reproduce(profile="full"), seeds=10).endswith(" h for this run")
