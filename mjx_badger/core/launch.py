"""Where a list of runs trains: here one after another, here several at once as processes sharing the device, or
as the tasks of one SLURM job array (submitit), each task resuming from its checkpoint when it is requeued.

A job is a picklable `Job(name, function, args)`; `function(*args)` trains one run (or one group of sweep
members) into its results files and resumes from its checkpoint when called again. A run that already landed is
skipped by the caller's planning (`reproduce` run again), so a job list is always what is still missing.
"""

import concurrent.futures
import dataclasses
import multiprocessing
import os
import shutil
import time
from pathlib import Path
from typing import Callable, Optional

from mjx_badger.core import stops
from mjx_badger.core.cache import enable_compilation_cache

EVERY_CHUNK = "MJX_BADGER_CHECKPOINT_EVERY_CHUNK"
"""Set in a cluster job: its runs checkpoint after every chunk, so a preempted job loses at most one chunk."""
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

    def __call__(self):
        return self.function(*self.args)


@dataclasses.dataclass(frozen=True)
class Slurm:
    """A SLURM job array's resources: one array task per `runs_per_device` runs, one device each."""

    partition: Optional[str] = None
    gpus: int = 0
    cpus: int = 2
    mem_gb: int = 16
    time_min: int = 240
    account: Optional[str] = None
    qos: Optional[str] = None
    folder: Optional[Path] = None
    """Where submitit keeps the jobs' pickles and logs (default: <results>/slurm)."""
    requeues: int = 3
    """How many times a task that reaches its time limit is requeued to resume from its checkpoint."""


def run(jobs: list[Job], runs_per_device: int = 1, slurm: Optional[Slurm] = None, shared: Optional[Path] = None,
        log: Callable[[str], None] = lambda line: print(line, flush=True)) -> None:
    """Run every job: here (one after another, or `runs_per_device` at a time) or, with `slurm`, as one array.

    `shared` is a folder every process sees (the results folder): the compile cache lives there so that a
    program compiles once for all the jobs, and submitit's files under it. Raises Failed naming the jobs that
    failed, after the others have finished.
    """
    if not jobs:
        return
    if slurm is not None:
        return submit(jobs, runs_per_device, slurm, shared, log)
    if runs_per_device == 1:
        for job in jobs:
            job()
        return
    failed = in_processes(jobs, runs_per_device, shared, log)
    if stops.requested():  # Ctrl-C reached every run's process: each saved its chunk
        raise stops.Interrupted(stops.requested(), f"stopped by {stops.name(stops.requested())}: every run saved "
                                "its last chunk; run the same command again to go on")
    if failed:
        raise Failed(f"{len(failed)} of {len(jobs)} runs failed: " + "; ".join(failed))


def in_processes(jobs: list[Job], runs_per_device: int, shared: Optional[Path], log) -> list[str]:
    """The jobs `runs_per_device` at a time, each in a fresh process with its share of the device's memory;
    returns 'name: error' of those that failed."""
    context = multiprocessing.get_context("spawn")  # a fresh JAX per run: a forked one would share its device state
    fraction = f"{MEMORY_SHARE / runs_per_device:.3f}"
    failed, started = [], time.perf_counter()
    with concurrent.futures.ProcessPoolExecutor(runs_per_device, mp_context=context, max_tasks_per_child=1,
                                                initializer=_child, initargs=(fraction, shared)) as pool:
        running = {pool.submit(job): job for job in jobs}
        for done, future in enumerate(concurrent.futures.as_completed(running), 1):
            job, error = running[future], future.exception()
            if error is not None:
                failed.append(f"{job.name}: {type(error).__name__}: {error}")
            minutes = (time.perf_counter() - started) / 60
            log(f"{done} of {len(jobs)} runs landed ({job.name}{' FAILED' if error else ''}), {minutes:.1f} min")
    return failed


def _child(fraction: str, shared: Optional[Path]) -> None:
    """A run's process: its share of the device's memory, the shared compile cache, no signal of its parent's."""
    os.environ["XLA_PYTHON_CLIENT_MEM_FRACTION"] = fraction
    if shared is not None:
        enable_compilation_cache(cache_folder(shared))


def cache_folder(shared: Path) -> Path:
    """The compile cache every job shares, so that a program compiles once for them all: MJX_BADGER_CACHE where set,
    else beside the results (a folder every node of a cluster sees)."""
    return Path(os.environ.get("MJX_BADGER_CACHE") or Path(shared) / ".jax-cache")


class Task:
    """What one array task runs: its jobs, `runs_per_device` at a time; requeued by submitit, it resumes them."""

    def __init__(self, jobs: list[Job], runs_per_device: int, shared: Optional[Path]):
        self.jobs, self.runs_per_device, self.shared = jobs, runs_per_device, shared

    def __call__(self) -> list[str]:
        os.environ[EVERY_CHUNK] = "1"
        if self.shared is not None:
            enable_compilation_cache(cache_folder(self.shared))
        # submitit's own handlers answer SIGTERM and USR2 (checkpoint, requeue, exit): the runs leave them be.
        with stops.left_to_caller():
            failed = in_processes(self.jobs, self.runs_per_device, self.shared, print) \
                if self.runs_per_device > 1 else [_one(job) for job in self.jobs]
        failed = [f for f in failed if f]
        if failed:
            raise RuntimeError("; ".join(failed))
        return [job.name for job in self.jobs]

    def checkpoint(self):
        """On preemption or time-out: run this task again; each run resumes from its last chunk's checkpoint."""
        import submitit

        return submitit.helpers.DelayedSubmission(self)


def _one(job: Job) -> str:
    job()
    return ""


def submit(jobs: list[Job], runs_per_device: int, slurm: Slurm, shared: Optional[Path], log) -> None:
    """The jobs as one SLURM array (`runs_per_device` runs per task), waited for; Failed naming the failures."""
    import submitit

    folder = slurm.folder or Path(shared or ".") / "slurm"
    executor = submitit.AutoExecutor(folder=folder / "%j", cluster="slurm", slurm_max_num_timeout=slurm.requeues)
    executor.update_parameters(
        timeout_min=slurm.time_min, cpus_per_task=slurm.cpus, mem_gb=slurm.mem_gb, tasks_per_node=1, nodes=1,
        name="mjx_badger",
        **({"gpus_per_node": slurm.gpus} if slurm.gpus else {}),
        **{f"slurm_{key}": value for key, value in (("partition", slurm.partition), ("account", slurm.account),
                                                      ("qos", slurm.qos)) if value is not None})
    groups = [jobs[i:i + runs_per_device] for i in range(0, len(jobs), runs_per_device)]
    with executor.batch():
        submitted = [executor.submit(Task(group, runs_per_device, shared)) for group in groups]
    log(f"submitted {len(submitted)} SLURM array tasks ({len(jobs)} runs, {runs_per_device} per device) as job "
        f"{submitted[0].job_id.split('_')[0]}; logs in {folder}")
    wait(submitted, groups, log)


def wait(submitted: list, groups: list, log, poll_s: float = 5.0) -> None:
    """Wait for every task, saying each that lands; Failed naming the failed ones once all have ended."""
    started, pending, failed = time.perf_counter(), dict(zip(submitted, groups)), []
    while pending:
        for job in [job for job in pending if job.done()]:
            group = pending.pop(job)
            names = ", ".join(j.name for j in group)
            try:
                job.result()
                state = "landed"
            except Exception as error:  # a task's failure is reported with the others', not raised alone
                failed.append(f"task {job.job_id} ({names}): {str(error).strip().splitlines()[-1][:300]}")
                state = "FAILED"
            minutes = (time.perf_counter() - started) / 60
            log(f"{len(submitted) - len(pending)} of {len(submitted)} tasks ended: {job.job_id} {state} ({names}), "
                f"{minutes:.1f} min")
        if pending:
            time.sleep(poll_s)
    if failed:
        raise Failed(f"{len(failed)} of {len(submitted)} SLURM tasks failed (logs beside their pickles): "
                           + "; ".join(failed))


def slurm_available() -> str | None:
    """None when SLURM's `sbatch` can be called here, else why not."""
    return None if shutil.which("sbatch") else "SLURM's sbatch is not on PATH"

