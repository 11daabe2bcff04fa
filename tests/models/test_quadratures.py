"""The integrable two-body case (28)–(30): the quadratures against ODE solutions of the generated
equations, at the turning points and near the separatrix, and their errors."""
from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest
from scipy.integrate import solve_ivp

from gyrochain.build import ModelError
from gyrochain.randspec import random_spec_text

ODE_TOL = 1e-13


def ode(model, x0, t1, params=None, **kw):
    sol = solve_ivp(lambda t, x: model.c.rhs(t, x, None, params), (0.0, t1), np.asarray(x0, float),
                    method="DOP853", rtol=ODE_TOL, atol=ODE_TOL, dense_output=True, **kw)
    assert sol.success, sol.message
    return sol


def ode_period(model, x0, kind, params=None, guess=None):
    """The period of φ from the ODE: the first return of φ to φ₀ (+2π for a rotation) with the
    sign of φ̇₀, located on the dense output to round-off."""
    phi0, s = x0[1], math.copysign(1.0, x0[3]) if x0[3] else 1.0
    shift = s * 2.0 * math.pi if kind == "rotation" else 0.0

    def back(t, x):
        return (x[1] - phi0 - shift) * (s if kind == "rotation" else 1.0)

    back.direction = s if kind == "libration" else 1.0
    sol = ode(model, x0, 1.5 * guess, params, events=back)
    times = [t for t in sol.t_events[0] if t > 1e-6 * guess]
    return times[0]


def random_two_body(make_model, seed):
    rng = np.random.default_rng(seed)
    return make_model(random_spec_text(rng, 2, name=f"twobody{seed}", theta1=0.0))


def find_state(model, kind, rng, params=None):
    """A random initial state whose motion is of the given kind (tries until one is)."""
    for _ in range(200):
        phidot = rng.uniform(0.3, 2.0) if kind == "libration" else rng.uniform(5.0, 60.0)
        x0 = np.array([rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-2, 2), rng.choice([-1, 1]) * phidot])
        if model.c.quad_motion(x0, params)["kind"] == kind:
            return x0
    raise AssertionError(f"no {kind} found")


def check_against_ode(model, x0, kind, params=None):
    info = model.c.quad_motion(x0, params)
    assert info["kind"] == kind
    T = info["period"]
    T_ode = ode_period(model, x0, kind, params, guess=T)
    assert abs(T - T_ode) <= 1e-10 * T, (T, T_ode)
    # φ(t), ψ(t) over ten periods, C and Python
    ts = np.linspace(0.0, 10.0 * T, 41)
    X_ode = ode(model, x0, ts[-1], params).sol(ts).T
    for X in (model.c.quad_state(ts, x0, params), model.py.quad_state(ts, x0, params)):
        assert np.max(np.abs(X[:, :2] - X_ode[:, :2])) <= 1e-9 * max(1.0, np.max(np.abs(X_ode[:, :2])))
        # the velocities too (scaled by their size)
        assert np.max(np.abs(X[:, 2:] - X_ode[:, 2:])) <= 1e-8 * max(1.0, np.max(np.abs(X_ode[:, 2:])))
    assert abs(model.py.quad_period(x0, params) - T) <= 1e-12 * T
    return info


GIMBAL_STATES = {
    "libration": [0.0, 0.3, 2.0, 0.5],
    "rotation": [0.0, 1.5, 0.0, 70.0],
}


@pytest.mark.parametrize("kind", ["libration", "rotation"])
def test_gimbal_quadrature_matches_ode(example, kind):
    check_against_ode(example("gimbal"), np.array(GIMBAL_STATES[kind]), kind)


@pytest.mark.parametrize("seed", [1, 2, 3])
@pytest.mark.parametrize("kind", ["libration", "rotation"])
def test_random_two_body_quadrature_matches_ode(make_model, seed, kind):
    model = random_two_body(make_model, seed)
    x0 = find_state(model, kind, np.random.default_rng(seed))
    check_against_ode(model, x0, kind)


# --------------------------------------------------------------------------- turning points
def test_accurate_at_and_through_the_turning_points(example):
    """Start at a turning point (φ̇₀ = 0): φ(t) at t = 0, T/2 (the other turning point), T, and
    at times 1e-9 … 1e-3 around them, against the ODE."""
    m = example("gimbal")
    x0 = np.array([0.2, 0.4, 2.0, 0.0])
    info = m.c.quad_motion(x0)
    assert info["kind"] == "libration" and info["phi_max"] == x0[1]  # φ₀ is φ₊ exactly
    T = info["period"]
    offsets = np.array([0.0, 1e-9, 1e-6, 1e-3])
    ts = np.unique(np.concatenate([c + s * offsets for c in (0.5 * T, T, 1.5 * T) for s in (-1, 1)]))
    X_ode = ode(m, x0, ts[-1]).sol(ts).T
    for X in (m.c.quad_state(ts, x0), m.py.quad_state(ts, x0)):
        assert np.max(np.abs(X - X_ode)) <= 1e-10
    # exactly at the turning points: φ̇ = 0 and φ at φ₋, φ₊
    X = m.c.quad_state(np.array([0.5 * T, T]), x0)
    assert abs(X[0, 1] - info["phi_min"]) <= 1e-14 and abs(X[1, 1] - info["phi_max"]) <= 1e-14
    assert np.all(np.abs(X[:, 3]) <= 1e-12)


# --------------------------------------------------------------------------- the separatrix
# The gimbal's separatrix: with ψ̇₀ = 0 at φ₀ = 1.5, P = E J − (k − λ cos φ)² has a double root at
# φ = π (the rotor axis pointing down the other way: an unstable steady motion) when
# A φ̇₀² J(π) = (k + λ)², i.e. for φ̇₀ = φ̇_s below.  φ̇₀ < φ̇_s: libration, φ̇₀ > φ̇_s: rotation.
G_A1, G_A2, G_A3, G_LAM = 0.005, (0.006, 0.006, 0.009), 0.0, 0.5


def gimbal_sep_phidot():
    k = G_LAM * math.cos(1.5)
    J_pi = G_A1 + G_A2[2]
    return math.sqrt((k + G_LAM) ** 2 / (G_A2[0] * J_pi))  # E(φ) = 2E = A φ̇₀² here


def gimbal_period_mp(E, k, kind, roots):
    """The period by (30) in 40-digit arithmetic (tanh-sinh), from the exact roots."""
    mpmath.mp.dps = 40
    E, k = mpmath.mpf(E), mpmath.mpf(k)

    def J(f):
        return G_A1 + G_A2[1] * mpmath.sin(f) ** 2 + G_A2[2] * mpmath.cos(f) ** 2

    def P(f):
        return 2 * E * J(f) - (k - G_LAM * mpmath.cos(f)) ** 2

    def Phi(f):
        return mpmath.sqrt(G_A2[0] * J(f) / P(f))

    if kind == "rotation":
        pi = mpmath.pi
        return mpmath.quad(Phi, [0, pi - mpmath.mpf("0.1"), pi, pi + mpmath.mpf("0.1"), 2 * pi], maxdegree=12)
    # P is a quadratic in u = cos φ here: its roots in 40 digits
    A1, A22, A23, lam = (mpmath.mpf(v) for v in (G_A1, G_A2[1], G_A2[2], G_LAM))
    a = 2 * E * (A23 - A22) - lam**2
    b, c = 2 * k * lam, 2 * E * (A1 + A22) - k**2
    us = [(-b + sg * mpmath.sqrt(b * b - 4 * a * c)) / (2 * a) for sg in (-1, 1)]
    u = min((u for u in us if abs(u) <= 1), key=lambda u: abs(u - math.cos(roots[1])))
    lo, hi = (math.copysign(1, r) * mpmath.acos(u) for r in roots)
    # φ = m + h sin θ takes the 1/√ out of the ends (tanh-sinh alone gets ~1e-9 there); the
    # near-singularity just beyond each end (the separatrix) sits at the split points
    m, h = (lo + hi) / 2, (hi - lo) / 2
    ends = [mpmath.pi / 2 - mpmath.mpf(10) ** -e for e in (1, 2, 3, 4, 6)]
    pts = [-mpmath.pi / 2] + [-e for e in ends] + [0] + ends[::-1] + [mpmath.pi / 2]
    # (nodes within ~1e-40 of an end may see P < 0 by the last digit: the real part is the integral)
    return mpmath.re(2 * mpmath.quad(lambda th: Phi(m + h * mpmath.sin(th)) * h * mpmath.cos(th), pts, maxdegree=10))


@pytest.mark.parametrize("delta", [1e-2, 1e-4, 1e-6, 1e-8])
@pytest.mark.parametrize("side", [-1, 1])
def test_period_near_the_separatrix(example, delta, side):
    """The period grows like log(1/δ) near the separatrix; the quadrature keeps its accuracy
    there (against 40-digit tanh-sinh for the same constants E, k)."""
    m = example("gimbal")
    x0 = np.array([0.0, 1.5, 0.0, gimbal_sep_phidot() * (1.0 + side * delta)])
    info = m.c.quad_motion(x0)
    assert info["kind"] == ("libration" if side < 0 else "rotation")
    ref = gimbal_period_mp(info["E"], info["k"], info["kind"], (info["phi_min"], info["phi_max"]))
    # the constants E, k carry round-off of relative size ~1e-16; the period's condition number
    # near the separatrix is ~1/(δ log(1/δ)), so 1e-16/δ is all any method can give
    tol = max(1e-12, 20 * 2.2e-16 / delta)
    assert abs(info["period"] - float(ref)) <= tol * float(ref), (info["period"], ref)
    assert abs(m.py.quad_period(x0) - float(ref)) <= tol * float(ref)


def test_period_grows_without_bound_at_the_separatrix(example):
    m = example("gimbal")
    periods = [m.c.quad_period(np.array([0.0, 1.5, 0.0, gimbal_sep_phidot() * (1.0 - d)])) for d in (1e-4, 1e-8, 1e-12)]
    assert periods[0] < periods[1] < periods[2]
    # T ≈ a + b log(1/δ): equal steps in log δ give equal steps in T (to a few per cent)
    assert abs((periods[2] - periods[1]) / (periods[1] - periods[0]) - 1.0) < 0.05


def test_on_the_separatrix_is_an_error_not_a_number(example):
    m = example("gimbal")
    x0 = np.array([0.0, 1.5, 0.0, gimbal_sep_phidot()])
    for call in (m.c.quad_period, m.c.quad_motion, lambda x: m.c.quad_state(1.0, x)):
        with pytest.raises(ModelError) as err:
            call(x0)
        assert err.value.code == 4  # NAME_SEPARATRIX
    with pytest.raises(m.py.SeparatrixError, match="separatrix"):
        m.py.quad_period(x0)


def test_steady_motion_and_bad_input(example):
    m = example("gimbal")
    # at rest, and a steady precession (φ̇ = 0 where P' = 0: φ = 0 by symmetry)
    for x0 in ([0.0, 0.3, 0.0, 0.0], [0.1, 0.0, 3.0, 0.0]):
        x0 = np.array(x0)
        assert m.c.quad_motion(x0)["kind"] == "steady"
        with pytest.raises(ModelError) as err:
            m.c.quad_period(x0)
        assert err.value.code == 5
        with pytest.raises(m.py.SteadyMotion):
            m.py.quad_period(x0)
        X = m.c.quad_state(np.array([0.0, 2.0]), x0)
        assert np.allclose(X[1], [x0[0] + 2.0 * x0[2], x0[1], x0[2], 0.0], rtol=0, atol=1e-15)
        X_ode = ode(m, x0, 2.0).sol(2.0)
        assert np.max(np.abs(X[1] - X_ode)) <= 1e-10
    with pytest.raises(ModelError) as err:
        m.c.quad_period(np.array([0.0, np.nan, 1.0, 1.0]))
    assert err.value.code == 2
    with pytest.raises(m.py.NonFiniteResult):
        m.py.quad_period([0.0, np.inf, 1.0, 1.0])


# --------------------------------------------------------------------------- symbolic, structure
GIMBAL_SYM = """
name = "gimbal_sym"
g = "g0"
[[body]]
theta = 0
m = 0.5
c = [0.0, 0.0, "c1"]
A = [["A1", 0.0, 0.0], [0.0, 0.003, 0.0], [0.0, 0.0, 0.003]]
s = [0.0, "s1", 0.0]
[[body]]
theta = "vt"
m = "m2"
c = ["c21", "c22", 0.0]
A = [[0.006, 0.0, 0.0], [0.0, 0.006, 0.0], [0.0, 0.0, "A33"]]
lambda = [0.0, 0.0, "lam"]
"""


def test_symbolic_parameters(make_model):
    """The quadratures of a spec with symbolic parameters: the same numbers as a numeric
    spec with those values folded in, C and Python; NO_PARAMS without p."""
    values = dict(g0=9.81, c1=0.0, A1=0.005, s1=0.0, vt=math.pi / 2, m2=1.2, c21=0.0, c22=0.0, A33=0.009, lam=0.5)
    sym = make_model(GIMBAL_SYM, dict(values))
    num = make_model(GIMBAL_SYM.replace('"gimbal_sym"', '"gimbal_num"').replace('"vt"', '"pi/2"')
                     .replace('"lam"', "0.5").replace('"A33"', "0.009").replace('"m2"', "1.2")
                     .replace('"g0"', "9.81").replace('"A1"', "0.005")
                     .replace('"c1"', "0.0").replace('"s1"', "0.0").replace('"c21"', "0.0").replace('"c22"', "0.0"))
    assert not num.spec.params and sym.c.lib.GIMBAL_SYM_HAS_QUADRATURES == 1
    for kind, x0 in GIMBAL_STATES.items():
        x0 = np.array(x0)
        T = num.c.quad_period(x0)
        assert abs(sym.c.quad_period(x0, values) - T) <= 1e-13 * T
        assert abs(sym.py.quad_period(x0, values) - T) <= 1e-13 * T
        assert np.allclose(sym.c.quad_state(3.3, x0, values), num.c.quad_state(3.3, x0), rtol=1e-11, atol=1e-11)
    with pytest.raises(ModelError) as err:
        sym.c.quad_period(np.array(GIMBAL_STATES["libration"]))
    assert err.value.code == 3
    # an offset spec with gravity: against the ODE of the same symbolic model
    values = dict(values, c1=0.05, s1=0.1, c21=0.03, c22=0.08, vt=1.2)
    x0 = np.array([0.0, 0.3, 1.0, 0.5])
    check_against_ode(sym, x0, sym.c.quad_motion(x0, values)["kind"], values)


@pytest.mark.parametrize("seed", [4, 5])
def test_E_J_minus_K2_is_a_trigonometric_polynomial_of_degree_3(make_model, seed):
    """The premise of the root walk and of the 8-sample Fourier coefficients."""
    model = random_two_body(make_model, seed)
    x0 = np.random.default_rng(seed).normal(size=4)
    phi = 2 * np.pi * np.arange(64) / 64
    f = model.py.quad_functions(phi, x0)
    P = f["E"] * f["J"] - f["K"] ** 2
    spec = np.abs(np.fft.rfft(P)) / 64
    assert spec[3] > 1e-6 * spec.max()  # degree 3 is there (random tensors)
    assert spec[4:].max() <= 1e-14 * spec.max()
    # the C and the Python give the same paper's functions
    for ph in (0.3, 2.0):
        c = model.c.quad_functions(ph, x0)
        py = model.py.quad_functions(ph, x0)
        assert np.allclose(c[:5], [py[k] for k in ("J", "C", "A", "E", "K")], rtol=1e-14, atol=1e-15)
