"""What a user types and what they get."""
from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest

from gyrochain import reference
from gyrochain.spec import load_spec
from conftest import ROOT


def run(*args, cache=None):
    """The command as a user runs it; ``cache``: its own model cache folder ($GYROCHAIN_CACHE)."""
    env = dict(os.environ, GYROCHAIN_CACHE=str(cache)) if cache else None
    return subprocess.run([sys.executable, "-m", "gyrochain", *args], capture_output=True, text=True, cwd=ROOT, env=env)


def test_generate_prints_op_counts_integrals_and_where(tmp_path):
    res = run("generate", "specs/gimbal.toml", "-o", str(tmp_path / "g"))
    assert res.returncode == 0, res.stderr
    assert "op counts: gimbal_mass_matrix" in res.stdout and "gimbal_qdd" in res.stdout
    assert "integrals: energy T - U (23): conserved" in res.stdout
    assert "momentum (27): conserved (axis l1 vertical" in res.stdout
    assert "quadratures (30): emitted (Nikolai's balanced gyroscope" in res.stdout
    # the [initial] state's motion, found by the generated module (C checks it in test_quadratures)
    line = next(ln for ln in res.stdout.splitlines() if ln.startswith("motion of [initial]: libration"))
    period = float(line.split("period ")[1].split()[0])
    from gyrochain.build import load_python
    spec = load_spec(ROOT / "specs" / "gimbal.toml")
    x0 = [*spec.initial["phi"], *spec.initial["phidot"]]
    assert abs(period - load_python(tmp_path / "g", "gimbal").quad_period(x0)) <= 1e-11 * period
    assert f"wrote {tmp_path / 'g'}/" in res.stdout
    assert "[" in res.stderr and "s]" in res.stderr  # progress lines with elapsed time
    assert list((tmp_path / "g").glob("_gimbal_cffi*.so")), "the cffi extension is built"
    header = (tmp_path / "g" / "gimbal.h").read_text()
    assert "#define GIMBAL_HAS_ENERGY_INTEGRAL 1" in header and "#define GIMBAL_HAS_MOMENTUM_INTEGRAL 1" in header


def test_check_names_parameters_and_their_values():
    res = run("check", "specs/furuta_sym.toml")
    assert res.returncode == 0 and "g0 = 9.81, m1 = 0.3, r = 0.2, J1 = 0.004, J1z = 0.0002, m2 = 0.1, l = 0.15" in res.stdout


def test_simulate_runs_the_emitted_c_and_agrees_with_the_reference_model():
    args = ("simulate", "specs/gimbal.toml", "--t1", "0.5", "--steps", "5", "--phi", "0,0.5", "--phidot", "1,0.5")
    ch = reference.numeric(load_spec(ROOT / "specs" / "gimbal.toml"))
    ref = reference.simulate(ch, [0.0, 0.5, 1.0, 0.5], np.linspace(0, 0.5, 6))
    for extra, tol in (((), 1e-9), (("--reference", "--rtol", "1e-12", "--atol", "1e-12"), 1e-12)):
        res = run(*args, *extra)
        assert res.returncode == 0, res.stderr
        rows = np.array([list(map(float, ln.split(","))) for ln in res.stdout.splitlines()[1:]])
        assert rows.shape == (6, 6) and list(rows[0, :5]) == [0.0, 0.0, 0.5, 1.0, 0.5]
        assert np.allclose(rows[:, 1:5], ref, rtol=0, atol=tol), extra
        assert np.ptp(rows[:, 5]) < 1e-10  # the energy (23), conserved
    res = run(*args, "--method", "rk4", "--h", "1e-4")
    rows = np.array([list(map(float, ln.split(","))) for ln in res.stdout.splitlines()[1:]])
    assert res.returncode == 0 and np.allclose(rows[:, 1:5], ref, rtol=0, atol=1e-9)


def test_simulate_uses_the_specs_values_and_names_what_is_missing(tmp_path):
    res = run("simulate", "specs/furuta_sym.toml", "--t1", "0.1", "--steps", "2")
    assert res.returncode == 0, res.stderr
    text = (ROOT / "specs" / "furuta_sym.toml").read_text()
    (tmp_path / "nv.toml").write_text(text[:text.index("[values]")] + "[values]\ng0 = 9.81\n")
    res = run("simulate", str(tmp_path / "nv.toml"))
    assert res.returncode == 2 and res.stderr.count("\n") == 1
    assert "no value for m1, r, J1, J1z, m2, l, J2, J2z" in res.stderr and "--param m1=" in res.stderr


def test_spec_text_is_data_in_every_output(tmp_path):
    """A description full of comment and string delimiters still gives valid C, Python, LaTeX."""
    import shutil

    from gyrochain.build import load, load_python

    evil = r'evil */ /* """ \" \\ % $ & # _ { } ~ ^ ??/ é \n end'
    text = (ROOT / "specs" / "gimbal.toml").read_text().replace('name = "gimbal"', 'name = "evil"')
    text = text.replace(text.splitlines()[1], "description = '''" + evil + "\nsecond line'''")
    spec = tmp_path / "evil.toml"
    spec.write_text(text)
    out = tmp_path / "evil"
    res = run("generate", str(spec), "-o", str(out))
    assert res.returncode == 0, res.stderr
    py = load_python(out)
    assert "evil" in py.__doc__ and py.N == 2
    c = load(out)
    assert np.allclose(c.qdd([0.1, 0.2, 0.3, 0.4]), py.qdd([0.1, 0.2, 0.3, 0.4]), rtol=1e-13)
    strict = subprocess.run(["gcc", "-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-c", str(out / "evil.c"),
                             "-o", str(tmp_path / "e.o")], capture_output=True, text=True)
    assert strict.returncode == 0, strict.stderr
    if shutil.which("lualatex"):
        tex = subprocess.run(["lualatex", "-interaction=nonstopmode", "-halt-on-error", "evil.tex"], cwd=out,
                             capture_output=True, text=True)
        assert tex.returncode == 0, tex.stdout[-2000:]


THETA_PARAM = """
name = "tilted"
g = 9.81
[[body]]
theta = "th1"
m = 1.0
c = [0.0, 0.1, 0.0]
A = [[0.02, 0.0, 0.0], [0.0, 0.03, 0.0], [0.0, 0.0, 0.03]]
s = [0.0, 0.2, 0.0]
[[body]]
theta = 1.0
m = 0.5
c = [0.1, 0.0, 0.05]
A = [[0.01, 0.0, 0.0], [0.0, 0.012, 0.0], [0.0, 0.0, 0.015]]
"""


def test_a_condition_on_a_parameter_is_stated_not_guessed(tmp_path):
    spec = tmp_path / "tilted.toml"
    spec.write_text(THETA_PARAM)
    res = run("generate", str(spec), "-o", str(tmp_path / "t"))
    assert res.returncode == 0, res.stderr
    assert "momentum (27): conserved only if sin(theta1) = 0 (theta1 = th1 is a parameter" in res.stdout
    assert "quadratures (30): not emitted: theta1 = th1 is a parameter" in res.stdout
    header = (tmp_path / "t" / "tilted.h").read_text()
    assert "#define TILTED_HAS_MOMENTUM_INTEGRAL 0" in header and "#define TILTED_MOMENTUM_CONDITION" in header
    assert "tilted_momentum(" in header and "#define TILTED_HAS_QUADRATURES 0" in header
    assert r"conserved, $= \ell$, only when the axis $l^1$ is vertical" in (tmp_path / "t" / "tilted.tex").read_text()
    # and the condition is right: conserved at th1 = 0 and at pi, not at 0.4
    from gyrochain.build import load
    from scipy.integrate import solve_ivp
    c = load(tmp_path / "t", "tilted")
    # the folder's one model without its name, from inside it too, and a folder without one said plainly
    from gyrochain.build import load_python

    here = os.getcwd()
    try:
        os.chdir(tmp_path / "t")
        assert load(".").name == "tilted" and load_python(".").N == 2
    finally:
        os.chdir(here)
    for folder, said in ((tmp_path / "none", "no such folder"), (tmp_path, "no generated model here")):
        with pytest.raises(FileNotFoundError, match=said):
            load(folder)
    x0 = np.array([0.1, 0.5, 1.0, -2.0])
    for th1, conserved in ((0.0, True), (np.pi, True), (0.4, False)):
        p = {"th1": th1}
        sol = solve_ivp(lambda t, x: c.rhs(t, x, None, p), (0, 2.0), x0, method="DOP853", rtol=1e-12, atol=1e-12)
        k = [c.momentum(x, p) for x in sol.y.T]
        assert (max(k) - min(k) <= 1e-9) == conserved


def test_distribution_console_command_and_version(tmp_path):
    """The distribution is gyrochain (free on the index; "codegen" there is someone else's), its
    console command does what python -m gyrochain does, and the version lives in one place."""
    import importlib.metadata
    import shutil
    from pathlib import Path

    import gyrochain

    assert importlib.metadata.version("gyrochain") == gyrochain.__version__
    res = run("--version")
    assert res.returncode == 0 and res.stdout.strip() == f"gyrochain {gyrochain.__version__}"
    exe = Path(sys.executable).parent / "gyrochain"
    exe = exe if exe.exists() else shutil.which("gyrochain")
    assert exe, "the console command gyrochain is installed with the package (pip install -e .)"
    res = subprocess.run([str(exe), "--version"], capture_output=True, text=True)
    assert res.returncode == 0 and res.stdout.strip() == f"gyrochain {gyrochain.__version__}"
    a, b = tmp_path / "a", tmp_path / "b"
    res = subprocess.run([str(exe), "generate", "specs/furuta.toml", "-o", str(a), "--no-build", "-q"],
                         capture_output=True, text=True, cwd=ROOT)
    assert res.returncode == 0, res.stderr
    assert run("generate", "specs/furuta.toml", "-o", str(b), "--no-build", "-q").returncode == 0
    assert sorted(p.name for p in a.iterdir()) == sorted(p.name for p in b.iterdir())
    for p in a.iterdir():
        assert p.read_bytes() == (b / p.name).read_bytes(), p.name
    bad = subprocess.run([str(exe), "check", "nope.toml"], capture_output=True, text=True, cwd=tmp_path)
    assert bad.returncode == 2 and bad.stderr.startswith("error: nope.toml")


def test_generate_does_not_recompile_what_has_not_changed(tmp_path):
    out, cache = tmp_path / "g", tmp_path / "cache"
    first = run("generate", "specs/gimbal.toml", "-o", str(out), "-q", cache=cache)
    assert first.returncode == 0 and "+ cffi extension" in first.stdout and "not recompiled" not in first.stdout
    so = next(out.glob("_gimbal_cffi*.so"))
    stamp = so.stat().st_mtime_ns
    second = run("generate", "specs/gimbal.toml", "-o", str(out), "-q", cache=cache)
    assert second.returncode == 0 and "not recompiled" in second.stdout, second.stdout
    so2 = next(out.glob("_gimbal_cffi*.so"))
    assert so2.stat().st_mtime_ns == stamp  # the same file, copied with its time
    from gyrochain.build import load
    assert np.all(np.isfinite(load(out, "gimbal").qdd(np.array([0.1, 0.2, 0.3, 0.4]))))
    # another folder, the same sources: the model cache's build, not compiled again
    other = run("generate", "specs/gimbal.toml", "-o", str(tmp_path / "h"), "-q", cache=cache)
    assert "not recompiled" in other.stdout and next((tmp_path / "h").glob("_gimbal_cffi*.so")).stat().st_mtime_ns == stamp
    # another mass of the balanced inner ring changes no equation (c = s = 0): the same C, reused
    spec = tmp_path / "gimbal.toml"
    spec.write_text((ROOT / "specs" / "gimbal.toml").read_text().replace("m = 1.2", "m = 1.25"))
    assert "not recompiled" in run("generate", str(spec), "-o", str(out), "-q", cache=cache).stdout
    # another inertia of the rotor ring does: compiled again
    spec.write_text(spec.read_text().replace("0.009]]", "0.0095]]"))
    third = run("generate", str(spec), "-o", str(out), "-q", cache=cache)
    assert third.returncode == 0 and "+ cffi extension" in third.stdout and "not recompiled" not in third.stdout
    # a key that does not match what is there (another compiler or flags): the folder's extension
    # is not trusted; the one built from these sources with these flags is put in with its key
    key = next(out.glob("_gimbal_cffi.key"))
    key.write_text("0" * 64 + "\n")
    fourth = run("generate", str(spec), "-o", str(out), "-q", cache=cache)
    assert fourth.returncode == 0 and key.read_text().strip() != "0" * 64
    assert np.all(np.isfinite(load(out, "gimbal").qdd(np.array([0.1, 0.2, 0.3, 0.4]))))


def test_the_api_pages_script_runs(tmp_path):
    """The Python API page's script (docs/reference/api.md), as a user pastes it (from the
    repository folder): it runs and its φ̈ is the reference model's."""
    sys.path.insert(0, str(ROOT / "tests"))
    import docrun

    block = next(b.text for b in docrun.blocks(ROOT / "docs" / "reference" / "api.md") if b.kind == "python")
    res = subprocess.run([sys.executable, "-c", block], capture_output=True, text=True, cwd=ROOT,
                         env={**os.environ, "GYROCHAIN_CACHE": str(tmp_path)})
    assert res.returncode == 0, res.stderr
    got = np.array([float(v) for v in res.stdout.strip().strip("[]").split()])
    spec = load_spec(ROOT / "specs" / "gimbal.toml")
    want = reference.qdd(reference.numeric(spec), [0.3, 0.0, 1.0, 0.0], None, 0.0)
    assert np.allclose(got, want, rtol=1e-10, atol=1e-12), (got, want)


def test_a_closed_pipe_ends_the_output_without_a_traceback():
    """`simulate ... | head -1`: the reader stops early; the command stops quietly."""
    proc = subprocess.Popen([sys.executable, "-m", "gyrochain", "simulate", "specs/gimbal.toml", "--t1", "0.1", "--steps", "20000"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=ROOT)
    assert proc.stdout.readline().startswith(b"t,phi1")
    proc.stdout.close()
    err = proc.stderr.read().decode()
    assert proc.wait(timeout=120) == 0 and "Traceback" not in err, err


# --------------------------------------------------------------------------- the build cache (docs/testing.md)
def _planted_extension(folder):
    """An "extension" under the exact name gimbal's build would have in ``folder``: were it loaded,
    the command would end in an internal error (it is not a shared object)."""
    import sysconfig

    from gyrochain import build, pipeline

    files, _ = pipeline.derive_and_render(load_spec(ROOT / "specs" / "gimbal.toml"), targets=("c",))
    key = build.key_of([files[f"gimbal{s}"].encode("utf-8") for s in pipeline.C_FILES])
    home = folder / f"gimbal-{key[:20]}"
    home.mkdir(parents=True)
    (home / f"{build.module_name('gimbal')}{sysconfig.get_config_var('EXT_SUFFIX')}").write_text("planted")
    return home


def _listing(folder):
    return sorted((str(p.relative_to(folder)), p.stat().st_mode, p.stat().st_size, p.stat().st_mtime_ns)
                  for p in folder.rglob("*"))


def _simulate_with(env):
    return subprocess.run([sys.executable, "-m", "gyrochain", "simulate", "specs/gimbal.toml", "--t1", "0.01", "--steps", "1"],
                          capture_output=True, text=True, cwd=ROOT, env=env, timeout=300)


def test_a_planted_cache_folder_is_never_built_into_or_loaded_from(tmp_path):
    import stat

    env = {k: v for k, v in os.environ.items() if k not in ("GYROCHAIN_CACHE", "XDG_CACHE_HOME")}
    cases = []
    anyone = tmp_path / "anyone"  # writable by everyone, with a planted extension
    _planted_extension(anyone)
    anyone.chmod(0o777)
    cases.append((anyone, "is writable by group and others (mode 0777)"))
    group = tmp_path / "group"
    group.mkdir(mode=0o770)
    group.chmod(0o770)
    cases.append((group, "is writable by group (mode 0770)"))
    open_parent = tmp_path / "open"  # a private folder inside one anyone can write (not sticky)
    (open_parent / "mine").mkdir(parents=True, mode=0o700)
    open_parent.chmod(0o777)
    cases.append((open_parent / "mine", f"lies in {open_parent}, which another user can change"))
    if os.getuid() == 0:  # only root can give a folder away: another user's folder, planted
        theirs = tmp_path / "theirs"
        _planted_extension(theirs)
        for p in [theirs, *theirs.rglob("*")]:
            os.chown(p, 65534, 65534)
        cases.append((theirs, "is owned by another user (uid 65534)"))
        home = tmp_path / "home"  # the default place, ~/.cache/gyrochain, made first by another user
        _planted_extension(home / ".cache" / "gyrochain")
        os.chown(home / ".cache" / "gyrochain", 65534, 65534)
        res = _simulate_with({**env, "HOME": str(home)})
        assert res.returncode == 2 and res.stderr.count("\n") == 1, res.stderr
        assert f"error: build cache {home / '.cache' / 'gyrochain'}: is owned by another user" in res.stderr
    for folder, why in cases:
        before = _listing(folder)
        res = _simulate_with({**env, "GYROCHAIN_CACHE": str(folder)})
        assert res.returncode == 2 and res.stderr.count("\n") == 1, (folder, res.stderr)
        assert res.stderr.startswith(f"error: $GYROCHAIN_CACHE {folder}: {why}"), res.stderr
        assert res.stdout == "" and _listing(folder) == before  # nothing built into it, nothing loaded
    # the control: a folder of ours is made private and used
    fresh = tmp_path / "fresh" / "cache"
    res = _simulate_with({**env, "GYROCHAIN_CACHE": str(fresh)})
    assert res.returncode == 0, res.stderr
    assert stat.S_IMODE(fresh.stat().st_mode) == 0o700 and any(p.name.startswith("gimbal-") for p in fresh.iterdir())
