"""One writer per output: a run holds an exclusive lock on `<results>.lock` while it writes there.

fcntl.flock locks belong to the open file, so the kernel drops them when the process ends,
however it ends: a killed run leaves no stale lock. The lock file holds the holder's pid and
command line, which a refused second run names.
"""

import contextlib
import fcntl
import os
import sys
from pathlib import Path

from mjx_badger.core.validation import Refused


def path_for(output: Path) -> Path:
    """The lock file of a results file or folder."""
    output = Path(output)
    return output.with_name(output.name + ".lock")


def holder(lock: Path) -> str:
    """What the lock file says of the process holding it."""
    try:
        return Path(lock).read_text().strip() or "another process"
    except OSError:
        return "another process"


@contextlib.contextmanager
def hold(output: Path, what: str = "this run"):
    """Hold the lock of `output` for the block; Refused naming the running process if another holds it."""
    lock = path_for(output)
    lock.parent.mkdir(parents=True, exist_ok=True)
    while True:
        handle = open(lock, "a+")
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            handle.close()
            raise Refused(f"{output} is being written by {holder(lock)}; wait for it to finish, stop it, or "
                          f"give {what} another output") from None
        # The holder before us may have removed the file after we opened it: then lock the new one.
        try:
            same = os.stat(lock).st_ino == os.fstat(handle.fileno()).st_ino
        except FileNotFoundError:
            same = False
        if same:
            break
        handle.close()
    try:
        handle.seek(0)
        handle.truncate()
        handle.write(f"process {os.getpid()} ({' '.join(sys.argv) or 'python'})\n")
        handle.flush()
        yield lock
    finally:
        with contextlib.suppress(OSError):
            lock.unlink()
        handle.close()
