"""``gyrochain steady``: equilibria, steady rotations and their stability against classical results
computed independently (closed forms, the reference model's M and potential)."""
from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from scipy.linalg import eigh

from gyrochain import reference, steady
from gyrochain.spec import load_spec, parse_spec
from conftest import ROOT, cli_in_process

CARDAN = '''
name = "cardan_up"
description = "heavy gyroscope in a Cardan suspension, outer axis horizontal"
g = 9.81
[[body]]
theta = "pi/2"
m = 0.3
c = [0.0, 0.0, 0.0]
A = [[0.004, 0.0, 0.0], [0.0, 0.002, 0.0], [0.0, 0.0, 0.002]]
s = [0.0, 0.0, 0.0]
[[body]]
theta = "pi/2"
m = 1.0
c = [0.0, 0.0, 0.05]
A = [[0.010, 0.0, 0.0], [0.0, 0.010, 0.0], [0.0, 0.0, 0.012]]
lambda = [0.0, 0.0, "h"]
'''


@pytest.fixture(scope="module")
def compiled():
    cache = {}

    def get(spec):
        if spec.name not in cache:
            cache[spec.name] = steady.compile_spec(spec)
        return cache[spec.name]

    return get


def test_double_pendulum_four_equilibria(compiled):
    spec = load_spec(ROOT / "specs" / "double_pendulum.toml")
    an = steady.Analysis(*compiled(spec))
    eqs = an.equilibria()
    assert len(eqs) == 4
    by = {tuple(np.round(e.phi / np.pi).astype(int)): e for e in eqs}
    assert set(by) == {(0, 0), (0, 1), (1, 0), (1, 1)}
    assert by[(0, 0)].verdict == "stable (energy–momentum)"
    assert all(by[k].verdict == "unstable" for k in ((0, 1), (1, 0), (1, 1)))
    # the small-oscillation frequencies against the reference model: M and the Hessian of the
    # potential by differences of its energy at rest
    ch = reference.numeric(spec)
    for key, e in by.items():
        phi = e.phi
        V = lambda q: reference.energy(ch, np.concatenate([q, [0.0, 0.0]]))  # noqa: E731  (T − U = −U at rest)
        h = 1e-4
        K = np.array([[(V(phi + h * (a + b)) - V(phi + h * (a - b)) - V(phi - h * (a - b)) + V(phi - h * (a + b))) / (4 * h * h)
                       for b in np.eye(2)] for a in np.eye(2)])
        assert np.allclose(e.K, K, rtol=1e-6, atol=1e-6 * np.max(np.abs(K)))
        lam = eigh(K, reference.mass_matrix(ch, phi), eigvals_only=True)  # s² = −λ
        want = np.sort(np.concatenate([np.sqrt(lam.astype(complex)) * 1j, -np.sqrt(lam.astype(complex)) * 1j]).imag)
        got = np.sort(np.concatenate([e.eigenvalues.imag[np.abs(e.eigenvalues.imag) > 0], []]))
        if key == (0, 0):
            assert np.allclose(got, want, rtol=1e-8)
        assert (np.max(e.eigenvalues.real) > 1e-3) == (np.min(lam) < 0)


def test_sleeping_gyrostat_threshold(compiled):
    """fast_gyro: a heavy gyrostat on a vertical outer axis.  With the carrier turning at ω about
    the vertical and the rotor axis vertical, the amended potential's curvature is
    K(ω) = (C − A)ω² ± λω ∓ mgl (upright / hanging): the verdict changes at its roots."""
    spec = load_spec(ROOT / "specs" / "fast_gyro.toml")
    an = steady.Analysis(*compiled(spec))
    assert an.cyclic
    A, C, lam, mgl = 0.00648, 0.009, 5.0, 1.2 * 9.81 * 0.02
    up = (-lam + np.sqrt(lam**2 + 4 * (C - A) * mgl)) / (2 * (C - A))
    down = (lam - np.sqrt(lam**2 - 4 * (C - A) * mgl)) / (2 * (C - A))
    branches = an.rotations(np.linspace(-0.5, 0.5, 21))
    changes = sorted((w, a, b) for br in branches for w, a, b in br.changes)
    assert len(changes) == 2
    (w1, a1, b1), (w2, a2, b2) = changes
    assert abs(w1 - up) <= 1e-9 * up and (a1, b1) == ("unstable", "stable (energy–momentum)")
    assert abs(w2 - down) <= 1e-9 * down and (a2, b2) == ("stable (energy–momentum)", "unstable")
    # K of the report is that curvature
    p = next(br for br in branches if abs(br.points[0].phi[1]) < 1e-6).points[-1]
    assert abs(p.K[0, 0] - ((C - A) * p.omega**2 + lam * p.omega - mgl)) <= 1e-10


def test_gyroscopic_stabilisation(compiled):
    """The upright Cardan gyroscope (outer axis horizontal): K = −mgl·I, unstable without spin;
    a rotor of momentum h stabilises it to first order above h_c = √(a₁mgl) + √(a₂mgl)
    (Kelvin–Tait–Chetaev), and the verdict names gyroscopic stabilisation."""
    cm, model = compiled(parse_spec(CARDAN))
    mgl = 1.0 * 9.81 * 0.05

    def upright(h):
        an = steady.Analysis(cm, model, {"h": h})
        e = an.classify(np.array([np.pi / 2, np.pi / 2]))
        assert np.allclose(an.solve(e.phi), e.phi, atol=1e-12)  # it is an equilibrium
        return e

    e = upright(0.5)
    assert e.verdict == "linearly stable" and "gyroscopic stabilisation" in e.reason
    assert np.allclose(e.K, -mgl * np.eye(2), atol=1e-12)
    assert np.allclose(e.G, -e.G.T, atol=1e-12) and abs(abs(e.G[0, 1]) - 0.5) < 1e-12
    assert upright(0.05).verdict == "unstable"
    M = cm.mass_matrix(np.array([np.pi / 2, np.pi / 2]), {"h": 0.0})
    hc = np.sqrt(M[0, 0] * mgl) + np.sqrt(M[1, 1] * mgl)
    lo, hi = 0.05, 0.5
    for _ in range(60):
        mid = (lo + hi) / 2
        lo, hi = (lo, mid) if upright(mid).verdict != "unstable" else (mid, hi)
    assert abs(hi - hc) <= 1e-6 * hc, (hi, hc)


def test_turntable_relative_equilibria(compiled):
    """On a table turning at Ω > Ω_c the pendulum's relative equilibrium cos φ = Ω_c²/Ω² is stable
    (Jacobi integral), the vertical unstable; below Ω_c the vertical is stable."""
    spec = load_spec(ROOT / "specs" / "turntable.toml")
    cm, model = compiled(spec)
    wc = 5.4315
    an = steady.Analysis(cm, model, {"Omega": 8.0})
    eqs = an.equilibria()
    stable = [e for e in eqs if e.verdict.startswith("stable")]
    assert stable and all(abs(np.cos(e.phi[0]) - (wc / 8.0) ** 2) < 1e-4 for e in stable)
    assert "Jacobi" in stable[0].reason
    assert any(abs(e.phi[0]) < 1e-9 and e.verdict == "unstable" for e in eqs)
    low = steady.Analysis(cm, model, {"Omega": 4.0}).equilibria()
    assert [e.verdict for e in low if abs(e.phi[0]) < 1e-9] == ["stable (energy–momentum)"]


def _cli(*args):
    return subprocess.run([sys.executable, "-m", "gyrochain", "steady", *args], capture_output=True, text=True, cwd=ROOT, timeout=300)


def test_cli_output_and_bad_input():
    res = _cli("specs/double_pendulum.toml")
    assert res.returncode == 0, res.stderr
    assert "equilibria: 4 found" in res.stdout and res.stdout.count("unstable") == 3
    for args, field in ((("specs/furuta.toml", "--u", "1,2"), "--u"), (("specs/double_pendulum.toml", "--start", "0,nan"), "--start"),
                        (("specs/kapitza.toml", "--period", "0.01"), "--period"),
                        (("specs/kapitza.toml", "--omega", "0:1:3"), "--omega"),
                        (("specs/kapitza.toml", "--vary", "b=0:1:3"), "--vary b"),
                        (("specs/gimbal.toml", "--vary", "a=0:1:3"), "--vary a"),
                        (("specs/gimbal.toml", "--omega", "5:1:3"), "--omega"),
                        (("specs/furuta_sym.toml", "--u", "0", "--param", "m2=-1"), "body[2].m"),
                        (("specs/furuta_sym.toml", "--param", "m=1"), "--param m")):
        res = cli_in_process("steady", *args)
        assert res.returncode == 2 and res.stdout == "", (args, res.stdout, res.stderr)
        assert len(res.stderr.strip().splitlines()) == 1 and field in res.stderr, (args, res.stderr)


def test_damping_in_joint_one_leaves_equilibria_and_no_steady_rotations(compiled):
    """A damped joint on a vertical axis (as imported arms have): φ¹ is still absent, so any φ¹ is
    an equilibrium, but the momentum p₁ decays, so there are no steady rotations and δp₁ is not
    fixed.  The verdict's eigenvalues are the full linearisation's without its one zero (the φ¹
    direction); the hanging pendulum is asymptotically stable.  (Found on the Panda: the branch
    continuation over ω compared Branches by value and ended in an internal error.)"""
    text = (ROOT / "specs" / "fast_gyro.toml").read_text().replace('name = "fast_gyro"', 'name = "damped_gyro"')
    spec = parse_spec(text.replace("[[body]]", "[[body]]\ndamping = 0.01"))
    assert [b.damping is not None for b in spec.bodies] == [True, True]
    an = steady.Analysis(*compiled(spec))
    assert an.cyclic and an.drains == ["body[1].damping"]
    with pytest.raises(steady.SteadyError, match="body\\[1\\].damping acts in joint 1"):
        an.rotations(np.linspace(-1, 1, 5))
    cm, _ = compiled(spec)
    eqs = an.equilibria()
    for e in eqs:
        A, _ = cm.linearize(np.concatenate([[0.7], e.phi[1:], np.zeros(spec.n)]))
        full = np.linalg.eigvals(A)
        full = np.delete(full, np.argmin(np.abs(full)))  # the φ¹ direction
        assert np.allclose(np.sort_complex(full), np.sort_complex(e.eigenvalues), rtol=1e-9, atol=1e-12)
    hanging = [e for e in eqs if e.verdict == "asymptotically stable"]
    assert len(hanging) == 1 and abs(np.cos(hanging[0].phi[1]) + 1) < 1e-9, [(e.phi, e.verdict) for e in eqs]  # φ² = π: c below O


def test_a_follower_load_is_named_not_gyroscopic_terms():
    """Ziegler's column at P = 8.33 (issue 49): stable to first order although the energy's Hessian
    is indefinite, and Γ ≡ 0 there: the reason names the follower load, not gyroscopic stabilisation."""
    from gyrochain.physical import run_values

    spec = load_spec(ROOT / "specs" / "ziegler.toml")
    an, eqs, _, _ = steady.analyze(spec, run_values(spec, {"P": 8.33}))
    (e,) = [e for e in eqs if np.allclose(e.phi, 0.0)]
    assert e.verdict == "linearly stable" and "gyroscopic" not in e.reason.replace("not by gyroscopic", "")
    assert "non-conservative loads (body[2].force[1] (a follower force))" in e.reason and "1 negative eigenvalue:" in e.reason
