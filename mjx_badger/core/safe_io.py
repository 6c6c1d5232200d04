"""Atomic writes: a file is replaced whole or not at all, so a full disk or a kill never leaves half a file.

Every results file, policy, figure, table, scoreboard and on-robot checkpoint file is written
through `write_bytes` (or `write_text`): into a temporary file beside the target, which then
replaces it (os.replace is atomic on one file system). A failed write removes its temporary
file and leaves the previous version as it was; the OSError goes on to the caller.
"""

import contextlib
import io
import os
import shutil
from pathlib import Path


def _put(path: Path, data: bytes) -> None:
    """The one place bytes reach the disk (tests make it fail as a full disk would)."""
    with open(path, "wb") as handle:
        handle.write(data)


@contextlib.contextmanager
def replacing(path: Path):
    """A temporary path beside `path`; it replaces `path` when the block succeeds and is removed when it fails."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        yield tmp
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            tmp.unlink()
        raise


def write_bytes(path: Path, data: bytes) -> Path:
    with replacing(path) as tmp:
        _put(tmp, data)
    return Path(path)


def write_text(path: Path, text: str) -> Path:
    return write_bytes(path, text.encode())


def save_figure(fig, path: Path, **kwargs) -> Path:
    """A matplotlib figure written atomically, in the format of the file's suffix."""
    buffer = io.BytesIO()
    fig.savefig(buffer, format=Path(path).suffix.lstrip(".") or "png", **kwargs)
    return write_bytes(path, buffer.getvalue())


def save_npz(path: Path, **arrays) -> Path:
    """np.savez, atomically."""
    import numpy as np

    buffer = io.BytesIO()
    np.savez(buffer, **arrays)
    return write_bytes(path, buffer.getvalue())


def save_npy(path: Path, array) -> Path:
    """np.save, atomically."""
    import numpy as np

    buffer = io.BytesIO()
    np.save(buffer, array)
    return write_bytes(path, buffer.getvalue())


def replace_folder(folder: Path, fill) -> Path:
    """Write a whole folder at once: `fill(tmp)` writes into a fresh folder that then takes `folder`'s place.

    The old folder is moved aside to `<folder>.old` first and removed last, so at every moment
    one complete version exists (`newest_folder` finds it).
    """
    folder = Path(folder)
    fresh, old = folder.with_name(folder.name + ".new"), folder.with_name(folder.name + ".old")
    shutil.rmtree(fresh, ignore_errors=True)
    fresh.mkdir(parents=True)
    try:
        fill(fresh)
    except BaseException:
        shutil.rmtree(fresh, ignore_errors=True)
        raise
    if folder.exists():
        shutil.rmtree(old, ignore_errors=True)
        os.replace(folder, old)
    os.replace(fresh, folder)
    shutil.rmtree(old, ignore_errors=True)
    return folder


def newest_folder(folder: Path) -> Path:
    """`folder`, or the previous version `replace_folder` moved aside if a save stopped between its two renames."""
    folder = Path(folder)
    old = folder.with_name(folder.name + ".old")
    return old if not folder.exists() and old.exists() else folder
