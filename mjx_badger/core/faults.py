"""How a command ends when its run cannot go on: one line on stderr and an exit status, never a traceback.

Refused (a damaged file of its own, another run writing the same output): 2, as for bad input.
Stopped by SIGINT or SIGTERM after saving (stops.py): 128 + the signal, as a shell reports it;
a second Ctrl-C, or one outside a run: 130.
A write that failed (a full disk, a folder made read-only under it): 1; every file is written
atomically (safe_io.py), so the results file and the checkpoint are those of the last chunk
saved, and the same command resumes from them.
"""

import errno
import sys

from mjx_badger.core.launch import Failed
from mjx_badger.core.stops import Interrupted
from mjx_badger.core.validation import Refused


def describe(error: OSError) -> str:
    """'No space left on device writing results/x.json' from an OSError."""
    reason = error.strerror or (errno.errorcode.get(error.errno, "") if error.errno else "") or str(error)
    return f"{reason} writing {error.filename}" if error.filename else reason


def run(command) -> int:
    """`command()`, its refusals, stops and failed writes turned into one line and an exit status."""
    try:
        return command()
    except Refused as error:
        print(f"error: {error}", file=sys.stderr)
        return 2
    except Failed as error:  # runs in their own processes or cluster jobs: each named with its error
        print(f"error: {error}", file=sys.stderr)
        return 1
    except Interrupted as stop:
        print(stop, file=sys.stderr)
        return stop.code
    except KeyboardInterrupt:  # a second Ctrl-C, or one outside a run's chunks
        print("interrupted; every file is whole (the last saved), and a training run resumes from its last "
              "checkpoint", file=sys.stderr)
        return 130
    except OSError as error:
        print(f"error: {describe(error)}; nothing is left half-written (files are replaced whole): make room and "
              "run the same command again (a training run resumes from its last checkpoint)", file=sys.stderr)
        return 1
