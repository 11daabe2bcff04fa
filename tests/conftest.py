"""Shared fixtures: derive and render a spec once per process, compile its C once per test
session (pipeline.compile, whose cache folder every xdist worker shares: one builds, the others
wait for its build), and hand back the spec, the generated Python module and the compiled C model."""
from __future__ import annotations

import hashlib
import os
import re
import shutil
import signal
import subprocess
import sys
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from gyrochain import build, loopform, pipeline, reference  # noqa: E402
from gyrochain.spec import ChainSpec, load_spec, parse_spec  # noqa: E402

EXAMPLES = sorted(p.stem for p in (ROOT / "specs").glob("*.toml"))
# the long chains (specs/cable64.toml): the tests that cost minutes per example there (sanitizers,
# differences of the reference model) run on the short examples and on long random chains of their own
LONG_EXAMPLES = [e for e in EXAMPLES if len(load_spec(ROOT / "specs" / f"{e}.toml").bodies) >= loopform.LOOP_MIN_N]
SHORT_EXAMPLES = [e for e in EXAMPLES if e not in LONG_EXAMPLES]
# The arms imported from URDF (specs/robots): their dynamics are checked against Pinocchio and MuJoCo
# (tests/models/test_robots.py).  The costliest checks of the generated C's form (sanitizers,
# cppcheck, the float build, pdflatex, the animation) run on one of them, the UR5: the Panda's and
# the two-link pendulum's code comes from the same printers and adds minutes, not coverage.
ONE_ARM = [e for e in EXAMPLES if e not in ("panda", "planar2dof")]
# The examples make test runs a per-example check on (make test-all: on every example).  Together
# they run every line and branch of the derivation and printers that the sixteen examples run
# (coverage.py, branch mode), but for the 64-rod cable's long-chain forms (loops, M⁻¹ formed), the
# Panda's functions cut in parts, joint damping, the quadratures' refusal of a tilted first axis and
# a few number formats of the LaTeX.  Those run in make test through test_fresh (every example
# derived, printed and compared byte for byte with generated/); the long-chain forms' C through the
# long random chains of test_scale.py, damping through the general random chains.
# They are the gimbal (the integrable case and its quadratures), gyrostat2 (rotors in both bodies,
# an inclined axis with an offset), the symbolic Furuta pendulum, Kapitza's pendulum (a
# time-dependent platform), the ship's gimbal (a rotating platform with springs), the turntable,
# Ziegler's follower force and the UR5 (an arm imported from URDF, with controls).
QUICK_EXAMPLES = ("furuta_sym", "gimbal", "gyrostat2", "kapitza", "ship_gimbal", "turntable", "ur5", "ziegler")


def tiered(cases, quick, key=None, rows: bool = False) -> list:
    """The cases of a test repeated over examples or random specs: those whose ``key`` (the case
    itself by default) is in ``quick`` run in make test, the others in make test-all only (marked
    extended).  ``rows``: each case is a tuple of a multi-argument parametrize's values."""
    out = []
    for c in cases:
        if (c if key is None else key(c)) in quick:
            out.append(c)
        else:
            out.append(pytest.param(*(c if rows else (c,)), marks=pytest.mark.extended))
    return out


def example_script(name: str):
    """examples/<name>.py imported as a module (the examples are scripts, not a package)."""
    import importlib.util

    spec = importlib.util.spec_from_file_location(f"example_{name}", ROOT / "examples" / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod

def _spec_values(name: str) -> dict:
    return dict(load_spec(ROOT / "specs" / f"{name}.toml").values)


# the examples' parameter values are the specs' own [values] tables: the Furuta pendulum of furuta.toml;
# a table turning above its critical rate, a pivot vibrating fast enough to hold the inverted pendulum
# up, a follower force below Ziegler's flutter load
FURUTA_SYM_PARAMS = _spec_values("furuta_sym")
GENERAL_PARAMS = {name: _spec_values(name) for name in ("turntable", "kapitza", "ziegler")}


def example_params(name: str) -> dict | None:
    return FURUTA_SYM_PARAMS if name == "furuta_sym" else GENERAL_PARAMS.get(name)


@dataclass
class Generated:
    spec: ChainSpec
    py: object  # the generated Python module
    c: build.CModel  # the compiled C through cffi
    ref: reference.NumericChain
    params: dict | None
    folder: Path


_cache: dict = {}


def generate(spec: ChainSpec, folder: Path, params=None, qdd_form: str = "auto", der_form: str = "auto",
             latex: bool = False, loops: str = "auto", hessian: bool = False) -> Generated:
    """The spec's files written under ``folder`` (in a subfolder of its own per spec text and
    forms), its Python module, its compiled C and the reference model.  ``latex``: write the
    LaTeX too (the slowest printer; only the tests that read it ask).  ``loops``: the loop form of
    long chains by n ("auto") or forced ("straight", "loops").  ``hessian``: generate --hessian."""
    key = (spec.source, str(params), qdd_form, der_form) + (() if loops == "auto" else (loops,)) + (("hessian",) if hessian else ())
    if key not in _cache or (latex and not (_cache[key].folder / f"{spec.name}.tex").exists()):
        targets = ("c", "python", "latex") if latex else ("c", "python")
        files, _model = pipeline.derive_and_render(spec, f"{spec.name}.toml", qdd_form=qdd_form, der_form=der_form,
                                                   targets=targets, loops=loops, hessian=hessian)
        digest = hashlib.sha256("\0".join(map(str, key)).encode("utf-8")).hexdigest()[:12]
        target = folder / f"{spec.name}-{digest}" / spec.name
        pipeline.write_tree(files, target, build_it=False, name=spec.name)
        _cache[key] = Generated(spec, build.load_python(target), pipeline.compile(files, spec.name),
                                reference.numeric(spec, params), params, target)
    return _cache[key]


def cli_in_process(*args, cwd: Path = ROOT) -> subprocess.CompletedProcess:
    """``gyrochain ARGS`` run by cli.main in this process, from ``cwd``: the exit status, stdout and
    stderr as a subprocess gives them (argparse's exit included).  For the many tests of what a
    command answers to a mistake, which need no process of their own (each would pay a second of
    interpreter start and imports); what only a process shows (the console script, the exit
    status through ``python -m``, Ctrl-C, no traceback on stderr) is tested with real processes
    (tests/tools/test_cli.py, test_help.py, test_second_wave.py)."""
    import contextlib
    import io

    from gyrochain.cli import main

    words = [str(a) for a in args]
    out, err = io.StringIO(), io.StringIO()
    here = os.getcwd()
    os.chdir(cwd)
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            try:
                code = main(words)
            except SystemExit as exc:  # argparse
                code = exc.code
    finally:
        os.chdir(here)
    return subprocess.CompletedProcess(["gyrochain", *words], code, out.getvalue(), err.getvalue())


# The strict compiles of the generated C.  gcc at -O2, keeping the object: the warnings of the middle
# end (-Wmaybe-uninitialized, -Warray-bounds, ...) need the optimiser, and they are the same for
# the same code in C++.  g++ (and clang, where installed) for what another front end adds (C++'s
# casts and keywords): that needs no optimiser and no object, -fsyntax-only.
STRICT_COMPILERS = [("gcc", ["-std=c99", "-O2", "-c"]), ("g++", ["-x", "c++", "-std=c++11", "-fsyntax-only"])]
if shutil.which("clang"):
    STRICT_COMPILERS += [("clang", ["-std=c99", "-fsyntax-only"])]


def strict_compile(cc: str, flags: list[str], warnings: list[str], src: Path, obj: Path) -> subprocess.CompletedProcess:
    """``cc`` on ``src`` with STRICT_COMPILERS' ``flags`` and ``warnings``; the object in ``obj``
    where the flags make one."""
    out = ["-o", str(obj)] if "-c" in flags else []
    return subprocess.run([cc, *flags, *warnings, str(src), *out], capture_output=True, text=True)


def _session_dir(tmp_path_factory) -> Path:
    """A folder of this test session that every xdist worker sees (the workers' base folders are
    siblings under it)."""
    base = tmp_path_factory.getbasetemp()
    return base.parent if os.environ.get("PYTEST_XDIST_WORKER") else base


@pytest.fixture(scope="session", autouse=True)
def model_cache(tmp_path_factory):
    """$GYROCHAIN_CACHE for the session: a folder shared by the workers, so that each model is
    compiled once per session (and Dask workers the tests start find the builds there)."""
    old = os.environ.get("GYROCHAIN_CACHE")
    path = _session_dir(tmp_path_factory) / "model-cache"
    path.mkdir(exist_ok=True)
    os.environ["GYROCHAIN_CACHE"] = str(path)
    yield path
    if old is None:
        os.environ.pop("GYROCHAIN_CACHE", None)
    else:
        os.environ["GYROCHAIN_CACHE"] = old


LAYERS = ("unit", "models", "physics", "tools")  # the folders of tests/, each a marker too


# The extended tier (make test-all, CI): the product as others see it, beyond the derivation, accuracy,
# physics and command tests of make test: the installed wheel, the Cortex-M4 under QEMU, the static
# analysers and the sanitizers, the fuzz lanes, the documentation's pages (their commands run, the
# site, every test that drives a browser), and TeX typesetting every document.  Where a check costs
# a build per example and takes the same printer's path on each (the FMUs, the GPU threads, the
# CasADi functions, the LaTeX read back from random general specs), and where a check is repeated
# over the examples or over random specs, make test runs it on the cases that take its every branch
# (QUICK_EXAMPLES, each test's own choice of random specs) and make test-all on all: tiered().
EXTENDED_FILES = {"test_install.py", "test_m4.py", "test_static_checks.py", "test_fuzz.py"}
EXTENDED_FIXTURES = {"browser", "site"}


def extended(item) -> bool:
    """Whether a test belongs to make test-all only (EXTENDED_FILES, a browser or the site, TeX)."""
    if item.path.name in EXTENDED_FILES or EXTENDED_FIXTURES & set(getattr(item, "fixturenames", ())):
        return True
    return any(m.name == "skipif" and "LuaLaTeX" in str(m.kwargs.get("reason", "")) for m in item.iter_markers())


def pytest_collection_modifyitems(config, items):
    for item in items:
        layer = item.path.parent.name
        if layer in LAYERS:
            item.add_marker(getattr(pytest.mark, layer))
        if extended(item):
            item.add_marker(pytest.mark.extended)


@pytest.fixture(autouse=True)
def unit_layer_has_no_compiler(request, monkeypatch):
    """The unit layer's contract: nothing there compiles C (`make test-fast` runs it alone)."""
    if request.node.path.parent.name != "unit":
        return

    def refuse(*args, **kwargs):
        raise AssertionError("a unit test compiled C: it belongs in tests/models, physics or tools")

    monkeypatch.setattr(build, "compile_model", refuse)


@contextmanager
def printer_setting(module, name: str, value):
    """A printer's module setting changed while the block runs (a test forcing a form or a size).
    The renderings and derivations this process keeps were made with the setting as it was, and
    those made inside were made with the other: both are forgotten on the way in and out."""
    old = getattr(module, name)
    pipeline.forget()
    setattr(module, name, value)
    try:
        yield
    finally:
        setattr(module, name, old)
        pipeline.forget()


@pytest.fixture
def sigint_from_a_terminal():
    """The commands a test interrupts start with Ctrl-C as a terminal gives it.  A suite started
    in the background of a script (`make test &`, nohup) runs with SIGINT ignored, which every
    program it starts inherits, and a command that finds SIGINT ignored keeps it so, as Python
    does: the test would then wait for a command that rightly does not stop.  A signal with a
    handler here reverts to its default in the programs started meanwhile."""
    old = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, old)


@pytest.fixture(scope="session")
def gen_dir(tmp_path_factory):
    return tmp_path_factory.mktemp("generated")


@pytest.fixture(scope="session")
def make_model(gen_dir):
    def make(spec_or_text, params=None, qdd_form: str = "auto", der_form: str = "auto", latex: bool = False,
             loops: str = "auto", hessian: bool = False) -> Generated:
        spec = parse_spec(spec_or_text) if isinstance(spec_or_text, str) else spec_or_text
        return generate(spec, gen_dir, params, qdd_form, der_form, latex, loops, hessian)

    return make


@pytest.fixture(scope="session")
def example(make_model):
    def get(name: str) -> Generated:
        return make_model(load_spec(ROOT / "specs" / f"{name}.toml"), example_params(name))

    return get


@pytest.fixture
def rng():
    return np.random.default_rng(20261122)


def stated_op_counts(header: str) -> dict:
    """The op counts a generated header states (``Op counts: name N, …``)."""
    line = header.split("Op counts:")[1].split("\n")[0]
    return {k: int(v) for k, v in re.findall(r"(\w+) (\d+)[,.]", line)}


def code_op_count(body: str, targets: str) -> int:
    """Operators (+ − * / and cos, sin calls) on the right of the temporaries and of the
    assignments to ``targets`` (a regex) in a C function body; a leading sign is no operation."""
    lines = [ln for ln in body.splitlines() if re.match(rf"\s+(const double \w+|{targets}) = ", ln)]
    rhs = [ln.split("=", 1)[1].strip().removeprefix("-") for ln in lines]
    return sum(len(re.findall(r"(?<![eE])[-+*/]", r)) + r.count("cos(") + r.count("sin(") for r in rhs)


def fd_jacobian(f, x, h: float = 1e-3) -> np.ndarray:
    """∂f/∂x by central differences with one Richardson step (error O(h⁴)): the independent check
    of the emitted exact derivatives (~1e-10 relative for the reference model's φ̈)."""
    x = np.asarray(x, dtype=float)
    cols = []
    for e in np.eye(len(x)):
        d1 = (f(x + h * e) - f(x - h * e)) / (2 * h)
        d2 = (f(x + h / 2 * e) - f(x - h / 2 * e)) / h
        cols.append((4 * d2 - d1) / 3)
    return np.array(cols).T if cols else np.zeros((0, 0))


def richardson(f, h: float = 1e-3):
    """d/ds f(s) at s = 0 by central differences with one Richardson step (error O(h⁴))."""
    d1 = (np.asarray(f(h)) - np.asarray(f(-h))) / (2 * h)
    d2 = (np.asarray(f(h / 2)) - np.asarray(f(-h / 2))) / h
    return (4 * d2 - d1) / 3


def check_derivatives(model, x, u=None, t=None, tol=1e-8):
    """NAME_qdd_derivatives of the C and the Python against differences of the reference model's
    φ̈ (relative to the largest entry); returns the largest relative error seen."""
    n, nu = model.spec.n, len(model.spec.controls)
    tt = 0.0 if t is None else t
    J = fd_jacobian(lambda z: reference.qdd(model.ref, z, u, tt), x)
    Ju = fd_jacobian(lambda w: reference.qdd(model.ref, x, w, tt), u) if nu else np.zeros((n, 0))
    want = np.hstack([J, Ju])
    scale = max(np.max(np.abs(want)), 1e-300)
    worst = 0.0
    td = model.c.time_dependent
    for got in (model.c.qdd_derivatives(x, u, model.params, t=tt),
                model.py.qdd_derivatives(*((tt,) if td else ()), x, u, model.params)):
        q, dq, dv, du = got
        assert np.allclose(q, reference.qdd(model.ref, x, u, tt), rtol=1e-10, atol=1e-10 * np.max(np.abs(q)))
        err = np.max(np.abs(np.hstack([dq, dv, du]) - want)) / scale
        worst = max(worst, err)
        assert err <= tol, (err, np.hstack([dq, dv, du]), want)
    return worst


def perturbed_c(model: Generated, folder: Path, block: str = "dqdd_dphi", factor: float = 1.0 + 1e-6) -> build.CModel:
    """The model's C with one block of its derivatives perturbed (every entry of ``block``, an
    output of NAME_qdd_derivatives, times ``factor``), built in ``folder``: whatever reads the
    derivatives (linearize, the variational equations, Newton) reads the perturbed ones.  The
    mutation check of a test that rests on the exact derivatives."""
    import shutil

    name, n = model.spec.name, model.spec.n
    src = (model.folder / f"{name}.c").read_text()
    head = f"int {name}_qdd_derivatives("
    assert src.count(head) == 1, "one definition of qdd_derivatives"
    src = src.replace(head, f"static int {name}_qdd_derivatives_exact_(")
    t_param, t_arg = ("double t, ", "t, ") if model.c.time_dependent else ("", "")
    src += (f"\nint {name}_qdd_derivatives({t_param}const double *x, const double *u, const {name}_params *p,\n"
            f"    double *qdd, double *dqdd_dphi, double *dqdd_dphidot, double *dqdd_du)\n{{\n"
            f"    int i, code = {name}_qdd_derivatives_exact_({t_arg}x, u, p, qdd, dqdd_dphi, dqdd_dphidot, dqdd_du);\n"
            f"    for (i = 0; {block} && i < {n * n if block != 'dqdd_du' else n * len(model.spec.controls)}; ++i) {{\n"
            f"        {block}[i] *= {factor!r};\n    }}\n    return code;\n}}\n")
    folder.mkdir(parents=True, exist_ok=True)
    (folder / f"{name}.c").write_text(src)
    for ext in (".h", ".cdef"):
        shutil.copy2(model.folder / f"{name}{ext}", folder / f"{name}{ext}")
    return build.CModel(build.compile_model(folder, name), name)


def _chromium() -> str | None:
    import shutil

    for name in ("chromium", "chromium-browser", "google-chrome"):
        path = shutil.which(name)
        if path:
            return path
    return None


@pytest.fixture(scope="module")
def browser():
    """Debian's Chromium driven by Playwright (headless, no sandbox: tests may run as root), closed
    at the end of the module."""
    sync_api = pytest.importorskip("playwright.sync_api", reason="Playwright for Python is not installed (make test installs it)")
    exe = _chromium()
    if exe is None:
        pytest.skip("no Chromium on PATH (apt-get install chromium; .ci/run installs it)")
    with sync_api.sync_playwright() as pw:
        b = pw.chromium.launch(executable_path=exe, args=["--no-sandbox"], timeout=60_000)
        try:
            yield b
        finally:
            b.close()
