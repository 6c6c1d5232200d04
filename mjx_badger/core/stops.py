"""Ctrl-C (SIGINT) and SIGTERM during a run: finish the chunk at hand, save it, and stop saying how to resume.

A compiled chunk cannot be cut short, so the first signal is noted and the run stops at the
next chunk's end, with that chunk's results written and a checkpoint of it saved (runner.py).
A second signal stops at once, as Python does by default; the last checkpoint saved still
resumes.
"""

import contextlib
import signal
import sys
import threading

SIGNALS = (signal.SIGINT, signal.SIGTERM)
_noted: list = []
_depth = [0]


class Interrupted(Exception):
    """A run stopped by a signal after saving; `code` is the shell's exit status for it (128 + signal)."""

    def __init__(self, signum: int, message: str):
        super().__init__(message)
        self.code = 128 + signum

    def __reduce__(self):  # so that a run's process can hand it to its parent
        return Interrupted, (self.code - 128, str(self))


def requested() -> int | None:
    """The signal a stop was asked by, or None."""
    return _noted[0] if _noted else None


def name(signum: int) -> str:
    return signal.Signals(signum).name


def _note(signum, frame) -> None:
    if _noted:
        raise KeyboardInterrupt
    _noted.append(signum)
    print(f"\n{name(signum)}: stopping after this chunk to save it ({name(signum)} again stops at once)",
          file=sys.stderr, flush=True)


@contextlib.contextmanager
def graceful():
    """While the block runs, SIGINT and SIGTERM ask for a stop (`requested`) instead of ending the process.

    Nested blocks share the outer one's handlers; off the main thread (where Python cannot set
    handlers) the signals keep their usual effect.
    """
    if _depth[0] or threading.current_thread() is not threading.main_thread():
        _depth[0] += 1
        try:
            yield
        finally:
            _depth[0] -= 1
        return
    previous = {signum: signal.signal(signum, _note) for signum in SIGNALS}
    _depth[0] += 1
    _noted.clear()
    try:
        yield
    finally:
        _depth[0] -= 1
        _noted.clear()
        for signum, handler in previous.items():
            signal.signal(signum, handler)


@contextlib.contextmanager
def left_to_caller():
    """While the block runs, SIGINT and SIGTERM keep the handlers they have (a SLURM job's, which submitit set to
    checkpoint and requeue): a run inside it checkpoints as usual but installs none of its own."""
    _depth[0] += 1
    try:
        yield
    finally:
        _depth[0] -= 1


def leave_all_to_caller() -> None:
    """For the rest of this process (a run's process inside a cluster task): as `left_to_caller`."""
    _depth[0] += 1
