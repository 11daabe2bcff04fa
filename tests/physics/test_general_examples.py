"""The general-case examples behave as their classical theory says.

* turntable: a pendulum on a table turning at Ω about the vertical leaves the vertical above
  Ω_c = √(m g l / (A₂₂ − A₃₃)), at cos φ* = Ω_c²/Ω²; its Jacobi integral is conserved.
* kapitza: the inverted pendulum on a vertically vibrating pivot is stable when
  a²w² > 2 g A₁₁ / (m l) (Kapitza's averaged theory), unstable below.
* ziegler: the double pendulum with joint springs under a tip follower force loses stability by
  flutter at P_cr = (7/2 − √2) k / l (Ziegler 1952), not at the static buckling load.
* springs keep an energy integral (the potential −½k(φ − rest)² is in U).
"""
from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

from gyrochain import reference
from gyrochain.randspec import random_spec_text


# ---------------------------------------------------------------------------------- turntable
def _turntable_constants(m):
    b = m.spec.bodies[0]
    mass, l = float(b.m), float(b.c[2])
    A22, A33 = float(b.A[1][1]), float(b.A[2][2])
    return mass * float(m.spec.g) * l / (A22 - A33)  # Ω_c²


def test_turntable_leaves_the_vertical_at_the_angle_theory_gives(example):
    m = example("turntable")
    Oc2 = _turntable_constants(m)
    Oc = math.sqrt(Oc2)
    assert not m.py.TIME_DEPENDENT and m.py.HAS_JACOBI_INTEGRAL and not m.py.HAS_ENERGY_INTEGRAL

    def qdd(phi, Omega):
        return m.c.qdd(np.array([phi, 0.0]), params=dict(Omega=Omega))[0]

    for ratio in (1.05, 1.5, 3.0):
        Omega = ratio * Oc
        phi_star = brentq(lambda f: qdd(f, Omega), 1e-6, math.pi / 2, xtol=1e-15, rtol=1e-15)
        assert abs(phi_star - math.acos(Oc2 / Omega**2)) <= 1e-9, (ratio, phi_star)
        # the vertical is unstable (φ̈ pushes away), the new position stable (φ̈ pulls back)
        assert qdd(1e-4, Omega) > 0 and qdd(phi_star + 1e-4, Omega) < 0 < qdd(phi_star - 1e-4, Omega)
    for ratio in (0.5, 0.95):
        Omega = ratio * Oc
        phis = np.linspace(1e-4, math.pi / 2, 200)
        assert all(qdd(f, Omega) < 0 for f in phis)  # only the vertical: φ̈ restores everywhere
    # the critical rate itself, from the sign change of ∂φ̈/∂φ at the vertical
    slope = lambda Omega: qdd(1e-6, Omega) / 1e-6  # noqa: E731
    assert abs(brentq(slope, 0.5 * Oc, 2 * Oc, xtol=1e-14) / Oc - 1.0) <= 1e-6


def test_turntable_motion_and_jacobi_integral(example):
    """From 0.1 rad at Ω = 8 rad/s (> Ω_c = 5.43) the pendulum swings out around φ*; the Jacobi
    integral stays constant to 1e-10 while T − U (the table does work) does not."""
    m = example("turntable")
    Oc2 = _turntable_constants(m)
    Omega = m.params["Omega"]
    phi_star = math.acos(Oc2 / Omega**2)
    t = np.linspace(0.0, 10.0, 2001)
    X = m.c.integrate(t, [0.1, 0.0], "dop853", rtol=1e-13, atol=1e-13, params=m.params)
    assert X[:, 0].max() > phi_star  # it leaves the vertical and overshoots φ*
    assert 0.0 < X[:, 0].min() and X[:, 0].max() < 2 * phi_star + 0.05
    h = np.array([m.c.jacobi(x, m.params) for x in X])
    E = np.array([m.c.energy(x, m.params) for x in X])
    assert np.max(np.abs(h - h[0])) <= 1e-10 * abs(h[0])
    assert np.max(np.abs(E - E[0])) > 1e-3 * abs(E[0])
    # the reference model agrees
    ref = reference.simulate(m.ref, [0.1, 0.0], t[:201])
    assert np.max(np.abs(X[:201] - ref)) <= 1e-8


# ---------------------------------------------------------------------------------- Kapitza
def _kapitza_theory(m):
    b = m.spec.bodies[0]
    mass, l, A11 = float(b.m), float(b.c[2]), float(b.A[0][0])
    a = m.params["a"]
    return math.sqrt(2 * float(m.spec.g) * A11 / (mass * l)) / a  # w_c


def _floquet(m, w, a):
    """Largest |multiplier| of the inverted position's monodromy matrix over one period 2π/w,
    from the emitted DOP853 (the inverted position is an exact solution)."""
    p = dict(a=a, w=w)
    T = 2 * math.pi / w
    x0 = np.array([math.pi, 0.0])
    eps = 1e-7
    cols = []
    for d in (np.array([eps, 0.0]), np.array([0.0, eps])):
        xp = m.c.integrate([0.0, T], x0 + d, "dop853", rtol=1e-13, atol=1e-15, params=p)[-1]
        xm = m.c.integrate([0.0, T], x0 - d, "dop853", rtol=1e-13, atol=1e-15, params=p)[-1]
        cols.append((xp - xm) / (2 * eps))
    return np.max(np.abs(np.linalg.eigvals(np.column_stack(cols))))


def test_kapitza_inverted_position_stabilised_above_the_critical_frequency(example):
    m = example("kapitza")
    a = m.params["a"]
    wc = _kapitza_theory(m)
    assert m.py.TIME_DEPENDENT
    # the monodromy matrix has determinant 1 (Hamiltonian): stable ⇔ both |μ| = 1
    assert _floquet(m, 1.3 * wc, a) < 1 + 1e-6
    assert _floquet(m, 0.7 * wc, a) > 1.01
    # the threshold by bisection on the Floquet multipliers, against the averaged theory
    lo, hi = 0.7 * wc, 1.3 * wc
    for _ in range(30):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if _floquet(m, mid, a) < 1 + 1e-6 else (mid, hi)
    assert abs(hi / wc - 1.0) < 0.02, (hi, wc)
    # and the nonlinear motion: 0.1 rad off the top it stays up above w_c and falls below
    t = np.linspace(0.0, 3.0, 3001)
    up = m.c.integrate(t, [math.pi - 0.1, 0.0], "dop853", rtol=1e-10, atol=1e-12, params=dict(a=a, w=1.3 * wc))
    down = m.c.integrate(t, [math.pi - 0.1, 0.0], "dop853", rtol=1e-10, atol=1e-12, params=dict(a=a, w=0.7 * wc))
    assert np.max(np.abs(up[:, 0] - math.pi)) < 0.2
    assert np.max(np.abs(down[:, 0] - math.pi)) > 1.0


# ---------------------------------------------------------------------------------- Ziegler
def _jacobian(m, P):
    x0 = np.zeros(4)
    h = 1e-6
    cols = []
    for i in range(4):
        d = np.zeros(4)
        d[i] = h
        cols.append((m.c.rhs(0.0, x0 + d, params=dict(P=P)) - m.c.rhs(0.0, x0 - d, params=dict(P=P))) / (2 * h))
    return np.column_stack(cols)


def _growth(m, P):
    A, _ = m.c.linearize(np.zeros(4), params=dict(P=P))  # the exact linearisation
    ev = np.linalg.eigvals(A)
    return np.max(ev.real) / np.max(np.abs(ev))


def test_ziegler_flutter_load(example):
    m = example("ziegler")
    b1, b2 = m.spec.bodies
    k, l = float(b1.spring), float(b1.s[2])
    Pcr = (3.5 - math.sqrt(2)) * k / l
    assert not m.py.HAS_ENERGY_INTEGRAL  # the follower force is not conservative
    assert _growth(m, 0.95 * Pcr) < 1e-6  # purely imaginary: oscillation, no growth
    assert _growth(m, 1.05 * Pcr) > 1e-3  # a complex pair with a positive real part: flutter
    # the static (divergence) load of a conservative force, (3 − √5)/2 k/l, is no threshold here
    assert _growth(m, 0.5 * (3 - math.sqrt(5)) * k / l * 1.2) < 1e-6
    assert np.allclose(_jacobian(m, 0.9 * Pcr), m.c.linearize(np.zeros(4), params=dict(P=0.9 * Pcr))[0], atol=1e-8)
    # point masses on massless bars, as Ziegler's (the spec's I_c = 0): the load where a complex
    # pair leaves the imaginary axis is P_cr to round-off
    lo, hi = 0.9 * Pcr, 1.1 * Pcr
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if _growth(m, mid) < 1e-7 else (lo, mid)
    assert abs(hi / Pcr - 1.0) < 1e-12, (hi, Pcr)


def test_springs_keep_the_energy_integral(example, make_model):
    # Ziegler's pendulum without its follower load: springs only, energy conserved to 1e-10
    m = example("ziegler")
    x0 = np.array([0.4, -0.3, 0.5, 1.0])
    t = np.linspace(0.0, 5.0, 51)
    X = m.c.integrate(t, x0, "dop853", rtol=1e-13, atol=1e-13, params=dict(P=0.0))
    E = np.array([m.c.energy(x, dict(P=0.0)) for x in X])
    assert np.max(np.abs(E - E[0])) <= 1e-10 * abs(E[0])
    # a random spatial chain with springs in every joint
    rng = np.random.default_rng(5)
    text = random_spec_text(rng, 3, name="springy")
    text = text.replace("[[body]]\n", "[[body]]\nspring = 1.5\nrest = 0.2\n")
    s = make_model(text)
    assert s.py.HAS_ENERGY_INTEGRAL and not s.py.TIME_DEPENDENT
    x0 = np.concatenate([rng.uniform(-1, 1, 3), rng.normal(size=3)])
    t = np.linspace(0.0, 2.0, 21)
    X = s.c.integrate(t, x0, "dop853", rtol=1e-13, atol=1e-13)
    E = np.array([s.c.energy(x) for x in X])
    T0 = 0.5 * x0[3:] @ s.c.mass_matrix(x0[:3]) @ x0[3:]
    assert np.max(np.abs(E - E[0])) <= 1e-10 * max(abs(E[0]), T0)
    assert np.allclose([reference.energy(s.ref, x) for x in X], E, rtol=1e-12, atol=1e-12)
    ref = reference.simulate(s.ref, x0, t)
    assert np.max(np.abs(ref - X)) <= 1e-8 * max(1.0, np.max(np.abs(ref)))


def test_ship_gimbal_against_the_reference(example):
    m = example("ship_gimbal")
    assert m.py.TIME_DEPENDENT and not m.py.HAS_ENERGY_INTEGRAL and not m.py.HAS_MOMENTUM_INTEGRAL
    x0 = np.array([*m.spec.initial["phi"], *m.spec.initial["phidot"]])
    t = np.linspace(0.0, 3.0, 31)
    X = m.c.integrate(t, x0, "dop853", rtol=1e-12, atol=1e-12)
    ref = reference.simulate(m.ref, x0, t)
    assert np.max(np.abs(X - ref)) <= 1e-8 * np.max(np.abs(ref))
