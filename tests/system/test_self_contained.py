"""Nothing in the repository points at a file outside it (a clone has only what is tracked)."""

import re
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
# Spelled in parts so that this file, too, holds none of them whole.
OUTSIDE = ("../" + "shared", "THESIS_CODE" + ".md", "DESIGN" + ".md")
SUFFIXES = (".py", ".md", ".toml", ".cfg", ".txt", ".yml", ".yaml")
# A Markdown link or image target: ](target) or ](target "title").
LINK = re.compile(r"\]\(([^)\s]+)")


def tracked():
    names = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True, check=True).stdout.split()
    return [name for name in names if (ROOT / name).is_file()]


def test_no_file_refers_outside_the_repository():
    found = []
    for name in tracked():
        path = ROOT / name
        if path.suffix in SUFFIXES or path.name in ("Makefile",) or name.startswith("docs/"):
            text = path.read_text(errors="ignore")
            found += [f"{name}: {needle}" for needle in OUTSIDE if needle in text]
    assert not found, found


def test_markdown_links_stay_inside_the_repository():
    """Every relative link of a tracked Markdown file names a file or folder of the repository."""
    names = set(tracked())
    folders = {str(Path(n).parent) for n in names} | {p for n in names for p in map(str, Path(n).parents)}
    bad = []
    for name in names:
        if not name.endswith(".md"):
            continue
        text = re.sub(r"```.*?```", "", (ROOT / name).read_text(errors="ignore"), flags=re.S)
        for target in LINK.findall(text):
            target = target.split("#")[0]
            if not target or re.match(r"[a-z]+:", target):  # an anchor on the same page, or a URL
                continue
            resolved = (ROOT / name).parent / target
            try:
                inside = resolved.resolve().relative_to(ROOT.resolve()).as_posix()
            except ValueError:
                bad.append(f"{name}: {target} (outside the repository)")
                continue
            if inside not in names and inside.rstrip("/") not in folders:
                bad.append(f"{name}: {target} (not tracked)")
    assert not bad, bad
