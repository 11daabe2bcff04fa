"""The architecture as a contract: the import layers of pyproject.toml ([tool.importlinter]),
and the size limits that keep each module one idea."""
from __future__ import annotations

import ast
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import ROOT

LINT = Path(sys.executable).parent / "lint-imports"
MAX_MODULE_LINES = 600
MAX_FUNCTION_LINES = 80
MAX_TEMPLATE_LINES = 450  # a template is one concern: model.c.jinja's parts include each other
ARGUMENT_TABLES: set = set()  # argparse tables long by nature and without logic (none now: parsers.py splits them)


def lint(cwd: Path) -> subprocess.CompletedProcess:
    if not LINT.exists():
        pytest.skip("lint-imports is not installed (pip install import-linter; make test installs it)")
    return subprocess.run([str(LINT), "--config", str(cwd / "pyproject.toml"), "--no-cache"], capture_output=True,
                          text=True, cwd=cwd, env={"PYTHONPATH": str(cwd), "PATH": "/usr/bin:/bin"}, timeout=120)


def test_the_layers_are_kept():
    res = lint(ROOT)
    assert res.returncode == 0, res.stdout + res.stderr
    assert "2 kept, 0 broken" in res.stdout, res.stdout


@pytest.mark.parametrize("module,planted", [
    ("chainspec/spec.py", "from ..commandline import cli  # planted: the lowest layer reaching the top"),
    ("printers/latex.py", "from ..models import pipeline  # planted: a printer calling the pipeline back"),
    ("derive/dynamics.py", "from . import aba  # planted: a cycle (aba imports dynamics), inside one subpackage"),
    ("analysis/floquet.py", "from ..ensembles import sweep  # planted: a capability reaching one above it"),
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


def test_no_template_is_too_long():
    long = {p.name: n for p in sorted((ROOT / "gyrochain" / "templates").glob("*"))
            if (n := len(p.read_text().splitlines())) > MAX_TEMPLATE_LINES}
    assert not long, long


# a decision in a template: a condition joined by and/or, or a value chosen by if/else
DECISION = re.compile(r"{%-?\s*(?:(?:el)?if\b[^%]*\b(?:and|or)\b|set\b[^%]*\bif\b[^%]*\belse\b)[^%]*%}")


def _decisions(text: str) -> list[str]:
    return DECISION.findall(text)


def test_templates_hold_layout_and_loops_not_decisions():
    """What a model needs (a helper, a block, a name) is decided by the printer and named in its data;
    a template tests one named fact at a time (a for loop's filter selects, it does not decide)."""
    found = {p.name: d for p in sorted((ROOT / "gyrochain" / "templates").glob("*.jinja"))
             if (d := _decisions(p.read_text()))}
    assert not found, found
    planted = ['{% if loops and canonical or der_world %}', '{%- elif a or b %}',
               '{% set out = "a" if col < n else "b" %}']
    assert all(_decisions(t) for t in planted)
    assert not _decisions('{% if helpers.ldlt_solve %}{% for v in vs if v.a and v.b %}{% set full = c - 8 %}')


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
    """Only commandline/ (cli.py, its grammar parsers.py, its small parsers cliargs.py, the reference
    page written from the grammar reference.py) and __main__ parse arguments or import cli."""
    for p in _modules():
        if p.name in ("cli.py", "parsers.py", "cliargs.py", "reference.py", "__main__.py"):
            continue
        text = p.read_text()
        assert "argparse" not in text and "from .cli" not in text and "import cli" not in text, p


DATA = {"kernels", "templates", "examples"}  # package data: C kernels, jinja2 templates, example specs


def _code(pattern: str) -> list:
    return [p for p in (ROOT / "gyrochain").glob(pattern) if p.parent.name not in DATA]


def _layers(i: int) -> set:
    import tomllib

    layers = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["importlinter"]["contracts"][i]["layers"]
    return {m.strip() for layer in layers for m in layer.split("|")}


def test_every_module_sits_in_a_subpackage_with_a_layer():
    """The package's top level holds only __init__ and __main__; every subpackage is a layer of the
    first contract, and every module of a subpackage (but the printers, one layer) one of the second:
    a module left out would escape the contract."""
    top = {p.name for p in (ROOT / "gyrochain").glob("*.py")}
    assert top == {"__init__.py", "__main__.py"}, top
    subpackages = {f"gyrochain.{p.parent.name}" for p in _code("*/__init__.py")}
    assert subpackages - _layers(0) == set(), sorted(subpackages - _layers(0))
    modules = {f"gyrochain.{p.parent.name}.{p.stem}" for p in _code("*/*.py")
               if p.stem != "__init__" and p.parent.name != "printers"}
    assert modules - _layers(1) == set(), sorted(modules - _layers(1))


def test_every_subpackage_and_data_folder_ships_in_the_wheel():
    """pyproject.toml names the packages the wheel holds: a subpackage left out of that list
    imports in the checkout but not from an installed wheel."""
    import tomllib

    shipped = set(tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["packages"])
    folders = {f"gyrochain.{p.name}" for p in (ROOT / "gyrochain").iterdir()
               if p.is_dir() and p.name != "__pycache__"}
    assert folders - shipped == set(), sorted(folders - shipped)


def test_every_subpackage_says_its_job_and_what_it_may_import():
    for init in sorted(_code("*/__init__.py")):
        doc = ast.get_docstring(ast.parse(init.read_text()))
        assert doc and len(doc.split()) >= 12, init
        if init.parent.name != "printers":
            assert "May import:" in doc, init


CAME_AFTER = ("gyrochain/analysis/continuation.py", "gyrochain/analysis/boundary.py", "gyrochain/analysis/branches.py",
              "gyrochain/analysis/cycles.py",
              "gyrochain/view/diagram.py")


def test_the_old_module_names_still_import_the_same_modules():
    """Scripts written before the package was laid out by capability (``from gyrochain import
    pipeline``, ``gyrochain.spec.load_spec``, ``import gyrochain.build``) get the same modules."""
    import importlib

    import gyrochain

    # (gyrochain.gpu, gyrochain.casadi, models/paramtable.py, models/selfcheck.py, models/calls.py, chainspec/tables.py and
    # derive/hessian.py and commandline/reference.py came after the move: their modules never had a top-level name)
    old = {p.stem for p in _code("*/*.py") if p.stem not in ("__init__", "paramtable", "selfcheck", "calls", "tables", "hessian")
           and p.parent.name not in ("printers", "gpu", "casadi")
               and p.relative_to(ROOT).as_posix() not in ("gyrochain/commandline/reference.py", *CAME_AFTER)}
    old.add("codes")
    assert set(gyrochain.MOVED) == old, set(gyrochain.MOVED) ^ old
    for name, new in gyrochain.MOVED.items():
        module = importlib.import_module(f"gyrochain.{name}")
        assert module is importlib.import_module(f"gyrochain.{new}"), name
        # the module keeps its own spec: a relative import inside it resolves by its package, which
        # Python 3.12 warns of, and a later Python refuses, where __package__ is not __spec__.parent
        assert module.__spec__.name == f"gyrochain.{new}" and module.__package__ == module.__spec__.parent, name
    from gyrochain import build, pipeline  # noqa: F401  (the documented API)
    from gyrochain.build import CModel, load  # noqa: F401
    from gyrochain.pipeline import compile, derive, derive_and_render, render  # noqa: F401
    from gyrochain.spec import SpecError, load_spec, parse_spec  # noqa: F401
    assert load_spec.__module__ == "gyrochain.chainspec.spec" and pipeline.derive is derive
