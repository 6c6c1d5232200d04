"""Where a list of runs trains here: one after another, or several at once as processes sharing the device
(slurm.py sends them to a SLURM cluster instead).

A job is a picklable `Job(name, function, args, progress)`; `function(*args)` trains one run (or one group of sweep
members) into its results files, resumes from its checkpoint when called again, and returns at once where its
results already landed (so that a requeued cluster task does not train again what it had finished). Its
`progress()`, read by the waiting process every PROGRESS_EVERY_S, says how far it has come from what it saved.
"""

import dataclasses
import multiprocessing
import multiprocessing.connection
import os
import signal
import time
from pathlib import Path
from typing import Callable, Optional

from mjx_badger.core import stops
from mjx_badger.core.cache import enable_compilation_cache

EVERY_CHUNK = "MJX_BADGER_CHECKPOINT_EVERY_CHUNK"
"""Set in a cluster job: its runs checkpoint after every chunk, so a preempted job loses at most one chunk."""
PROGRESS_EVERY_S = 120.0
"""How often the waiting process says how far the runs at hand have come (their bars would interleave)."""
MEMORY_SHARE = 0.9
"""Of a GPU's memory, the part the runs on it share (XLA_PYTHON_CLIENT_MEM_FRACTION each: MEMORY_SHARE / N)."""


class Failed(Exception):
    """Runs that failed in their own processes or cluster tasks, each named with its error."""


@dataclasses.dataclass(frozen=True)
class Job:
    """One unit of work: `function(*args)` trains `name` into its results files."""

    name: str
    function: Callable
    args: tuple
    progress: Optional[Callable[[], str]] = None
    """How far it has come, read from what it saved (None: it cannot say)."""

    def __call__(self):
        return self.function(*self.args)


STOPPED = "stopped by a signal"
"""How a run's process reports that a signal stopped it after its last save."""


def run(jobs: list[Job], runs_per_device: int = 1, shared: Optional[Path] = None,
        log: Callable[[str], None] = lambda line: print(line, flush=True)) -> None:
    """Run every job here: one after another in this process, or `runs_per_device` at a time in processes of their
    own (`shared`, the results folder, holds their compile cache). Raises Failed naming the jobs that failed, after
    the others have ended; stops.Interrupted after a Ctrl-C, once the runs at hand have saved.
    """
    if not jobs:
        return
    if runs_per_device == 1:
        for job in jobs:
            job()
        return
    failed = in_processes(jobs, runs_per_device, shared, log)
    if stops.requested():  # passed on to the runs at hand: each saved its chunk
        raise stops.Interrupted(stops.requested(), f"stopped by {stops.name(stops.requested())}: the runs at hand "
                                "saved their last chunk, the others did not start; run the same command again to go on")
    if failed:
        raise Failed(f"{len(failed)} of {len(jobs)} runs failed: " + "; ".join(failed))


def in_processes(jobs: list[Job], runs_per_device: int, shared: Optional[Path], log, in_task: bool = False) -> list:
    """The jobs `runs_per_device` at a time, each in a fresh process with its share of the device's memory;
    returns 'name: error' of those that failed (a process that died without a word included).

    Each process has a process group of its own, so that a Ctrl-C reaches this one, which passes the stop on once
    to the runs at hand (each saves its chunk) and starts no more. In a SLURM task (`in_task`) the processes leave
    SIGTERM and USR2 to the task's own handler, which requeues it.
    """
    context = multiprocessing.get_context("spawn")  # a fresh JAX per run: a forked one would share its device state
    fraction = f"{MEMORY_SHARE / runs_per_device:.3f}"
    outcomes = context.SimpleQueue()
    waiting, running, reported, failed = list(enumerate(jobs)), {}, {}, []
    passed_on, started = False, time.perf_counter()
    said = started
    try:
        while waiting or running:
            while waiting and len(running) < runs_per_device and not stops.requested():
                index, job = waiting.pop(0)
                process = context.Process(target=_child, args=(job, index, fraction, shared, in_task, outcomes))
                process.start()
                running[index] = (job, process)
            if not running:
                break
            multiprocessing.connection.wait([process.sentinel for _, process in running.values()], timeout=1.0)
            if stops.requested() and not passed_on:
                passed_on = True
                for _, process in running.values():
                    os.kill(process.pid, stops.requested())
            for index in [i for i, (_, process) in running.items() if not process.is_alive()]:
                job, process = running.pop(index)
                process.join()
                while not outcomes.empty():
                    reported.update([outcomes.get()])
                error = reported.get(index, f"its process ended with exit code {process.exitcode} and no word")
                if error:
                    failed.append(f"{job.name}: {error}")
                minutes = (time.perf_counter() - started) / 60
                outcome = "stopped, resumes from its last save" if error.startswith(STOPPED) else \
                    "FAILED" if error else "landed"
                log(f"{len(jobs) - len(waiting) - len(running)} of {len(jobs)} runs ended: {job.name} "
                    f"{outcome}, {minutes:.1f} min")
            if time.perf_counter() - said >= PROGRESS_EVERY_S:
                said = time.perf_counter()
                say_progress([job for job, _ in running.values()], log)
    finally:  # this process stops at once (a second Ctrl-C, an error): its runs with it, each from its last save
        for _, process in running.values():
            process.terminate()
    return failed


def say_progress(jobs: list, log) -> None:
    """A line for each job that has something to say of how far it has come."""
    for job in jobs:
        said = job.progress() if job.progress is not None else ""
        if said:
            log(f"  {job.name}: {said}")


def _child(job: Job, index: int, fraction: str, shared: Optional[Path], in_task: bool, outcomes) -> None:
    """A run's process: its share of the device's memory, the shared compile cache; its outcome, '' or the error."""
    os.setpgrp()
    os.environ["XLA_PYTHON_CLIENT_MEM_FRACTION"] = fraction
    restore_device_memory()
    if shared is not None:
        enable_compilation_cache(cache_folder(shared))
    if in_task:
        signal.signal(signal.SIGTERM, signal.SIG_IGN)
        signal.signal(signal.SIGUSR2, signal.SIG_IGN)
        stops.leave_all_to_caller()
    try:
        job()
        error = ""
    except stops.Interrupted as stop:  # asked to stop (the Ctrl-C passed on): it saved, it did not fail
        error = f"{STOPPED}: {stop}"
    except BaseException as failure:  # reported, not raised: the parent names it beside the others
        error = f"{type(failure).__name__}: {failure}"
    outcomes.put((index, error))


PREALLOCATE = "XLA_PYTHON_CLIENT_PREALLOCATE"
_BEFORE = "MJX_BADGER_PREALLOCATE_BEFORE"


def spare_device() -> None:
    """In the process that only plans and waits: JAX takes device memory as it needs it, not 75 % of a GPU up
    front, so that the runs' processes have theirs; they get the setting back (`restore_device_memory`)."""
    os.environ.setdefault(_BEFORE, os.environ.get(PREALLOCATE, ""))
    os.environ[PREALLOCATE] = "false"


def restore_device_memory() -> None:
    """A run's process: JAX's memory setting as it was before `spare_device`."""
    if _BEFORE in os.environ:
        before = os.environ.pop(_BEFORE)
        if before:
            os.environ[PREALLOCATE] = before
        else:
            os.environ.pop(PREALLOCATE, None)


def cache_folder(shared: Path) -> Path:
    """The compile cache every job shares, so that a program compiles once for them all: MJX_BADGER_CACHE where set,
    else beside the results (a folder every node of a cluster sees)."""
    return Path(os.environ.get("MJX_BADGER_CACHE") or Path(shared) / ".jax-cache")
