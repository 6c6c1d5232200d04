"""A SLURM array task: checkpoints every chunk, leaves signals to submitit, requeues itself; the waiting names a
failed task by its error and a task lost without a result; a stop ends the waiting, not the tasks."""

import os
import signal
from types import SimpleNamespace

import pytest

from mjx_badger.core import launch, slurm, stops
from tests.core.test_launch import record


def test_an_array_task_checkpoints_every_chunk_leaves_signals_to_submitit_and_requeues_itself(tmp_path):
    submitit = pytest.importorskip("submitit")
    previous = signal.signal(signal.SIGTERM, signal.SIG_IGN)  # stands in for submitit's handler
    try:
        def inside(folder):
            with stops.graceful():  # a run's own handlers, which a task must not install
                assert signal.getsignal(signal.SIGTERM) == signal.SIG_IGN
            return record(folder, "task")

        task = slurm.Task([launch.Job("one", inside, (str(tmp_path),))], 1, None)
        assert task() == ["one"]
    finally:
        signal.signal(signal.SIGTERM, previous)
        os.environ.pop(launch.EVERY_CHUNK, None)
    assert (tmp_path / "task").read_text().split()[2] == "1"
    again = task.checkpoint()
    assert isinstance(again, submitit.helpers.DelayedSubmission) and again.function is task


class FakeJob:
    """A submitted task as submitit shows it: done or not, its result or its error."""

    def __init__(self, job_id, done=True, error=None):
        self.job_id, self._done, self._error = job_id, done, error
        self.paths = SimpleNamespace(stderr=f"/logs/{job_id}_0_log.err")

    def done(self):
        return self._done

    def result(self):
        if self._error:
            raise self._error
        return ["ran"]


TRACE = ("Job (task=0) failed during processing with trace:\n----------------------\nTraceback (most recent call "
         "last):\n  File \"x.py\", line 1\nValueError: the run's own reason\n\n----------------------\nYou can check "
         "full logs with 'job.stderr(0)' and 'job.stdout(0)'or at paths:\n  - /logs/err\n  - /logs/out")


def test_the_waiting_names_a_failed_tasks_error_and_a_lost_task_after_the_others_have_ended(monkeypatch):
    monkeypatch.setattr(slurm, "queued", lambda job_id: False)
    monkeypatch.setattr(slurm, "LOST_AFTER_S", -1.0)
    jobs = [FakeJob("7_0"), FakeJob("7_1", error=RuntimeError(TRACE)), FakeJob("7_2", done=False)]
    groups = [[launch.Job(name, print, ())] for name in ("a", "b", "c")]
    lines = []
    with pytest.raises(launch.Failed) as failed:
        slurm.wait(jobs, groups, lines.append, "7", poll_s=0.0)
    assert "2 of 3 SLURM tasks failed" in str(failed.value)
    assert "task 7_1: ValueError: the run's own reason" in str(failed.value)
    assert "task 7_2: ended without a result" in str(failed.value) and "/logs/7_2_0_log.err" in str(failed.value)
    assert [line.split(": ")[1].split(" (")[0] for line in lines] == ["7_0 landed", "7_1 FAILED", "7_2 LOST"]


def test_a_stop_ends_the_waiting_and_says_how_to_stop_the_tasks(monkeypatch):
    monkeypatch.setattr(stops, "requested", lambda: signal.SIGINT)
    with pytest.raises(stops.Interrupted, match="the 1 tasks not yet ended go on \\(scancel 7 stops them\\)"):
        slurm.wait([FakeJob("7_0", done=False)], [[launch.Job("a", print, ())]], print, "7", poll_s=0.0)


def test_slurm_is_named_when_sbatch_is_missing(monkeypatch):
    monkeypatch.setenv("PATH", "/nonexistent")
    assert slurm.available() == "SLURM's sbatch is not on PATH"
