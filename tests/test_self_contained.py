"""Nothing in the repository points at a file outside it (a clone has only what is tracked)."""

import subprocess
from pathlib import Path

ROOT = Path(__file__).parent.parent
OUTSIDE = ("../shared", "THESIS_CODE.md", "DESIGN.md")


def test_no_file_refers_outside_the_repository():
    tracked = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True, check=True).stdout.split()
    found = []
    for name in tracked:
        path = ROOT / name
        if path.suffix in (".py", ".md", ".toml", ".cfg", ".txt") or path.name in ("Makefile",):
            text = path.read_text(errors="ignore")
            found += [f"{name}: {needle}" for needle in OUTSIDE if needle in text and path != Path(__file__)]
    assert not found, found
