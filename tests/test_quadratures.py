"""The integrable two-body case (28)–(30): the quadratures against ODE solutions of the generated
equations, at the turning points and near the separatrix, and their errors."""
from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest
from scipy.integrate import solve_ivp

from codegen.build import ModelError
from codegen.randspec import random_spec_text

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
