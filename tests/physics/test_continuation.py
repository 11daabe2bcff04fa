"""``gyrochain continue``: branches of equilibria and their special points, and the curves those
points trace in two parameters, against closed forms derived here by hand from the specs' numbers
and against Mathieu's characteristic curves (Hill's determinant, computed here)."""
from __future__ import annotations

import csv
import io

import numpy as np
import pytest

from gyrochain.analysis import branches
from gyrochain.chainspec.physical import run_values
from gyrochain.spec import load_spec, parse_spec
from conftest import ROOT, cli_in_process

G = 9.81

# An inverted gyropendulum on two horizontal axes: a ring (A11 = 0.002 about its axis l1) and, on
# the perpendicular axis l2 through the same point, a pendulum of 1 kg whose centre is d = 0.1 m
# up its rotor's axis ê²₃, its inertia diag(0.02, 0.02, 0.004) about O, and a rotor of momentum h.
GYRO_UP = """
name = "gyro_up"
description = "an inverted gyropendulum on two horizontal axes"
g = 9.81
[[body]]
theta = "pi/2"
m = 0.3
c = [0.0, 0.0, 0.0]
A = [[0.002, 0.0, 0.0], [0.0, 0.001, 0.0], [0.0, 0.0, 0.001]]
s = [0.0, 0.0, 0.0]
[[body]]
theta = "pi/2"
m = 1.0
c = [0.0, 0.0, 0.1]
A = [[0.02, 0.0, 0.0], [0.0, 0.02, 0.0], [0.0, 0.0, 0.004]]
lambda = [0.0, 0.0, "h"]
[values]
h = 0.0
"""


DOUBLE_TURNTABLE = """
name = "double_turntable"
description = "a double pendulum of two rods in a plane turning with a table about the vertical at the rate Omega"
g = 9.81
[base]
rotation = [{axis = [1, 0, 0], angle = "Omega*t"}]
[[body]]
theta = "pi/2"
m = 0.5
c = [0.0, 0.0, 0.25]
A = [["1/24", 0.0, 0.0], [0.0, "1/24", 0.0], [0.0, 0.0, 0.0001]]
s = [0.0, 0.0, 0.5]
control = true
[[body]]
theta = 0.0
m = 0.5
c = [0.0, 0.0, 0.25]
A = [["1/24", 0.0, 0.0], [0.0, "1/24", 0.0], [0.0, 0.0, 0.0001]]
[values]
Omega = 12.0
"""


def _run(spec, ranges, given=None, u=None, starts=()):
    """As the command runs: the first parameter starts at its value (--param, the spec's) in its range."""
    lo = {r[0]: r[1] for r in ranges if r[0] not in spec.values and r[0] != branches.RATE}
    params = run_values(spec, {**lo, **(given or {})})
    return branches.run(spec, params, u, ranges, starts)


def _close(a, b, rel=1e-10):
    return abs(a - b) <= rel * abs(b)


def test_turntable_branch_point_and_the_branch_it_meets():
    """A rod on a table turning at Ω (specs/turntable.toml, A about the hinge O1): the potential in
    the turning frame is −mgc cos φ − ½Ω²(A33 cos²φ + A22 sin²φ), so the vertical loses stability
    at Ω_c² = mgc/(A22 − A33), where the branch cos φ = Ω_c²/Ω² leaves it both ways (a pitchfork)."""
    spec = load_spec(ROOT / "specs" / "turntable.toml")
    res = _run(spec, [("Omega", 2.0, 12.0)])  # from the equilibria at the spec's Ω = 8, both ways
    wc = np.sqrt(0.5 * G * 0.25 / (1 / 24 - 0.0001))
    vertical = next(br for br in res.branches if br.origin.startswith("phi = [0]"))
    (bp,) = vertical.specials
    assert bp.kind == "BP" and _close(bp.point.alpha, wc), (bp.point.alpha, wc)
    assert (bp.before, bp.after) == ("stable (energy–momentum)", "unstable")
    assert vertical.points[0].alpha == 2.0 and vertical.points[-1].alpha == 12.0
    (fork,) = [br for br in res.branches if max(abs(p.phi[0]) for p in br.points) > 0.5 and
               min(abs(abs(p.phi[0]) - np.pi) for p in br.points) > 0.5]
    assert fork.end == "both ways reached the range's end, Omega = 12", fork.end
    assert {np.sign(fork.points[0].phi[0]), np.sign(fork.points[-1].phi[0])} == {-1.0, 1.0}
    (meets,) = fork.specials  # it meets the vertical there, and turns back
    assert meets.kind == "BP" and _close(meets.point.alpha, wc) and abs(meets.point.phi[0]) < 1e-6
    for p in fork.points:
        assert abs(np.cos(p.phi[0]) - (wc / p.alpha) ** 2) <= 1e-10, (p.alpha, p.phi)
    assert all(p.verdict == "stable (energy–momentum)" for p in fork.points if abs(p.phi[0]) > 1e-3)


def test_turntable_with_a_torque_has_a_fold():
    """A constant torque u at the hinge breaks the symmetry: the pitchfork becomes a fold, where
    f = mgc sin φ − Ω²(A22 − A33) sin φ cos φ − u and ∂f/∂φ vanish together (solved here)."""
    text = (ROOT / "specs" / "turntable.toml").read_text().replace('theta = "pi/2"', 'theta = "pi/2"\ncontrol = true')
    spec = parse_spec(text)
    u, a, b = 0.02, 0.5 * G * 0.25, 1 / 24 - 0.0001
    res = _run(spec, [("Omega", 2.0, 12.0)], u=[u], starts=[[-1.0]])  # at the spec's Ω = 8, on the far branch
    folds = [s for br in res.branches for s in br.specials if s.kind == "LP"]
    assert len(folds) == 1, branches.report(res)
    fold = folds[0]
    phi, w = fold.point.phi[0], fold.point.alpha
    for _ in range(50):  # Newton on (f, f_φ) = 0 in (φ, Ω), from the located point
        F = np.array([a * np.sin(phi) - b * w**2 * np.sin(phi) * np.cos(phi) - u, a * np.cos(phi) - b * w**2 * np.cos(2 * phi)])
        J = np.array([[a * np.cos(phi) - b * w**2 * np.cos(2 * phi), -2 * b * w * np.sin(phi) * np.cos(phi)],
                      [-a * np.sin(phi) + 2 * b * w**2 * np.sin(2 * phi), -2 * b * w * np.cos(2 * phi)]])
        phi, w = np.array([phi, w]) - np.linalg.solve(J, F)
    assert _close(fold.point.alpha, w) and abs(fold.point.phi[0] - phi) <= 1e-9, (fold.point.alpha, w, fold.point.phi, phi)
    assert sorted(v.split()[0] for v in (fold.before, fold.after)) == ["linearly", "unstable"], (fold.before, fold.after)


def test_ziegler_flutter_load():
    """Ziegler's pendulum (specs/ziegler.toml): the straight column flutters above
    P_cr = (7/2 − √2) k/l, where two eigenvalues on the imaginary axis meet and leave it."""
    spec = load_spec(ROOT / "specs" / "ziegler.toml")
    res = _run(spec, [("P", 0.0, 12.0)])
    (br,) = res.branches
    (kc,) = br.specials
    assert kc.kind == "KC" and _close(kc.point.alpha, (3.5 - np.sqrt(2)) * 2.0 / 0.5), kc.point.alpha
    assert (kc.before, kc.after) == ("linearly stable", "unstable") and "not conservative" in kc.detail


def _ziegler_damped():
    text = (ROOT / "specs" / "ziegler.toml").read_text().replace("spring = 2.0", 'spring = 2.0\ndamping = "c"')
    return parse_spec(text.replace('name = "ziegler"', 'name = "ziegler_damped"').replace("[values]", "[values]\nc = 0.05"))


def _hopf_load(c: float) -> float:
    """Ziegler's column with a viscous damper c in each joint, by hand: with m l² = 0.125, k = 2,
    l = 0.5, M = m l² [[6, 2], [2, 1]], C = c I, K = [[k, P l], [0, k]] (the follower force's
    work is −P l sin φ² δφ¹); the load where the Hurwitz determinant a₁a₂a₃ − a₀a₃² − a₁²a₄ of
    det(λ²M + λC + K) = Σ aₖλᵏ vanishes (scipy's brentq)."""
    from numpy.polynomial import polynomial as poly
    from scipy.optimize import brentq

    def hurwitz(P):
        m = [[(2.0, c, 0.75), (0.5 * P, 0.0, 0.25)], [(0.0, 0.0, 0.25), (2.0, c, 0.125)]]  # entries' coefficients in λ
        a = poly.polysub(poly.polymul(m[0][0], m[1][1]), poly.polymul(m[0][1], m[1][0]))
        a0, a1, a2, a3, a4 = a
        return a1 * a2 * a3 - a0 * a3**2 - a1**2 * a4

    return brentq(hurwitz, 0.1, 8.3, xtol=1e-15, rtol=1e-15)


def test_ziegler_with_damping_hopf_load_and_its_curve():
    """With damping the column loses stability at a Hopf point, below the undamped flutter load as
    the damping vanishes (Ziegler's destabilisation paradox); the Hopf point continued in (P, c)
    follows the Hurwitz condition at every point."""
    spec = _ziegler_damped()
    res = _run(spec, [("P", 0.0, 12.0), ("c", 0.001, 0.5)])
    (br,) = res.branches
    (h,) = br.specials
    assert h.kind == "H" and _close(h.point.alpha, _hopf_load(0.05)), (h.point.alpha, _hopf_load(0.05))
    assert (h.before, h.after) == ("asymptotically stable", "unstable")
    (curve,) = res.curves
    cs = [c for (_p, c), _phi, _y in curve.points]
    assert min(cs) == 0.001 and max(cs) == 0.5 and len(cs) >= 10
    for (P, c), _phi, _y in curve.points:
        assert _close(P, _hopf_load(c)), (P, c, _hopf_load(c))
    assert _hopf_load(0.001) < 0.71 * (3.5 - np.sqrt(2)) * 4  # the paradox: far below the undamped 8.34


def test_gyroscopic_stabilisation_threshold_and_krein_signatures():
    """GYRO_UP upright: M = diag(A1, A2) with A1 = 0.002 + 0.02, A2 = 0.02, K = −k I with
    k = mgd = 0.981, G = ±h: λ⁴A1A2 + λ²(h² − k(A1 + A2)) + k² = 0. The roots λ² are complex between
    h = √k |√A1 − √A2| (real eigenvalues meet) and h_c = √k (√A1 + √A2), where they meet on the
    imaginary axis with opposite Krein signatures: above h_c the rotor holds it up."""
    spec = parse_spec(GYRO_UP)
    res = _run(spec, [("h", 0.0, 0.6)], starts=[[-np.pi / 2, -np.pi / 2]])
    (br,) = res.branches
    k, a1, a2 = 0.981, 0.022, 0.02
    rc, kc = br.specials
    assert rc.kind == "RC" and _close(rc.point.alpha, np.sqrt(k) * (np.sqrt(a1) - np.sqrt(a2))), rc.point.alpha
    assert (rc.before, rc.after) == ("unstable", "unstable")
    assert kc.kind == "KC" and _close(kc.point.alpha, np.sqrt(k) * (np.sqrt(a1) + np.sqrt(a2))), kc.point.alpha
    assert (kc.before, kc.after) == ("unstable", "linearly stable")
    assert "Krein signatures -, +" in kc.detail or "Krein signatures +, -" in kc.detail
    omega = np.sqrt(k / np.sqrt(a1 * a2))  # at the collision λ² = −k/√(A1A2)
    assert f"ω = {omega:.10g}"[:14] in kc.detail, (kc.detail, omega)


def _hill(diagonal, off) -> float:
    return float(np.linalg.eigvalsh(np.diag(diagonal) + np.diag(off, 1) + np.diag(off, -1))[0])


def a0(q, terms: int = 40) -> float:
    """Mathieu's a₀(q): the smallest eigenvalue of the symmetrised recurrence of ce₀ (Hill's determinant)."""
    off = np.full(terms - 1, q)
    off[0] *= np.sqrt(2)
    return _hill(np.array([(2.0 * r) ** 2 for r in range(terms)]), off)


def b1(q, terms: int = 40) -> float:
    """Mathieu's b₁(q): the smallest eigenvalue of the recurrence of se₁."""
    d = np.array([(2.0 * r + 1) ** 2 for r in range(terms)])
    d[0] -= q
    return _hill(d, np.full(terms - 1, q))


def test_kapitza_boundaries_are_mathieus_curves():
    """Kapitza's pendulum linearised about the upright (hanging) position is Mathieu's equation
    with α = −4g/(lω²) (+4g/(lω²)) and q = 2a/l. Continued in a at ω = 300 rad/s, the upright
    position gains stability through the multiplier +1 and loses it through −1; each point traced
    in (a, ω) over a decade of ω, 100 to 1000 rad/s, lies on a₀(q) = α and b₁(q) = α to 1e-9."""
    spec = load_spec(ROOT / "specs" / "kapitza.toml")
    res = _run(spec, [("a", 0.001, 0.15), ("w", 100.0, 1000.0)], given={"w": 300.0})
    l = 0.2
    kinds = sorted(c.kind for c in res.curves)
    assert kinds == ["+1", "PD", "PD"], branches.report(res)
    for c in res.curves:
        upright = abs(abs(c.points[0][1][0]) - np.pi) < 1e-9
        sign = -1.0 if upright else 1.0
        curve = a0 if c.kind == "+1" else b1
        ws = [w for (_a, w), _phi, _y in c.points]
        assert min(ws) == 100.0 and max(ws) == 1000.0 and len(c.points) >= 10, c.ends
        for (a, w), _phi, _y in c.points:
            mathieu = np.sqrt(sign * 4 * G / (l * curve(2 * a / l)))
            assert abs(w - mathieu) <= 1e-9 * w, (c.kind, a, w, mathieu)


def test_the_command_its_file_and_its_errors(tmp_path):
    res = cli_in_process("continue", str(ROOT / "specs" / "ziegler.toml"), "--vary", "P=0:12", "-o", str(tmp_path / "z.csv"))
    assert res.returncode == 0, res.stderr
    assert "KC  P = 8.34314575051" in res.stdout and "linearly stable -> unstable" in res.stdout
    rows = list(csv.DictReader(io.StringIO((tmp_path / "z.csv").read_text())))
    assert [r["kind"] for r in rows].count("KC") == 1 and rows[0]["part"] == "branch 1"
    special = next(r for r in rows if r["kind"] == "KC")
    assert abs(float(special["P"]) - 8.34314575050762) < 1e-9 and len(special["spectrum"].split()) == 4
    # the same as a Zarr store, a column an array, which plot draws too
    res = cli_in_process("continue", str(ROOT / "specs" / "ziegler.toml"), "--vary", "P=0:12", "-o", str(tmp_path / "z.zarr"))
    assert res.returncode == 0, res.stderr
    import zarr

    g = zarr.open_group(str(tmp_path / "z.zarr"), mode="r")
    kinds = list(dict(g.attrs)["gyrochain_continue"]["kinds"])
    at = [i for i, k in enumerate(g["kind"][...]) if k >= 0 and kinds[k] == "KC"]
    assert len(at) == 1 and g["P"][at[0]] == float(special["P"]) and g["phi"].shape == (len(rows), 2)
    assert np.allclose(g["spectrum"][at[0]][:, 0] + 1j * g["spectrum"][at[0]][:, 1],
                       [complex(z) for z in special["spectrum"].split()])
    res = cli_in_process("plot", str(tmp_path / "z.zarr"), "-o", str(tmp_path / "zs.png"))
    assert res.returncode == 0 and (tmp_path / "zs.png").exists(), res.stderr
    res = cli_in_process("continue", str(ROOT / "specs" / "ziegler.toml"), "--vary", "P=0:12", "-o", str(tmp_path / "z.zarr"))
    assert res.returncode == 2 and "exists; pass --force" in res.stderr
    (tmp_path / "other.zarr").mkdir()
    res = cli_in_process("continue", str(ROOT / "specs" / "ziegler.toml"), "--vary", "P=0:12", "-o", str(tmp_path / "other.zarr"),
                         "--force")
    assert res.returncode == 2 and "not a store of continue" in res.stderr and not any((tmp_path / "other.zarr").iterdir())
    # its diagram: the branches with their special points labelled
    res = cli_in_process("plot", str(tmp_path / "z.csv"), "-o", str(tmp_path / "z.png"))
    assert res.returncode == 0 and (tmp_path / "z.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", res.stderr
    (tmp_path / "other.csv").write_text("t,phi1\n0,1\n")
    for args, field in (((str(tmp_path / "other.csv"), "-o", str(tmp_path / "o.png")), "store"),
                        ((str(tmp_path / "z.csv"), "-o", str(tmp_path / "o.png"), "--component", "phi3"), "--component"),
                        ((str(tmp_path / "z.csv"), "-o", str(tmp_path / "o.png"), "--log"), "--log")):
        res = cli_in_process("plot", *args)
        assert res.returncode == 2 and len(res.stderr.strip().splitlines()) == 1 and field in res.stderr, res.stderr
        assert not (tmp_path / "o.png").exists()
    # a bound on the steps: said, and what was found is kept
    res = cli_in_process("continue", str(ROOT / "specs" / "ziegler.toml"), "--vary", "P=0:12", "--max-steps", "3",
                         "-o", str(tmp_path / "short.csv"))
    assert res.returncode == 0 and "ran out of steps (3" in res.stdout, res.stdout
    assert len((tmp_path / "short.csv").read_text().splitlines()) == 1 + 4
    torque = tmp_path / "torque.toml"
    torque.write_text((ROOT / "specs" / "turntable.toml").read_text().replace('theta = "pi/2"', 'theta = "pi/2"\ncontrol = true'))
    spec = str(ROOT / "specs" / "turntable.toml")
    for args, field in (((spec, "--vary", "Omegx=2:12"), "--vary Omegx"),
                        ((spec, "--vary", "Omega=12:2"), "--vary Omega"),
                        ((spec, "--vary", "Omega=2:12", "--vary", "Omega=1:3"), "--vary Omega"),
                        ((spec, "--vary", "Omega=2:12", "--from", "0,1"), "--from"),
                        ((spec, "--vary", "Omega=2:12", "--param", "Omega=5.431464068243395", "--from", "0"), "--from"),
                        ((str(torque), "--vary", "Omega=2:12", "--u", "10"), "--vary Omega"),
                        ((str(torque), "--vary", "Omega=2:12", "--u", "10", "--from", "1"), "--from"),
                        ((spec, "--vary", "Omega=2:12", "--step", "0"), "--step"),
                        ((str(ROOT / "specs" / "kapitza.toml"), "--vary", "a=0:0.1", "--vary", "w=100:200"), "--vary w"),
                        ((spec, "--vary", "Omega=2:12", "-o", spec), "-o")):
        out = tmp_path / "bad.csv"
        res = cli_in_process("continue", *args, *(() if "-o" in args else ("-o", str(out))))
        assert res.returncode == 2 and res.stdout == "", (args, res.stdout, res.stderr)
        assert len(res.stderr.strip().splitlines()) == 1 and field in res.stderr, (args, res.stderr)
        assert not out.exists()


def test_double_turntable_fold_against_a_direct_solve_and_a_peer():
    """The double pendulum on a turntable with a small torque at its first joint (0.01 N m, which
    breaks the pitchfork into a fold): the branch from φ = (−1.4588, −0.0299) at Ω = 12 turns at a
    fold. Its location agrees to 1e-10 with a direct Newton solve of F = 0, det ∂F/∂φ = 0 in (φ, Ω)
    (the extended system's Jacobian by differences); PyCont-Lite, given the same right side (the
    emitted φ̈), follows the same branch, and its points pass the fold within its step. Both times
    are printed."""
    import time

    from gyrochain.analysis import steady

    spec = parse_spec(DOUBLE_TURNTABLE)
    u, x0 = np.array([0.01]), np.array([-1.45882035, -0.0299122186])
    cm, _model = steady.compile_spec(spec, driven_ok=True)  # built once (and kept): both times are of the work alone
    t0 = time.perf_counter()
    res = _run(spec, [("Omega", 2.0, 12.0)], u=u, starts=[x0])
    ours = time.perf_counter() - t0
    (br,) = res.branches
    (lp,) = br.specials
    assert lp.kind == "LP" and {lp.before, lp.after} == {"unstable", "linearly stable"}

    def F(z):
        phi, w = z[:2], z[2]
        q, dq, _, _ = cm.qdd_derivatives(np.concatenate([phi, [0.0, 0.0]]), u, {"Omega": w})
        return np.append(q, np.linalg.det(dq[:, :2]))

    z = np.append(lp.point.phi, lp.point.alpha) + np.array([1e-3, -1e-3, 1e-3])  # a little off, and solved again
    for _ in range(30):
        J = np.column_stack([(F(z + e) - F(z - e)) / 2e-7 for e in np.eye(3) * 1e-7])
        z = z - np.linalg.solve(J, F(z))
    assert _close(lp.point.alpha, z[2]) and np.max(np.abs(lp.point.phi - z[:2])) < 1e-8, (lp.point.alpha, z)
    pycont = pytest.importorskip("pycont", reason="the peer, PyCont-Lite (pip install pycont-lite; the test extra has it)")

    def G(x, p):
        return cm.qdd(np.concatenate([x, [0.0, 0.0]]), u, {"Omega": p})

    t0 = time.perf_counter()
    peer = pycont.arclengthContinuation(G, x0, 12.0, ds_min=1e-6, ds_max=0.05, ds_0=0.0125, n_steps=2000,
                                        solver_parameters={"param_min": 2.0, "param_max": 12.0, "tolerance": 1e-12},
                                        verbosity=0)
    theirs = time.perf_counter() - t0
    path = peer.branches[0]
    i = int(np.argmin(path.p_path))
    folds = [e.p for e in peer.events if e.kind == "LP"]
    print(f"\nfold: ours Omega = {lp.point.alpha:.12f} in {ours:.3f} s; PyCont-Lite: LP events {folds}, its "
          f"points' least Omega {path.p_path[i]:.9f} ({len(path.p_path)} points) in {theirs:.3f} s")
    assert 0 <= path.p_path[i] - lp.point.alpha < 1e-3 and np.max(np.abs(path.u_path[i] - lp.point.phi)) < 0.05


def test_steady_rotations_of_a_heavy_gyrostat_and_its_precessions():
    """fast_gyro with a slow rotor (λ = 0.02 as a parameter): the carrier turning at ω = φ̇¹ about
    the vertical with the rotor's axis vertical is a steady rotation at every ω; its amended
    potential, −½ω²(A sin²θ + C cos²θ) − λω cos θ + mgl cos θ in the tilt θ = φ², has the
    curvature (C − A)ω² + λω − mgl there, whose roots are branch points; the steady precessions
    that leave them satisfy (C − A)ω² cos θ + λω − mgl = 0 at every point."""
    text = (ROOT / "specs" / "fast_gyro.toml").read_text().replace("lambda = [0.0, 0.0, 5.0]", 'lambda = [0.0, 0.0, "lam"]')
    spec = parse_spec(text.replace('name = "fast_gyro"', 'name = "slow_gyro"') + "\n[values]\nlam = 0.02\n")
    res = _run(spec, [("phidot1", -20.0, 20.0)])
    A, C, lam, mgl = 0.00648, 0.009, 0.02, 1.2 * 9.81 * 0.02
    roots = np.sort(np.roots([C - A, lam, -mgl]).real)
    vertical = next(br for br in res.branches if br.origin.startswith("phi = [0, 0]"))
    assert [s.kind for s in vertical.specials] == ["BP", "BP"]
    for s, w in zip(vertical.specials, roots):
        assert _close(s.point.alpha, w), (s.point.alpha, w)
    assert (vertical.specials[0].before, vertical.specials[0].after) == ("stable (energy–momentum)", "unstable")
    tilted = [br for br in res.branches if br.origin.startswith("the branch point")]
    assert len(tilted) == 4
    for br in tilted:
        for p in br.points[1:]:
            w, th = p.alpha, p.phi[1]
            terms = max(abs((C - A) * w * w), abs(lam * w), mgl)
            assert abs((C - A) * w * w * np.cos(th) + lam * w - mgl) <= 1e-10 * terms, (w, th)
