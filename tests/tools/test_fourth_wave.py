"""The fourth wave of mistakes, as rules: units and signs checked before anything is printed; a
design with too few samples refused; an option that cannot apply refused; the cheap checks before
the expensive work; a long read announced with its bound; file positions as an editor counts them;
output folders handled alike by every command, and named as the user named them; one message per
situation.  Each case failed on the code before this wave."""
from __future__ import annotations

import os
import shutil

import numpy as np
import pytest

from conftest import ROOT
from test_third_wave import bench, gyro, refused  # noqa: F401  (the recordings, and how a command is run)

SPECS = ROOT / "specs"


@pytest.fixture(scope="module")
def units(bench):  # noqa: F811
    """The bench's recording with its torque in N mm, and in N m of the wrong sign."""
    data = np.genfromtxt(bench / "data.csv", delimiter=",", names=True)
    cols = [data[k] for k in ("t", "phi1", "phi2", "u1")]
    for name, factor in (("nmm.csv", 1000.0), ("minus.csv", -1.0)):
        np.savetxt(bench / name, np.column_stack(cols[:3] + [cols[3] * factor]), delimiter=",", header="t,phi1,phi2,u1",
                   comments="", fmt="%.17g")
    return bench


@pytest.mark.parametrize("file, words", [
    ("nmm.csv", "joint 1's measured torque is 1e+03 times what the spec's parameters give for this motion"),
    ("minus.csv", "joint 1's measured torque runs against what the spec's parameters give"),
])
def test_units_and_signs_are_checked_before_anything_is_printed(units, file, words):
    code, out, err = gyro("identify", "furuta.toml", file, "-o", f"{file}.toml", cwd=units)
    assert code == 2 and out == "" and words in err and "No estimate is printed" in err, (out, err)
    assert not (units / f"{file}.toml").exists()


def test_the_plot_is_in_the_format_its_name_says(bench):  # noqa: F811
    code, out, err = gyro("identify", "furuta.toml", "data.csv", "--validate", "held.csv", "--plot", "fit.pdf", "-o",
                          "fit.toml", "--force", cwd=bench)
    assert code == 0, err
    assert (bench / "fit.pdf").read_bytes()[:5] == b"%PDF-"


@pytest.mark.parametrize("args, words", [
    (["excite", "furuta.toml", "--samples", "2"], "--samples: 2: expected at least 11 (more than two per period"),
    (["excite", "furuta.toml", "--harmonics", "8", "--samples", "16"], "--samples: 16: expected at least 17"),
    (["excite", "ur5.toml", "--u-max", "5"], "--u-max: applies to a chain with passive joints"),
    (["excite", "furuta.toml", "--phi-max", "0.01", "--phidot-max", "0.01", "--harmonics", "3", "--evaluations", "60"],
     "of the base regressor: its motion does not determine the base parameters"),
    (["steady", "furuta.toml", "--max-equilibria", "0"], "--max-equilibria: 0: expected at least 1 (leave it out"),
    (["steady", "furuta.toml", "--digits", "18"], "--digits: 18: expected 1 to 17 (a double holds 17 significant digits)"),
    (["orbits", "gimbal.toml", "--omega", "0"], "--omega: 0: a rotation at rate 0 is an equilibrium"),
    (["orbits", "gimbal.toml", "--omega", "-1:1:3"], "--omega: 0: a rotation at rate 0 is an equilibrium"),
    (["check", SPECS / "robots" / "ur5_robot.urdf"], "is a robot description (XML), not a spec: `gyrochain import "
                                                     "ur5_robot.urdf -o ur5_robot.toml`"),
    (["generate", ROOT / "tests" / "mjcf" / "styled" / "cheetah_leg.xml"], "`gyrochain import cheetah_leg.xml"),
])
def test_an_option_that_cannot_apply_is_refused(tmp_path, args, words):
    for name in ("furuta", "ur5", "gimbal"):
        shutil.copy(SPECS / f"{name}.toml", tmp_path / f"{name}.toml")
    refused(*args, cwd=tmp_path, words=words)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["furuta.toml", "gimbal.toml", "ur5.toml"]


def test_more_equilibria_than_seventeen_may_be_asked_for(tmp_path):
    shutil.copy(SPECS / "furuta.toml", tmp_path)
    code, out, err = gyro("steady", "furuta.toml", "--max-equilibria", "18", "--no-rotations", cwd=tmp_path)
    assert code == 0 and "equilibri" in out, err


def test_the_cheap_checks_come_before_the_model_is_built(tmp_path, monkeypatch, capsys):
    """excite on a spec without controls, or with an option that cannot apply: said before the
    model is derived and built (which took 5 s)."""
    from gyrochain import cli, excite

    monkeypatch.setattr(excite, "compiled", lambda spec: pytest.fail("the model was built first"))
    for spec, extra in (("gimbal", []), ("ur5", ["--u-max", "2"]), ("furuta", ["--samples", "3"])):
        shutil.copy(SPECS / f"{spec}.toml", tmp_path)
        assert cli.main(["excite", str(tmp_path / f"{spec}.toml"), "-o", str(tmp_path / "x.csv"), *extra]) == 2
        assert capsys.readouterr().err.startswith("error: ")


def test_a_bad_cell_is_said_on_its_line_as_an_editor_counts(tmp_path):
    """Blank lines and # comments in a recording: the line of a NaN, of a cell that is not a
    number, and of a t that does not increase, as an editor numbers the file's lines."""
    shutil.copy(SPECS / "furuta.toml", tmp_path)
    rows = [f"{0.01 * i:.2f},{0.1 * np.sin(i / 7):.6f},{0.1 * np.cos(i / 9):.6f},{0.05 * np.sin(i / 3):.6f}" for i in range(200)]

    def file(name, at, cell):
        lines = ["t,phi1,phi2,u1", "", "# recorded on the bench"] + rows[:100] + [""] + rows[100:]
        k = lines.index(rows[at])
        lines[k] = ",".join(v if j != 1 else cell for j, v in enumerate(rows[at].split(",")))
        (tmp_path / name).write_text("\n".join(lines) + "\n")
        return k + 1  # the line an editor shows

    line = file("nan.csv", 150, "nan")
    refused("identify", "furuta.toml", "nan.csv", cwd=tmp_path, words=f"line {line}, column 'phi1' is not finite")
    line = file("word.csv", 120, "1.2.3")
    refused("identify", "furuta.toml", "word.csv", cwd=tmp_path, words=f"on line {line}, column 2")
    lines = ["t,phi1,phi2,u1", ""] + rows[:50] + ["# a pause"] + [rows[10]] + rows[51:]
    (tmp_path / "back.csv").write_text("\n".join(lines) + "\n")
    refused("identify", "furuta.toml", "back.csv", cwd=tmp_path, words=f"t does not increase on line {lines.index(rows[10], 40) + 1}")


def test_a_long_read_is_announced_with_its_bound(tmp_path, monkeypatch, capsys):
    from gyrochain.models import files

    path = tmp_path / "big.csv"
    path.write_text("t,phi1\n" + "".join(f"{i},{i / 2}\n" for i in range(1000)))
    monkeypatch.setattr(files, "LONG_TABLE_BYTES", 1000)
    files.read_table(str(path), str(path), ["t"], "t, phi1")
    assert capsys.readouterr().err == f"reading {path}: 0 MiB, about 0 s\n"


def _immutable(folder) -> bool:
    """The folder made unwritable even for root (chattr +i); False where the file system cannot."""
    return shutil.which("chattr") is not None and os.system(f"chattr +i '{folder}' 2>/dev/null") == 0


@pytest.mark.parametrize("args", [
    ["generate", "gimbal.toml", "-o", "{ro}/gen", "--no-build", "-q"],
    ["sweep", "gimbal.toml", "--t1", "0.1", "-o", "{ro}/s.zarr"],
    ["animate", "gimbal.toml", "--t1", "0.1", "-o", "{ro}/x.gif"],
    ["import", str(SPECS / "robots" / "ur5_robot.urdf"), "-o", "{ro}/u.toml"],
    ["fmu", "gimbal.toml", "-o", "{ro}/x.fmu"],
    ["excite", "furuta.toml", "-o", "{ro}/e.csv"],
])
def test_a_folder_that_cannot_be_written_is_one_message_in_every_command(tmp_path, args):
    """Every command that writes: the same line, naming the user's path and the folder, before the
    work (generate, sweep and animate named our hidden temporary instead)."""
    for name in ("gimbal", "furuta"):
        shutil.copy(SPECS / f"{name}.toml", tmp_path)
    ro = tmp_path / "ro"
    ro.mkdir()
    if not _immutable(ro):
        pytest.skip("chattr +i is not available here: no folder root cannot write")
    try:
        args = [a.replace("{ro}", str(ro)) for a in args]
        err = refused(*args, cwd=tmp_path, words=f"error: {args[args.index('-o') + 1]}: cannot be written: the folder {ro} "
                                                   "is not writable (")
        assert ".tmp" not in err
    finally:
        os.system(f"chattr -i '{ro}'")


def test_a_path_of_ours_is_said_as_the_output_it_stands_for():
    from gyrochain.commandline.cli import users_path

    for ours, theirs in (("/a/b/.gen.tmp-7j7fih96", "/a/b/gen"), ("/a/.gen.tmp-7j7fih96/gen.c", "/a/gen"),
                         ("out/.x.tmp-123.gif", "out/x.gif"), (".x.toml.tmp-123", "x.toml"), ("p/.f.png.tmp", "p/f.png"),
                         ("/a/plain.csv", "/a/plain.csv")):
        assert users_path(ours) == theirs


@pytest.mark.parametrize("args", [
    ["import", str(SPECS / "robots" / "ur5_robot.urdf"), "-o", "new/a/k.toml"],
    ["export", "double_pendulum.toml", "--to", "urdf", "-o", "new/b/d.urdf"],
    ["fmu", "double_pendulum.toml", "-o", "new/c/x.fmu"],
    ["generate", "double_pendulum.toml", "-o", "new/d/gen", "--no-build", "-q"],
    ["animate", "double_pendulum.toml", "--t1", "0.1", "-o", "new/e/x.gif"],
])
def test_every_command_makes_the_folder_it_is_told_to_write_in(tmp_path, args):
    """One rule for output folders: a missing folder (its parents too) is made, as `generate`
    always made its own, and the command's line names the path."""
    shutil.copy(SPECS / "double_pendulum.toml", tmp_path)
    code, out, err = gyro(*args, cwd=tmp_path)
    assert code == 0, err
    path = args[args.index("-o") + 1]
    assert (tmp_path / path).exists() and path.rstrip("/") in out + err


def test_a_store_of_one_run_is_not_a_plot(tmp_path):
    shutil.copy(SPECS / "gimbal.toml", tmp_path)
    code, _, err = gyro("sweep", "gimbal.toml", "--t1", "0.1", "-o", "one.zarr", cwd=tmp_path)
    assert code == 0, err
    refused("plot", "one.zarr", "-o", "p.png", cwd=tmp_path, words="holds one run (its sweep varied nothing)")


def test_the_spec_s_limits_set_excite_s_defaults_and_check_identify_s_data(units):
    """A spec with joint limits: excite's design stays within 90 % of the way to them by default
    (and says so); identify refuses a recording that leaves a range or runs at twice an effort
    limit, before any fit."""
    limited = (units / "furuta.toml").read_text().replace(
        "control = true           # motor torque on the arm", "control = true\nlimits = {lower = -1.0, upper = 3.0, effort = 0.3}")
    (units / "limited.toml").write_text(limited)
    code, out, err = gyro("excite", "limited.toml", "--harmonics", "3", "--evaluations", "60", "-o", "lim.csv", "--force",
                          cwd=units)
    assert code == 0, err
    assert "from the spec's joint limits: --center, --phi-max, --u-max (the middle of each range, 90% of the way" in out
    d = np.genfromtxt(units / "lim.csv", delimiter=",", names=True)
    assert np.all(np.abs(d["phi1"] - 1.0) <= 0.9 * 2.0 + 1e-9) and np.all(np.abs(d["u1"]) <= 0.9 * 0.3 + 1e-12)
    assert abs(d["phi1"] - 1.0).max() > 1.0  # it uses the range, beyond the 1 rad of a spec without limits
    refused("identify", "limited.toml", "degrees.csv", cwd=units, words="beyond joint 1's range -1 to 3 rad by more than 0.1 rad")
    refused("identify", "limited.toml", "nmm.csv", cwd=units, words="times joint 1's effort limit 0.3 N m (the spec's limits): "
                                                                     "other units (N mm?)")
    one_sided = limited.replace("limits = {lower = -1.0, upper = 3.0, effort = 0.3}", "limits = {lower = 0.5}")
    (units / "one_sided.toml").write_text(one_sided)  # one bound alone: the design stays above it, the data must too
    code, out, err = gyro("excite", "one_sided.toml", "--harmonics", "3", "--evaluations", "60", "-o", "one.csv", "--force",
                          cwd=units)
    assert code == 0, err
    assert np.genfromtxt(units / "one.csv", delimiter=",", names=True)["phi1"].min() >= 0.5
    refused("identify", "one_sided.toml", "data.csv", cwd=units, words="beyond joint 1's lower limit 0.5 rad")
    refused("excite", "limited.toml", "--phi-max", "2.5", cwd=units, words="--phi-max: 2.5 about the centre 1 reaches past "
                                                                             "joint 1's range, -1 to 3 rad")
    code, out, err = gyro("identify", "limited.toml", "data.csv", "-o", "lim_id.toml", cwd=units)
    assert code == 0, err


def test_a_design_of_driven_joints_keeps_their_effort_limits(tmp_path):
    """Every joint driven: the torques follow from the designed trajectories; beyond a joint's
    effort limit the design is refused (it was written, and said to keep the limit)."""
    spec = (SPECS / "planar2dof.toml").read_text()
    body = spec.index("[[body]]")
    end = spec.index("[[body]]", body + 1)
    first = spec[body:end].rstrip("\n") + "\nlimits = {lower = -2, upper = 2, velocity = 3, effort = 0.01}\n\n"
    (tmp_path / "weak.toml").write_text(spec[:body] + first + spec[end:])
    refused("excite", "weak.toml", "--evaluations", "60", cwd=tmp_path, words="the design's torque u1 reaches")
    assert not (tmp_path / "weak_excite.csv").exists()


def test_the_savitzky_golay_bias_is_in_the_standard_errors(bench, tmp_path):  # noqa: F811
    """Exact data (no noise, exact angles) and --filter savgol: the derivative filters' bias left
    estimates 30 standard errors from the spec's values with exit 0; the standard errors now hold
    the estimates' change with a longer window, and the truth lies within three of them."""
    from gyrochain import identify
    from gyrochain.identification.measured import Filter
    from gyrochain.spec import load_spec

    code, _, err = gyro("excite", "furuta.toml", "--u-max", "0.05", "--period", "5", "--harmonics", "3", "--evaluations",
                        "60", "--experiment", "30", "--noise", "0", "--encoder", "0", "-o", tmp_path / "exact.csv", cwd=bench)
    assert code == 0, err
    said = []
    fig = identify.run(load_spec(bench / "furuta.toml"), str(tmp_path / "exact.csv"), {}, str(tmp_path / "id.toml"), False,
                       how=Filter(kind="savgol"), say=said.append)
    far = np.abs(fig["beta"] - fig["beta_spec"]) / fig["se"]
    assert far.max() <= 3.0, far
    assert any("and of the filter's bias (the estimates' change with a window of 0.3 s" in line for line in said)


def test_an_import_s_mistakes_name_what_the_user_gave(tmp_path):
    """A bad value in the file is said of its joint (not body[1] of a spec the user never saw); a
    clashing name asks for --name; --g is named; --g over a file that disables gravity is said so;
    MuJoCo's warnings become comments, not stderr lines and a MUJOCO_LOG.TXT in the user's folder."""
    pytest.importorskip("mujoco", reason="MuJoCo compiles MJCF")
    body = '<body name="l1" pos="0 0 1"><joint name="j1" axis="0 1 0"{extra}/><geom type="capsule" fromto="0 0 0 .3 0 0" size=".02"/></body>'
    negative = body.format(extra=' armature="-0.1"')
    (tmp_path / "neg.xml").write_text(f'<mujoco model="negarm"><worldbody>{negative}</worldbody></mujoco>')
    refused("import", "neg.xml", cwd=tmp_path, words="error: neg.xml: joint 'j1': a motor's reflected inertia is not negative")
    (tmp_path / "r.xml").write_text(f'<mujoco model="r"><worldbody>{body.format(extra="")}</worldbody></mujoco>')
    refused("import", "r.xml", cwd=tmp_path, words="error: r.xml: robot name 'r': ")
    refused("import", "r.xml", "--name", "if", cwd=tmp_path, words="error: --name if: ")
    refused("import", "r.xml", "--name", "arm", "--g", "-1", cwd=tmp_path, words="error: --g -1: ")
    (tmp_path / "off.xml").write_text('<mujoco model="off"><option><flag gravity="disable"/></option><worldbody>'
                                      f'{body.format(extra="")}</worldbody></mujoco>')
    code, out, err = gyro("import", "off.xml", "--name", "arm", "--g", "9.81", "-o", "-", cwd=tmp_path)
    assert code == 0 and "# gravity 9.81 (--g), where the file has 0" in out and "\ng = 9.81\n" in out, (out, err)
    code, out, err = gyro("import", ROOT / "tests" / "mjcf" / "dm_control" / "cheetah.xml", "--base", "torso", "--tip", "ffoot",
                          "-o", "c.toml", cwd=tmp_path)
    assert code == 0 and "WARNING" not in err and not (tmp_path / "MUJOCO_LOG.TXT").exists(), err
    assert "# MuJoCo's compiler warned: compiler attribute 'settotalmass' is deprecated" in (tmp_path / "c.toml").read_text()


def test_a_plot_goes_where_it_is_told(bench):  # noqa: F811
    """identify --plot into a folder that does not exist yet: made, as every command makes it (it
    failed after the fit, naming a temporary file)."""
    code, out, err = gyro("identify", "furuta.toml", "data.csv", "--validate", "held.csv", "--plot", "new/plots/fit.png",
                          "-o", "new/fit.toml", cwd=bench)
    assert code == 0, err
    assert (bench / "new" / "plots" / "fit.png").read_bytes()[:4] == b"\x89PNG"
