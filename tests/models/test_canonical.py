"""Hamilton's variables and the symplectic GAUSS2: NAME_momenta, NAME_velocities, NAME_pdot against
the independent Lagrangian (tests/lagrange.py) and differences of the emitted momenta along the
flow; the one-step map of GAUSS2_SYMPLECTIC preserves the symplectic form where GAUSS2's does not;
over thousands of periods of a gyrostat without a reversing symmetry its energy error stays
bounded and the momentum (27) is kept to round-off while GAUSS2's drift."""
from __future__ import annotations

import numpy as np
import pytest

from gyrochain.build import IntegrationError
from gyrochain.randspec import random_spec_text
from conftest import EXAMPLES, QUICK_EXAMPLES, richardson, tiered
from lagrange import lagrangian_np
from test_models import CASES, IDS, QUICK

GYRO_X0 = np.array([0.0, 0.8, 1.5, 0.0])  # specs/gyrostat2.toml's [initial]


@pytest.fixture(params=tiered(list(zip(CASES, IDS)), QUICK, key=lambda c: c[1]), ids=IDS, scope="module")
def case(request, make_model):
    (n, planar, gyro, controls, theta1), cid = request.param
    rng = np.random.default_rng(sum(map(ord, cid)))
    text = random_spec_text(rng, n, name=f"r{n}_{sum(map(ord, cid)) % 1000}", planar=planar, gyro=gyro,
                            controls=controls, theta1=theta1)
    return make_model(text), rng


def lagrangian_momenta(ch, x):
    """p = ∂ℒ/∂φ̇ and ∂ℒ/∂φ of the independent Lagrangian: unit-step polarization in φ̇ (exact,
    ℒ is quadratic in φ̇) and complex steps in φ."""
    n = ch.n
    phi, v, E, t = np.asarray(x[:n], complex), np.asarray(x[n:], float), np.eye(n), 1e-30
    p = np.array([(lagrangian_np(ch, phi, v + E[i]) - lagrangian_np(ch, phi, v - E[i])).real / 2 for i in range(n)])
    dL = np.array([lagrangian_np(ch, phi + 1j * t * E[k], v).imag / t for k in range(n)])
    return p, dL


def test_momenta_and_their_rate_equal_the_lagrangians(case):
    """p = ∂ℒ/∂φ̇ and ṗ = ∂ℒ/∂φ + u (C and Python) on random chains, planar and spatial, with
    rotors and controls; NAME_velocities inverts NAME_momenta."""
    model, rng = case
    n, spec = model.spec.n, model.spec
    assert model.c.has_canonical and model.py.HAS_CANONICAL
    for _ in range(3):
        x = np.concatenate([rng.uniform(-np.pi, np.pi, n), rng.normal(size=n) * 2.0])
        u = rng.normal(size=len(spec.controls)) if spec.controls else None
        p_ref, dL = lagrangian_momenta(model.ref, x)
        pdot_ref = dL.copy()
        for i, k in enumerate(spec.controls):
            pdot_ref[k - 1] += u[i]
        for impl in (model.c, model.py):
            p = impl.momenta(x)
            assert np.max(np.abs(p - p_ref)) <= 1e-12 * np.max(np.abs(p_ref)), (p, p_ref)
            pd = impl.pdot(x, u)
            assert np.max(np.abs(pd - pdot_ref)) <= 1e-11 * max(1.0, np.max(np.abs(pdot_ref))), (pd, pdot_ref)
            qd = impl.velocities(x[:n], p)
            assert np.max(np.abs(qd - x[n:])) <= 1e-11 * max(1.0, np.max(np.abs(x[n:])))


@pytest.mark.parametrize("name", tiered(EXAMPLES, QUICK_EXAMPLES))
def test_examples_momenta_move_as_pdot_says(example, name):
    """d/dt p(x(t)) (Richardson differences of the emitted momenta along the emitted flow) equals
    NAME_pdot, springs, dampers and loads included; p₁ is the momentum (27).  Models with a moving
    platform or time-dependent terms have no canonical form and refuse the method."""
    g = example(name)
    c, spec = g.c, g.spec
    n = spec.n
    if not c.has_canonical:
        assert c.time_dependent or spec.base is not None
        with pytest.raises(ValueError, match="gauss2_symplectic"):
            c.integrate([0.0, 0.1], np.zeros(2 * n), "gauss2_symplectic", h=0.01, params=g.params)
        return
    rng = np.random.default_rng(7)
    for _ in range(2):
        x = np.concatenate([rng.uniform(-1.0, 1.0, n), rng.normal(size=n)])
        u = rng.normal(size=len(spec.controls)) if spec.controls else None
        xd = c.rhs(0.0, x, u, g.params)
        fd = richardson(lambda e: c.momenta(x + e * xd, g.params), 1e-3)
        pd = c.pdot(x, u, g.params)
        assert np.max(np.abs(pd - fd)) <= 1e-8 * max(1.0, np.max(np.abs(pd))), (pd, fd)
        assert np.max(np.abs(g.py.pdot(x, u, g.params) - pd)) <= 1e-12 * max(1.0, np.max(np.abs(pd)))
        if c.has_momentum:
            assert abs(c.momenta(x, g.params)[0] - c.momentum(x, g.params)) <= 1e-13 * max(1.0, abs(c.momentum(x, g.params)))


def _omega(n):
    return np.block([[np.zeros((n, n)), np.eye(n)], [-np.eye(n), np.zeros((n, n))]])


def test_the_step_map_is_symplectic_in_canonical_variables(example):
    """ΨᵀΩΨ = Ω for the one-step map Ψ: (φ, p) ↦ (φ, p) of GAUSS2_SYMPLECTIC (to the differences'
    accuracy; its stages solved by simplified Newton with a differenced Jacobian, which changes the
    rate, not the solution); GAUSS2 on (φ, φ̇) misses it by orders of magnitude more."""
    c = example("gyrostat2").c
    n = 2
    T = c.quad_period(GYRO_X0)
    h = T / 20

    def step(y, method):
        x0 = np.r_[y[:n], c.velocities(y[:n], y[n:])]
        X, st = c.integrate([0.0, h], x0, method, h=h, full_output=True)
        assert st["n_newton"] == 1  # at this step the stages are solved by Newton (differenced J)
        return np.r_[X[1, :n], c.momenta(X[1])]

    y0 = np.r_[GYRO_X0[:n], c.momenta(GYRO_X0)]
    defect = {}
    for method in ("gauss2_symplectic", "gauss2"):
        J = np.empty((2 * n, 2 * n))
        for j in range(2 * n):
            e = np.zeros(2 * n)
            e[j] = 1.0
            J[:, j] = richardson(lambda s: step(y0 + s * e, method), 1e-3 * max(1.0, abs(y0[j])))
        defect[method] = np.max(np.abs(J.T @ _omega(n) @ J - _omega(n)))
    assert defect["gauss2_symplectic"] < 1e-9, defect
    assert defect["gauss2"] > 1e3 * defect["gauss2_symplectic"] and defect["gauss2"] > 1e-7, defect


def test_energy_stays_bounded_where_gauss2_drifts(example):
    """gyrostat2 (C ≠ 0, λ ≠ 0: no reversing symmetry), h = T/20, 3000 periods: GAUSS2's energy
    error grows linearly (≥ 2.5× from period 1000 to 3000) and so does its error in the momentum
    (27); GAUSS2_SYMPLECTIC's stays below 1e-6 (over 1e5 periods `make bench` charts it bounded
    at 3e-6), 1000× below GAUSS2's, and the momentum (27) is kept to 1e-12."""
    c = example("gyrostat2").c
    T = c.quad_period(GYRO_X0)
    t = np.linspace(0.0, 3000 * T, 301)
    E0, K0 = c.energy(GYRO_X0), c.momentum(GYRO_X0)
    err = {}
    for method in ("gauss2_symplectic", "gauss2"):
        X = c.integrate(t, GYRO_X0, method, h=T / 20)
        err[method] = (np.abs([c.energy(x) / E0 - 1 for x in X]), np.abs([c.momentum(x) / K0 - 1 for x in X]))
    dE, dK = err["gauss2_symplectic"]
    gE, gK = err["gauss2"]
    assert dE.max() < 1e-6 and dK.max() < 1e-12, (dE.max(), dK.max())
    assert gE[-1] > 1e3 * dE.max() and gE[-1] > 2.5 * gE[100], (gE[100], gE[-1], dE.max())
    assert gK[-1] > 2.5 * gK[100] > 1e-7, (gK[100], gK[-1])


def test_symplectic_gauss2_converges_at_order_4_and_stops_cleanly(example):
    c = example("gyrostat2").c
    T = c.quad_period(GYRO_X0)
    ref = c.quad_state(2 * T, GYRO_X0)
    errs = [np.max(np.abs(c.integrate([0, 2 * T], GYRO_X0, "gauss2_symplectic", h=T / k)[1] - ref)) for k in (40, 80, 160)]
    ratios = [errs[0] / errs[1], errs[1] / errs[2]]
    assert all(13 < r < 19 for r in ratios), (errs, ratios)
    with pytest.raises(IntegrationError) as ei:  # out of its step budget: the last state reached, as (φ, φ̇)
        c.integrate([0, T], GYRO_X0, "gauss2_symplectic", h=T / 40, max_steps=10)
    e = ei.value
    assert e.code == c.lib.GYROSTAT2_TOO_MANY_STEPS and abs(e.t - 10 * T / 40) < 1e-12
    assert np.max(np.abs(e.x - c.quad_state(e.t, GYRO_X0))) < 1e-5
