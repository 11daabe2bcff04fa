"""The discrete-time model in C: NAME_step (one RK4 step with u held) and NAME_step_jacobian (its
exact derivatives Ad, Bd, ∂xn/∂h, by the chain rule through the four stages).  The step against
NAME_integrate's RK4 bit for bit; the Jacobian against differences of NAME_step; the API's edges;
a perturbed derivative is caught; and the worked example examples/furuta_dlqr.c, which designs a
discrete LQR on them in plain C99 and balances the Furuta pendulum through its disturbances."""
from __future__ import annotations

import re
import subprocess

import numpy as np
import pytest

from gyrochain.build import ModelError
from conftest import ROOT, example_params, fd_jacobian, perturbed_c

STRICT = ["-Wall", "-Wextra", "-Wpedantic", "-Werror"]
# fixed-base chains with and without controls, a symbolic one, a platform that moves with t
CASES = ["furuta", "furuta_sym", "double_pendulum", "spatial3", "gyrostat2", "kapitza"]


def _state(rng, n):
    return np.concatenate([rng.uniform(-np.pi, np.pi, n), rng.normal(size=n)])


def _relative(got, want):
    return np.max(np.abs(got - want)) / max(np.max(np.abs(want)), 1e-300)


@pytest.mark.parametrize("name", CASES)
def test_step_is_the_integrators_rk4_step(example, rng, name):
    m = example(name)
    params, nu = example_params(name), m.c.nu
    for t0 in (0.0, 0.0, rng.uniform(0.0, 1.0)):
        x, h = _state(rng, m.spec.n), 10.0 ** rng.uniform(-4, -1.5)
        u = rng.normal(size=nu) if nu else None
        want = m.c.integrate([t0, t0 + h], x, method="rk4", h=h, u=u, params=params)[-1]
        if t0 == 0.0:  # (t0 + h) - t0 is h: the integrator takes the same step
            assert np.array_equal(m.c.step(x, h, u, params, t=t0), want)
        else:  # its step is (t0 + h) - t0, h to round-off
            assert np.allclose(m.c.step(x, h, u, params, t=t0), want, rtol=1e-14, atol=1e-14)


@pytest.mark.parametrize("name", CASES)
def test_step_jacobian_equals_differences_of_the_step(example, rng, name):
    m = example(name)
    params, nu, d = example_params(name), m.c.nu, 2 * m.spec.n
    timed = m.c.time_dependent
    for h in (1e-3, 2e-2):
        x, t0 = _state(rng, m.spec.n), rng.uniform(0.0, 1.0)
        u = rng.normal(size=nu) if nu else np.zeros(0)
        xn, Ad, Bd, dh = m.c.step_jacobian(x, h, u if nu else None, params, t=t0)
        assert np.allclose(xn, m.c.step(x, h, u if nu else None, params, t=t0), rtol=1e-13, atol=1e-13)
        step = lambda z: m.c.step(z[:d], z[-1], z[d:d + nu] if nu else None, params, t=t0)  # noqa: E731
        # (the Kapitza pivot's 260 rad/s: differences of 1e-5 in h)
        want = fd_jacobian(step, np.concatenate([x, u, [h]]), h=1e-5 if timed else 1e-4)
        got = np.hstack([Ad, Bd, dh[:, None]])
        assert _relative(got, want) <= 1e-8
        assert Ad.shape == (d, d) and Bd.shape == (d, nu)


def test_step_api_edges(example, rng):
    m = example("furuta")
    c, ffi = m.c, m.c.ffi
    x = _state(rng, 2)
    xp = ffi.cast("double *", ffi.from_buffer(np.ascontiguousarray(x)))
    out = np.zeros(4)
    op = ffi.cast("double *", ffi.from_buffer(out))
    bad = c.lib.FURUTA_BAD_ARGUMENT
    assert c.lib.furuta_step(0.0, ffi.NULL, ffi.NULL, ffi.NULL, 1e-3, op) == bad
    assert c.lib.furuta_step(0.0, xp, ffi.NULL, ffi.NULL, float("nan"), op) == bad
    assert c.lib.furuta_step(float("inf"), xp, ffi.NULL, ffi.NULL, 1e-3, op) == bad
    # a NaN step: BAD_ARGUMENT, and NaN out as on any failure
    out[:] = 0.0
    assert c.lib.furuta_step(0.0, xp, ffi.NULL, ffi.NULL, float("nan"), op) == bad and np.isnan(out).all()
    # a non-finite state: NONFINITE and NaN out
    y = np.array([np.nan, 0.0, 0.0, 0.0])
    assert c.lib.furuta_step(0.0, ffi.cast("double *", ffi.from_buffer(y)), ffi.NULL, ffi.NULL, 1e-3, op) == c.lib.FURUTA_NONFINITE
    assert np.isnan(out).all()
    # the step may write over its own input (a control loop's x = step(x))
    inplace = np.array(x)
    ip = ffi.cast("double *", ffi.from_buffer(inplace))
    assert c.lib.furuta_step(0.0, ip, ffi.NULL, ffi.NULL, 1e-3, ip) == 0
    assert np.array_equal(inplace, c.step(x, 1e-3))
    # NULL outputs are not written: Ad alone
    Ad = np.zeros((4, 4))
    assert c.lib.furuta_step_jacobian(0.0, xp, ffi.NULL, ffi.NULL, 1e-3, ffi.NULL, ffi.cast("double *", ffi.from_buffer(Ad)),
                                      ffi.NULL, ffi.NULL) == 0
    assert np.array_equal(Ad, c.step_jacobian(x, 1e-3)[1])
    # a symbolic model without its parameters
    sym = example("furuta_sym").c
    with pytest.raises(ModelError):
        sym.step(x, 1e-3)


def test_a_perturbed_derivative_fails_the_difference_check(example, rng, tmp_path):
    m = example("furuta")
    bad = perturbed_c(m, tmp_path / "perturbed", block="dqdd_du", factor=1.0 + 1e-6)
    x, u, h = _state(rng, 2), rng.normal(size=1), 2e-2
    _, Ad, Bd, dh = bad.step_jacobian(x, h, u)
    step = lambda z: bad.step(z[:4], z[-1], z[4:5])  # noqa: E731
    want = fd_jacobian(step, np.concatenate([x, u, [h]]), h=1e-4)
    assert _relative(np.hstack([Ad, Bd, dh[:, None]]), want) > 1e-8


@pytest.fixture(scope="module")
def dlqr(example, tmp_path_factory):
    m = example("furuta")
    exe = tmp_path_factory.mktemp("dlqr") / "furuta_dlqr"
    run = subprocess.run(["cc", "-std=c99", "-O2", *STRICT, "-I", str(m.folder), str(ROOT / "examples" / "furuta_dlqr.c"),
                          str(m.folder / "furuta.c"), "-lm", "-o", str(exe)], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    return m, exe


def test_the_c_lqr_balances_the_furuta_pendulum_through_its_disturbances(dlqr):
    m, exe = dlqr
    run = subprocess.run([str(exe)], capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stdout
    K = np.array([float(v) for v in re.search(r"K = (.*)", run.stdout).group(1).split()])
    # the gain is the discrete LQR of the step's exact Jacobian: scipy's DARE on NAME_step_jacobian agrees
    from scipy.linalg import solve_discrete_are

    _, Ad, Bd, _ = m.c.step_jacobian(np.array([0.0, np.pi, 0.0, 0.0]), 1e-3, np.zeros(1))
    Q, R = np.diag([1.0, 10.0, 0.1, 0.1]), np.array([[10.0]])
    P = solve_discrete_are(Ad, Bd, Q, R)
    want = np.linalg.solve(R + Bd.T @ P @ Bd, Bd.T @ P @ Ad)[0]
    assert np.allclose(K, want, rtol=1e-9)
    tilts = [float(v) for v in re.findall(r"largest tilt \S+ t = \S+ s: (\S+) rad", run.stdout)]
    assert len(tilts) == 4 and max(tilts[1:]) < 0.2  # each strike is caught well short of a fall
    end = re.search(r"tilt (\S+) rad, rates (\S+) (\S+)", run.stdout.splitlines()[-1])
    assert abs(float(end.group(1))) < 1e-3


def test_without_the_controller_the_pendulum_falls(dlqr):
    _, exe = dlqr
    run = subprocess.run([str(exe), "open"], capture_output=True, text=True, timeout=60)
    assert run.returncode == 1
    assert max(float(v) for v in re.findall(r"largest tilt \S+ t = \S+ s: (\S+) rad", run.stdout)) > 1.0
