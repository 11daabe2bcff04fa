"""``generate``'s self-check: the emitted model is held to the independent model before anything is
written, so a defect of the generator is one internal-error line and no files, never a wrong model
with exit 0.  Each test plants a defect where one could hide — the derivation's old shortcut for
θ = π, one sign in the C template, one in the Python template — and checks that ``generate``
refuses, names the function, and leaves the output folder as it was."""
from __future__ import annotations

import hashlib
import shutil

import pytest

from gyrochain import pipeline
from gyrochain.derive import kinematics
from gyrochain.models import selfcheck
from gyrochain.printers import common
from conftest import ROOT, cli_in_process

FLIPPED = ROOT / "tests" / "models" / "data" / "flipped3.urdf"


def _tree(folder):
    return {p.relative_to(folder).as_posix(): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(folder.rglob("*")) if p.is_file()}


def _refused(result, function: str, what: str) -> None:
    lines = [ln for ln in result.stderr.splitlines() if ln.strip()]
    assert result.returncode == 1, (result.returncode, result.stderr)
    assert len(lines) == 1 and lines[0].startswith("error: internal error"), result.stderr
    assert "EmittedModelError" in lines[0] and f"the emitted {what} {function} differs from the independent model" in lines[0]
    assert "nothing was written" in lines[0] and "phi = (" in lines[0]


@pytest.fixture
def flipped(tmp_path):
    """flipped3.urdf imported (θ = π between its second and third axes), in an empty folder."""
    result = cli_in_process("import", FLIPPED, cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    return tmp_path


@pytest.fixture
def forgetful():
    """The renderings and derivations this process keeps are dropped before and after (a planted
    defect must reach the printers, and must not stay for the next test)."""
    pipeline.forget()
    yield
    pipeline.forget()


@pytest.mark.parametrize("build", [True, False], ids=["C", "Python"])
def test_the_old_shortcut_for_theta_pi_is_refused_and_nothing_is_written(flipped, build, monkeypatch, forgetful):
    """The derivation's shortcut that took R₂(π) for the identity (kinematics.Joint.is_planar
    checked sin θ only): articulated φ̈ wrong by O(1), caught in the C (built) and in the Python
    mirror (--no-build)."""
    monkeypatch.setattr(kinematics.Joint, "is_planar", lambda self: self.st.is_zero())
    args = ["generate", "-q", "flipped3.toml", "--qdd-form", "articulated", *(() if build else ("--no-build",))]
    _refused(cli_in_process(*args, cwd=flipped), "flipped3_qdd", "C" if build else "Python")
    assert not (flipped / "generated").exists()


def test_a_wrong_sign_in_the_c_template_leaves_the_folder_as_it_was(flipped, tmp_path_factory, monkeypatch, forgetful):
    """A folder from a good generation, then one sign flipped in model_dynamics.c.jinja (φ̈ of the
    composite form, after the solve): the next generate refuses and every file of the folder is as
    it was."""
    assert cli_in_process("generate", "-q", "flipped3.toml", cwd=flipped).returncode == 0
    before = _tree(flipped / "generated")
    templates = tmp_path_factory.mktemp("templates") / "templates"
    shutil.copytree(common.TEMPLATES, templates)
    src = (templates / "model_dynamics.c.jinja").read_text()
    old = "        qdd[i] = f[i];\n"
    assert src.count(old) == 1
    (templates / "model_dynamics.c.jinja").write_text(src.replace(old, "        qdd[i] = -f[i];\n"))
    monkeypatch.setattr(common, "TEMPLATES", templates)
    result = cli_in_process("generate", "-q", "flipped3.toml", "--qdd-form", "composite", cwd=flipped)
    _refused(result, "flipped3_qdd", "C")
    assert _tree(flipped / "generated") == before


def test_a_wrong_sign_in_the_python_template_is_refused(flipped, tmp_path_factory, monkeypatch, forgetful):
    templates = tmp_path_factory.mktemp("templates") / "templates"
    shutil.copytree(common.TEMPLATES, templates)
    src = (templates / "model.py.jinja").read_text()
    old = "        y[i] -= L[i, :i] @ y[:i]\n"
    assert src.count(old) == 1
    (templates / "model.py.jinja").write_text(src.replace(old, "        y[i] += L[i, :i] @ y[:i]\n"))
    monkeypatch.setattr(common, "TEMPLATES", templates)
    result = cli_in_process("generate", "-q", "flipped3.toml", "--qdd-form", "composite", cwd=flipped)
    _refused(result, "flipped3_qdd", "Python")
    assert not (flipped / "generated").exists()


def test_the_check_passes_the_correct_model_and_states_its_states(flipped, forgetful):
    """The same generation without a defect: exit 0, the self-check's step in the progress and
    what it compared in the report."""
    result = cli_in_process("generate", "flipped3.toml", "--qdd-form", "articulated", cwd=flipped)
    assert result.returncode == 0, result.stderr
    assert f"the self-check: the emitted C and Python against the independent model at {selfcheck.STATES} random states" in result.stderr
    line = next(ln for ln in result.stdout.splitlines() if ln.startswith("self-check: "))
    assert line.startswith(f"self-check: the emitted C and Python equal the independent model at {selfcheck.STATES} random states (")
    compared = line.split(" (", 1)[1].split(";")[0].split(", ")
    assert {"mass_matrix", "forces", "qdd", "rhs", "qdd_derivatives", "linearize", "energy", "integrate"} <= set(compared)
    result = cli_in_process("generate", "-q", "flipped3.toml", "--no-build", "-o", "py", cwd=flipped)
    assert "self-check: the emitted Python equal the independent model" in result.stdout
