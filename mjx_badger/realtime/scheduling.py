"""Who gets a core first, and whose pages stay in memory: the control thread's.

The learner keeps both cores of a small machine busy, and the control thread must wake on
time every 25 ms. On Linux it asks for the real-time class SCHED_FIFO, which preempts every
ordinary thread the moment it wakes; that takes root, CAP_SYS_NICE or an rtprio limit
(`ulimit -r`). Without it the control thread stays ordinary and the learner's compute threads
are niced instead, which helps less: measured on the 2-core development machine, a 40 Hz
sleep loop beside two niced CPU hogs woke up to 11 ms late, under SCHED_FIFO at most 0.1 ms.

Memory: a kernel may drop pages of the process it sees unused (shared-library code, for one;
the development machine runs DAMON's proactive pageout) and read them back from disk on the
next touch, a major page fault that stalls the thread for milliseconds. A control path taken
once a minute is exactly such code, so the loop locks the process's pages in memory
(mlockall), which takes CAP_IPC_LOCK or a large enough `ulimit -l`. (Measured here: one major
fault in an unlocked 20k-step run, none locked.)

Neither can hide a machine's own stalls: on the development VM a bare SCHED_FIFO sleep loop,
alone on the machine, still stalls for 10-35 ms at times, from none in one 20k-period reading
to 42 in another while the host was busy (`python -m benchmarks.bench_realtime --floor`).
"""

import contextlib
import ctypes
import os
import resource
import sys
import time
from pathlib import Path

CONTROL_PRIORITY = 50
"""SCHED_FIFO priority of the control thread (1-99); a simulated robot's physics runs one above."""
COMPUTE_NICENESS = 10
"""Niceness of XLA's compute threads. Raising it needs no privilege but lowering it back does,
so they stay niced after the run (it only matters when threads compete for a core)."""


GIL_SWITCH_INTERVAL_S = 0.0002
"""Python hands the GIL between threads every 5 ms by default; the control thread waking for
its deadline must not wait that long behind the learner's or a simulated robot's Python code."""


@contextlib.contextmanager
def control_thread(lock: bool = True):
    """The calling thread as a control thread for the block: SCHED_FIFO, memory locked (if `lock`),
    a short GIL switch interval; yields (fifo, locked) as granted and undoes all of it after."""
    switch_interval = sys.getswitchinterval()
    sys.setswitchinterval(GIL_SWITCH_INTERVAL_S)
    fifo = raise_to_realtime()
    locked = lock and lock_memory()
    try:
        yield fifo, locked
    finally:
        if locked:
            unlock_memory()
        if fifo:
            back_to_normal()
        sys.setswitchinterval(switch_interval)


def sleep_until(deadline: float) -> bool:
    """Sleep to `deadline` (a time.perf_counter() reading); False, at once, if it has passed."""
    delay = deadline - time.perf_counter()
    if delay <= 0:
        return False
    time.sleep(delay)
    return True


def raise_to_realtime(priority: int = CONTROL_PRIORITY) -> bool:
    """Put the calling thread in SCHED_FIFO at `priority`; False where that is not allowed."""
    try:
        os.sched_setscheduler(0, os.SCHED_FIFO, os.sched_param(priority))
    except (AttributeError, OSError):
        return False
    return True


def back_to_normal() -> None:
    """The calling thread back to the ordinary scheduler (always allowed)."""
    try:
        os.sched_setscheduler(0, os.SCHED_OTHER, os.sched_param(0))
    except (AttributeError, OSError):
        pass


def is_realtime() -> bool:
    """Whether the calling thread runs in SCHED_FIFO."""
    try:
        return os.sched_getscheduler(0) == os.SCHED_FIFO
    except (AttributeError, OSError):
        return False


def nice_compute_threads() -> int:
    """Lower XLA's compute threads to COMPUTE_NICENESS; returns how many were found (0 off Linux)."""
    found = 0
    for task in Path("/proc/self/task").glob("*") if Path("/proc/self/task").exists() else ():
        try:
            if not (task / "comm").read_text().startswith("tf_"):
                continue
            thread_id = int(task.name)
            os.setpriority(os.PRIO_PROCESS, thread_id,
                           max(os.getpriority(os.PRIO_PROCESS, thread_id), COMPUTE_NICENESS))
            found += 1
        except (OSError, ValueError):
            continue  # the thread ended meanwhile
    return found


_MCL_CURRENT = 1


def lock_memory() -> bool:
    """Lock every page mapped now in RAM (mlockall); False where that is not allowed."""
    try:
        return ctypes.CDLL(None, use_errno=True).mlockall(_MCL_CURRENT) == 0
    except (AttributeError, OSError):
        return False


def unlock_memory() -> None:
    """Let the kernel page the process out again (always allowed)."""
    try:
        ctypes.CDLL(None).munlockall()
    except (AttributeError, OSError):
        pass


def major_page_faults() -> int:
    """Page faults of this process that waited for the disk, so far."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_majflt
