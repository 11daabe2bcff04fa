"""The derivatives in t of a model that reads t (a moving platform, a rotor spun up, a load of t):
NAME_time_derivative (∂φ̈/∂t), the step's ∂xn/∂h and ∂xn/∂t (NAME_step_jacobian: the stages' times
t + c h move with both), and t as the last variable of NAME_rhs_hessian and NAME_step_hessian;
each against central differences of the emitted functions at random points and times, for the
Kapitza pendulum (a vibrating pivot), a gimbal on a rolling ship with a motor on its outer ring,
a chain whose rotor spins up under a load of t, and a chain of the angles users write (θ = π,
−π/2, −π) with rotors spinning, loads, springs and offsets on a platform that turns and moves."""
from __future__ import annotations

import numpy as np
import pytest

from gyrochain.chainspec.randspec import BodyPlan, ChainPlan, geometry_spec_text
from gyrochain.spec import load_spec
from conftest import ROOT, example_params, fd_jacobian, richardson

TOL = 1e-7

SPUN_UP = """
name = "spun_up"
g = 9.81
[[body]]
theta = 0.0
m = 0.4
c = [0.0, 0.05, 0.0]
A = [[0.004, 0.0, 0.0], [0.0, 0.003, 0.0], [0.0, 0.0, 0.002]]
s = [0.0, 0.1, 0.0]
control = true
[[body]]
theta = "pi/2"
m = 0.6
c = [0.0, 0.0, 0.03]
A = [[0.003, 0.0, 0.0], [0.0, 0.003, 0.0], [0.0, 0.0, 0.004]]
lambda = [0.0, 0.0, "0.2 + 0.3*t"]
torque = "0.05*sin(3*t)"
"""


# the geometry test's moving_base chain (tests/models/test_geometry.py): the special angles on a platform that turns and moves
MOVING_GEOMETRY = ChainPlan((BodyPlan("pi", "full", rotor="full", spring=True),
                             BodyPlan("-pi/2", "point", damping=True, control=True, torque=True),
                             BodyPlan("-pi", "full", rotor="spin", offset="number")), seed=16, base="both", loads=True)


def _ship_gimbal_with_a_motor() -> str:
    text = (ROOT / "specs" / "ship_gimbal.toml").read_text()
    return text.replace('name = "ship_gimbal"', 'name = "ship_motor"').replace("s = [0.0, 0.0, 0.0]\n", "s = [0.0, 0.0, 0.0]\ncontrol = true\n", 1)


@pytest.fixture(scope="module")
def timed_models(make_model):
    return {"kapitza": (make_model(load_spec(ROOT / "specs" / "kapitza.toml"), example_params("kapitza"), hessian=True),
                        example_params("kapitza")),
            "ship_motor": (make_model(_ship_gimbal_with_a_motor(), hessian=True), None),
            "spun_up": (make_model(SPUN_UP, hessian=True), None),
            "moving_geometry": (make_model(geometry_spec_text(MOVING_GEOMETRY, "tgeom"), hessian=True), None)}


def _point(rng, n, nu):
    return (np.concatenate([rng.uniform(-np.pi, np.pi, n), rng.normal(size=n)]), rng.normal(size=nu),
            rng.normal(size=2 * n), float(rng.uniform(0.0, 2.0)))


def _relative(got, want):
    return np.max(np.abs(got - want)) / max(np.max(np.abs(want)), 1e-300)


@pytest.mark.parametrize("name", ["kapitza", "ship_motor", "spun_up", "moving_geometry"])
def test_the_derivatives_in_t_equal_differences(timed_models, rng, name):
    m, prm = timed_models[name]
    c, n, nu = m.c, m.spec.n, m.c.nu
    assert c.time_dependent
    uu = lambda v: v if nu else None  # noqa: E731
    scale = 1e-5 if name == "kapitza" else 1e-4  # the pivot vibrates at 260 rad/s
    for _ in range(5):
        x, u, lam, t = _point(rng, n, nu)
        qdd, dt = c.time_derivative(x, uu(u), prm, t=t)
        assert np.allclose(qdd, c.qdd(x, uu(u), prm, t=t), rtol=1e-12, atol=1e-12)  # (qdd may be the composite form)
        want = richardson(lambda s: c.qdd(x, uu(u), prm, t=t + s), h=scale)
        assert _relative(dt, want) <= TOL, (dt, want)
        # the step: Ad, Bd, xn_h, xn_t against differences of NAME_step in (x, u, h, t)
        h = 0.01 if name != "kapitza" else 1e-3
        xn, Ad, Bd, dh, dtn = c.step_jacobian(x, h, uu(u), prm, t=t, with_t=True)
        d = 2 * n

        def step(w):
            return c.step(w[:d], w[d + nu], uu(w[d:d + nu]), prm, t=w[-1])
        J = fd_jacobian(step, np.concatenate([x, u, [h, t]]), h=scale)
        assert _relative(np.hstack([Ad, Bd, dh[:, None], dtn[:, None]]), J) <= 1e-8
        # the Hessians, t the last variable: against differences of the exact first derivatives
        H = c.rhs_hessian(x, lam, uu(u), prm, t=t)
        assert H.shape == (d + nu + 1,) * 2 and np.array_equal(H, H.T)

        def grad(z):
            A, B = c.linearize(z[:d], uu(z[d:d + nu]), prm, t=z[-1])
            return np.concatenate([A.T @ lam, B.T @ lam, [lam[n:] @ c.time_derivative(z[:d], uu(z[d:d + nu]), prm, t=z[-1])[1]]])
        D = fd_jacobian(grad, np.concatenate([x, u, [t]]), h=scale)
        assert _relative(H, D) <= TOL
        Hs = c.step_hessian(x, h, lam, uu(u), prm, t=t)
        assert Hs.shape == (d + nu + 2,) * 2 and np.array_equal(Hs, Hs.T)

        def sgrad(w):
            _, A, B, g_h, g_t = c.step_jacobian(w[:d], w[d + nu], uu(w[d:d + nu]), prm, t=w[-1], with_t=True)
            return np.concatenate([A.T @ lam, B.T @ lam, [g_h @ lam, g_t @ lam]])
        D = fd_jacobian(sgrad, np.concatenate([x, u, [h, t]]), h=scale)
        assert _relative(Hs, D) <= TOL


def test_an_autonomous_model_has_no_derivative_in_t(example, rng):
    m = example("furuta")
    x = np.concatenate([rng.normal(size=2), rng.normal(size=2)])
    with pytest.raises(AttributeError, match="does not read t"):
        m.c.step_jacobian(x, 0.01, with_t=True)
    with pytest.raises(AttributeError, match="time_derivative"):
        m.c.time_derivative(x)
