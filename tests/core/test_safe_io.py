"""Atomic writes: a failed write or folder save leaves the file or folder before it, and no temporary file."""

import errno
import os

import pytest

from mjx_badger.core import safe_io


def test_a_failed_write_leaves_the_file_before_and_no_temporary_file(tmp_path, monkeypatch):
    target = tmp_path / "board.md"
    safe_io.write_text(target, "before")
    real = safe_io._put

    def half_then_full(tmp, data):
        real(tmp, data[:3])
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(tmp))

    monkeypatch.setattr(safe_io, "_put", half_then_full)
    with pytest.raises(OSError):
        safe_io.write_text(target, "after, longer")
    assert target.read_text() == "before" and sorted(p.name for p in tmp_path.iterdir()) == ["board.md"]


def test_a_failed_folder_save_leaves_the_one_before(tmp_path):
    folder = tmp_path / "run.checkpoint"
    safe_io.replace_folder(folder, lambda f: (f / "a").write_text("one"))

    def fails(fresh):
        (fresh / "a").write_text("two")
        raise OSError(errno.ENOSPC, "No space left on device")

    with pytest.raises(OSError):
        safe_io.replace_folder(folder, fails)
    assert (folder / "a").read_text() == "one" and sorted(p.name for p in tmp_path.iterdir()) == ["run.checkpoint"]
    folder.rename(tmp_path / "run.checkpoint.old")  # killed between the two renames of a save
    assert safe_io.newest_folder(folder) == tmp_path / "run.checkpoint.old"
