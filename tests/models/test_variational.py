"""NAME_integrate_variational: the state with its fundamental matrix Φ (Φ' = A Φ, A the exact
Jacobian of the emitted φ̈).  Φ against Richardson differences of the emitted flow; Liouville's
theorem (det Φ = det M(φ₀) / det M(φ(t)), 1 where M is constant) and symplecticity in Hamilton's
variables (Φ_cᵀ J Φ_c = J, with ∂p/∂φ from the independent sympy Lagrangian of tests/lagrange.py)
over many periods; the API's edges; a derivative perturbed by one part in 10⁶ is caught."""
from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from gyrochain.build import IntegrationError
from gyrochain.spec import phi_symbol, phidot_symbol
from conftest import example_params, perturbed_c
from lagrange import lagrangian

TIGHT = dict(rtol=1e-12, atol=1e-12)


def _start(n, rng, amp=1.0):
    return np.concatenate([rng.uniform(-amp, amp, n), rng.normal(scale=amp, size=n)])


def _flow(m, x, t1, params, t0=0.0):
    return m.c.integrate([t0, t1], x, rtol=1e-13, atol=1e-13, params=params)[-1]


def _differenced_phi(m, x0, t1, params, h=1e-4):
    """∂x(t1)/∂x(0) by central differences of the emitted DOP853 flow, one Richardson step."""
    dim = len(x0)

    def central(step):
        cols = []
        for e in np.eye(dim):
            cols.append((_flow(m, x0 + step * e, t1, params) - _flow(m, x0 - step * e, t1, params)) / (2 * step))
        return np.array(cols).T

    return (4 * central(h / 2) - central(h)) / 3


# (example, time span): the fixed-base chains over a few swings, the driven ones over several periods
CASES = [("double_pendulum", 3.0), ("spatial3", 2.0), ("kapitza", 5 * 2 * np.pi / 260.0), ("ship_gimbal", 6.0)]


@pytest.mark.parametrize("name,t1", CASES, ids=[c[0] for c in CASES])
def test_fundamental_matrix_is_the_derivative_of_the_flow(example, rng, name, t1):
    m = example(name)
    params = example_params(name)
    x0 = _start(m.spec.n, rng, 0.8)
    if name == "kapitza":
        x0 = np.array([np.pi - 0.1, 0.3])
    x1, Phi, stats = m.c.integrate_variational(0.0, t1, x0, params=params, full_output=True, **TIGHT)
    assert stats["n_rhs"] > 0 and stats["n_steps"] > 0
    x_ref = _flow(m, x0, t1, params)
    assert np.max(np.abs(x1 - x_ref)) <= 1e-9 * max(1.0, np.max(np.abs(x_ref)))
    D = _differenced_phi(m, x0, t1, params)
    err = np.max(np.abs(Phi - D)) / np.max(np.abs(D))
    assert err <= 1e-8, err


def test_a_perturbed_derivative_is_caught(example, rng, tmp_path):
    """∂φ̈/∂φ (then ∂φ̈/∂φ̇) times 1 + 1e-6 in the emitted C: Φ no longer matches the flow."""
    m = example("double_pendulum")
    x0 = _start(2, rng, 0.8)
    D = _differenced_phi(m, x0, 3.0, None)
    for block in ("dqdd_dphi", "dqdd_dphidot"):
        bad = perturbed_c(m, tmp_path / block, block)
        _, Phi = bad.integrate_variational(0.0, 3.0, x0, **TIGHT)
        assert np.max(np.abs(Phi - D)) / np.max(np.abs(D)) > 1e-8, block


# regular motions near a stable equilibrium (spatial3's from `gyrochain steady`), where det Φ is well
# conditioned over many periods (in a chaotic motion Φ grows as e^(λt) and its determinant is lost
# to cancellation, not to the integration)
NEAR = {"double_pendulum": [0.0, 0.0], "spatial3": [1.33227005, 1.25831554, -1.64484794], "gimbal": [0.0, 0.3],
        "kapitza": [np.pi], "ship_gimbal": [0.0, 0.3]}


def _near(name, rng, amp=0.2):
    phi = np.asarray(NEAR[name])
    return np.concatenate([phi + rng.uniform(-amp, amp, len(phi)), rng.uniform(-amp, amp, len(phi))])


@pytest.mark.parametrize("name,t1", [("double_pendulum", 40.0), ("spatial3", 20.0), ("gimbal", 20.0),
                                     ("kapitza", 200 * 2 * np.pi / 260.0), ("ship_gimbal", 5.0)])
def test_liouville(example, rng, name, t1):
    """The flow keeps volume in Hamilton's variables (φ, p), whose Jacobian over (φ, φ̇) is det M:
    det Φ(t) det M(φ(t)) = det M(φ₀), over many periods (double pendulum: 17 of its slow mode;
    kapitza: 200 of its pivot; the gimbal on the rolling ship only over 5 s: its gyroscope's motion
    is chaotic, and by 30 s cond Φ is 5e13)."""
    m = example(name)
    params = example_params(name)
    x0 = _near(name, rng)
    n = m.spec.n
    x1, Phi = m.c.integrate_variational(0.0, t1, x0, params=params, **TIGHT)
    ratio = np.linalg.det(Phi) * np.linalg.det(m.c.mass_matrix(x1[:n], params)) / np.linalg.det(m.c.mass_matrix(x0[:n], params))
    assert abs(ratio - 1.0) <= 1e-10, ratio - 1.0


def _momentum_jacobian(spec):
    """(φ, φ̇) ↦ (p, ∂p/∂(φ, φ̇)) with p = ∂ℒ/∂φ̇ of the independent sympy Lagrangian: p lambdified,
    its Jacobian by complex steps (Im p(x + i h eⱼ)/h, h = 1e-30: no difference is taken, so it is
    exact to round-off; sympy's own Jacobian of spatial3's p took 20 s to form and lambdify)."""
    n = spec.n
    phi = [phi_symbol(k) for k in range(1, n + 1)]
    phidot = [phidot_symbol(k) for k in range(1, n + 1)]
    L = lagrangian(spec, phi, phidot)
    p = sp.lambdify([phi, phidot], [sp.diff(L, v) for v in phidot], "numpy")
    h = 1e-30

    def momenta_and_jacobian(q, v):
        x = np.concatenate([q, v]).astype(complex)
        J = np.empty((n, 2 * n))
        for j in range(2 * n):
            xj = x.copy()
            xj[j] += 1j * h
            J[:, j] = np.imag(np.asarray(p(xj[:n], xj[n:]), dtype=complex)) / h
        return np.real(np.asarray(p(x[:n], x[n:]), dtype=complex)), J

    return momenta_and_jacobian


@pytest.mark.parametrize("name,t1", [("double_pendulum", 30.0), ("spatial3", 15.0)])
def test_symplectic_in_hamiltons_variables(example, rng, name, t1):
    """Φ_c = T(x(t)) Φ T(x₀)⁻¹, T = ∂(φ, p)/∂(φ, φ̇), keeps J: Φ_cᵀ J Φ_c = J to 1e-10, over many
    swings; p is the Lagrangian's, checked first against the emitted NAME_momenta."""
    m = example(name)
    n = m.spec.n
    pj = _momentum_jacobian(m.spec)
    x0 = _near(name, rng)
    x1, Phi = m.c.integrate_variational(0.0, t1, x0, **TIGHT)

    def T(x):
        p, J = pj(x[:n], x[n:])
        assert np.allclose(np.ravel(p), m.c.momenta(x), rtol=1e-12, atol=1e-14)
        return np.vstack([np.hstack([np.eye(n), np.zeros((n, n))]), np.asarray(J, float)])

    Pc = T(x1) @ Phi @ np.linalg.inv(T(x0))
    J = np.block([[np.zeros((n, n)), np.eye(n)], [-np.eye(n), np.zeros((n, n))]])
    err = np.max(np.abs(Pc.T @ J @ Pc - J)) / max(1.0, np.max(np.abs(Pc)) ** 2)
    assert err <= 1e-10, err


def test_api_edges(example, rng):
    m = example("double_pendulum")
    c, ffi = m.c, m.c.ffi
    x0 = _start(2, rng, 0.5)
    # Phi(t0) given: the result is the fundamental matrix times it (the equations are linear in Phi)
    _, Phi = c.integrate_variational(0.0, 1.0, x0, **TIGHT)
    P0 = rng.normal(size=(4, 4))
    _, PhiP = c.integrate_variational(0.0, 1.0, x0, Phi0=P0, **TIGHT)
    assert np.max(np.abs(PhiP - Phi @ P0)) <= 1e-9 * np.max(np.abs(PhiP))
    # t1 = t0: the identity and x0 itself; backwards in time: the inverse map
    x1, I0 = c.integrate_variational(0.5, 0.5, x0)
    assert np.array_equal(x1, x0) and np.array_equal(I0, np.eye(4))
    x1, Phi = c.integrate_variational(0.0, 1.0, x0, **TIGHT)
    xb, Phib = c.integrate_variational(1.0, 0.0, x1, **TIGHT)
    assert np.max(np.abs(xb - x0)) <= 1e-9 and np.max(np.abs(Phib @ Phi - np.eye(4))) <= 1e-8
    # the codes: NULL buffers and bad tolerances, a non-finite input
    fn = c._fn("integrate_variational")
    buf = lambda a: ffi.cast("double *", ffi.from_buffer(a))  # noqa: E731
    x, out, P = np.array(x0), np.empty(4), np.eye(4)
    assert fn(0.0, 1.0, 0.0, 1e-8, 1e-8, ffi.NULL, ffi.NULL, ffi.NULL, buf(out), buf(P), ffi.NULL) == 10
    assert fn(0.0, 1.0, 0.0, 1e-8, 1e-8, buf(x), ffi.NULL, ffi.NULL, buf(out), ffi.NULL, ffi.NULL) == 10
    assert fn(0.0, 1.0, 0.0, -1.0, 1e-8, buf(x), ffi.NULL, ffi.NULL, buf(out), buf(P), ffi.NULL) == 10
    assert fn(0.0, float("inf"), 0.0, 1e-8, 1e-8, buf(x), ffi.NULL, ffi.NULL, buf(out), buf(P), ffi.NULL) == 10
    P[1, 2] = np.nan
    assert fn(0.0, 1.0, 0.0, 1e-8, 1e-8, buf(x), ffi.NULL, ffi.NULL, buf(out), buf(P), ffi.NULL) == 2
    # a failure: the last accepted state, and Phi NaN (a rate that overflows every stage)
    with pytest.raises(IntegrationError) as err:
        c.integrate_variational(0.0, 1.0, np.array([0.1, 0.2, 1e200, 0.0]))
    assert err.value.code in (2, 7) and np.allclose(err.value.x, [0.1, 0.2, 1e200, 0.0])


def test_symbolic_parameters_are_required(example):
    m = example("furuta_sym")
    fn, ffi = m.c._fn("integrate_variational"), m.c.ffi
    x, out, P = np.zeros(4), np.empty(4), np.eye(4)
    buf = lambda a: ffi.cast("double *", ffi.from_buffer(a))  # noqa: E731
    assert fn(0.0, 1.0, 0.0, 1e-8, 1e-8, buf(x), ffi.NULL, ffi.NULL, buf(out), buf(P), ffi.NULL) == 3
    x1, Phi = m.c.integrate_variational(0.0, 0.5, np.array([0.0, 3.0, 0.1, 0.0]), u=[0.0], params=m.params, **TIGHT)
    assert np.all(np.isfinite(Phi)) and np.all(np.isfinite(x1))
