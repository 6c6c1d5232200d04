"""The benchmark results files say in whole what they hold."""

import ast
import json
from pathlib import Path

from mjx_badger import results

ROOT = Path(__file__).parent.parent


def test_what_is_the_docstrings_first_paragraph_on_one_line():
    assert results.what("How fast the\n  env steps.\n\n    python x.py\n") == "How fast the env steps."


def test_no_committed_what_is_cut_at_a_line_break_of_its_scripts_docstring():
    firsts = {}
    for script in (ROOT / "benchmarks").glob("*.py"):
        doc = ast.get_docstring(ast.parse(script.read_text()), clean=False)
        if doc and doc.split("\n\n")[0].count("\n"):  # a first paragraph of several lines
            firsts[doc.splitlines()[0]] = script.name
    cut = []
    for path in (ROOT / "benchmarks" / "results").glob("*.json"):
        document = json.loads(path.read_text())
        if isinstance(document, dict) and document.get("what") in firsts:
            cut.append(f"{path.name}: {firsts[document['what']]}'s first line only")
    assert not cut, cut
