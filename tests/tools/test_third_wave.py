"""The third wave of mistakes (robot descriptions and the newer commands): no wrong answer with
exit 0, nothing the user gave lost, every option applied or refused, messages that name the real
cause, and no long silence.  Each case failed on the code before this wave."""
from __future__ import annotations

import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

from conftest import ROOT

SPECS = ROOT / "specs"
ROBOTS = ROOT / "tests" / "robots"


def gyro(*args, cwd, timeout=300, user=None):
    r = subprocess.run([sys.executable, "-m", "gyrochain", *map(str, args)], capture_output=True, text=True, cwd=cwd,
                       timeout=timeout, user=user, env={**os.environ, "PYTHONPATH": str(ROOT)})
    return r.returncode, r.stdout, r.stderr


def refused(*args, cwd, words: str) -> str:
    code, out, err = gyro(*args, cwd=cwd)
    assert code == 2 and err.count("\n") == 1 and err.startswith("error: "), (args, code, out, err)
    assert words in err and "Traceback" not in err, (words, err)
    return err


@pytest.fixture(scope="module")
def bench(tmp_path_factory):
    """A Furuta pendulum's simulated recordings (30 s and a held-out 10 s), and variants of the
    first as real files come: rates in deg/s, angles in degrees, time in ms, a torque of the wrong
    sign, a torque column for the passive joint, Excel's byte-order mark."""
    d = tmp_path_factory.mktemp("bench")
    shutil.copy(SPECS / "furuta.toml", d / "furuta.toml")
    base = ["excite", "furuta.toml", "--u-max", "0.05", "--period", "5", "--harmonics", "3", "--evaluations", "60"]
    for args in (["--experiment", "30", "-o", "data.csv"], ["--experiment", "10", "--seed", "1", "-o", "held.csv"]):
        code, _, err = gyro(*base, *args, cwd=d)
        assert code == 0, err
    data = np.genfromtxt(d / "data.csv", delimiter=",", names=True)
    t, p1, p2, u1 = data["t"], data["phi1"], data["phi2"], data["u1"]

    def save(name, cols, head):
        np.savetxt(d / name, np.column_stack(cols), delimiter=",", header=head, comments="", fmt="%.17g")

    deg = 180 / np.pi
    save("degps.csv", [t, p1, p2, np.gradient(p1, t) * deg, np.gradient(p2, t) * deg, u1], "t,phi1,phi2,phidot1,phidot2,u1")
    save("degrees.csv", [t, p1 * deg, p2 * deg, u1], "t,phi1,phi2,u1")
    save("ms.csv", [t * 1000, p1, p2, u1], "t,phi1,phi2,u1")
    save("flipped.csv", [t, p1, p2, -u1], "t,phi1,phi2,u1")
    save("passive_u.csv", [t, p1, p2, u1, 0.1 * u1], "t,phi1,phi2,u1,u2")
    (d / "bom.csv").write_text((d / "data.csv").read_text(), encoding="utf-8-sig")
    return d


# --------------------------------------------------------------------------- no wrong answer with exit 0
def test_an_excitation_respects_the_limits_it_is_given(tmp_path):
    """furuta's passive pendulum: torques at --u-max drove φ¹ to ±30 rad with --phi-max 1."""
    shutil.copy(SPECS / "furuta.toml", tmp_path / "furuta.toml")
    code, out, err = gyro("excite", "furuta.toml", "--harmonics", "3", "--evaluations", "60", "-o", "x.csv", cwd=tmp_path)
    assert code == 0, err
    d = np.genfromtxt(tmp_path / "x.csv", delimiter=",", names=True)
    assert max(abs(d["phi1"]).max(), abs(d["phi2"]).max()) <= 1.0 + 1e-9
    assert max(abs(d["phidot1"]).max(), abs(d["phidot2"]).max()) <= 2.0 + 1e-9
    assert "scaled to" in out  # and it says what it did to stay within them


@pytest.mark.parametrize("file, words", [
    ("degps.csv", "column 'phidot1' is not the derivative of phi1"),
    ("degrees.csv", "the CSV's units are N m, rad, rad/s and s"),  # φ in degrees: the spec's torques 170 times the measured
    ("passive_u.csv", "column 'u2': the spec has 1 control torque"),
    ("ms.csv", "is t in seconds"),
])
def test_data_in_other_units_or_columns_are_refused_not_fitted(bench, file, words):
    out = f"out_{file}.toml"
    refused("identify", "furuta.toml", file, "-o", out, cwd=bench, words=words)
    assert not (bench / out).exists()


def test_contradictory_data_print_no_estimates_even_with_physical(bench):
    err = refused("identify", "furuta.toml", "flipped.csv", "--physical", "-o", "out.toml", cwd=bench,
                  words="joint 1's measured torque runs against what the spec's parameters give")
    assert "No estimate is printed" in err and not (bench / "out.toml").exists()


def test_the_standard_errors_say_what_they_do_not_cover(bench):
    code, out, err = gyro("identify", "furuta.toml", "bom.csv", "-o", "bom_id.toml", cwd=bench)  # Excel's BOM read
    assert code == 0, err
    assert "standard errors: of the noise the residuals show; they assume the filter adds no bias" in out
    code, out, err = gyro("identify", "bom_id.toml", "data.csv", "-o", "again.toml", cwd=bench)  # its own output, again
    assert code == 0, err
    assert 'name = "furuta_identified"' in (bench / "again.toml").read_text()


# --------------------------------------------------------------------------- nothing the user gave is lost
@pytest.mark.parametrize("args, words", [
    (["data.csv", "--validate", "held.csv", "-o", "held.csv", "--force"], "-o held.csv: is a file the command reads"),
    (["data.csv", "--validate", "held.csv", "--plot", "furuta.toml", "--force"], "--plot furuta.toml: a picture is named"),
    (["data.csv", "--validate", "held.csv", "--plot", "data.csv.png", "-o", "data.csv.png"], "--plot data.csv.png"),
    (["data.csv", "-o", "furuta.toml", "--force"], "-o furuta.toml: is a file the command reads"),
])
def test_no_output_replaces_an_input(bench, args, words):
    before = {p.name: p.read_bytes() for p in bench.iterdir()}
    refused("identify", "furuta.toml", *args, cwd=bench, words=words)
    assert {p.name: p.read_bytes() for p in bench.iterdir()} == before


def test_an_interrupted_first_generate_leaves_no_empty_folder(tmp_path, monkeypatch):
    from gyrochain import pipeline

    def interrupted(files, name):
        raise KeyboardInterrupt

    monkeypatch.setattr(pipeline, "extension", interrupted)
    target = tmp_path / "generated" / "m"
    with pytest.raises(KeyboardInterrupt):
        pipeline.write_tree({"m.c": "int x;\n"}, target, True, "m")
    assert list(tmp_path.iterdir()) == []


# --------------------------------------------------------------------------- an option applies or is refused
@pytest.mark.parametrize("args, words", [
    (["excite", "furuta.toml", "--rate", "500"], "--rate: applies to --experiment"),
    (["excite", "furuta.toml", "--noise", "0.1", "-o", "x.csv"], "--noise: applies to --experiment"),
    (["identify", "furuta.toml", "data.csv", "--window", "0.3"], "--window: applies to --filter savgol"),
    (["identify", "furuta.toml", "data.csv", "--filter", "savgol", "--cutoff", "3"], "--cutoff: applies to --filter butter"),
    (["identify", "furuta.toml", "data.csv", "--plot", "fit.png"], "--plot: draws the held-out comparison"),
    (["fmu", "furuta.toml", "--kind", "me,me"], "--kind: expected me, cs or me,cs, got me,me"),
    (["simulate", "furuta.toml", "--t1", "0.1", "--t1", "0.2"], "--t1: given twice"),
    (["import", ROBOTS / "ur_description" / "ur5_robot.urdf", "-o", "a.toml", "-o", "b.toml"], "-o: given twice"),
    (["import", ROBOTS / "ur_description" / "ur5_robot.urdf", "--out", "a.toml", "--output", "b.toml"], "--out: given twice"),
    (["import", SPECS / "robots" / "panda.urdf", "--lock", "panda_finger_joint1=5", "--lock", "panda_finger_joint2=0"],
     "--lock panda_finger_joint1=5: outside the joint's limits, 0.0 to 0.04 m"),
    (["import", SPECS / "robots" / "panda.urdf", "--list", "--tip", "panda_link7"], "--list prints the tree"),
    (["examples", "copy", "gimbal", "kapitza", "-o", "two.toml"], "names a file, and 2 examples need a folder"),
])
def test_every_option_applies_or_is_refused(bench, args, words):
    refused(*args, cwd=bench, words=words)


def test_a_file_is_what_its_name_says(tmp_path):
    code, out, err = gyro("examples", "copy", "gimbal", "-o", "gimbal2.toml", cwd=tmp_path)
    assert code == 0 and (tmp_path / "gimbal2.toml").is_file(), err
    assert "generate gimbal2.toml" in out


# --------------------------------------------------------------------------- messages name the real cause
def test_a_folder_that_cannot_be_written_is_said_before_the_work(bench, tmp_path, monkeypatch, capsys):
    """A folder this user may not write in (root may write anywhere, so the permission is taken
    away where the product asks for it): one line naming the file and the folder, never our
    temporary file, and before the fit."""
    from gyrochain import cli, excite, files, identify, measured

    ro = tmp_path / "ro"
    ro.mkdir()
    for f in ("furuta.toml", "data.csv"):
        shutil.copy(bench / f, ro / f)
    real = os.access
    monkeypatch.setattr(files.os, "access", lambda p, mode: False if os.path.realpath(p) == str(ro) else real(p, mode))
    for module in (measured, identify, excite):  # where the commands call it (imported by name)
        monkeypatch.setattr(module, "compiled", lambda spec: pytest.fail("the work began"))
    monkeypatch.chdir(ro)
    for args in (["identify", "furuta.toml", "data.csv"], ["import", str(ROBOTS / "ur_description" / "ur5_robot.urdf")],
                 ["excite", "furuta.toml"]):
        code = cli.main(args)
        err = capsys.readouterr().err
        assert code == 2 and f"the folder {ro} is not writable (permission denied)" in err and ".tmp" not in err, err


def test_orbits_of_a_chain_with_motors_at_rest(tmp_path):
    """`control = true` (what import adds) with no torque given removes no integral."""
    code, _, err = gyro("new", "double-pendulum", "--control", "-o", "m.toml", cwd=tmp_path)
    assert code == 0, err
    code, out, err = gyro("orbits", "m.toml", cwd=tmp_path)
    assert code == 0 and "orbit" in out.lower(), err
    refused("orbits", "m.toml", "--u", "0.1,0", cwd=tmp_path, words="the control torques --u removed it")


def test_a_name_that_collides_with_a_shipped_header_is_refused(tmp_path):
    spec = (SPECS / "furuta.toml").read_text().replace('name = "furuta"', 'name = "fmi3Functions"')
    (tmp_path / "s.toml").write_text(spec)
    refused("check", "s.toml", cwd=tmp_path, words="collide with fmi3Functions.h")


def test_a_urdf_mass_too_small_to_write_is_said_as_such(tmp_path):
    (tmp_path / "r.urdf").write_text(
        '<robot name="r"><link name="a"/><link name="b"><inertial><mass value="1e-300"/><inertia ixx="0" iyy="0" izz="0" '
        'ixy="0" ixz="0" iyz="0"/></inertial></link><joint name="j" type="revolute"><parent link="a"/><child link="b"/>'
        '<axis xyz="0 1 0"/></joint></robot>')
    refused("import", "r.urdf", cwd=tmp_path, words="has a mass of 1.0e-300 kg, too small to be written")


# --------------------------------------------------------------------------- no work without a bound
def test_simulate_has_a_bound(tmp_path, monkeypatch):
    from gyrochain import simulate
    from gyrochain.errors import SpecError
    from gyrochain.spec import load_spec

    refused("simulate", SPECS / "furuta.toml", "--t1", "1e308", cwd=tmp_path, words="more than 1e+09 s")
    monkeypatch.setattr(simulate, "MAX_ADAPTIVE_STEPS", 500)
    with pytest.raises(SpecError, match="its budget of 5e\\+02 steps"):
        simulate.run(load_spec(SPECS / "furuta.toml"), [1.0, 1.0, 0.0, 0.0], 1000.0, 10)
