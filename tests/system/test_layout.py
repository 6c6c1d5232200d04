"""The house in layers: imports only point down (import-linter), no module over 350 lines, a test file per module."""

import ast
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PACKAGE = ROOT / "mjx_badger"
LINT_IMPORTS = Path(sys.executable).parent / "lint-imports"
MAX_LINES = 350
WITHOUT_BEHAVIOUR = ()
"""Modules with nothing to test (none today: even the constants and types have a test of what they promise)."""


def _modules() -> list[Path]:
    """Every module inside a layer (the top level holds __init__ and __main__ only)."""
    return sorted(p for p in PACKAGE.rglob("*.py") if p.name != "__init__.py" and p.parent != PACKAGE)


def test_the_top_level_holds_only_the_package_and_its_entry_point():
    assert sorted(p.name for p in PACKAGE.glob("*.py")) == ["__init__.py", "__main__.py"]
    layers = sorted(p.name for p in PACKAGE.iterdir() if p.is_dir() and p.name != "__pycache__")
    declared = re.findall(r"^    ([a-z| ]+)$", (ROOT / ".importlinter").read_text(), re.M)
    assert sorted(name.strip() for line in declared for name in line.split("|")) == layers


def test_every_layer_says_what_it_holds_and_what_it_may_import():
    for init in sorted(PACKAGE.glob("*/__init__.py")):
        body = ast.parse(init.read_text()).body
        assert len(body) == 1, f"{init} holds more than its docstring: import from the module itself"
        assert "import" in ast.get_docstring(ast.parse(init.read_text())), init


def test_no_module_is_over_350_lines():
    long = {str(p.relative_to(ROOT)): n for p in _modules() if (n := len(p.read_text().splitlines())) > MAX_LINES}
    assert not long, long


def test_every_module_is_imported_by_its_own_test_file():
    missing = []
    for module in _modules():
        layer, name = module.parent.name, module.stem
        test = ROOT / "tests" / layer / f"test_{name}.py"
        imported = test.exists() and re.search(
            rf"^from mjx_badger\.{layer} import [^\n]*\b{name}\b|^from mjx_badger\.{layer}\.{name} import", test.read_text(),
            re.M)
        if not imported and f"{layer}/{name}" not in WITHOUT_BEHAVIOUR:
            missing.append(f"tests/{layer}/test_{name}.py")
    assert not missing, missing


def _lint_imports(package_parent: Path) -> subprocess.CompletedProcess:
    return subprocess.run([str(LINT_IMPORTS), "--no-cache"], cwd=package_parent, capture_output=True, text=True,
                          env={"PYTHONPATH": str(package_parent), "PATH": str(LINT_IMPORTS.parent)})


@pytest.mark.skipif(not LINT_IMPORTS.exists(), reason="import-linter is not installed (the test extra pins it)")
def test_the_layers_contract_holds_and_fails_on_an_upward_import(tmp_path):
    kept = _lint_imports(ROOT)
    assert kept.returncode == 0 and "Contracts: 2 kept, 0 broken." in kept.stdout, kept.stdout[-2000:]
    shutil.copytree(PACKAGE, tmp_path / "mjx_badger", ignore=shutil.ignore_patterns("__pycache__"))
    shutil.copy(ROOT / ".importlinter", tmp_path)
    with open(tmp_path / "mjx_badger" / "core" / "validation.py", "a") as module:
        module.write("\n\ndef _upward():\n    from mjx_badger.cli import main  # inside a function: a circle still\n")
    broken = _lint_imports(tmp_path)
    assert broken.returncode == 1, broken.stdout[-2000:]
    assert "mjx_badger.core is not allowed to import mjx_badger.cli" in broken.stdout
    assert "mjx_badger.core.validation -> mjx_badger.cli.main" in broken.stdout
