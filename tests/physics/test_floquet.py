"""Floquet stability of driven pendulums (gyrochain/analysis/floquet.py) against the Mathieu equation.

Kapitza's pendulum (specs/kapitza.toml: a point bob on a light rod of l = 0.2 m, the pivot moving
as a cos(ω t) along the vertical) linearised about the upright position θ = φ − π is, with
τ = ω t / 2, Mathieu's equation y'' + (α − 2q cos 2τ) y = 0 with α = −4g/(lω²) and q = 2a/l (about
the hanging position α = +4g/(lω²)).  The upright position is stable where α > a₀(q), the hanging
one unstable in the first tongue b₁(q) < α < a₁(q).  The characteristic values are checked three
ways: the series of NIST's DLMF §28.6 (28.6.1–3, to q⁸; the same as Abramowitz & Stegun 20.2.25)
at small q, to the series' own accuracy; a 40-digit computation (mpmath: the smallest eigenvalue
of the recurrence of the π-periodic even Mathieu functions, truncated at 40 terms) at the
example's q; and scipy.special.mathieu_a / mathieu_b."""
from __future__ import annotations

import math

import mpmath as mp
import numpy as np
import pytest
from scipy.special import mathieu_a, mathieu_b

from gyrochain import floquet, pipeline
from gyrochain.spec import load_spec
from conftest import ROOT, cli_in_process, perturbed_c

G, L = 9.81, 0.2  # the example's gravity and the bob's distance from the pivot


def a0_series(q):  # DLMF 28.6.1
    return -q**2 / 2 + 7 * q**4 / 128 - 29 * q**6 / 2304 + 68687 * q**8 / 18874368


def a1_series(q):  # DLMF 28.6.2
    return (1 + q - q**2 / 8 - q**3 / 64 - q**4 / 1536 + 11 * q**5 / 36864 + 49 * q**6 / 589824
            - 55 * q**7 / 9437184 - 83 * q**8 / 35389440)


def b1_series(q):  # DLMF 28.6.3
    return (1 - q - q**2 / 8 + q**3 / 64 - q**4 / 1536 - 11 * q**5 / 36864 + 49 * q**6 / 589824
            + 55 * q**7 / 9437184 - 83 * q**8 / 35389440)


def a0_precise(q, terms: int = 40):
    """a₀(q) to 40 digits: the smallest eigenvalue of the symmetrised recurrence of ce₀ (DLMF 28.4.5)."""
    with mp.workdps(40):
        q = mp.mpf(q)
        M = mp.zeros(terms, terms)
        for r in range(terms):
            M[r, r] = (2 * r) ** 2
            if r + 1 < terms:
                M[r, r + 1] = M[r + 1, r] = q * (mp.sqrt(2) if r == 0 else 1)
        return min(mp.eigsy(M, eigvals_only=True))


@pytest.fixture(scope="module")
def kapitza():
    spec = load_spec(ROOT / "specs" / "kapitza.toml")
    cm, model = pipeline.compiled(spec)
    return cm, model, dict(spec.values)


def _boundary(an, name, values, phi):
    """The first verdict change of the equilibrium phi along name = values."""
    eq = next(e for e in an.equilibria() if abs(floquet.wrap(e.phi[0] - phi)) < 1e-9)
    cont = an.along(name, np.asarray(values, float), eq)
    assert cont.changes, [d.verdict for _, d in cont.points]
    return cont.changes


def test_the_period_comes_from_the_spec(kapitza):
    cm, model, values = kapitza
    T, how = floquet.time_period(model, values)
    assert T == pytest.approx(2 * math.pi / values["w"], rel=1e-15)
    assert "w" in how
    floquet.check_period(cm, T, values, None)
    with pytest.raises(floquet.SpecError):
        floquet.check_period(cm, 0.7 * T, values, None)


# the series' first omitted term of a₀ is −(123707/104857600) q¹⁰ (the literature's next term; checked
# against the 40-digit a₀ in test_the_series_and_its_error)
A0_NEXT = 123707 / 104857600


def test_the_series_and_its_error():
    """The references agree: DLMF's series, scipy and the 40-digit value, and the series' error is
    its next term (so that the bound below is the series' own accuracy)."""
    for q, rel in ((0.001, 1e-5), (0.05, 1e-2), (0.3, 0.1)):
        precise = a0_precise(q)
        assert abs(mathieu_a(0, q) - float(precise)) <= 1e-14
        with mp.workdps(40):
            err = a0_series(mp.mpf(q)) - precise  # (the series in 40 digits too)
            assert abs(err / (A0_NEXT * mp.mpf(q) ** 10) - 1) <= rel


@pytest.mark.parametrize("w", [70.0, 100.0, 200.0, 600.0])
def test_upright_boundary_against_the_series(kapitza, w):
    """Along the amplitude a at a fixed ω: the upright pendulum becomes stable where
    α = −4g/(lω²) = a₀(q), q = 2a/l.  At these ω the boundary's q is 0.28, 0.20, 0.10, 0.033: the
    series (to q⁸) agrees with the computed boundary to its own accuracy (twice its first omitted
    term, 3e-10 at q = 0.28, 1e-20 at 0.033) plus 1e-9 of α; scipy's a₀ to 1e-9 of α."""
    cm, model, values = kapitza
    an = floquet.DrivenAnalysis(cm, model, {**values, "w": w})
    a_avg = math.sqrt(2 * G * L) / w  # the averaged criterion a²ω² = 2gl
    changes = _boundary(an, "a", np.linspace(0.5 * a_avg, 1.5 * a_avg, 5), math.pi)
    a_c, before, after = changes[0]
    assert (before, after) == ("unstable", "linearly stable")
    q, alpha = 2 * a_c / L, -4 * G / (L * w * w)
    bound = 2 * A0_NEXT * q**10 + 1e-9 * abs(alpha)
    assert abs(a0_series(q) - alpha) <= bound, (a0_series(q) - alpha, bound)
    assert abs(mathieu_a(0, q) - alpha) <= 1e-9 * abs(alpha)
    # the averaged criterion is short by the series' next term: a²ω² = 2gl (1 − 7q²/64)^-1 to first order
    assert a_c / a_avg - 1 == pytest.approx(7 * q * q / 128, rel=0.1)


def test_upright_boundary_at_the_examples_amplitude(kapitza):
    """At ω = 260 rad/s (the example's): a_c against the 40-digit root of a₀(q) = α, to 1e-9."""
    cm, model, values = kapitza
    an = floquet.DrivenAnalysis(cm, model, values)
    (a_c, before, after), = _boundary(an, "a", [0.005, 0.0075, 0.0100], math.pi)
    alpha = -4 * G / (L * values["w"] ** 2)
    with mp.workdps(40):
        q = mp.findroot(lambda z: a0_precise(z) - alpha, math.sqrt(-2 * alpha))
        want = float(q * L / 2)
    assert abs(a_c - want) <= 1e-9 * want, (a_c - want) / want
    assert (before, after) == ("unstable", "linearly stable")


def test_hanging_pendulum_first_tongue(kapitza):
    """The hanging pendulum is unstable near ω = 2√(g/l) (parametric resonance): the tongue
    b₁(q) < 4g/(lω²) < a₁(q) at a = 1 cm (q = 0.1), both edges along ω to 1e-9 (scipy's values)."""
    cm, model, values = kapitza
    an = floquet.DrivenAnalysis(cm, model, values)
    w0 = math.sqrt(G / L)
    changes = _boundary(an, "w", np.linspace(1.8 * w0, 2.2 * w0, 9), 0.0)
    assert [c[1:] for c in changes] == [("linearly stable", "unstable"), ("unstable", "linearly stable")]
    q = 2 * values["a"] / L
    for (w, _, _), edge in zip(changes, (mathieu_a(1, q), mathieu_b(1, q))):  # α falls as ω grows
        alpha = 4 * G / (L * w * w)
        assert abs(alpha - edge) <= 1e-9 * edge, (alpha - edge) / edge
    assert abs(a1_series(q) - mathieu_a(1, q)) < 1e-11 and abs(b1_series(q) - mathieu_b(1, q)) < 1e-11


def test_a_perturbed_derivative_moves_the_boundary(kapitza, tmp_path, example):
    """∂φ̈/∂φ times 1 + 1e-6 in the emitted C: the upright boundary misses the 40-digit value by
    more than the tolerance of the test above."""
    cm, model, values = kapitza
    bad = perturbed_c(example("kapitza"), tmp_path / "bad")
    an = floquet.DrivenAnalysis(bad, model, values)
    (a_c, _, _), = _boundary(an, "a", [0.005, 0.0075, 0.0100], math.pi)
    alpha = -4 * G / (L * values["w"] ** 2)
    with mp.workdps(40):
        want = float(mp.findroot(lambda z: a0_precise(z) - alpha, math.sqrt(-2 * alpha)) * L / 2)
    assert abs(a_c - want) > 1e-9 * want


def test_multipliers_of_a_conservative_drive_are_symplectic(kapitza):
    """A driven conservative model: det Φ(T) = 1 and the multipliers in pairs μ, 1/μ̄ (here
    on the unit circle: both positions linearly stable at the example's values)."""
    cm, model, values = kapitza
    an = floquet.DrivenAnalysis(cm, model, values)
    eqs = an.equilibria()
    assert [round(float(e.phi[0]), 9) for e in eqs] == [0.0, round(math.pi, 9)]
    for e in eqs:
        assert abs(np.linalg.det(e.monodromy) - 1.0) <= 1e-10
        assert np.allclose(np.abs(e.multipliers), 1.0, atol=1e-9)
        assert e.verdict == "linearly stable"


KAPITZA = (ROOT / "specs" / "kapitza.toml").read_text()


@pytest.mark.parametrize("position,field,words", [
    ('["a*w*t", 0, 0]', "steady", "do not depend on t"),
    ('["a*w*t*t*t", 0, 0]', "steady", "not periodic in t: t enters the equations as a polynomial"),
    ('["a*cos(w*t) + a*cos(sqrt(2)*w*t)", 0, 0]', "steady", "quasi-periodic"),
    ('["a*cos(w*t)*t", 0, 0]', "steady", "not periodic in t"),
])
def test_a_model_that_is_not_periodic_is_one_line(tmp_path, position, field, words):
    spec = tmp_path / "drift.toml"
    spec.write_text(KAPITZA.replace('position = ["a*cos(w*t)", 0, 0]', f"position = {position}"))
    res = cli_in_process("steady", spec)
    assert res.returncode == 2 and res.stdout == "", (res.stdout, res.stderr)
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and field in lines[0] and words in lines[0], res.stderr


def test_the_period_of_several_frequencies(example):
    """The rolling ship: heave 0.6, roll 0.5 and pitch 0.7 rad/s, so T = 2π/0.1; a T that does not
    fit is refused; no equilibrium persists (the drive moves every one), and a start the user
    gives is then a one-line error."""
    import subprocess
    import sys

    m = pipeline.compiled(load_spec(ROOT / "specs" / "ship_gimbal.toml"))
    T, _ = floquet.time_period(m[1], None)
    assert T == pytest.approx(20 * math.pi, rel=1e-14)
    floquet.check_period(m[0], T, None, None)
    with pytest.raises(floquet.SpecError):
        floquet.check_period(m[0], T / 2, None, None)
    res = subprocess.run([sys.executable, "-m", "gyrochain", "steady", "specs/ship_gimbal.toml"], capture_output=True,
                         text=True, cwd=ROOT)
    assert res.returncode == 0 and "equilibria for all t: 0 found" in res.stdout
    res = cli_in_process("steady", "specs/ship_gimbal.toml", "--start", "0,0.3")
    assert res.returncode == 2 and len(res.stderr.strip().splitlines()) == 1 and "--start 0,0.3" in res.stderr


def test_the_sweep_measure_sees_a_perturbed_derivative(kapitza, example, tmp_path):
    """floquet.sweep_moduli (what `sweep --measure floquet` stores) at amplitudes 1e-7 either side
    of the 40-digit upright boundary at ω = 260 rad/s: unstable below it, stable above; with ∂φ̈/∂φ
    perturbed by 1e-6 in the C the boundary moves by more than that, and a point changes side."""
    cm, model, values = kapitza
    alpha = -4 * G / (L * values["w"] ** 2)
    with mp.workdps(40):
        a_c = float(mp.findroot(lambda z: a0_precise(z) - alpha, math.sqrt(-2 * alpha)) * L / 2)
    X0 = np.array([[math.pi, 0.0], [math.pi, 0.0]])
    params = [{**values, "a": a_c * (1 - 1e-7)}, {**values, "a": a_c * (1 + 1e-7)}]

    def sides(c):
        mu, codes = floquet.sweep_moduli(c, model, X0, params, None, False)
        assert not codes.any()
        return [bool(m > 1 + floquet.MU_TOL) for m in mu]

    assert sides(cm) == [True, False]
    assert sides(perturbed_c(example("kapitza"), tmp_path / "bad")) != [True, False]
