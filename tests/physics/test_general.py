"""The general equations (8)–(10): random chains on moving platforms (translation, rotation,
both) with follower and fixed forces, moments, springs, dampers, torque expressions and rotors
spinning up.  φ̈ of the C and the Python against the independent reference model; trajectories
of the emitted integrators against the reference integrator; the work–energy balance."""
from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from gyrochain import reference
from gyrochain.randspec import random_general_spec_text
from conftest import check_derivatives, tiered

# (n, translate, rotate, loads, springs, spin_up)
CASES = [
    (1, True, True, True, True, True),
    (2, True, False, True, True, False),
    (2, False, True, False, True, True),
    (3, True, True, True, True, True),
    (4, False, True, True, False, True),
    (5, True, True, True, True, True),
]
IDS = [f"n{n}-{'T' if tr else ''}{'R' if ro else ''}{'-loads' if lo else ''}{'-springs' if sp else ''}{'-spinup' if su else ''}"
       for n, tr, ro, lo, sp, su in CASES]
# make test's cases: each part of the general equations on and off (make test-all: the longer
# chains with every part on, too)
QUICK = {"n1-TR-loads-springs-spinup", "n2-T-loads-springs", "n2-R-springs-spinup", "n4-R-loads-spinup"}


@pytest.fixture(params=tiered(list(zip(CASES, IDS)), QUICK, key=lambda c: c[1]), ids=IDS, scope="module")
def case(request, make_model):
    (n, tr, ro, lo, sp, su), cid = request.param
    seed = sum(map(ord, cid))
    rng = np.random.default_rng(seed)
    text = random_general_spec_text(rng, n, name=f"g{n}_{seed % 1000}", translate=tr, rotate=ro, loads=lo,
                                    springs=sp, spin_up=su)
    return make_model(text), rng


def _state(rng, n):
    return np.concatenate([rng.uniform(-np.pi, np.pi, n), rng.normal(size=n) * 2.0])


def _targs(model, t):
    return (t,) if model.py.TIME_DEPENDENT else ()


def test_flags(case):
    model, _ = case
    spec = model.spec
    moves = spec.base is not None and spec.base.moves
    assert model.py.TIME_DEPENDENT and model.c.time_dependent  # every random case reads t
    assert not model.py.HAS_ENERGY_INTEGRAL  # dampers, follower forces or a moving base do work
    assert model.py.HAS_JACOBI_INTEGRAL is False
    assert model.py.HAS_QUADRATURES is False
    assert moves or any(b.loaded for b in spec.bodies)


def test_derivatives_match_differences(case):
    """∂φ̈/∂(φ, φ̇) of the time-dependent models (platform, loads, springs, dampers, torque
    expressions of the state) against differences of the reference."""
    model, rng = case
    for _ in range(2):
        check_derivatives(model, _state(rng, model.spec.n), t=rng.uniform(-2.0, 5.0))


def test_qdd_matches_reference(case):
    model, rng = case
    n = model.spec.n
    for _ in range(6):
        x, t = _state(rng, n), rng.uniform(-2.0, 5.0)
        ref = reference.qdd(model.ref, x, None, t)
        scale = max(np.max(np.abs(ref)), 1e-3)
        got_c = model.c.qdd(x, t=t)
        got_py = model.py.qdd(t, x)
        assert np.max(np.abs(got_c - ref)) <= 1e-10 * scale, (got_c, ref)
        assert np.max(np.abs(got_py - ref)) <= 1e-10 * scale, (got_py, ref)
        # the mass matrix does not see the platform or the loads
        assert np.allclose(model.c.mass_matrix(x[:n]), reference.mass_matrix(model.ref, x[:n]), rtol=1e-11, atol=1e-12)
        assert np.allclose(model.c.rhs(t, x), np.concatenate([x[n:], ref]), rtol=1e-10, atol=1e-10 * scale)
        # energy T − U (absolute velocities, springs, constant fixed forces) and the momentum function
        assert abs(model.c.energy(x, t=t) - reference.energy(model.ref, x, t)) <= 1e-11 * max(1.0, abs(model.c.energy(x, t=t)))
        if model.c.has_momentum:
            assert abs(model.c.momentum(x, t=t) - reference.momentum(model.ref, x, t)) <= 1e-11


def test_trajectory_of_the_emitted_integrator_matches_the_reference(case):
    """DOP853 in C (stage times t + cᵢh) against the reference model under scipy's DOP853, both at
    1e-12, over 1 s started at t = 0.3."""
    model, rng = case
    n = model.spec.n
    x0 = _state(rng, n) * 0.5
    t = np.linspace(0.3, 1.3, 11)
    ours = model.c.integrate(t, x0, "dop853", rtol=1e-12, atol=1e-12)
    ref = reference.simulate(model.ref, x0, t)
    scale = max(1.0, np.max(np.abs(ref)))
    assert np.max(np.abs(ours - ref)) <= 1e-8 * scale


def test_fixed_step_methods_see_the_time(case):
    """RK4 and GAUSS2 (order 4) on the time-dependent model: halving h divides the error by ~16
    (with the stage times wrong the error would stay at order 1)."""
    model, rng = case
    n = model.spec.n
    x0 = _state(rng, n) * 0.3
    t = np.array([0.5, 1.0])
    ref = reference.simulate(model.ref, x0, t)[-1]
    for method in ("rk4", "gauss2"):
        errs = [np.max(np.abs(model.c.integrate(t, x0, method, h=h)[-1] - ref)) for h in (0.01, 0.005)]
        assert errs[1] < 1e-6 and 8.0 < errs[0] / errs[1] < 40.0, (method, errs)


def test_work_energy_balance(case):
    """Along a solution, the change of T − U equals the work of the joint torques (damping,
    torque expressions), of the loads without a force function, of the motors that spin the
    rotors up and of the platform, each integrated alongside from the reference model's powers."""
    model, rng = case
    n = model.spec.n
    x0 = _state(rng, n) * 0.5
    t0, t1 = 0.2, 1.2

    def f(t, y):
        x = y[:-1]
        pw = reference.powers(model.ref, t, x)
        return np.concatenate([model.c.rhs(t, x), [sum(pw.values())]])

    sol = solve_ivp(f, (t0, t1), np.concatenate([x0, [0.0]]), method="DOP853", rtol=1e-11, atol=1e-11,
                    t_eval=np.linspace(t0, t1, 6))
    assert sol.success
    E = np.array([model.c.energy(y[:-1], t=t) for t, y in zip(sol.t, sol.y.T)])
    W = sol.y[-1]
    T0 = 0.5 * x0[n:] @ model.c.mass_matrix(x0[:n]) @ x0[n:]
    scale = max(abs(E[0]), T0, 1.0)
    assert np.max(np.abs(E - E[0])) > 1e-4 * scale  # the loads do work: the balance is not trivial
    assert np.max(np.abs((E - E[0]) - W)) <= 1e-8 * scale, (E - E[0], W)
