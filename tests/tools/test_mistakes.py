"""The mistakes people make with the commands (issue 26): each one ends in one line on stderr
``error: <what>: <why>``, exit 2, nothing written, within seconds; and the friction that was no
mistake at all (a negative list, no --u, no --param) is gone."""
from __future__ import annotations

import os
import re
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from gyrochain import __version__, cli, pipeline
from gyrochain.cli import main
from conftest import ROOT, cli_in_process

SPECS = ROOT / "specs"


def run(*args):
    """The command in this process (as `python -m gyrochain` runs it): status, stdout, stderr, seconds."""
    t0 = time.perf_counter()
    res = cli_in_process(*args, cwd=Path.cwd())
    return res.returncode, res.stdout, res.stderr, time.perf_counter() - t0


def refused(field: str, *args, words: str = "", within: float = 30.0) -> str:
    code, out, err, dt = run(*args)
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert code == 2, (args, code, out, err)
    assert len(lines) == 1, err
    assert lines[0].startswith(f"error: {field}"), lines[0]
    assert words in lines[0], lines[0]
    assert "Traceback" not in err and dt < within, dt
    return lines[0]


def nothing_in(folder: Path, *keep: str) -> None:
    assert sorted(p.name for p in folder.iterdir()) == sorted(keep)


# --------------------------------------------------------------------------- wrong parameter names and values
@pytest.mark.parametrize("command", ["simulate", "animate", "steady", "sweep"])
def test_a_wrong_param_name_is_refused_by_every_command(command, tmp_path):
    """Was: animate a traceback (cffi's AttributeError), simulate exit 0 with unchanged numbers."""
    extra = {"animate": ["-o", tmp_path / "x.gif"], "sweep": ["--vary", "phi1=0:1:2", "-o", tmp_path / "s.zarr"]}
    refused("--param m", command, SPECS / "gimbal.toml", "--param", "m=2", *extra.get(command, []),
            words="unknown parameter (the spec's are: none)")
    refused("--param J2x", command, SPECS / "furuta_sym.toml", "--param", "J2x=1", *extra.get(command, []),
            words="the spec's are: g0, m1")
    nothing_in(tmp_path)


@pytest.mark.parametrize("command", ["simulate", "animate", "steady", "sweep"])
def test_a_negative_mass_given_at_run_time_is_refused_quickly(command, tmp_path):
    """Was: simulate furuta_sym --param m2=-0.1 ran more than 10 minutes without output."""
    extra = {"animate": ["-o", tmp_path / "x.gif"], "sweep": ["--vary", "phi1=0:1:2", "-o", tmp_path / "s.zarr"]}
    line = refused("body[2].m", command, SPECS / "furuta_sym.toml", "--param", "m2=-0.1", *extra.get(command, []),
                   words="mass must be positive, got -0.1 with --param m2=-0.1", within=10)
    assert "[values]" in line
    refused("--param m2", command, SPECS / "furuta_sym.toml", "--param", "m2=nan", *extra.get(command, []), words="not a finite")
    nothing_in(tmp_path)


def test_a_symbolic_mass_and_inertia_are_checked_like_spec_numbers(tmp_path):
    """Was: m = "heavy" with --param heavy=-1 ran."""
    text = (SPECS / "double_pendulum.toml").read_text().replace("m = 1.0", 'm = "heavy"', 1)
    (tmp_path / "h.toml").write_text(text)
    refused("body[1].m", "simulate", tmp_path / "h.toml", "--param", "heavy=-1", words="mass must be positive")
    # m = 0.05 leaves the inertia about the centre of mass negative: A is about O1 (parallel axis)
    refused("body[1].A", "simulate", tmp_path / "h.toml", "--param", "heavy=5", words="negative principal moment")
    refused("body[1].m", "sweep", tmp_path / "h.toml", "--vary", "heavy=-1:1:3", "-o", tmp_path / "s.zarr",
            words="(a point of --vary)")
    nothing_in(tmp_path, "h.toml")


def test_a_chain_whose_mass_matrix_is_singular_everywhere_is_refused_by_every_command(tmp_path):
    """A point mass on its own joint axis: one line naming the body and the joint, before anything
    is derived (was: a ZeroDivisionError deep in the exact derivation)."""
    text = (SPECS / "double_pendulum_point.toml").read_text()
    body2 = text.index("[[body]]", text.index("[[body]]") + 1)
    text = text[:body2] + text[body2:].replace("theta = 0.0", 'theta = "pi/2"').replace("c = [0.0, 0.0, 1.0]", "c = [0.0, 0.0, 0.0]")
    (tmp_path / "axis.toml").write_text(text)
    lines = {refused("body[2]", *args, words="singular in every configuration: turning joint 2 moves no mass")
             for args in (["generate", tmp_path / "axis.toml", "--no-build", "-o", tmp_path / "g"],
                          ["simulate", tmp_path / "axis.toml"], ["steady", tmp_path / "axis.toml"],
                          ["animate", tmp_path / "axis.toml", "--frame", "0", "-o", tmp_path / "a.png"])}
    assert len(lines) == 1
    nothing_in(tmp_path, "axis.toml")


def test_a_mass_matrix_not_positive_definite_at_the_start_has_the_c_words():
    """simulate and animate check M at the start (values valid body by body can still make it
    singular there) with the words of the C's SINGULAR, which ends a motion that reaches one."""
    from gyrochain.codes import status_text
    from gyrochain.errors import SpecError
    from gyrochain.simulate import check_start

    check_start(np.array([[2.0, 1.0], [1.0, 1.0]]))
    with pytest.raises(SpecError, match="SINGULAR") as exc:
        check_start(np.array([[1.0, 1.0], [1.0, 1.0]]))
    assert status_text(1) in str(exc.value)


# --------------------------------------------------------------------------- plot and simulate options
@pytest.fixture(scope="module")
def store(tmp_path_factory):
    pytest.importorskip("zarr")
    path = tmp_path_factory.mktemp("store") / "dp.zarr"
    code, _, err, _ = run("sweep", SPECS / "double_pendulum.toml", "--vary", "phi1=-1:1:5", "--vary", "phi2=0:1:3",
                          "--t1", "0.5", "-q", "-o", path)
    assert code == 0, err
    return path


def test_plot_mistakes_are_one_line(store, tmp_path):
    """Was: FileNotFoundError, matplotlib's ValueError, zarr's GroupNotFoundError."""
    pytest.importorskip("matplotlib")
    refused("-o", "plot", store, "-o", tmp_path / "m.jpgg", words="an image type plot does not write")
    refused("store", "plot", SPECS / "gimbal.toml", "-o", tmp_path / "m.png", words="is not a sweep store")
    refused("store", "plot", tmp_path / "nope.zarr", "-o", tmp_path / "m.png", words="no such store")
    refused("--cmap", "plot", store, "--cmap", "magam", "-o", tmp_path / "m.png", words="not a matplotlib colour map")
    refused("--component", "plot", store, "--measure", "final", "--component", "9", "-o", tmp_path / "m.png", words="0..3")
    nothing_in(tmp_path)
    code, _, err, _ = run("plot", store, "-o", tmp_path / "nope" / "deeper" / "map.png")  # folders are made
    assert code == 0, err
    assert (tmp_path / "nope" / "deeper" / "map.png").read_bytes()[:4] == b"\x89PNG"
    nothing_in(tmp_path / "nope" / "deeper", "map.png")


@pytest.mark.parametrize("args, field, words", [
    (["--steps", "-5"], "--steps", "from 1 to"),
    (["--t1", "-1"], "--t1", "positive"),
    (["--t1", "nan"], "--t1", "positive"),
    (["--method", "euler"], "--method", "dop853, rk4"),
    (["--rtol", "0", "--atol", "0"], "--atol", "must be > 0"),
    (["--atol", "-inf"], "--atol", "finite tolerance"),
    (["--t1", "-1e3"], "--t1", "positive"),
    (["--phi", "1,2,3"], "--phi", "expected 2"),
    (["--phidot", "1,x"], "--phidot", "numbers"),
    (["--phi", "nan,0"], "--phi", "finite"),
    (["--u", "1"], "--u", "no controlled joint"),
    (["--param", "m"], "--param m", "name=number"),
    (["--steps", "x"], "--steps", "invalid int value"),
    (["--frobnicate"], "--frobnicate", "no such option of"),
    (["--phdot", "0,0"], "--phdot", "did you mean --phidot?"),
    (["extra_word"], "extra_word", "unexpected argument"),
])
def test_simulate_option_mistakes(args, field, words):
    refused(field, "simulate", SPECS / "gimbal.toml", *args, words=words)


def test_a_mistyped_command_is_answered_with_the_nearest(tmp_path):
    refused("command", "chek", SPECS / "gimbal.toml", words="no such command 'chek'; did you mean check?")
    refused("--t1", "simulate", SPECS / "gimbal.toml", "--t1", "abc", words="invalid float value: 'abc'")
    refused("--measure", "sweep", SPECS / "gimbal.toml", "--vary", "phi1=0:1:2", "--measure", "flip_tme", "-o", tmp_path / "s.zarr",
            words="did you mean flip_time?")
    nothing_in(tmp_path)


def test_internal_errors_say_so_and_exit_1(monkeypatch):
    def broken(args):
        raise RuntimeError("a bug")
    monkeypatch.setattr(cli, "cmd_check", broken)
    code, _, err, _ = run("check", SPECS / "gimbal.toml")
    assert code == 1 and err.count("\n") == 1 and f"internal error in gyrochain {__version__}: RuntimeError: a bug — please report it" in err
    # the page the line names is in the documentation, under that title
    title = re.search(r'"([^"]+)" in the documentation', err).group(1)
    assert (ROOT / "docs" / "report.md").read_text(encoding="utf-8").startswith(f"# {title}\n")
    assert f"{title}: report.md" in (ROOT / "mkdocs.yml").read_text(encoding="utf-8")


def test_a_missing_package_file_is_an_internal_error_not_the_users(monkeypatch, tmp_path):
    """A template missing from an installation (jinja2's TemplateNotFound is an OSError) is ours:
    exit 1 with the version, not exit 2 as if the user's file were wrong; --debug shows the traceback."""
    from gyrochain.printers import common

    monkeypatch.setattr(common, "TEMPLATES", tmp_path / "nowhere")
    pipeline.forget()  # a rendering kept from an earlier test would need no template
    code, _, err, _ = run("generate", "-q", "--no-build", SPECS / "gimbal.toml", "-o", tmp_path / "out")
    assert code == 1 and err.count("\n") == 1, err
    assert f"internal error in gyrochain {__version__}: TemplateNotFound" in err and "please report it" in err
    assert not (tmp_path / "out").exists()
    with pytest.raises(OSError, match="_c.jinja"):
        main(["generate", "-q", "--no-build", str(SPECS / "gimbal.toml"), "-o", str(tmp_path / "out"), "--debug"])


def test_a_file_system_error_is_one_line(tmp_path, store):
    pytest.importorskip("matplotlib")
    (tmp_path / "file").write_text("")
    refused(str(tmp_path / "file"), "plot", store, "-o", tmp_path / "file" / "m.png")


def test_a_compiler_that_is_not_there_is_named_in_one_line(tmp_path, monkeypatch):
    """$CC naming no program: the model's build says which compiler it could not run, exit 2, and
    generate writes nothing (was: an internal error from cffi's VerificationError)."""
    monkeypatch.setenv("CC", "no-such-cc")
    refused("no-such-cc", "generate", "-q", SPECS / "gimbal.toml", "-o", tmp_path / "out",
            words="No such file or directory (the C compiler of $CC)")
    nothing_in(tmp_path)


# --------------------------------------------------------------------------- what was friction
def test_negative_numbers_in_every_list_option(tmp_path):
    """Was: argparse's "expected one argument" for --phi -1,0."""
    code, out, err, _ = run("simulate", SPECS / "gimbal.toml", "--phi", "-1,0", "--phidot", "-0.5,-.25", "--steps", "1", "--t1", "0.01")
    assert code == 0, err
    assert [float(v) for v in out.splitlines()[1].split(",")[1:5]] == [-1.0, 0.0, -0.5, -0.25]
    code, out, err, _ = run("steady", SPECS / "furuta.toml", "--u", "-0.001", "--no-rotations")
    assert code == 0 and "u = [-0.001]" in out, err
    code, _, err, _ = run("animate", SPECS / "gimbal.toml", "--phi", "-1,0", "--view", "-30,-10", "--frame", "0.1",
                          "--size", "64x64", "-o", tmp_path / "f.png")
    assert code == 0, err


def test_controlled_specs_default_to_zero_torque_everywhere(tmp_path):
    """Was: sweep insisted on --u (and steady too) while simulate and animate default to zero."""
    pytest.importorskip("zarr")
    code, _, err, _ = run("sweep", SPECS / "furuta.toml", "--vary", "phi2=0:0.5:2", "--t1", "0.2", "-q", "-o", tmp_path / "f.zarr")
    assert code == 0, err
    code, out, err, _ = run("steady", SPECS / "furuta.toml", "--no-rotations")
    assert code == 0 and "phi = [0, 0]" in out, err


EXAMPLES_WITH_PARAMETERS = ["furuta_sym", "kapitza", "turntable", "ziegler"]


@pytest.mark.parametrize("name", EXAMPLES_WITH_PARAMETERS)
def test_examples_with_symbolic_parameters_run_every_command_without_param(name, tmp_path):
    """Their [values] are the defaults (was: one --param per parameter, nine for furuta_sym)."""
    spec = SPECS / f"{name}.toml"
    for args in (["check", spec], ["simulate", spec, "--t1", "0.05", "--steps", "2"],
                 ["animate", spec, "--frame", "0.05", "--size", "64x64", "-o", tmp_path / "a.png"]):
        code, out, err, _ = run(*args)
        assert code == 0, (args, err)
    pytest.importorskip("zarr")
    code, _, err, _ = run("sweep", spec, "--vary", "phi1=0:0.2:2", "--t1", "0.05", "-q", "-o", tmp_path / "s.zarr")
    assert code == 0, err
    code, out, err, _ = run("steady", spec, "--no-rotations")
    if name in ("furuta_sym", "ziegler"):
        assert code == 0 and "phi = [0, 0]" in out, err
    elif name == "turntable":  # a table turning at a constant rate: steady in the turning frame
        assert code == 0 and "equilibria" in out, err
    else:  # a vibrating pivot: its equilibria for all t, by Floquet multipliers
        assert code == 0 and "periodic in t" in out and "phi = [3.14159265]: linearly stable" in out, err


# --------------------------------------------------------------------------- sweep points and workers
def test_an_at_outside_the_grid_is_refused_and_a_snap_is_said(store, tmp_path):
    """Was: --at phi1=9,phi2=0 snapped to the nearest point without a word."""
    pytest.importorskip("PIL")
    refused("--at", "animate", store, "--at", "phi1=9,phi2=0", "--frame", "0", "-o", tmp_path / "a.png",
            words="phi1=9 is outside the sweep's grid (phi1 from -1 to 1)")
    code, _, err, _ = run("animate", store, "--at", "phi1=0.45,phi2=0.5", "--frame", "0", "--size", "64x64", "-o", tmp_path / "a.png")
    assert code == 0, err
    assert "--at: not a point of the grid; the nearest one is shown (phi1=0.45 → 0.5)" in err
    code, _, err, _ = run("animate", store, "--at", "phi1=0.5,phi2=0.5", "--frame", "0", "--size", "64x64", "-o", tmp_path / "b.png")
    assert code == 0 and "nearest" not in err, err


def test_a_rerun_with_nothing_to_do_starts_no_cluster(store, monkeypatch):
    from gyrochain import sweep

    def no_cluster(*a, **k):
        raise AssertionError("a cluster was started")
    monkeypatch.setattr(sweep, "_dask_results", no_cluster)
    monkeypatch.setattr(sweep.pipeline, "derive_and_render", no_cluster)
    code, _, err, _ = run("sweep", SPECS / "double_pendulum.toml", "--vary", "phi1=-1:1:5", "--vary", "phi2=0:1:3",
                          "--t1", "0.5", "-q", "--workers", "2", "-o", store)
    assert code == 0 and "0 chunks computed, 1 already done" in err, err


def test_point_masses_and_slender_rods_are_accepted(tmp_path):
    """Was: "not positive definite (principal moments 0, 0, 0)"."""
    code, out, err, _ = run("check", SPECS / "double_pendulum_point.toml")
    assert code == 0, err
    rod = (SPECS / "double_pendulum.toml").read_text().replace(
        "A = [[0.3335, 0.0, 0.0], [0.0, 0.3335, 0.0], [0.0, 0.0, 0.001]]", "I_c = [0.0833333333333, 0.0833333333333, 0.0, 0, 0, 0]")
    (tmp_path / "rod.toml").write_text(rod)
    code, out, err, _ = run("simulate", tmp_path / "rod.toml", "--t1", "0.1", "--steps", "1")
    assert code == 0, err


def test_the_command_line_entry_point_prints_one_line(tmp_path):
    """The real `python -m gyrochain` once (the others run in this process): one line, exit 2."""
    res = subprocess.run([sys.executable, "-m", "gyrochain", "animate", str(SPECS / "gimbal.toml"), "--param", "m=2",
                          "-o", str(tmp_path / "x.gif")], capture_output=True, text=True, cwd=ROOT,
                         env=dict(os.environ, PYTHONPATH=str(ROOT)))
    assert res.returncode == 2 and res.stderr.count("\n") == 1 and res.stderr.startswith("error: --param m:"), res.stderr
    assert not list(tmp_path.iterdir())


def test_normal_modes_of_two_point_masses():
    """double_pendulum_point: ω² = (g/l)(2 ∓ √2) for equal masses on equal massless rods."""
    from gyrochain.spec import load_spec

    cm, _ = pipeline.compiled(load_spec(SPECS / "double_pendulum_point.toml"))
    A, _ = cm.linearize(np.zeros(4))
    w2 = np.sort(np.linalg.eigvals(-A[2:, :2]).real)
    g, l = 9.81, 1.0
    want = np.array([(g / l) * (2 - np.sqrt(2)), (g / l) * (2 + np.sqrt(2))])
    assert np.allclose(w2, want, rtol=1e-12, atol=0), w2 - want
