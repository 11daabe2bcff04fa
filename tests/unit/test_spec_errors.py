"""Bad specs: one line on stderr naming the field, exit status 2, nothing written (check and\ngenerate --no-build, in this process: no compiler)."""
from __future__ import annotations

import contextlib
import io
import subprocess
import sys

import pytest

from gyrochain.cli import main
from conftest import ROOT

GOOD = (ROOT / "specs" / "furuta.toml").read_text()
BODY2 = """
[[body]]
theta = "pi/2"
m = 0.1
c = [0.0, 0.0, 0.15]
A = [[0.003, 0.0, 0.0], [0.0, 0.003, 0.0], [0.0, 0.0, 0.00001]]
"""


def spec(body1: str = "", top: str = 'name = "bad"\ng = 9.81\n', body2: str = BODY2) -> str:
    b1 = body1 or """theta = 0.0
m = 0.3
c = [0.0, 0.0, -0.1]
A = [[0.0042, 0.0, 0.0], [0.0, 0.0041, 0.0], [0.0, 0.0, 0.0002]]
s = [0.0, 0.0, -0.2]
"""
    return top + "\n[[body]]\n" + b1 + body2


def replace_body1(line_key: str, new_line: str) -> str:
    b1 = """theta = 0.0
m = 0.3
c = [0.0, 0.0, -0.1]
A = [[0.0042, 0.0, 0.0], [0.0, 0.0041, 0.0], [0.0, 0.0, 0.0002]]
s = [0.0, 0.0, -0.2]
"""
    lines = [new_line if ln.startswith(line_key + " ") else ln for ln in b1.splitlines()]
    if not any(ln.startswith(line_key + " ") for ln in b1.splitlines()):
        lines.append(new_line)
    return spec("\n".join(l for l in lines if l) + "\n")


CASES = [
    # (id, spec text, field named in the message, words in the message)
    ("missing-top", 'g = 9.81\n[[body]]\ntheta = 0\nm = 1\nc = [0,0,0]\nA = [[1,0,0],[0,1,0],[0,0,1]]\n', "name", "missing"),
    ("missing-body-field", replace_body1("m", ""), "body[1].m", "missing"),
    ("missing-s", replace_body1("s", ""), "body[1].s", "missing"),
    ("unknown-top", spec(top='name = "bad"\ng = 9.81\ncolour = "red"\n'), "colour", "unknown field"),
    ("unknown-body", replace_body1("mass", "mass = 2.0"), "body[1].mass", "unknown field"),
    ("typo-body", replace_body1("lambda", "lamda = [0, 0, 1]"), "body[1].lamda", "unknown field (did you mean lambda?"),
    ("s-on-last", spec(body2=BODY2 + "s = [0.0, 0.0, 1.0]\n"), "body[2].s", "last body"),
    ("vector-shape", replace_body1("c", "c = [0.0, 0.1]"), "body[1].c", "3 entries"),
    ("matrix-shape", replace_body1("A", "A = [[0.004, 0.0], [0.0, 0.004]]"), "body[1].A", "3×3"),
    ("non-numeric", replace_body1("m", "m = true"), "body[1].m", "boolean"),
    ("non-numeric-list", replace_body1("c", 'c = [0.0, [1.0], 0.0]'), "body[1].c[2]", "expected a number"),
    ("nan", replace_body1("m", "m = nan"), "body[1].m", "not a finite"),
    ("inf", replace_body1("c", "c = [0.0, inf, 0.0]"), "body[1].c[2]", "not a finite"),
    ("mass-negative", replace_body1("m", "m = -1.0"), "body[1].m", "positive"),
    ("A-asymmetric", replace_body1("A", "A = [[0.0042, 0.001, 0.0], [0.0, 0.0041, 0.0], [0.0, 0.0, 0.0002]]"), "body[1].A", "not symmetric"),
    ("A-not-pd", replace_body1("A", "A = [[0.0042, 0.0, 0.0], [0.0, 0.0041, 0.0], [0.0, 0.0, -0.0002]]"), "body[1].A", "negative principal moment"),
    ("A-below-parallel-axis", replace_body1("A", "A = [[0.001, 0.0, 0.0], [0.0, 0.001, 0.0], [0.0, 0.0, 0.0002]]"), "body[1].A", "negative principal moment"),
    ("A-triangle", replace_body1("A", "A = [[0.0042, 0.0, 0.0], [0.0, 0.0033, 0.0], [0.0, 0.0, 0.0002]]"), "body[1].A", "triangle"),
    ("name-not-identifier", spec(top='name = "my-pendulum"\ng = 9.81\n'), "name", "not a C identifier"),
    ("name-keyword", spec(top='name = "double"\ng = 9.81\n'), "name", "keyword"),
    ("param-not-identifier", replace_body1("m", 'm = "μ1"'), "body[1].m", "not an identifier"),
    ("param-keyword", replace_body1("m", 'm = "int"'), "body[1].m", "keyword"),
    ("param-collides-state", replace_body1("m", 'm = "phi_1"'), "body[1].m", "collides"),
    ("param-collides-arg", replace_body1("m", 'm = "x"'), "body[1].m", "collides"),
    ("param-collides-temp", replace_body1("m", 'm = "w3"'), "body[1].m", "collides"),
    ("expr-syntax", replace_body1("m", 'm = "2*(l"'), "body[1].m", "does not parse"),
    ("expr-caret", replace_body1("m", 'm = "l^2"'), "body[1].m", "'**'"),
    ("expr-call", replace_body1("m", 'm = "__import__(1)"'), "body[1].m", "may be called"),
    ("expr-attribute", replace_body1("m", 'm = "l.real"'), "body[1].m", "not allowed"),
    ("expr-huge-power", replace_body1("m", 'm = "10**10**10"'), "body[1].m", "exponent"),
    ("expr-div-zero", replace_body1("m", 'm = "1/0"'), "body[1].m", "division by zero"),
    ("n-zero", 'name = "bad"\ng = 9.81\nbody = []\n', "body", "n = 0"),
    ("not-toml", 'name = "bad"\ng = = 9.81\n', "spec", "not valid TOML"),
    ("g-negative", spec(top='name = "bad"\ng = -9.81\n'), "g", "negative"),
    # the general case (8)–(10)
    ("base-unknown", spec(top='name = "bad"\ng = 9.81\n[base]\nspin = 1\n'), "base.spin", "unknown field"),
    ("base-position-shape", spec(top='name = "bad"\ng = 9.81\n[base]\nposition = ["t", "0"]\n'), "base.position", "3 entries"),
    ("base-position-state", spec(top='name = "bad"\ng = 9.81\n[base]\nposition = ["phi1", 0, 0]\n'), "base.position[1]", "prescribed"),
    ("base-position-unknown-body", spec(top='name = "bad"\ng = 9.81\n[base]\nposition = ["phi3", 0, 0]\n'), "base.position[1]", "unknown symbol"),
    ("base-axis-zero", spec(top='name = "bad"\ng = 9.81\n[base]\nrotation = [{axis = [0, 0, 0], angle = "t"}]\n'), "base.rotation[1].axis", "zero length"),
    ("base-rotation-missing-angle", spec(top='name = "bad"\ng = 9.81\n[base]\nrotation = [{axis = [1, 0, 0]}]\n'), "base.rotation[1].angle", "missing"),
    ("base-rotation-not-list", spec(top='name = "bad"\ng = 9.81\n[base]\nrotation = 3\n'), "base.rotation", "list of tables"),
    ("t-in-constant", replace_body1("m", 'm = "1 + t"'), "body[1].m", "'t' is not allowed"),
    ("state-in-lambda", replace_body1("lambda", 'lambda = ["phidot1", 0, 0]'), "body[1].lambda[1]", "prescribed"),
    ("rest-without-spring", replace_body1("rest", "rest = 0.1"), "body[1].rest", "without a spring"),
    ("spring-negative", replace_body1("spring", "spring = -1.0"), "body[1].spring", "negative"),
    ("damping-negative", replace_body1("damping", "damping = -0.1"), "body[1].damping", "negative"),
    ("torque-unknown-body", replace_body1("torque", 'torque = "-0.1*phidot7"'), "body[1].torque", "unknown symbol"),
    ("torque-syntax", replace_body1("torque", 'torque = "sin(t"'), "body[1].torque", "does not parse"),
    ("force-frame", spec(body2=BODY2 + '[[body.force]]\npoint = [0, 0, 1]\nF = [0, 0, 1]\nframe = "world"\n'), "body[2].force[1].frame", "\"body\" or \"fixed\""),
    ("force-components", spec(body2=BODY2 + '[[body.force]]\npoint = [0, 0, 1]\nF = [0, 1]\nframe = "body"\n'), "body[2].force[1].F", "3 entries"),
    ("force-missing-point", spec(body2=BODY2 + '[[body.force]]\nF = [0, 0, 1]\nframe = "body"\n'), "body[2].force[1].point", "missing"),
    ("force-point-state", spec(body2=BODY2 + '[[body.force]]\npoint = [0, 0, "phi1"]\nF = [0, 0, 1]\nframe = "body"\n'), "body[2].force[1].point[3]", "constant"),
    ("moment-unknown", spec(body2=BODY2 + '[[body.moment]]\nM = [0, 0, 1]\nframe = "body"\npoint = [0, 0, 0]\n'), "body[2].moment[1].point", "unknown field"),
    ("force-not-table", spec(body2=BODY2 + 'force = 3\n'), "body[2].force", "expected"),
    # the inertia and the rotor as CAD, URDF and MuJoCo give them (A or I_c, 3×3 or six numbers)
    ("A-and-I_c", replace_body1("I_c", "I_c = [0.001, 0.001, 0.0002, 0, 0, 0]"), "body[1].A", "give the inertia once"),
    ("no-inertia", replace_body1("A", ""), "body[1].A", "missing field"),
    ("tensor-five-numbers", replace_body1("A", "A = [0.0042, 0.0041, 0.0002, 0.0, 0.0]"), "body[1].A", "six numbers"),
    ("A-asymmetric-beyond-round-off", replace_body1("A", "A = [[0.0042, 1e-9, 0.0], [0.0, 0.0041, 0.0], [0.0, 0.0, 0.0002]]"),
     "body[1].A", "more than round-off"),
    ("I_c-not-pd", replace_body1("A", "I_c = [0.0042, 0.0041, -0.0002, 0, 0, 0]"), "body[1].I_c", "negative principal moment"),
    ("I_c-asymmetric", replace_body1("A", "I_c = [[0.001, 0.0002, 0], [0, 0.001, 0], [0, 0, 0.0005]]"), "body[1].I_c", "not symmetric"),
    ("rotor-and-lambda", replace_body1("rotor", "lambda = [0, 0, 1]\nrotor = {axis = [0, 0, 1], inertia = 2e-4, speed = 500}"),
     "body[1].rotor", "give the rotor once"),
    ("rotor-negative-inertia", replace_body1("rotor", "rotor = {axis = [0, 0, 1], inertia = -2e-4, speed = 500}"),
     "body[1].rotor.inertia", "positive"),
    ("rotor-zero-inertia", replace_body1("rotor", "rotor = {axis = [0, 0, 1], inertia = 0, speed = 500}"), "body[1].rotor.inertia", "positive"),
    ("rotor-zero-axis", replace_body1("rotor", "rotor = {axis = [0, 0, 0], inertia = 2e-4, speed = 500}"), "body[1].rotor.axis", "zero axis"),
    ("rotor-axis-shape", replace_body1("rotor", "rotor = {axis = [0, 1], inertia = 2e-4, speed = 500}"), "body[1].rotor.axis", "3 entries"),
    ("rotor-missing-speed", replace_body1("rotor", "rotor = {axis = [0, 0, 1], inertia = 2e-4}"), "body[1].rotor.speed", "missing"),
    ("rotor-unknown", replace_body1("rotor", "rotor = {axis = [0, 0, 1], inertia = 2e-4, speed = 500, mass = 1}"), "body[1].rotor.mass", "unknown field"),
    ("rotor-not-table", replace_body1("rotor", "rotor = 3"), "body[1].rotor", "expected a table"),
    ("rotor-speed-of-state", replace_body1("rotor", 'rotor = {axis = [0, 0, 1], inertia = 2e-4, speed = "phidot1"}'),
     "body[1].rotor.speed", "prescribed"),
    # issue 26: names sympy, Python or C give a meaning are not parameters; [values]; expressions that
    # would not finish; a slender rod's moments still obey the triangle inequality
    ("param-nan", replace_body1("m", 'm = "nan"'), "body[1].m", "reserved"),
    ("param-inf", replace_body1("m", 'm = "Inf"'), "body[1].m", "reserved"),
    ("param-E", replace_body1("m", 'm = "2*E"'), "body[1].m", "reserved"),
    ("param-I", replace_body1("m", 'm = "I"'), "body[1].m", "reserved"),
    ("param-M_PI", replace_body1("m", 'm = "M_PI"'), "body[1].m", "reserved"),
    ("values-unknown", replace_body1("m", 'm = "heavy"') + '\n[values]\nlight = 1.0\n', "values.light", "not a parameter"),
    ("values-negative-mass", replace_body1("m", 'm = "heavy"') + '\n[values]\nheavy = -1.0\n', "body[1].m", "mass must be positive"),
    ("values-nan", replace_body1("m", 'm = "heavy"') + '\n[values]\nheavy = nan\n', "values.heavy", "not a finite"),
    ("values-expression-of-names", replace_body1("m", 'm = "heavy"') + '\n[values]\nheavy = "2*light"\n', "values.heavy", "must be a number"),
    ("values-not-table", spec(top='name = "bad"\ng = 9.81\nvalues = 3\n'), "values", "expected a table"),
    ("values-inertia", replace_body1("A", 'A = [["J", 0, 0], [0, "J", 0], [0, 0, 0.0002]]') + '\n[values]\nJ = 0.0001\n',
     "body[1].A", "negative principal moment"),
    ("expr-tower", replace_body1("m", 'm = "9**9**9"'), "body[1].m", "exponent"),
    ("expr-long", replace_body1("m", 'm = "' + "1+" * 100_000 + '1"'), "body[1].m", "longer than"),
    ("expr-deep-negative", replace_body1("m", 'm = "' + "-(" * 65 + "1" + ")" * 65 + '"'), "body[1].m", "mass must be positive"),
    ("rod-triangle", replace_body1("A", "I_c = [0.0, 0.001, 0.003, 0, 0, 0]"), "body[1].I_c", "triangle inequality"),
    ("armature-negative", replace_body1("armature", "armature = -0.1"), "body[1].armature", "not negative"),
    ("disturbance-not-bool", replace_body1("disturbance", "disturbance = 1"), "body[1].disturbance", "true or false"),
    ("disturbance-and-control", spec(body2=BODY2 + "control = true\ndisturbance = true\n"), "body[2].disturbance",
     "adds to u"),
    ("limits-not-table", replace_body1("limits", "limits = [-1, 1]"), "body[1].limits", "expected a table"),
    ("limits-typo", replace_body1("limits", "limits = {lower = -1, uper = 1}"), "body[1].limits.uper", "did you mean upper?"),
    ("limits-empty-range", replace_body1("limits", "limits = {lower = 1, upper = -1}"), "body[1].limits.upper", "not above lower"),
    ("limits-speed", replace_body1("limits", "limits = {velocity = 0}"), "body[1].limits.velocity", "must be positive"),
    ("limits-effort", replace_body1("limits", "limits = {effort = -5}"), "body[1].limits.effort", "must be positive"),
    ("limits-parameter", replace_body1("limits", 'limits = {upper = "qmax"}'), "body[1].limits.upper", "limits are data"),
    ("limits-inf", replace_body1("limits", "limits = {upper = inf}"), "body[1].limits.upper", "finite"),
]


def run(*args):
    """The command in this process (cli.main, as `python -m gyrochain` runs it): its exit status
    and what it printed (test_missing_file runs the real entry point once)."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(list(args))
    return subprocess.CompletedProcess(args, code, out.getvalue(), err.getvalue())


@pytest.mark.parametrize("case_id,text,field,words", CASES, ids=[c[0] for c in CASES])
def test_bad_spec_is_rejected_with_one_line_and_nothing_written(tmp_path, case_id, text, field, words):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    out = tmp_path / "out"
    for cmd in (["generate", str(path), "-o", str(out), "--no-build"], ["check", str(path)]):
        res = run(*cmd)
        assert res.returncode == 2, (cmd, res.stdout, res.stderr)
        lines = [ln for ln in res.stderr.splitlines() if ln.strip()]
        assert len(lines) == 1, res.stderr
        assert lines[0].startswith(f"error: {field}:"), lines[0]
        assert words in lines[0], lines[0]
    assert not out.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.toml"]  # no temporary left behind


def test_good_spec_passes_check(tmp_path):
    path = tmp_path / "good.toml"
    path.write_text(spec())
    res = run("check", str(path))
    assert res.returncode == 0, res.stderr
    assert "ok" in res.stdout


def test_missing_file(tmp_path):
    res = run("check", str(tmp_path / "nope.toml"))
    assert res.returncode == 2 and "no such file" in res.stderr
    res = subprocess.run([sys.executable, "-m", "gyrochain", "check", str(tmp_path / "nope.toml")], capture_output=True,
                         text=True, cwd=ROOT)
    assert res.returncode == 2 and res.stderr.count("\n") == 1 and "no such file" in res.stderr


def test_refuses_to_replace_a_folder_gyrochain_did_not_write(tmp_path):
    path = tmp_path / "good.toml"
    path.write_text(spec())
    out = tmp_path / "mine"
    out.mkdir()
    (out / "notes.txt").write_text("precious")
    res = run("generate", str(path), "-o", str(out), "--no-build")
    assert res.returncode == 2 and "-o:" in res.stderr and "--force" in res.stderr
    assert (out / "notes.txt").read_text() == "precious"
    assert sorted(p.name for p in out.iterdir()) == ["notes.txt"]


def test_regenerating_replaces_own_output(tmp_path):
    path = tmp_path / "good.toml"
    path.write_text(spec())
    out = tmp_path / "gen"
    assert run("generate", str(path), "-o", str(out), "--no-build", "-q").returncode == 0
    first = {p.name: p.read_bytes() for p in out.iterdir()}
    assert run("generate", str(path), "-o", str(out), "--no-build", "-q").returncode == 0
    assert {p.name: p.read_bytes() for p in out.iterdir()} == first
    assert sorted(p.name for p in tmp_path.iterdir()) == ["gen", "good.toml"]
