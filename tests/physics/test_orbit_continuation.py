"""``gyrochain continue --orbits``: branches of periodic orbits by continuation, against the
pendulum's period in closed form (the complete elliptic integral, by the arithmetic-geometric
mean here), Mathieu's curves for Kapitza's upright orbit, and independent solves of the shooting
equations (the flow integrated without the variational equations, a bordered Newton on the fold)."""
from __future__ import annotations

import csv
import io
import math

import numpy as np

from gyrochain.analysis import branches, steady
from gyrochain.spec import load_spec, parse_spec
from conftest import ROOT, cli_in_process
from test_continuation import a0, b1

G = 9.81
PENDULUM = """
name = "pendulum"
description = "a bob of 0.1 kg on a light rod of 0.2 m"
g = 9.81
[[body]]
theta = "pi/2"
m = 0.1
c = [0.0, 0.0, 0.2]
I_c = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
"""
# the same pendulum, its pivot shaken horizontally by a cos(w t), with a damper in the joint
FORCED = PENDULUM.replace('name = "pendulum"', 'name = "forced"').replace(
    "g = 9.81", 'g = 9.81\n[base]\nposition = [0, "a*cos(w*t)", 0]') + "damping = 0.0011\n[values]\na = 0.012\nw = 5.0\n"


def _elliptic_k(m: float) -> float:
    """K(m) = π / (2 AGM(1, √(1 − m)))."""
    a, b = 1.0, math.sqrt(1.0 - m)
    for _ in range(40):  # quadratic: a and b agree to the last bit after a handful
        a, b = (a + b) / 2, math.sqrt(a * b)
    return math.pi / (2 * a)


def _run(text, ranges, **kw):
    spec = parse_spec(text) if isinstance(text, str) else text
    return branches.run(spec, {**spec.values, **kw.pop("given", {})}, None, ranges, **kw)


def test_the_pendulums_family_has_the_elliptic_period():
    """The one nonlinear normal mode of a pendulum, over the energy above the hanging position up
    to 0.9 of the barrier 2mgl: every orbit's period is 4K(k)/ω₀ with k² = E/(2mgl), to 1e-10."""
    mgl = 0.1 * G * 0.2
    res = _run(PENDULUM, [(branches.ENERGY, 0.001, 1.8 * mgl)])
    (br,) = res.branches
    assert res.orbits == "modes" and br.ends == ("reached the range's end, energy = 0.001",
                                                 "reached the range's end, energy = 0.35316"), br.ends
    assert len(br.points) >= 20 and br.points[0].alpha == 0.001 and br.points[-1].alpha == 1.8 * mgl
    w0 = math.sqrt(G / 0.2)
    for p in br.points:
        exact = 4 * _elliptic_k(p.alpha / (2 * mgl)) / w0
        assert abs(p.period - exact) <= 1e-10 * exact, (p.alpha, p.period, exact)
        assert abs(p.amplitude[0] - 2 * math.asin(math.sqrt(p.alpha / (2 * mgl)))) < 1e-3  # the diagram's swing
    assert not br.specials


def test_the_double_pendulums_modes_and_where_one_loses_stability():
    """Both normal-mode families of the textbook double pendulum over E − E₀ = 0.01…30 J: every
    fourth orbit closes when integrated again without the variational equations (1e-9) at its
    energy (1e-10);
    the faster mode loses stability where a pair of multipliers passes +1: the root of q(1) from
    ``orbits``' own shooting at six energies around it is that energy to 1e-9."""
    from gyrochain.analysis import orbits

    spec = load_spec(ROOT / "specs" / "double_pendulum_point.toml")
    res = _run(spec, [(branches.ENERGY, 0.01, 30.0)])
    assert len(res.branches) == 2 and [len(b.specials) for b in res.branches] == [0, 1], branches.report(res)
    cm, _model = steady.compile_spec(spec)
    E0 = float(cm.energy(np.zeros(4)))
    for br in res.branches:
        for p in br.points[::4]:
            x0 = np.concatenate([p.phi, p.phidot])
            x1 = cm.integrate([0.0, p.period], x0, rtol=1e-13, atol=1e-13)[-1]
            assert np.max(np.abs(x1 - x0)) < 1e-9 and abs(float(cm.energy(x0)) - E0 - p.alpha) < 1e-10
    s = res.branches[1].specials[0]
    assert s.kind == "+1" and (s.before, s.after) == ("linearly stable", "unstable") and 10 < s.point.alpha < 20
    sh = orbits.Shooting(cm, None, None, phase=int(np.argmin(np.abs(s.point.phidot))) + 2)
    offsets = np.array([-0.15, -0.1, -0.05, 0.05, 0.1, 0.15])  # J: q(1) by orbits' own shooting around it, fitted
    q1 = []
    for dE in offsets:
        guess = min(res.branches[1].points, key=lambda p: abs(p.alpha - s.point.alpha - dE))
        x0, _T, Phi, _c = sh.solve(np.concatenate([guess.phi, guess.phidot]), guess.period, E0 + s.point.alpha + dE)
        x1, Phi = cm.integrate_variational(0.0, _T, x0, rtol=1e-14, atol=1e-14)
        q = np.polydiv(np.real(np.poly(np.linalg.eigvals(Phi))), [1.0, -2.0, 1.0])[0]
        q1.append(np.polyval(q, 1.0))
    assert np.all(np.sign(q1) == -np.sign(offsets)), q1
    fit = np.polyfit(offsets, q1, 5)
    root = min((r.real for r in np.roots(fit) if abs(r.imag) < 1e-12), key=abs)
    assert abs(root) < 1e-9 * s.point.alpha, root


def test_the_forced_pendulums_folds():
    """A damped pendulum shaken horizontally, over the drive's frequency through its resonance:
    the softening spring bends the response curve back, two folds bound the unstable middle; each
    fold agrees to 1e-9 in w (1e-8 in its start) with a Newton solve of x(T) = x₀, det(Φ − I) = 0
    in (x₀, w) (the Jacobian by differences, the tangent not used)."""
    spec = parse_spec(FORCED)
    res = _run(spec, [("w", 5.0, 9.0)], orbits=True)
    (br,) = res.branches
    assert [s.kind for s in br.specials] == ["LP", "LP"], branches.report(res)
    assert [(s.before, s.after) for s in br.specials] == [("asymptotically stable", "unstable"),
                                                         ("unstable", "asymptotically stable")]
    hi, lo = (s.point.alpha for s in br.specials)
    assert 6.3 < lo < hi < 6.7 and max(p.amplitude[0] for p in br.points) > 1.0
    cm, _model = steady.compile_spec(spec, driven_ok=True)

    def G_(z):
        params = {"a": 0.012, "w": z[2]}
        x1, Phi = cm.integrate_variational(0.0, 2 * math.pi / z[2], z[:2], params=params, rtol=1e-14, atol=1e-14)
        return np.append(x1 - z[:2], np.linalg.det(Phi - np.eye(2)))

    for s in br.specials:
        z = np.array([*s.point.phi, *s.point.phidot, s.point.alpha + 1e-4])
        for _ in range(30):
            g = G_(z)
            J = np.column_stack([(G_(z + h) - G_(z - h)) / 2e-7 for h in np.eye(3) * 1e-7])
            dz = np.linalg.solve(J, -g)
            z += dz
            if np.max(np.abs(dz)) < 1e-13:
                break
        assert np.max(np.abs(G_(z))) < 1e-10  # converged
        assert abs(z[2] - s.point.alpha) < 1e-9 and np.max(np.abs(z[:2] - [*s.point.phi, *s.point.phidot])) < 1e-8, \
            (z, s.point.alpha)


def test_kapitzas_upright_orbit_meets_mathieus_curves():
    """The upright rest of Kapitza's pendulum is a periodic orbit of the drive's period for every
    amplitude a. Continued in a at ω = 300 rad/s it gains stability at a branch point (the
    multiplier +1: a pair of tilted orbits leaves it) where a₀(2a/l) = −4g/(lω²), and loses it by
    period doubling where b₁(2a/l) = −4g/(lω²): both to 1e-9, with the tilted orbits traced."""
    spec = load_spec(ROOT / "specs" / "kapitza.toml")
    res = _run(spec, [("a", 0.001, 0.15)], given={"w": 300.0}, starts=[np.array([math.pi])], orbits=True)
    upright = res.branches[0]
    assert [s.kind for s in upright.specials] == ["BP", "PD"], branches.report(res)
    assert [(s.before, s.after) for s in upright.specials] == [("unstable", "linearly stable"), ("linearly stable", "unstable")]
    l, alpha = 0.2, -4 * G / (0.2 * 300.0 ** 2)
    for s, curve in zip(upright.specials, (a0, b1)):
        lo, hi = 0.9 * s.point.alpha, 1.1 * s.point.alpha  # Mathieu's a, by bisection
        for _ in range(100):
            mid = (lo + hi) / 2
            lo, hi = (mid, hi) if (curve(2 * mid / l) - alpha) * (curve(2 * lo / l) - alpha) > 0 else (lo, mid)
        assert abs(s.point.alpha - lo) <= 1e-9 * lo, (s.kind, s.point.alpha, lo)
    tilted = res.branches[1:]
    assert len(tilted) == 2 and all(b.origin.startswith("the branch point") for b in tilted)
    assert all(p.verdict == "unstable" for b in tilted for p in b.points[1:])  # the saddles that bound the basin
    sides = [{np.sign(p.phi[0] - math.pi) for p in b.points[1:]} for b in tilted]
    assert sorted(sides) == [{-1.0}, {1.0}], sides  # one tilted either way


def test_the_command_its_file_its_diagram_and_its_errors(tmp_path):
    spec = tmp_path / "forced.toml"
    spec.write_text(FORCED)
    out = tmp_path / "f.csv"
    res = cli_in_process("continue", str(spec), "--orbits", "--vary", "w=5:9", "-o", str(out))
    assert res.returncode == 0, res.stderr
    assert "periodic orbits of the drive's period continued in w" in res.stdout and res.stdout.count("LP  w = 6.") == 2
    rows = list(csv.DictReader(io.StringIO(out.read_text())))
    assert list(rows[0])[2:8] == ["w", "phi1", "phidot1", "period", "amp1", "verdict"]
    assert all(abs(float(r["period"]) - 2 * math.pi / float(r["w"])) < 1e-15 * 10 for r in rows)
    res = cli_in_process("plot", str(out), "-o", str(tmp_path / "f.png"))
    assert res.returncode == 0 and (tmp_path / "f.png").read_bytes()[:4] == b"\x89PNG", res.stderr
    res = cli_in_process("continue", str(spec), "--orbits", "--vary", "w=5:9", "-o", str(tmp_path / "f.zarr"))
    assert res.returncode == 0, res.stderr
    header, stored = branches.read_store(tmp_path / "f.zarr")
    assert header == list(rows[0]) and [float(r["amp1"]) for r in stored] == [float(r["amp1"]) for r in rows]
    pendulum = tmp_path / "pendulum.toml"
    pendulum.write_text(PENDULUM)
    res = cli_in_process("continue", str(pendulum), "--vary", "energy=0.01:0.3", "--mode", "1")
    assert res.returncode == 0 and "nonlinear normal modes" in res.stdout, res.stderr
    # past the separatrix (2mgl = 0.3924 J) the family ends, and says why; a run's steps spent say which mode is left
    res = cli_in_process("continue", str(pendulum), "--vary", "energy=0.01:1")
    assert res.returncode == 0 and "the family nears an orbit of infinite period" in res.stdout, res.stdout
    res = cli_in_process("continue", str(ROOT / "specs" / "double_pendulum_point.toml"), "--vary", "energy=0.01:30",
                         "--max-steps", "1")
    assert res.returncode == 0 and "mode 2 (linear: omega = 5.787351298 rad/s): not traced" in res.stdout, res.stdout
    assert "branch 1, from mode 1" in res.stdout and "reached the range's end, energy = 0.01; ran out of steps" in res.stdout
    for args, field in (((str(pendulum), "--vary", "energy=0.01:0.3", "--mode", "2"), "--mode"),
                        ((str(pendulum), "--orbits", "--vary", "g=1:2"), "--vary"),
                        ((str(spec), "--vary", "energy=0.01:0.3"), "--vary energy"),
                        ((str(spec), "--orbits", "--vary", "w=5:9", "--vary", "a=0:0.1"), "--vary a"),
                        ((str(spec), "--vary", "w=5:9", "--mode", "1"), "--mode"),
                        ((str(ROOT / "specs" / "ziegler.toml"), "--vary", "energy=0.1:1"), "--vary energy"),
                        ((str(ROOT / "specs" / "turntable.toml"), "--orbits", "--vary", "Omega=2:12"), "--orbits"),
                        ((str(ROOT / "specs" / "gimbal.toml"), "--vary", "energy=0.01:1"), "--vary energy"),  # phi1 cyclic
                        # from the linear mode at 5 J Newton finds only x(T) = x0 at T -> 0, no orbit
                        ((str(ROOT / "specs" / "double_pendulum_point.toml"), "--vary", "energy=5:25", "--mode", "2"),
                         "--vary energy"),
                        ((str(pendulum), "--vary", "energy=0:1"), "--vary energy"),
                        ((str(pendulum), "--vary", "energy=0.01:0.3", "--period", "1"), "--period"),
                        ((str(spec), "--orbits", "--vary", "w=5:9", "--mode", "1"), "--mode"),
                        ((str(spec), "--orbits", "--vary", "w=5:9", "--period", "1.2566370614359172"), "--period"),
                        ((str(spec), "--orbits", "--vary", "w=5:9", "--from", "0,0,0"), "--from")):
        res = cli_in_process("continue", *args, "-o", str(tmp_path / "bad.csv"))
        assert res.returncode == 2 and len(res.stderr.strip().splitlines()) == 1 and field in res.stderr, (args, res.stderr)
        assert "Traceback" not in res.stderr and not (tmp_path / "bad.csv").exists()
