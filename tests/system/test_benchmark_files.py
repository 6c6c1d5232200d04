"""The benchmark, tool and investigation results files say in whole what they hold, and each lives where it belongs."""

import ast
import json
from pathlib import Path

from mjx_badger.records import results

ROOT = Path(__file__).resolve().parents[2]


def test_what_is_the_docstrings_first_paragraph_on_one_line():
    assert results.what("How fast the\n  env steps.\n\n    python x.py\n") == "How fast the env steps."


# Benchmarks and their outputs, the tools and theirs, and the one-off investigations beside the docs page citing them.
SCRIPTS = ("benchmarks/*.py", "tools/*.py", "docs/*/*.py")
RESULTS = ("benchmarks/results/*.json", "tools/results/*.json", "docs/*/*.json")


def test_no_committed_what_is_cut_at_a_line_break_of_its_scripts_docstring():
    firsts = {}
    for script in (path for pattern in SCRIPTS for path in ROOT.glob(pattern)):
        doc = ast.get_docstring(ast.parse(script.read_text()), clean=False)
        if doc and doc.split("\n\n")[0].count("\n"):  # a first paragraph of several lines
            firsts[doc.splitlines()[0]] = script.name
    cut = []
    for path in (path for pattern in RESULTS for path in ROOT.glob(pattern)):
        document = json.loads(path.read_text())
        if isinstance(document, dict) and document.get("what") in firsts:
            cut.append(f"{path.name}: {firsts[document['what']]}'s first line only")
    assert not cut, cut


def test_benchmarks_holds_only_the_benchmarks_and_an_investigation_sits_beside_its_page():
    scripts = {p.name for p in (ROOT / "benchmarks").glob("*.py")} - {"__init__.py", "common.py"}
    assert scripts and all(name.startswith("bench_") for name in scripts), sorted(scripts)
    for script in ROOT.glob("docs/*/*.py"):
        assert script.parent.with_suffix(".md").is_file(), f"{script}: no docs page {script.parent.name}.md"
