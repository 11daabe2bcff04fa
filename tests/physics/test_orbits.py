"""Periodic orbits by shooting (gyrochain/analysis/orbits.py): the nonlinear normal modes of the double pendulum
of point masses grow out of its linear modes, ω² = (g/l)(2 ∓ √2); every orbit closes under the
independent reference model; the multipliers agree with differences of the flow (and a perturbed
derivative is caught); a steady rotation of the heavy gyrostat as an orbit has the multipliers
exp(λT) of steady's eigenvalues; bad input is one line."""
from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest

from gyrochain import orbits, pipeline, reference, steady
from gyrochain.spec import load_spec
from conftest import ROOT, cli_in_process, perturbed_c

G, L = 9.81, 1.0


@pytest.fixture(scope="module")
def point():
    spec = load_spec(ROOT / "specs" / "double_pendulum_point.toml")
    cm, model = pipeline.compiled(spec)
    return spec, cm


def test_normal_modes_grow_out_of_the_linear_modes(point):
    """The period at small energies above the hanging equilibrium, extrapolated to zero energy
    (T(E) = T₀ + cE + O(E²) from E = 1e-4 and 2e-4 J), is 2π/ω with ω² = (g/l)(2 ∓ √2), to 1e-9."""
    _, cm = point
    fams = orbits.normal_modes(cm, np.zeros(2), np.array([1e-4, 2e-4]))
    for fam, sign in zip(fams, (-1, 1)):
        (a, b) = fam.orbits
        T0 = 2 * a.period - b.period
        want = 2 * math.pi / math.sqrt(G / L * (2 + sign * math.sqrt(2)))
        assert abs(T0 - want) <= 1e-9 * want, (T0 - want) / want
        assert a.verdict == "linearly stable"


def test_every_orbit_closes_under_the_reference_model(point):
    """Along both modes up to 8 J above the equilibrium: x(T) = x₀ by the independent numpy model
    and scipy's DOP853 (at 1e-12), to 1e-8; the period grows with the energy (both modes soften)."""
    spec, cm = point
    ref = reference.numeric(spec)
    fams = orbits.normal_modes(cm, np.zeros(2), np.linspace(1.0, 8.0, 4))
    E0 = cm.energy(np.zeros(4))  # the hanging equilibrium's: each orbit is at E0 + its value
    for fam in fams:
        assert not fam.stopped and len(fam.orbits) == 4
        assert all(b.period > a.period for a, b in zip(fam.orbits, fam.orbits[1:]))
        for o in fam.orbits:
            x = reference.simulate(ref, o.x0, [0.0, o.period])[-1]
            assert np.max(np.abs(x - o.x0)) <= 1e-8, np.max(np.abs(x - o.x0))
            assert abs(o.energy - (E0 + o.value)) <= 1e-9 * max(1.0, abs(E0)), (o.energy, E0, o.value)
            assert o.trivial_gap <= 1e-4


def _differenced_monodromy(cm, x0, T, h=1e-5):
    def flow(x):
        return cm.integrate([0.0, T], x, rtol=1e-13, atol=1e-13)[-1]

    def central(step):
        return np.array([(flow(x0 + step * e) - flow(x0 - step * e)) / (2 * step) for e in np.eye(len(x0))]).T

    return (4 * central(h / 2) - central(h)) / 3


def test_multipliers_agree_with_differences_of_the_flow(point, example, tmp_path):
    """The nontrivial multipliers of the mode-2 orbit at 4 J against the eigenvalues of the
    differenced monodromy, to 1e-7; with ∂φ̈/∂φ perturbed by 1e-6 in the C, Newton still closes
    the orbit but its multipliers miss by more."""
    _, cm = point
    orb = orbits.normal_modes(cm, np.zeros(2), np.array([1.0, 4.0]), modes=[2])[0].orbits[-1]
    D = _differenced_monodromy(cm, orb.x0, orb.period)
    mu = np.linalg.eigvals(D)
    far = mu[np.argsort(np.abs(mu - 1.0))[2:]]

    def miss(got):
        return max(np.min(np.abs(far - z)) for z in got)

    assert miss(orb.multipliers) <= 1e-7, miss(orb.multipliers)
    bad = perturbed_c(example("double_pendulum_point"), tmp_path / "bad")
    orb_bad = orbits.normal_modes(bad, np.zeros(2), np.array([1.0, 4.0]), modes=[2])[0].orbits[-1]
    assert np.max(np.abs(orb_bad.x0 - orb.x0)) <= 1e-8  # the same orbit
    assert miss(orb_bad.multipliers) > 1e-7


def test_a_steady_rotation_as_a_periodic_orbit():
    """fast_gyro (a heavy gyrostat on a vertical outer axis): the upright steady rotations at
    ω = 1, 2, 3 rad/s as orbits of period 2π/ω; their nontrivial multipliers are exp(λT) of the
    eigenvalues λ that steady gives for the reduced linearisation, to 1e-8."""
    spec = load_spec(ROOT / "specs" / "fast_gyro.toml")
    cm, model = pipeline.compiled(spec)
    fam = orbits.analyze(spec, omegas=np.array([1.0, 2.0, 3.0]))[0]
    an = steady.Analysis(cm, model)
    assert len(fam.orbits) == 3
    for o in fam.orbits:
        lam = an.classify(o.x0[:2], o.value).eigenvalues
        want = np.exp(lam * o.period)
        assert max(np.min(np.abs(want - z)) for z in o.multipliers) <= 1e-8
        assert o.verdict == "linearly stable"


def _cli(*args):
    return subprocess.run([sys.executable, "-m", "gyrochain", "orbits", *args], capture_output=True, text=True, cwd=ROOT)


def test_the_command_and_its_mistakes():
    res = _cli("specs/double_pendulum_point.toml", "--energy", "0.5:2:4", "--mode", "1")
    assert res.returncode == 0, res.stderr
    assert "nonlinear normal mode 1 at phi = [0, 0] (linear: omega = 2.397199398 rad/s" in res.stdout
    assert res.stdout.count("linearly stable") == 4 and "mode 2" not in res.stdout
    for args, field in ((("specs/kapitza.toml",), "orbits"),
                        (("specs/double_pendulum_point.toml", "--mode", "3"), "--mode"),
                        (("specs/double_pendulum_point.toml", "--at", "3.14159,0"), "--at"),
                        (("specs/double_pendulum_point.toml", "--energy", "-1:2:3"), "--energy"),
                        (("specs/double_pendulum_point.toml", "--energy", "1:2"), "--energy"),
                        (("specs/double_pendulum_point.toml", "--omega", "1"), "--omega"),
                        (("specs/double_pendulum_point.toml", "--vary", "m=1:2:3"), "--vary m"),
                        (("specs/furuta.toml", "--u", "0.5"), "orbits"),
                        (("specs/nosuch.toml",), "nosuch")):
        res = cli_in_process("orbits", *args)
        assert res.returncode == 2 and res.stdout == "", (args, res.stdout, res.stderr)
        assert len(res.stderr.strip().splitlines()) == 1 and field in res.stderr, (args, res.stderr)


def test_more_mistakes_are_one_line():
    """A long chain is refused before it is built; a bad --omega, a --vary that leaves the drive."""
    for args, field in ((("orbits", "specs/cable64.toml"), "orbits"),
                        (("orbits", "specs/double_pendulum_point.toml", "--omega", "abc"), "--omega"),
                        (("steady", "specs/kapitza.toml", "--vary", "w=0:100:3"), "--vary w")):
        res = cli_in_process(*args)
        assert res.returncode == 2 and res.stdout == "", (args, res.stdout, res.stderr)
        assert len(res.stderr.strip().splitlines()) == 1 and field in res.stderr, (args, res.stderr)
