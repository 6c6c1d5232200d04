"""MkDocs hook: the docs pages show figures that live outside docs/ (figures/, benchmarks/results/).

A page links such a figure by its path relative to the page's own file, e.g. `../figures/x.png` from
docs/results.md, so the link also works on GitHub. MkDocs only knows files under docs/, so this hook
(1) adds every tracked image under SHARED to the site's files at its repository path (figures/x.png in
the site), and (2) rewrites each link of a page that points into SHARED to the page-relative path of
that site file. MkDocs then validates the rewritten link like any other: a figure that is missing or
not tracked by git is "not found", a warning, and `mkdocs build --strict` fails on it.
"""

import posixpath
import re
import subprocess
from pathlib import Path

from mkdocs.structure.files import File

ROOT = Path(__file__).parent
SHARED = ("figures/", "benchmarks/results/")
SUFFIXES = (".png", ".gif", ".svg", ".jpg", ".jpeg")
# A Markdown link or image target, or an HTML src/href attribute.
LINK = re.compile(r"(\]\(|\b(?:src|href)=\")([^)\"\s]+)")


def _tracked_images():
    try:
        names = subprocess.run(["git", "ls-files", "--", *SHARED], cwd=ROOT, capture_output=True, text=True,
                               check=True).stdout.splitlines()
    except (OSError, subprocess.CalledProcessError):  # not a git checkout: take the files that are there
        names = [p.relative_to(ROOT).as_posix() for folder in SHARED for p in (ROOT / folder).rglob("*")]
    return sorted(n for n in names if n.lower().endswith(SUFFIXES))


def on_files(files, config):
    for name in _tracked_images():
        files.append(File(name, str(ROOT), config["site_dir"], config["use_directory_urls"]))
    return files


def on_page_markdown(markdown, page, config, files):
    docs = Path(config["docs_dir"]).resolve().relative_to(ROOT.resolve()).as_posix()
    page_dir = posixpath.dirname(page.file.src_uri)

    def rewrite(match):
        target = match.group(2)
        path, _, fragment = target.partition("#")
        in_repo = posixpath.normpath(posixpath.join(docs, page_dir, path))
        if not path.startswith("../") or not in_repo.startswith(SHARED):
            return match.group(0)
        relative = posixpath.relpath(in_repo, page_dir or ".")
        return match.group(1) + relative + ("#" + fragment if fragment else "")

    return LINK.sub(rewrite, markdown)
