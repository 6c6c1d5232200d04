"""Faults during a real (tiny) training run: a full disk, SIGINT and SIGTERM; nothing is lost and the rerun resumes
to the numbers of the uninterrupted run. Every run here is the suite's tiny program, compiled once for the file."""

import errno
import json
import os
import signal
from pathlib import Path

import pytest

from mjx_badger.cli.main import main
from mjx_badger.core import faults, safe_io
from mjx_badger.core.stops import Interrupted
from mjx_badger.core.validation import Refused
from mjx_badger.learning import checkpoints
from mjx_badger.records import policy, results
from tests.conftest import TINY_TRAIN

TRAIN = ["train", "--approach", TINY_TRAIN.approach, "--task", TINY_TRAIN.task, "--steps", str(TINY_TRAIN.total_steps),
         "--chunk-steps", str(TINY_TRAIN.chunk_steps), "--warmup-steps", str(TINY_TRAIN.warmup_steps), "--eval-steps",
         str(TINY_TRAIN.eval_steps), "--seeds", "2", "--quiet", "--no-tensorboard"]
RESULT = f"{TINY_TRAIN.name}.json"
POLICY = policy.path_for(Path(RESULT)).name


@pytest.fixture(scope="module")
def whole(tmp_path_factory):
    """The uninterrupted run's results document."""
    out = tmp_path_factory.mktemp("whole")
    assert main([*TRAIN, "--out", str(out)]) == 0
    return results.read(out / RESULT)


def _without_clock(document: dict) -> dict:
    return {k: v for k, v in document.items() if k not in ("wall_clock", "hardware", "versions", "git_commit")}


def _on_write(monkeypatch, name: str, nth: int, action) -> None:
    """Call `action(target)` instead of (or before) the `nth` write (from 1) of the file `name` through safe_io."""
    real, seen = safe_io._put, [0]

    def put(tmp: Path, data: bytes) -> None:
        if tmp.name.startswith(f".{name}."):
            seen[0] += 1
            if seen[0] == nth:
                action(tmp)
        real(tmp, data)

    monkeypatch.setattr(safe_io, "_put", put)


def _full_disk(tmp: Path) -> None:
    raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(tmp))


def _one_line_error(capsys, says: str) -> str:
    err = capsys.readouterr().err
    lines = [line for line in err.splitlines() if line.startswith("error: ")]
    assert len(lines) == 1 and says in lines[0] and "Traceback" not in err, err
    return lines[0]


def _resumes_to_whole(capsys, out: Path, whole: dict, at_step: int) -> None:
    """The same command again resumes at `at_step` and ends with the uninterrupted run's numbers."""
    assert main([*TRAIN, "--out", str(out)]) == 0
    assert f"resuming {RESULT} at step {at_step}" in capsys.readouterr().err
    assert _without_clock(results.read(out / RESULT)) == _without_clock(whole)
    assert not checkpoints.folder(out / RESULT).exists() and (out / POLICY).exists()
    assert not list(out.glob(".*.tmp")), "a temporary file was left behind"


def test_a_full_disk_while_writing_results_keeps_the_last_results_and_checkpoint(tmp_path, whole, monkeypatch, capsys):
    _on_write(monkeypatch, RESULT, 2, _full_disk)  # the second chunk's results
    assert main([*TRAIN, "--out", str(tmp_path)]) == 1
    _one_line_error(capsys, "No space left on device")
    kept = results.read(tmp_path / RESULT)
    assert kept["steps"] == [TINY_TRAIN.chunk_steps] and not kept["complete"]
    assert (checkpoints.folder(tmp_path / RESULT) / "1").is_dir()
    monkeypatch.undo()
    _resumes_to_whole(capsys, tmp_path, whole, TINY_TRAIN.chunk_steps)


def test_a_full_disk_while_saving_a_checkpoint_keeps_the_one_before(tmp_path, whole, monkeypatch, capsys):
    monkeypatch.setattr(checkpoints, "interval", lambda *_: 1)  # a checkpoint after every chunk
    real, calls = checkpoints.Checkpoints.save, [0]

    def save(self, chunks_done, carry):
        calls[0] += 1
        if calls[0] == 2:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(self.path / str(chunks_done)))
        real(self, chunks_done, carry)

    monkeypatch.setattr(checkpoints.Checkpoints, "save", save)
    assert main([*TRAIN, "--out", str(tmp_path)]) == 1
    _one_line_error(capsys, "No space left on device")
    assert len(results.read(tmp_path / RESULT)["steps"]) == 2  # the results run ahead of the checkpoint
    monkeypatch.undo()
    _resumes_to_whole(capsys, tmp_path, whole, TINY_TRAIN.chunk_steps)


def test_a_full_disk_while_saving_the_policy_leaves_a_run_that_resumes(tmp_path, whole, monkeypatch, capsys):
    monkeypatch.setattr(checkpoints, "interval", lambda *_: 1)
    _on_write(monkeypatch, POLICY, 1, _full_disk)
    assert main([*TRAIN, "--out", str(tmp_path)]) == 1
    _one_line_error(capsys, "No space left on device")
    stopped = results.read(tmp_path / RESULT)
    assert not stopped["complete"] and len(stopped["steps"]) == TINY_TRAIN.num_chunks  # not complete without its policy
    assert not (tmp_path / POLICY).exists()
    monkeypatch.undo()
    _resumes_to_whole(capsys, tmp_path, whole, 2 * TINY_TRAIN.chunk_steps)


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
def test_a_signal_stops_after_the_chunk_at_hand_saved_and_the_rerun_resumes(tmp_path, whole, monkeypatch, capsys,
                                                                             signum):
    """Ctrl-C or SIGTERM while the first chunk's results are written: that chunk is saved, checkpoint included."""
    _on_write(monkeypatch, RESULT, 1, lambda _: os.kill(os.getpid(), signum))
    before = {s: signal.getsignal(s) for s in (signal.SIGINT, signal.SIGTERM)}  # SIG_IGN where started in background
    assert main([*TRAIN, "--out", str(tmp_path)]) == 128 + signum
    err = capsys.readouterr().err
    assert f"stopped by {signal.Signals(signum).name} at step {TINY_TRAIN.chunk_steps}" in err
    assert "run the same command again to resume" in err and "Traceback" not in err
    assert results.read(tmp_path / RESULT)["steps"] == [TINY_TRAIN.chunk_steps]
    assert (checkpoints.folder(tmp_path / RESULT) / "1").is_dir()
    assert {s: signal.getsignal(s) for s in before} == before  # the run's handlers are gone again
    monkeypatch.undo()
    _resumes_to_whole(capsys, tmp_path, whole, TINY_TRAIN.chunk_steps)


def test_a_damaged_results_file_is_named_and_resume_refuses_it_before_compiling(tmp_path, whole, capsys):
    path = tmp_path / RESULT
    text = json.dumps(whole)
    for damaged in (text[: len(text) // 2], json.dumps(dict(whole, seeds="0,1"))):
        path.write_text(damaged)
        assert main([*TRAIN, "--out", str(tmp_path)]) == 2
        line = _one_line_error(capsys, "cannot resume")
        assert str(path) in line and "--restart" in line
        assert path.read_text() == damaged  # refused: left as it was


@pytest.mark.slow  # a sweep program of its own: minutes of compile (`make test-slow`)
def test_a_sweep_stopped_by_sigterm_resumes_to_the_uninterrupted_sweep(tmp_path, monkeypatch, capsys):
    sweep = ["sweep", *TRAIN[1:], "--vary", "task_params.target_velocity=0.4,0.5"]
    members = [f"{TINY_TRAIN.name}_target_velocity={v}.json" for v in ("0.4", "0.5")]
    assert main([*sweep, "--out", str(tmp_path / "whole")]) == 0
    out = tmp_path / "stopped"
    _on_write(monkeypatch, members[1], 1, lambda _: os.kill(os.getpid(), signal.SIGTERM))
    assert main([*sweep, "--out", str(out)]) == 128 + signal.SIGTERM
    assert "stopped by SIGTERM at step 100" in capsys.readouterr().err
    assert all(results.read(out / name)["steps"] == [TINY_TRAIN.chunk_steps] for name in members)
    monkeypatch.undo()
    assert main([*sweep, "--out", str(out)]) == 0
    assert "resuming" in capsys.readouterr().err
    for name in members:
        assert _without_clock(results.read(out / name)) == _without_clock(results.read(tmp_path / "whole" / name))


def _raising(error):
    def command():
        raise error
    return command


def test_each_way_a_command_can_end_is_one_line_and_its_exit_status(capsys):
    assert faults.run(lambda: 0) == 0
    cases = ((Refused("results/x.json is being written by another run"), 2, "error: results/x.json is being written"),
             (Interrupted(15, "stopped by SIGTERM at step 2000"), 143, "stopped by SIGTERM at step 2000"),
             (KeyboardInterrupt(), 130, "interrupted; every file is whole"),
             (OSError(errno.ENOSPC, "No space left on device", "results/x.json"), 1,
              "error: No space left on device writing results/x.json; nothing is left half-written"))
    for error, code, says in cases:
        assert faults.run(_raising(error)) == code
        err = capsys.readouterr().err
        assert err.startswith(says) and err.count("\n") == 1, err
    assert faults.describe(OSError(errno.EACCES, "")) == "EACCES"
