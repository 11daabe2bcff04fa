"""The architecture as a contract: the import layers of pyproject.toml ([tool.importlinter]),
and the size limits that keep each module one idea."""
from __future__ import annotations

import ast
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import ROOT

LINT = Path(sys.executable).parent / "lint-imports"
MAX_MODULE_LINES = 600
MAX_FUNCTION_LINES = 80
ARGUMENT_TABLES: set = set()  # argparse tables long by nature and without logic (none now: parsers.py splits them)


def lint(cwd: Path) -> subprocess.CompletedProcess:
    if not LINT.exists():
        pytest.skip("lint-imports is not installed (pip install import-linter; make test installs it)")
    return subprocess.run([str(LINT), "--config", str(cwd / "pyproject.toml"), "--no-cache"], capture_output=True,
                          text=True, cwd=cwd, env={"PYTHONPATH": str(cwd), "PATH": "/usr/bin:/bin"}, timeout=120)


def test_the_layers_are_kept():
    res = lint(ROOT)
    assert res.returncode == 0, res.stdout + res.stderr
    assert "1 kept, 0 broken" in res.stdout, res.stdout


@pytest.mark.parametrize("module,planted", [
    ("spec.py", "from . import cli  # planted: the lowest layer reaching the top"),
    ("printers/latex.py", "from .. import pipeline  # planted: a printer calling the pipeline back"),
    ("dynamics.py", "from . import aba  # planted: a cycle (aba imports dynamics)"),
])
def test_an_upward_import_breaks_the_contract(tmp_path, module, planted):
    """A copy of the package with one import planted against the layers: lint-imports fails and
    names it."""
    shutil.copytree(ROOT / "gyrochain", tmp_path / "gyrochain", ignore=shutil.ignore_patterns("__pycache__"))
    shutil.copy(ROOT / "pyproject.toml", tmp_path / "pyproject.toml")
    path = tmp_path / "gyrochain" / module
    path.write_text(path.read_text() + "\n" + planted + "\n")
    res = lint(tmp_path)
    assert res.returncode != 0, res.stdout
    assert "BROKEN" in res.stdout, res.stdout
    importer = "gyrochain." + module.removesuffix(".py").replace("/", ".")
    assert importer in res.stdout, res.stdout


def _modules():
    return sorted((ROOT / "gyrochain").rglob("*.py"))


def test_no_module_is_too_long():
    long = {str(p.relative_to(ROOT)): n for p in _modules() if (n := len(p.read_text().splitlines())) > MAX_MODULE_LINES}
    assert not long, long


def test_no_function_is_too_long():
    found = []
    for p in _modules():
        for node in ast.walk(ast.parse(p.read_text())):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                n = node.end_lineno - node.lineno + 1
                if n > MAX_FUNCTION_LINES and (p.name, node.name) not in ARGUMENT_TABLES:
                    found.append(f"{p.relative_to(ROOT)}:{node.lineno} {node.name} ({n} lines)")
    assert not found, found


def test_no_library_module_touches_the_command_line():
    """Only cli.py, its grammar (parsers.py), its small parsers (cliargs.py) and __main__ parse
    arguments or import cli."""
    for p in _modules():
        if p.name in ("cli.py", "parsers.py", "cliargs.py", "__main__.py"):
            continue
        text = p.read_text()
        assert "argparse" not in text and "from .cli" not in text and "import cli" not in text, p


def test_every_module_has_a_layer():
    """A module left out of the layers would escape the contract."""
    import tomllib

    layers = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["importlinter"]["contracts"][0]["layers"]
    named = {m.strip() for layer in layers for m in layer.split("|")}
    modules = {f"gyrochain.{p.stem}" for p in (ROOT / "gyrochain").glob("*.py") if p.stem != "__init__"}
    modules |= {f"gyrochain.{p.parent.name}" for p in (ROOT / "gyrochain").glob("*/__init__.py")}
    assert modules - named == set(), sorted(modules - named)
