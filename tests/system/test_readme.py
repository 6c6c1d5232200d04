"""The README's first screen: short, and its Python example runs as written (the tiny run the tests share)."""

import contextlib
import io
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
README = (ROOT / "README.md").read_text()


def test_the_readme_is_short_and_names_every_layer_in_its_layout():
    assert len(README.splitlines()) <= 150
    layout = README[README.index("## Layout"):README.index("## The claims")]
    layers = sorted(p.name for p in (ROOT / "mjx_badger").iterdir() if p.is_dir() and p.name != "__pycache__")
    assert sorted(re.findall(r"^  ([a-z]+)/ ", layout, re.M)) == layers


def test_the_python_example_builds_an_env_trains_a_tiny_run_and_evaluates_it(tmp_path, monkeypatch):
    example = re.search(r"## In Python\n\n```python\n(.*?)```", README, re.S)[1]
    assert len(example.strip().splitlines()) <= 10
    monkeypatch.chdir(tmp_path)
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        exec(compile(example, "README.md", "exec"), {})
    sizes, report = printed.getvalue().splitlines()[0], printed.getvalue().splitlines()[-1]
    assert sizes == "54 12" and (tmp_path / "results" / "tiny" / "jt-oef.json").is_file()
    assert report.startswith("{'seconds': 1.0, 'command': [0.5, 0.0, 0.0], 'heading_velocity_along_command': ")
    assert "'path': " in report
    assert "'engine': 'native', 'seed': 0, 'conditions': 'sim'}" in report
