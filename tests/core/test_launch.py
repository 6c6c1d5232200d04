"""Runs here one after another, several at once in processes of their own, or as SLURM array tasks (submitit)."""

import functools
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
    assert [line.split(":")[0] for line in lines] == [f"{k} of 3 runs ended" for k in (1, 2, 3)]
    assert all(" landed, " in line for line in lines)


def slow_record(folder: str, name: str) -> str:
    import time
    time.sleep(1.5)
    return record(folder, name)


def test_the_waiting_process_says_how_far_the_runs_at_hand_have_come(tmp_path, monkeypatch):
    monkeypatch.setattr(launch, "PROGRESS_EVERY_S", 0.0)  # every pass of the wait
    jobs = [launch.Job("a", slow_record, (str(tmp_path), "a"), functools.partial(str, "3 of 5 steps")),
            launch.Job("b", slow_record, (str(tmp_path), "b"), functools.partial(str, ""))]
    lines = []
    launch.run(jobs, runs_per_device=2, log=lines.append)
    assert "  a: 3 of 5 steps" in lines
    assert not any(line.startswith("  b") for line in lines)  # nothing to say, no line


def die(code: int) -> None:
    os._exit(code)


def stopped(signum: int) -> None:
    raise stops.Interrupted(signum, "stopped after saving")


def test_a_run_stopped_by_a_signal_is_said_to_have_stopped_not_failed(tmp_path):
    lines = []
    jobs = [launch.Job("asked", stopped, (signal.SIGINT,)), launch.Job("good", record, (str(tmp_path), "good"))]
    with pytest.raises(launch.Failed, match="asked: stopped by a signal"):  # it did not land: the command says so
        launch.run(jobs, runs_per_device=2, log=lines.append)
    said = {line.split(" runs ended: ")[1].rsplit(", ", 1)[0] for line in lines}
    assert said == {"asked stopped, resumes from its last save", "good landed"}


def test_failed_and_dead_runs_are_named_after_the_others_have_ended(tmp_path):
    jobs = [launch.Job("bad", fail, ("the reason",)), launch.Job("dead", die, (3,)),
            launch.Job("good", record, (str(tmp_path), "good"))]
    with pytest.raises(launch.Failed) as failed:
        launch.run(jobs, runs_per_device=2, log=lambda line: None)
    assert "2 of 3 runs failed" in str(failed.value) and "bad: ValueError: the reason" in str(failed.value)
    assert "dead: its process ended with exit code 3 and no word" in str(failed.value)
    assert (tmp_path / "good").is_file()  # a run that died took no other with it


def test_a_stop_passes_on_to_the_runs_at_hand_and_starts_no_more(tmp_path, monkeypatch):
    monkeypatch.setattr(stops, "requested", lambda: signal.SIGTERM)
    jobs = [launch.Job(name, record, (str(tmp_path), name)) for name in ("a", "b", "c")]
    with pytest.raises(stops.Interrupted, match="the others did not start"):
        launch.run(jobs, runs_per_device=2, log=lambda line: None)
    assert not list(tmp_path.iterdir())  # asked to stop before any started


def test_the_process_that_waits_spares_the_devices_memory_and_the_runs_get_it_back(monkeypatch):
    monkeypatch.setenv(launch.PREALLOCATE, "true")
    monkeypatch.delenv(launch._BEFORE, raising=False)
    launch.spare_device()
    assert os.environ[launch.PREALLOCATE] == "false"
    launch.restore_device_memory()
    assert os.environ[launch.PREALLOCATE] == "true" and launch._BEFORE not in os.environ


def test_the_compile_cache_is_the_users_or_beside_the_results(tmp_path, monkeypatch):
    monkeypatch.delenv("MJX_BADGER_CACHE", raising=False)
    assert launch.cache_folder(tmp_path) == tmp_path / ".jax-cache"
    monkeypatch.setenv("MJX_BADGER_CACHE", str(tmp_path / "mine"))
    assert launch.cache_folder(tmp_path) == tmp_path / "mine"
