"""A list of runs as one SLURM job array (submitit): each task trains its runs, checkpoints every chunk, and is
requeued at its time limit or when preempted, to resume from the checkpoints; the command waits for them all."""

import dataclasses
import os
import re
import shutil
import subprocess
import time
from pathlib import Path
from typing import Optional

from mjx_badger.core import launch, stops
from mjx_badger.core.cache import enable_compilation_cache

LOST_AFTER_S = 60.0
"""A task that has left SLURM's queue without a result for this long is reported as lost."""


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
    signal_delay_s: int = 600
    """How long before its time limit a task is told to requeue: the signal is acted on between chunks, and a
    full-profile chunk on a CPU takes minutes."""


class Task:
    """What one array task runs: its jobs, `runs_per_device` at a time; requeued by submitit, it resumes them."""

    def __init__(self, jobs: list, runs_per_device: int, shared: Optional[Path]):
        self.jobs, self.runs_per_device, self.shared = jobs, runs_per_device, shared

    def __call__(self) -> list[str]:
        os.environ[launch.EVERY_CHUNK] = "1"
        launch.restore_device_memory()
        if self.shared is not None:
            enable_compilation_cache(launch.cache_folder(self.shared))
        # submitit's own handlers answer SIGTERM and USR2 (checkpoint, requeue, exit): the runs leave them be.
        with stops.left_to_caller():
            if self.runs_per_device > 1:
                failed = launch.in_processes(self.jobs, self.runs_per_device, self.shared, print, in_task=True)
            else:
                failed = []
                for job in self.jobs:
                    job()
        if failed:
            raise RuntimeError("; ".join(failed))
        return [job.name for job in self.jobs]

    def checkpoint(self):
        """On preemption or time-out: run this task again; each run resumes from its last chunk's checkpoint, and
        one that had landed returns at once."""
        import submitit

        return submitit.helpers.DelayedSubmission(self)


def submit(jobs: list, runs_per_device: int, slurm: Slurm, shared: Optional[Path], log) -> None:
    """The jobs as one SLURM array (`runs_per_device` runs per task), waited for; launch.Failed naming failures."""
    import submitit

    folder = slurm.folder or Path(shared or ".") / "slurm"
    executor = submitit.AutoExecutor(folder=folder / "%j", cluster="slurm", slurm_max_num_timeout=slurm.requeues)
    executor.update_parameters(
        timeout_min=slurm.time_min, cpus_per_task=slurm.cpus, mem_gb=slurm.mem_gb, tasks_per_node=1, nodes=1,
        name="mjx_badger", slurm_signal_delay_s=slurm.signal_delay_s,
        **({"gpus_per_node": slurm.gpus} if slurm.gpus else {}),
        **{f"slurm_{key}": value for key, value in (("partition", slurm.partition), ("account", slurm.account),
                                                      ("qos", slurm.qos)) if value is not None})
    groups = [jobs[i:i + runs_per_device] for i in range(0, len(jobs), runs_per_device)]
    with executor.batch():
        submitted = [executor.submit(Task(group, runs_per_device, shared)) for group in groups]
    array = submitted[0].job_id.split("_")[0]
    log(f"submitted {len(submitted)} SLURM array tasks ({len(jobs)} runs, {runs_per_device} per device) as job "
        f"{array}; logs in {folder}")
    wait(submitted, groups, log, array)


def wait(submitted: list, groups: list, log, array: str, poll_s: float = 5.0) -> None:
    """Wait for every task, saying each that ends; launch.Failed naming the failed or lost ones once all have
    ended. A stop (Ctrl-C) ends the waiting, not the tasks."""
    started, pending, failed, gone = time.perf_counter(), dict(zip(submitted, groups)), [], {}
    said = started
    while pending:
        if stops.requested():
            raise stops.Interrupted(stops.requested(), f"stopped waiting: the {len(pending)} tasks not yet ended go "
                                    f"on (scancel {array} stops them); run the same command again once they have "
                                    "ended to draw what landed")
        for job in list(pending):
            state = None
            if job.done():
                try:
                    job.result()
                    state = "landed"
                except Exception as error:  # a task's failure is reported with the others', not raised alone
                    failed.append(f"task {job.job_id}: {reason(error)}")
                    state = "FAILED"
            elif not queued(job.job_id):  # no result and out of the queue: killed, out of memory, cancelled
                gone.setdefault(job.job_id, time.monotonic())
                if time.monotonic() - gone[job.job_id] > LOST_AFTER_S:
                    failed.append(f"task {job.job_id}: ended without a result (killed, out of memory or cancelled; "
                                  f"see {job.paths.stderr})")
                    state = "LOST"
            if state is not None:
                names = ", ".join(j.name for j in pending.pop(job))
                log(f"{len(submitted) - len(pending)} of {len(submitted)} tasks ended: {job.job_id} {state} "
                    f"({names}), {(time.perf_counter() - started) / 60:.1f} min")
        if pending and time.perf_counter() - said >= launch.PROGRESS_EVERY_S:  # read from the shared results folder
            said = time.perf_counter()
            launch.say_progress([j for group in pending.values() for j in group], log)
        if pending:
            time.sleep(poll_s)
    if failed:
        raise launch.Failed(f"{len(failed)} of {len(submitted)} SLURM tasks failed: " + "; ".join(failed))


def queued(job_id: str) -> bool:
    """Whether SLURM still holds the task (pending, running or requeued); True when squeue cannot say."""
    listed = subprocess.run(["squeue", "-h", "-j", job_id, "-o", "%i"], capture_output=True, text=True)
    return listed.returncode != 0 or bool(listed.stdout.strip())


def reason(error: Exception) -> str:
    """The last line of a failed task's trace (submitit's message wraps it between dashed lines)."""
    text = str(error)
    parts = re.split(r"\n-{5,}\n", text)
    lines = [line.strip() for line in (parts[1] if len(parts) >= 3 else text).splitlines() if line.strip()]
    return (lines[-1] if lines else type(error).__name__)[:300]


def available() -> str | None:
    """None when SLURM's `sbatch` can be called here, else why not."""
    return None if shutil.which("sbatch") else "SLURM's sbatch is not on PATH"
