"""Runs here one after another, several at once in processes of their own, or as SLURM array tasks (submitit)."""

import os
import signal
from pathlib import Path

import pytest

from mjx_badger.core import launch, stops


def record(folder: str, name: str) -> str:
    """A job: what its process saw, written to <folder>/<name>."""
    seen = f"{os.getpid()} {os.environ.get('XLA_PYTHON_CLIENT_MEM_FRACTION')} {os.environ.get(launch.EVERY_CHUNK)}"
    Path(folder, name).write_text(seen)
    return name


def fail(message: str) -> None:
    raise ValueError(message)


def test_runs_here_go_one_after_another_in_this_process(tmp_path):
    jobs = [launch.Job(name, record, (str(tmp_path), name)) for name in ("a", "b")]
    launch.run(jobs)
    seen = {name: (tmp_path / name).read_text().split() for name in ("a", "b")}
    assert seen["a"][0] == seen["b"][0] == str(os.getpid())


def test_several_runs_per_device_each_get_a_process_and_their_share_of_its_memory(tmp_path):
    jobs = [launch.Job(name, record, (str(tmp_path), name)) for name in ("a", "b", "c")]
    lines = []
    launch.run(jobs, runs_per_device=2, log=lines.append)
    pids = {(tmp_path / name).read_text().split()[0] for name in ("a", "b", "c")}
    assert len(pids) == 3 and str(os.getpid()) not in pids  # a fresh process per run
    assert {(tmp_path / name).read_text().split()[1] for name in "abc"} == {f"{launch.MEMORY_SHARE / 2:.3f}"}
    assert [line.split(" (")[0] for line in lines] == [f"{k} of 3 runs landed" for k in (1, 2, 3)]


def test_a_failed_run_is_named_after_the_others_have_finished(tmp_path):
    jobs = [launch.Job("bad", fail, ("the reason",)), launch.Job("good", record, (str(tmp_path), "good"))]
    with pytest.raises(launch.Failed, match="1 of 2 runs failed: bad: ValueError: the reason"):
        launch.run(jobs, runs_per_device=2, log=lambda line: None)
    assert (tmp_path / "good").is_file()


def test_an_array_task_checkpoints_every_chunk_leaves_signals_to_submitit_and_requeues_itself(tmp_path):
    submitit = pytest.importorskip("submitit")
    previous = signal.signal(signal.SIGTERM, signal.SIG_IGN)  # stands in for submitit's handler
    try:
        def inside(folder):
            with stops.graceful():  # a run's own handlers, which a task must not install
                assert signal.getsignal(signal.SIGTERM) == signal.SIG_IGN
            return record(folder, "task")

        task = launch.Task([launch.Job("one", inside, (str(tmp_path),))], 1, None)
        assert task() == ["one"]
    finally:
        signal.signal(signal.SIGTERM, previous)
        os.environ.pop(launch.EVERY_CHUNK, None)
    assert (tmp_path / "task").read_text().split()[2] == "1"
    again = task.checkpoint()
    assert isinstance(again, submitit.helpers.DelayedSubmission) and again.function is task


def test_the_compile_cache_is_the_users_or_beside_the_results(tmp_path, monkeypatch):
    monkeypatch.delenv("MJX_BADGER_CACHE", raising=False)
    assert launch.cache_folder(tmp_path) == tmp_path / ".jax-cache"
    monkeypatch.setenv("MJX_BADGER_CACHE", str(tmp_path / "mine"))
    assert launch.cache_folder(tmp_path) == tmp_path / "mine"


def test_slurm_is_named_when_sbatch_is_missing(monkeypatch):
    monkeypatch.setenv("PATH", "/nonexistent")
    assert launch.slurm_available() == "SLURM's sbatch is not on PATH"
