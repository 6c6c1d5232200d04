"""Nothing lost, nothing crashes (issue 35): bad input refused in one line before anything runs, references never
clobbered, damaged files named, one writer per output, memory checked before compiling. Nothing here compiles."""

import errno
import os
import shutil
import signal
from pathlib import Path

import pytest

from mjx_badger.cli.main import main
from mjx_badger.core import safe_io, stops
from mjx_badger.learning import memory
from mjx_badger.scoring import claims
from tests import conftest
from tests.commands import refused

REPO = Path(__file__).resolve().parents[2]
REFERENCE = REPO / "figures" / "data" / "quick" / "thesis-code"
WALKER = str(REFERENCE / "forward" / "jt-oef_crossq_forward.json")  # a committed result with its policy


def _tree(folder: Path) -> dict:
    return {str(p.relative_to(folder)): p.stat().st_mtime_ns for p in folder.rglob("*")}


# The three defects of the issue.

def test_reproduce_with_an_empty_experiment_list_is_refused_and_writes_nothing(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    scoreboard = (REPO / "figures" / "claims_quick.md").read_bytes()
    refused(capsys, ["reproduce", "--profile", "quick", "--experiments"], "--experiments needs at least one name",
             "forward")
    refused(capsys, ["reproduce", "--experiments", "forward", "forward"], "names an experiment twice")
    assert _tree(tmp_path) == {} and (REPO / "figures" / "claims_quick.md").read_bytes() == scoreboard


def test_train_with_more_steps_than_the_step_counters_hold_is_refused(capsys):
    refused(capsys, ["train", "--steps", "99999999999999999999"], "total_steps must be an integer in 1..2147483647",
             "int32 step counters")
    # DroQ's 20 updates per step leave a twentieth of the range.
    refused(capsys, ["train", "--algo", "droq", "--steps", "200000000"], "1..107374182")
    refused(capsys, ["train", "--steps", "2000000000", "--chunk-steps", "1999999999"], "chunk_steps (1999999999) "
             "rounds the run up")


# Bad input of every kind: one line naming the field and what it takes.

@pytest.mark.parametrize("argv, says", [
    (["train", "--gait-seconds", "nan"], "gait_seconds must be a finite number in (0, 60]"),
    (["train", "--eval-steps", "1000000000"], "eval_steps must be an integer in 1..100000"),
    (["train", "--seeds", "3", "--first-seed", "2147483647"], "--first-seed must be an integer in 0..2147483645"),
    (["train", "--set", "action_delay=maybe"], "protocol field action_delay must be True or False"),
    (["train", "--set", "rewards=thesis-paper"], "protocol field rewards takes thesis-code, thesis-text"),
    (["train", "--set", "episode_seconds=inf"], "protocol field episode_seconds must be a finite number"),
    (["train", "--algo-param", "learning_rate=1e999"], "algorithm parameter learning_rate must be a finite number"),
    (["train", "--algo-param", "hidden=[256,0]"], "algorithm parameter hidden entry must be an integer in 1.."),
    (["train", "--algo-param", "batch_size=2.5"], "algorithm parameter batch_size must be an integer"),
    (["train", "--approach", "jt-lpf", "--approach-param", "cutoff_hz=nan"], "approach parameter cutoff_hz"),
    (["train", "--task-param", "target_velocity=fast"], "task parameter target_velocity must be a finite number"),
    (["train", "--coordinator", "localhost", "--num-processes", "2", "--process-id", "0"], "HOST:PORT"),
    (["sweep", "--vary", "algo_params.learning_rate=0.001,1e999"], "learning_rate must be a finite number"),
    (["realtime", "--target-velocity", "nan"], "target_velocity must be a finite number in [-5, 5]"),
    (["realtime", "--seed", "-1"], "seed must be an integer in 0..2147483647"),
    (["realtime", "--reset-seconds", "inf"], "--reset-seconds must be a finite number"),
    (["evaluate", "x.json", "--seconds", "nan"], "--seconds must be a finite number in (0, 3600]"),
    (["render", "x.json", "--seconds", "600"], "--seconds must be a finite number in (0, 60]"),
    (["evaluate", WALKER, "--command", "0.5,0,inf"],
     "--command YAW must be a finite number"),
    (["evaluate", WALKER, "--conditions", "moon"],
     "--conditions 'moon': choose from sim, office, outdoor"),
    (["attribute", "--only"], "--only needs at least one swap"),
    (["claims", "--json", "/proc/version/board.json"], "is a file, not a folder"),
    (["claims", "--json", "b.json", "--markdown", "b.json"], "--json and --markdown name the same file"),
    (["publish", "--results-dir", str(REPO / "figures" / "data")], "--to names the reference folder"),
    (["train", "--coordinator", "localhost:70000", "--num-processes", "2", "--process-id", "0"], "port in 1..65535"),
    (["train", "--coordinator", "localhost:1234"], "--coordinator needs --num-processes and --process-id"),
    (["train", "--coordinator", "localhost:1234", "--num-processes", "2", "--process-id", "2"], "--process-id must be in 0..1"),
    (["sweep", "--vary", "algo_params.learning_rate=0.1,0.2", "--vary", "algo_params.learning_rate=0.3,0.4"],
     "a field is swept twice"),
    (["sweep", "--grid", "/nonexistent/grid.json"], "cannot read the grid file"),
    (["claims", "--budgets", "quick", "quick"], "--budgets names a profile twice"),
    (["evaluate", "nothere.json"], "no results file 'nothere.json'"),
    (["evaluate", WALKER, "--command", "1,2"], "three numbers"),
    (["evaluate", WALKER, "--command", "20,0,0"],
     "--command VX must be a finite number in [-10, 10]"),
    (["evaluate", WALKER, "--seed", "0"], "holds seeds [1], not 0"),
    (["estimator", "collect", "--out", "x.txt"], "must end in .npz"),
    (["estimator", "collect", "--steps", "100"], "at least 500 per env"),
    (["estimator", "collect", "--action-noise", "3"], "--action-noise 3.0: choose within 0..2"),
    (["estimator", "fit", "--dataset", "none.npz"], "no dataset 'none.npz'"),
    (["estimator", "fit", "--epochs", "0"], "--epochs must be a positive number"),
    (["train", "--set", "jt_pd_gains=5"], "protocol field jt_pd_gains must be a non-empty list"),
    (["train", "--set", "lowpass=foo"], "protocol field lowpass takes butterworth, first-order"),
    (["train", "--algo-param", "batch_size=0"], "algorithm parameter batch_size must be an integer in 1.."),
    (["train", "--seeds", "2000000"], "--seeds must be an integer in 1..1000000"),
    (["train", "--gait-seconds", "61"], "gait_seconds must be a finite number in (0, 60]"),
    (["realtime", "--reset-seconds", "-1"], "--reset-seconds must be a finite number in [0, 3600], not -1.0"),
])
def test_bad_values_are_refused_in_one_line_naming_the_field(capsys, argv, says):
    refused(capsys, argv, says)


def test_an_unwritable_output_is_refused_and_the_check_creates_nothing(capsys, tmp_path):
    (tmp_path / "file").write_text("")
    refused(capsys, ["train", "--out", str(tmp_path / "file" / "sub")], "not writable")
    refused(capsys, ["reproduce", "--results-dir", str(tmp_path / "new"), "--figures-dir", str(tmp_path / "file")],
             "is a file, not a folder")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["file"]  # the results folder was not created


# Memory, checked before anything compiles.

def test_a_run_that_cannot_fit_is_refused_with_the_estimate_before_compiling(capsys, monkeypatch, tmp_path):
    monkeypatch.setattr(memory, "available", lambda: (8 * memory.GIB, 16 * memory.GIB, "memory"))
    compiles = len(conftest.COMPILES)
    err = refused(capsys, ["train", "--seeds", "1000", "--steps", "50000", "--out", str(tmp_path / "out")],
                   "the run does not fit", "1000 seeds x 26.2 MiB carry", "8.0 GiB memory available of 16.0 GiB")
    assert float(err.split("~")[1].split(" GiB")[0]) > 50  # 1000 x 26 MiB, twice, and the process
    # Building the env's shapes dispatches a few eager conversions (milliseconds each); a training program's
    # chunk compiles for 30-60 s.
    compiled = [(program, s) for _, phase, program, s in conftest.COMPILES[compiles:] if phase == "xla_compile_s"]
    assert sum(s for _, s in compiled) < 1.0 and not any("chunk" in program for program, _ in compiled), compiled
    assert not (tmp_path / "out").exists()
    refused(capsys, ["sweep", "--seeds", "200", "--vary", "algo_params.learning_rate=0.001,0.002", "--out",
                      str(tmp_path / "out")], "the run does not fit", "2 members x 200 seeds")
    refused(capsys, ["realtime", "--steps", "2000000000"], "the run does not fit", "2000000000 steps of replay")


def test_dry_run_prints_the_plan_and_its_memory_and_trains_nothing(capsys, tmp_path):
    assert main(["train", "--seeds", "10", "--dry-run", "--out", str(tmp_path / "out")]) == 0
    out = capsys.readouterr().out
    assert "would train jt-oef_crossq_forward" in out and "10 seeds x 50000 steps in 50 chunks" in out
    assert "memory: ~" in out and "10 seeds x 26.2 MiB carry, 23.3 MiB of it replay" in out and "available of" in out
    assert not (tmp_path / "out").exists()
    assert main(["sweep", "--vary", "algo_params.learning_rate=0.001,0.003", "--dry-run", "--out",
                 str(tmp_path / "sweep")]) == 0
    assert "2 members x 3 seeds" in capsys.readouterr().out and not (tmp_path / "sweep").exists()


# One writer per output; a killed holder leaves no stuck lock.


# Damaged files are named and skipped (figures, claims) or refused (evaluate, render); the tests of resuming
# from one are in test_faults.py.

@pytest.fixture
def damaged_forward(tmp_path):
    """The committed quick forward results copied, one of them cut short and one policy cut short."""
    folder = tmp_path / "results" / "quick" / "thesis-code" / "forward"
    shutil.copytree(REFERENCE / "forward", folder)
    cut = folder / "jt-nf_crossq_forward.json"
    cut.write_text(cut.read_text()[:5000])
    policy = folder / "cpg-d_crossq_forward.policy.npz"
    policy.write_bytes(policy.read_bytes()[:3000])
    return folder


def test_figures_and_claims_skip_a_damaged_results_file_naming_it(capsys, damaged_forward, tmp_path):
    results_dir = tmp_path / "results"
    assert main(["claims", "--results-dir", str(results_dir), "--protocol", "thesis-code"]) == 0
    captured = capsys.readouterr()
    assert f"skipping {damaged_forward / 'jt-nf_crossq_forward.json'} cannot be read" in captured.err
    assert "Traceback" not in captured.err and "thesis-code protocol, quick profile" in captured.out
    assert main(["figures", "--results-dir", str(results_dir)]) == 0
    captured = capsys.readouterr()
    assert "skipping" in captured.err and "jt-nf_crossq_forward.json" in captured.err
    assert (results_dir / "figures" / "thesis-code" / "forward_quick.png").exists()  # under the results folder


# References are never clobbered: a run draws under its results folder, and a partial redraw keeps what it cannot redraw.

def _fake_reproduce(monkeypatch, ran=None):
    def fake_run(config, seeds, path, **kwargs):
        (ran if ran is not None else []).append(path.name)
        return {"wall_clock": {"run_s": 0.0}}

    monkeypatch.setattr("mjx_badger.learning.runner.run", fake_run)
    monkeypatch.setattr("mjx_badger.outputs.videos.draw", lambda *args, **kwargs: [])


def test_a_partial_reproduce_draws_under_its_results_and_keeps_the_verdicts_it_cannot_redraw(tmp_path, monkeypatch,
                                                                                           capsys):
    monkeypatch.chdir(tmp_path)
    _fake_reproduce(monkeypatch)
    board = tmp_path / "results" / "figures" / "claims_quick.md"
    board.parent.mkdir(parents=True)
    shutil.copy(REPO / "figures" / "claims_quick.md", board)
    shutil.copy(REPO / "figures" / "claims_quick.json", board.with_suffix(".json"))  # its verdicts as data
    before = board.read_text()
    assert main(["reproduce", "--experiments", "forward"]) == 0
    out = capsys.readouterr().out
    rows = lambda text: [line for line in text.splitlines() if line.startswith("| ")]
    assert rows(board.read_text()) == rows(before)  # no results here: every verdict kept, totals the same
    kept = [line for line in out.splitlines() if line.startswith("kept ")]
    assert len(kept) == 2 * len(claims.CLAIMS) - before.count("not run yet") and "no results for it under" in kept[0]
    assert [p.name for p in tmp_path.iterdir()] == ["results"]  # nothing written outside the run's results folder


def test_a_full_disk_while_drawing_keeps_the_figure_before(tmp_path, monkeypatch, capsys):
    results_dir = tmp_path / "results"
    shutil.copytree(REFERENCE / "forward", results_dir / "quick" / "thesis-code" / "forward")
    figure = results_dir / "figures" / "thesis-code" / "forward_quick.png"
    figure.parent.mkdir(parents=True)
    figure.write_bytes(b"before")
    real = safe_io._put

    def full(tmp, data):
        if tmp.name.startswith(".forward_quick.png."):  # as a full disk does: part of it written, then the error
            real(tmp, data[:10])
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(tmp))
        real(tmp, data)

    monkeypatch.setattr(safe_io, "_put", full)
    assert main(["figures", "--results-dir", str(results_dir)]) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "error: No space left on device writing" in err, err
    assert figure.read_bytes() == b"before" and not list(figure.parent.glob(".*.tmp"))


# SIGTERM and Ctrl-C in reproduce: the run at hand saves itself (test_faults.py); between runs it stops there.

def test_reproduce_stops_between_runs_on_sigterm_and_draws_nothing(tmp_path, monkeypatch, capsys):
    ran = []

    def run_then_signal(config, seeds, path, **kwargs):
        ran.append(path.name)
        os.kill(os.getpid(), signal.SIGTERM)
        return {"wall_clock": {"run_s": 0.0}}

    monkeypatch.setattr("mjx_badger.learning.runner.run", run_then_signal)
    assert main(["reproduce", "--profile", "smoke", "--experiments", "forward", "--results-dir",
                 str(tmp_path)]) == 128 + signal.SIGTERM
    err = capsys.readouterr().err
    assert len(ran) == 1 and "stopped by SIGTERM before run 2 of 6" in err and "run the same command again" in err
    assert not (tmp_path / "figures").exists()
    assert signal.getsignal(signal.SIGTERM) == signal.SIG_DFL  # the handlers are given back


def test_a_run_stopped_by_a_signal_ends_reproduce_with_its_line(tmp_path, monkeypatch, capsys):
    def stopped(config, seeds, path, **kwargs):
        raise stops.Interrupted(signal.SIGINT, f"stopped by SIGINT at step 100 of 300: results in {path}")

    monkeypatch.setattr("mjx_badger.learning.runner.run", stopped)
    assert main(["reproduce", "--profile", "smoke", "--experiments", "forward", "--results-dir",
                 str(tmp_path)]) == 130
    assert "stopped by SIGINT at step 100 of 300" in capsys.readouterr().err
