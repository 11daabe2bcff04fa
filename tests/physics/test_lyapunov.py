"""Lyapunov spectra by the QR method on the emitted variational equations (measures.lyapunov_spectrum)
and the sweep's variational measures (lyapunov_spectrum, floquet) end to end.

The double pendulum of rods: at low energy the motion is regular and every exponent tends to 0
(as log t / t); released from (2.5, −2) rad it is chaotic, with a positive exponent and its
negative partner.  A conservative model's spectrum comes in ± pairs summing to 0: the pairing
error is reported (and bounded here).  Over a short time the QR spectrum is exactly
log|Rᵢᵢ| / t of Φ(t) = Q R, so it is checked against Φ from differences of the flow; a derivative
perturbed by one part in 10⁶ fails that check."""
from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from gyrochain import sweep
from gyrochain.measures import lyapunov, lyapunov_spectrum, pairing
from conftest import ROOT, cli_in_process, perturbed_c

REGULAR, CHAOTIC = [0.3, 0.2, 0.0, 0.0], [2.5, -2.0, 0.0, 0.0]


def test_regular_and_chaotic_spectra(example):
    m = example("double_pendulum").c
    lam, codes = lyapunov_spectrum(m, np.array([REGULAR, CHAOTIC], float), 200.0, 0.5, None, rtol=1e-10, atol=1e-10)
    assert not codes.any()
    reg, cha = lam
    assert np.all(np.diff(reg) <= 0) and np.all(np.diff(cha) <= 0)  # in decreasing order
    assert np.max(np.abs(reg)) < 0.03, reg  # → 0 as log t / t (0.016 at t = 200 s)
    assert cha[0] > 1.0 and cha[-1] < -1.0, cha  # a positive pair
    for spectrum in (reg, cha):
        err, total = pairing(spectrum)
        assert err < 0.01 and total < 0.01, (err, total)


def test_the_largest_exponent_two_ways(example):
    """The two-trajectory estimate (the sweep's `lyapunov`, d0 = 1e-8 renormalised every 0.5 s)
    and the spectrum's first exponent over 2000 s agree to 5 % (1.309 and 1.348 /s here): finite-
    time estimates along trajectories that part after ~30 s (NAME_qdd and the derivatives' φ̈
    differ in the last bit), converging slowly to the same exponent (10 % apart at 200 s, 3.5 % at
    1000 s)."""
    m = example("double_pendulum").c
    x0 = np.array([CHAOTIC], float)
    lam, _ = lyapunov_spectrum(m, x0, 2000.0, 0.5, None, rtol=1e-10, atol=1e-10)
    sw = sweep.Sweep(spec_text="", vary=[], t1=2000.0, measures=["lyapunov"], lyap_interval=0.5)
    two, _ = lyapunov(m, x0, sw, dict(method="dop853", h=0.0, rtol=1e-10, atol=1e-10, u=None), None)
    assert abs(two[0] - lam[0, 0]) < 0.05 * lam[0, 0], (two[0], lam[0, 0])


def _qr_exponents_of(Phi, t):
    _, R = np.linalg.qr(Phi)
    return np.sort(np.log(np.abs(np.diag(R))))[::-1] / t


def test_short_time_spectrum_against_differences(example, tmp_path):
    """Over t = 3 s (six QR steps of 0.5 s) the spectrum equals log|Rᵢᵢ|/t of Φ(3) from Richardson
    differences of the emitted flow, to 1e-8; a perturbed ∂φ̈/∂φ misses by more."""
    g = example("double_pendulum")
    x0, t = np.array(CHAOTIC, float), 3.0

    def flow(x):
        return g.c.integrate([0.0, t], x, rtol=1e-13, atol=1e-13)[-1]

    def central(h):
        return np.array([(flow(x0 + h * e) - flow(x0 - h * e)) / (2 * h) for e in np.eye(4)]).T

    want = _qr_exponents_of((4 * central(5e-6) - central(1e-5)) / 3, t)
    # the sum exactly: (1/t) log det Φ(t) = (1/t) log(det M(φ₀) / det M(φ(t))) (Liouville)
    x1 = flow(x0)
    exact_sum = np.log(np.linalg.det(g.c.mass_matrix(x0[:2])) / np.linalg.det(g.c.mass_matrix(x1[:2]))) / t

    def misses(lam):
        # the smallest exponent of the differenced Φ is the least accurate (its R₄₄ is 1e-4 of |Φ|):
        # it is checked through the sum instead
        return max(np.max(np.abs(lam[:3] - want[:3])), abs(np.sum(lam) - exact_sum))

    got, _ = lyapunov_spectrum(g.c, x0[None, :], t, 0.5, None, rtol=1e-12, atol=1e-12)
    assert misses(got[0]) <= 1e-8, (got[0] - want, np.sum(got[0]) - exact_sum)
    bad = perturbed_c(g, tmp_path / "bad")
    off, _ = lyapunov_spectrum(bad, x0[None, :], t, 0.5, None, rtol=1e-12, atol=1e-12)
    assert misses(off[0]) > 1e-8, (off[0] - want, np.sum(off[0]) - exact_sum)


def _run(*args):
    return subprocess.run([sys.executable, "-m", "gyrochain", *args], capture_output=True, text=True, cwd=ROOT)


def test_the_sweep_measures(tmp_path, capsys, monkeypatch):
    """lyapunov_spectrum over two starts: an array with an 'exponent' dimension, plotted by
    component; floquet over (a, w) of Kapitza's pendulum at the upright position: every point's
    largest |μ| matches the verdict steady gives there, and the plot draws the stable region."""
    import zarr

    store = tmp_path / "lyap.zarr"
    res = _run("sweep", "specs/double_pendulum.toml", "--vary", "phi1=0.3:2.5:2", "--phi", "0,-2", "--t1", "20",
               "--lyap-interval", "0.5", "--measure", "lyapunov_spectrum", "--rtol", "1e-10", "--atol", "1e-10", "-q",
               "-o", str(store))
    assert res.returncode == 0, res.stderr
    arr = zarr.open_group(str(store), mode="r")["lyapunov_spectrum"]
    assert arr.shape == (2, 4) and list(arr.metadata.dimension_names) == ["phi1", "exponent"]
    lam = np.asarray(arr[...])
    assert np.all(np.isfinite(lam)) and np.all(np.diff(lam, axis=1) <= 0)
    res = _run("plot", str(store), "--component", "3", "-o", str(tmp_path / "l.png"))
    assert res.returncode == 0 and (tmp_path / "l.png").stat().st_size > 1000, res.stderr
    res = cli_in_process("plot", store, "--component", "4", "-o", tmp_path / "l.png")
    assert res.returncode == 2 and "--component" in res.stderr

    store = tmp_path / "floquet.zarr"
    res = _run("sweep", "specs/kapitza.toml", "--phi", "3.141592653589793", "--vary", "a=0:0.012:4", "--vary",
               "w=200:300:3", "--measure", "floquet", "-q", "-o", str(store))
    assert res.returncode == 0, res.stderr
    g = zarr.open_group(str(store), mode="r")
    mu = np.asarray(g["floquet"][...])
    a, w = np.asarray(g["a"][...]), np.asarray(g["w"][...])
    from gyrochain import cli

    monkeypatch.chdir(ROOT)
    for i, ai in enumerate(a):
        for j, wj in enumerate(w):
            # the command in this process (its text as the command line prints it): twelve
            # interpreters, each importing sympy and deriving the model, took 12 of the test's 22 s
            capsys.readouterr()
            assert cli.main(["steady", "specs/kapitza.toml", "--param", f"a={ai}", "--param", f"w={wj}"]) == 0
            out = capsys.readouterr().out
            upright = [ln for ln in out.splitlines() if ln.startswith("  phi = [3.14159265]")][0]
            assert (mu[i, j] > 1 + 1e-6) == ("unstable" in upright), (ai, wj, mu[i, j], upright)
    res = _run("plot", str(store), "-o", str(tmp_path / "f.png"))
    assert res.returncode == 0 and (tmp_path / "f.png").stat().st_size > 1000, res.stderr


@pytest.mark.parametrize("args,field", [
    (("specs/kapitza.toml", "--vary", "phi1=0:3:3", "--measure", "floquet"), "--measure floquet"),
    (("specs/double_pendulum.toml", "--vary", "phi1=0:3:3", "--measure", "floquet"), "--measure floquet"),
    (("specs/kapitza.toml", "--vary", "a=0:0.1:3", "--measure", "floquet"), "--phi"),
    (("specs/kapitza.toml", "--vary", "a=0:0.1:3", "--phi", "3.14159265", "--phidot", "1", "--measure", "floquet"), "--phidot"),
    (("specs/kapitza.toml", "--vary", "a=0:0.1:3", "--measure", "floquet", "--method", "rk4", "--h", "0.01"), "--method"),
    (("specs/double_pendulum.toml", "--vary", "phi1=0:3:3", "--measure", "lyapunov_spectrum", "--lyap-interval", "0"),
     "--lyap-interval"),
    (("specs/double_pendulum.toml", "--vary", "phi1=0:3:3", "--measure", "lyapunov_spectra"), "--measure"),
])
def test_sweep_measure_mistakes(tmp_path, args, field):
    res = cli_in_process("sweep", *args, "-q", "-o", tmp_path / "s.zarr")
    assert res.returncode == 2 and res.stdout == "", (res.stdout, res.stderr)
    assert len(res.stderr.strip().splitlines()) == 1 and field in res.stderr, res.stderr
    assert not (tmp_path / "s.zarr").exists()
