"""The emitted integrators (NAME_integrate, NAME_integrate_grid): against scipy and the exact
two-body quadratures, their orders, and where they fail: RK4's stability bound, GAUSS2's bounded
energy where RK4 drifts, DOP853 on a fast rotor and out of budget, the gimbal lock."""
from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from gyrochain.build import METHODS, IntegrationError

GIMBAL_X0 = np.array([0.0, 0.3, 2.0, 0.5])  # specs/gimbal.toml [initial]: a libration
FAST_X0 = np.array([0.0, 2.6, 1.0, 0.0])  # specs/fast_gyro.toml [initial]

# Gyroscope in a Cardan suspension with ideal rings: ring masses and inertias mr, ar are
# parameters so that they can be zero (a spec with numbers would be refused as unphysical).  With
# massless rings M loses rank where the rotor axis l3 lines up with l1 (phi2 = 0, pi): the gimbal lock.
CARDAN = """
name = "cardan"
description = "Gyroscope in a Cardan suspension; rings of mass mr and inertia ar"
g = 9.81
[[body]]
theta = 0
m = "mr"
c = [0, 0, 0]
A = [["ar", 0, 0], [0, "ar", 0], [0, 0, "ar"]]
s = [0, 0, 0]
[[body]]
theta = "pi/2"
m = "mr"
c = [0, 0, 0]
A = [["ar", 0, 0], [0, "ar", 0], [0, 0, "ar"]]
s = [0, 0, 0]
[[body]]
theta = "pi/2"
m = 1.0
c = [0, 0, 0]
A = [[0.01, 0, 0], [0, 0.01, 0], [0, 0, 0.02]]
"""
IDEAL = dict(mr=0.0, ar=0.0)


def _relerr(a, b):
    return np.max(np.abs(a - b) / np.maximum(np.abs(b), 1.0))


def _energy_error(c, X, E0):
    return np.abs(np.array([c.energy(x) for x in X]) - E0) / abs(E0)


def test_dop853_is_scipys_dop853_and_its_dense_output_is_7th_order(example):
    """Same method, same error norm and step control as scipy's DOP853: same error and almost the
    same count; output times inside steps (dense output) as accurate as the steps themselves."""
    c = example("gimbal").c
    T = c.quad_period(GIMBAL_X0)
    t = np.linspace(0.0, 10 * T, 11)
    ref = c.quad_state(t, GIMBAL_X0)
    X, st = c.integrate(t, GIMBAL_X0, "dop853", rtol=1e-8, atol=1e-10, full_output=True)
    sol = solve_ivp(lambda tt, x: c.rhs(tt, x), (0, 10 * T), GIMBAL_X0, method="DOP853", rtol=1e-8, atol=1e-10,
                    t_eval=t)
    ours, theirs = _relerr(X, ref), _relerr(sol.y.T, ref)
    assert abs(ours / theirs - 1) < 0.01, (ours, theirs)
    # scipy's count includes its 2 evaluations of the first step and of f(t0); ours 1
    assert abs(st["n_rhs"] - sol.nfev) <= 12, (st["n_rhs"], sol.nfev)
    # 1000 output times between the steps: no worse than at the step ends
    tf = np.linspace(0.0, 10 * T, 1001)
    Xf = c.integrate(tf, GIMBAL_X0, "dop853", rtol=1e-12, atol=1e-12)
    assert _relerr(Xf, c.quad_state(tf, GIMBAL_X0)) < 1e-9


@pytest.mark.parametrize("method", ["rk4", "gauss2"])
def test_fixed_step_methods_converge_at_order_4(example, method):
    c = example("gimbal").c
    T = c.quad_period(GIMBAL_X0)
    ref = c.quad_state(3 * T, GIMBAL_X0)
    errs = [_relerr(c.integrate([0, 3 * T], GIMBAL_X0, method, h=T / k)[1], ref) for k in (80, 160, 320)]
    ratios = [errs[0] / errs[1], errs[1] / errs[2]]
    assert all(13 < r < 19 for r in ratios), (errs, ratios)


def test_c_api_integrate_and_python_agree(example):
    """NAME_integrate (the embedding API) gives the grid's last row and counts the evaluations."""
    g = example("gimbal")
    c, ffi, lib = g.c, g.c.ffi, g.c.lib
    x1 = ffi.new("double[4]")
    n_rhs = ffi.new("long *")
    for name, method in METHODS.items():
        kw = dict(h=0.01) if name != "dop853" else dict(h=0.0)
        rc = lib.gimbal_integrate(method, 0.0, 1.0, kw["h"], 1e-10, 1e-10, list(GIMBAL_X0), ffi.NULL, ffi.NULL,
                                  x1, n_rhs)
        X, st = c.integrate([0.0, 1.0], GIMBAL_X0, name, rtol=1e-10, atol=1e-10, full_output=True, **kw)
        assert rc == 0 and list(x1) == list(X[1]) and n_rhs[0] == st["n_rhs"] > 0
    assert lib.GIMBAL_RK4 == 1 and lib.GIMBAL_DOP853 == 2 and lib.GIMBAL_GAUSS2 == 3


def test_backward_in_time_and_gauss2_is_symmetric(example):
    c = example("spatial3").c
    x0 = np.array([0.3, -0.2, 0.5, 1.0, -0.5, 2.0])
    u = np.array([0.05])
    fwd = c.integrate([0.0, 0.5], x0, "gauss2", h=0.005, u=u)[1]
    back = c.integrate([0.5, 0.0], fwd, "gauss2", h=0.005, u=u)[1]
    assert np.max(np.abs(back - x0)) < 1e-12  # a symmetric method retraces its steps
    for method, kw in [("dop853", dict(rtol=1e-11, atol=1e-11)), ("rk4", dict(h=0.001))]:
        f = c.integrate([0.0, 0.5], x0, method, u=u, **kw)[1]
        b = c.integrate([0.5, 0.0], f, method, u=u, **kw)[1]
        assert np.max(np.abs(b - x0)) < 1e-8, method


def _jacobian(c, x, eps=1e-7):
    J = np.empty((len(x), len(x)))
    for j in range(len(x)):
        d = np.zeros(len(x))
        d[j] = eps
        J[:, j] = (c.rhs(0, x + d) - c.rhs(0, x - d)) / (2 * eps)
    return J


@pytest.mark.parametrize("name, xe", [("double_pendulum", [0.0, 0.0, 0.0, 0.0]),
                                      ("gimbal", [0.0, np.pi / 2, 0.0, 0.0])])
def test_rk4_blows_up_just_above_its_linear_stability_bound(example, name, xe):
    """RK4 is stable on the imaginary axis up to |h w| = 2 sqrt 2.  The fastest frequency w of the
    linearised model (the double pendulum's fast mode; the gimbal's nutation, gyroscopic) gives the
    bound; bisection finds the step above which a small oscillation grows 100-fold in 2000 steps."""
    c = example(name).c
    xe = np.array(xe)
    lam = np.linalg.eigvals(_jacobian(c, xe))
    assert np.max(np.abs(lam.real)) < 1e-6 * np.max(np.abs(lam))  # an oscillation: a centre
    bound = 2 * np.sqrt(2) / np.max(np.abs(lam.imag))
    dx = 1e-4 * np.random.default_rng(5).standard_normal(len(xe))
    E0, e0 = c.energy(xe), abs(c.energy(xe + dx) - c.energy(xe))

    def blows(h, N=2000):
        try:
            X = c.integrate(np.arange(N + 1) * h, xe + dx, "rk4", h=h)
        except IntegrationError:
            return True
        return not np.all(np.abs([c.energy(x) - E0 for x in X]) < 100 * e0)

    lo, hi = 0.8 * bound, 1.2 * bound
    assert not blows(lo) and blows(hi)
    for _ in range(30):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if blows(mid) else (mid, hi)
    assert abs(hi / bound - 1) < 2e-3, (hi, bound)


def test_gauss2_energy_stays_bounded_over_1e5_steps_where_rk4_drifts(example):
    """Gimbal at h = T/20, 1e5 steps (5000 periods), energy sampled at every step of the first
    period and every 10th after.  GAUSS2: bounded (at most 10x its first-period error, at the end
    too); momentum likewise.  RK4 at the same step: its error grows by more than 100x."""
    c = example("gimbal").c
    T = c.quad_period(GIMBAL_X0)
    h, N = T / 20, 100_000
    E0, p0 = c.energy(GIMBAL_X0), c.momentum(GIMBAL_X0)
    t_first = np.arange(21) * h
    t_all = np.arange(0, N + 1, 10) * h
    for method in ("gauss2", "rk4"):
        first = _energy_error(c, c.integrate(t_first, GIMBAL_X0, method, h=h), E0).max()
        X = c.integrate(t_all, GIMBAL_X0, method, h=h)
        dE = _energy_error(c, X, E0)
        if method == "gauss2":
            dp = np.abs([c.momentum(x) - p0 for x in X]) / abs(p0)
            dp_first = np.abs([c.momentum(x) - p0 for x in c.integrate(t_first, GIMBAL_X0, method, h=h)]) / abs(p0)
            assert dE.max() < 10 * first and dE[-100:].max() < 10 * first, (first, dE.max())
            assert dp.max() < 10 * max(dp_first.max(), 1e-13), (dp_first.max(), dp.max())
        else:
            assert dE[-100:].max() > 100 * first, (first, dE[-100:].max())


def test_dop853_reaches_its_tolerance_on_the_fast_gyrostat(example):
    """fast_gyro: rotor at 555 rad/s, nutation period 22 ms, 1 s = 45 nutations, against the
    quadratures.  The global error follows the tolerance (proportional, and within 1000 tol)."""
    c = example("fast_gyro").c
    ref = c.quad_state(1.0, FAST_X0)
    errs = []
    for tol in (1e-6, 1e-8, 1e-10):
        X, st = c.integrate([0.0, 1.0], FAST_X0, "dop853", rtol=tol, atol=tol, full_output=True)
        errs.append(_relerr(X[1], ref))
        assert errs[-1] < 1e3 * tol, (tol, errs[-1])
    assert 30 < errs[0] / errs[1] < 300 and 30 < errs[1] / errs[2] < 300, errs


def test_dop853_says_so_when_it_cannot(example):
    """Out of its step budget on the fast gyrostat: TOO_MANY_STEPS, where it stopped, and the
    state there still right (not garbage); rows not reached are NaN."""
    c = example("fast_gyro").c
    t = np.linspace(0.0, 5.0, 6)
    with pytest.raises(IntegrationError) as ei:
        c.integrate(t, FAST_X0, "dop853", rtol=1e-10, atol=1e-10, max_steps=2000)
    e = ei.value
    assert e.code == c.lib.FAST_GYRO_TOO_MANY_STEPS and "TOO_MANY_STEPS" in str(e)
    assert 0.0 < e.t < 5.0 and e.stats["n_steps"] + e.stats["n_rejected"] == 2000
    assert _relerr(e.x, c.quad_state(e.t, FAST_X0)) < 1e-7
    reached = t <= e.t
    assert np.all(np.isfinite(e.X[reached])) and np.all(np.isnan(e.X[~reached]))


def test_bad_arguments_are_refused(example):
    c = example("gimbal").c
    lib = c.lib
    for kw, code in [
        (dict(method="rk4", h=0.0), lib.GIMBAL_BAD_ARGUMENT),
        (dict(method="gauss2", h=np.inf), lib.GIMBAL_BAD_ARGUMENT),
        (dict(method="dop853", rtol=-1.0), lib.GIMBAL_BAD_ARGUMENT),
        (dict(method="dop853", rtol=0.0, atol=0.0), lib.GIMBAL_BAD_ARGUMENT),
    ]:
        with pytest.raises(IntegrationError) as ei:
            c.integrate([0.0, 1.0], GIMBAL_X0, **kw)
        assert ei.value.code == code, kw
    with pytest.raises(IntegrationError) as ei:
        c.integrate([0.0, 1.0, 0.5], GIMBAL_X0, "rk4", h=0.1)  # not monotone
    assert ei.value.code == lib.GIMBAL_BAD_ARGUMENT
    assert lib.gimbal_integrate(7, 0.0, 1.0, 0.1, 1e-6, 1e-6, list(GIMBAL_X0), c.ffi.NULL, c.ffi.NULL,
                                c.ffi.NULL, c.ffi.NULL) == lib.GIMBAL_BAD_ARGUMENT
    with pytest.raises(IntegrationError) as ei:
        c.integrate([0.0, 1.0], [np.nan, 0, 0, 0], "dop853")
    assert ei.value.code == lib.GIMBAL_NONFINITE
    sym = example("furuta_sym").c
    with pytest.raises(IntegrationError) as ei:
        sym.integrate([0.0, 1.0], [0, 0.1, 0, 0], "rk4", h=0.01)
    assert ei.value.code == sym.lib.FURUTA_SYM_NO_PARAMS


@pytest.mark.parametrize("method", list(METHODS))
@pytest.mark.parametrize("dist", [0.0, 1e-9])
def test_every_integrator_stops_at_the_gimbal_lock(make_model, method, dist):
    """Rotor axis within dist of the outer axis (massless rings: M has rank 2 there): SINGULAR,
    from every method, with the start as the last good state and no row of garbage."""
    g = make_model(CARDAN, IDEAL)
    c = g.c
    assert np.linalg.eigvalsh(g.py.mass_matrix([0, 1.0, 0], IDEAL))[0] > 1e-3  # away from it M is fine
    x0 = np.array([0.3, dist, -0.2, 0.5, 1.0, 2.0])
    kw = dict(h=0.01) if method != "dop853" else dict(rtol=1e-8, atol=1e-8)
    with pytest.raises(IntegrationError) as ei:
        c.integrate(np.linspace(0, 1, 5), x0, method, params=IDEAL, **kw)
    e = ei.value
    assert e.code == c.lib.CARDAN_SINGULAR and e.t == 0.0 and np.array_equal(e.x, x0), (e.code, e.t)
    assert np.array_equal(e.X[0], x0) and np.all(np.isnan(e.X[1:]))
    # the C API leaves the last good state in x1
    x1 = c.ffi.new("double[6]")
    p = c._p(IDEAL)
    assert c.lib.cardan_integrate(METHODS[method], 0.0, 1.0, kw.get("h", 0.0), 1e-8, 1e-8, list(x0), c.ffi.NULL, p,
                                  x1, c.ffi.NULL) == c.lib.CARDAN_SINGULAR
    assert list(x1) == list(x0)


def test_a_motion_through_the_lock_is_followed_or_stopped_never_garbage(make_model):
    """A rotor tumbling about the inner ring's axis (a steady rotation about a principal axis)
    passes the lock every half turn with finite rates.  Each integrator follows it (phi2 = w t,
    the rest still), or stops with SINGULAR if a stage lands within round-off of the lock; it
    never returns wrong numbers and does not stop short of it."""
    g = make_model(CARDAN, IDEAL)
    c = g.c
    w = 3.0
    x0 = np.array([0.0, -1.0, 0.0, 0.0, w, 0.0])
    t = np.linspace(0.0, 2.0, 9)
    exact = np.array([[0.0, -1.0 + w * ti, 0.0, 0.0, w, 0.0] for ti in t])
    for method, kw in [("rk4", dict(h=0.01)), ("gauss2", dict(h=0.01)), ("dop853", dict(rtol=1e-10, atol=1e-10))]:
        try:
            X = c.integrate(t, x0, method, params=IDEAL, **kw)
        except IntegrationError as e:
            assert e.code == c.lib.CARDAN_SINGULAR, (method, e)
            X = e.X[np.isfinite(e.X[:, 0])]
        assert np.max(np.abs(X - exact[: len(X)])) < 1e-9, method


def test_gauss2_newton_on_long_steps(example):
    """GAUSS2 solves its stages by simplified Newton with the exact Jacobian where the sweeps would
    take longer: the same collocation solution as the sweeps alone (GAUSS2_FIXED) where both
    converge, fewer rhs calls per step on long steps, and steps the sweeps cannot take at all
    (the fast gyrostat at h = 0.01, nutation period 0.022 s) with an error of order h⁴."""
    g = example("gimbal")
    t = np.linspace(0.0, 1.0, 3)
    for h in (0.001, 0.03):
        Xf, sf = g.c.integrate(t, GIMBAL_X0, "gauss2_fixed", h=h, full_output=True)
        Xn, sn = g.c.integrate(t, GIMBAL_X0, "gauss2", h=h, full_output=True)
        assert sf["n_newton"] == 0
        assert np.max(np.abs(Xn - Xf)) <= 1e-12 * np.max(np.abs(Xf))
    assert sn["n_newton"] > 0 and sn["n_rhs"] < 0.8 * sf["n_rhs"]  # h = 0.03: Newton pays
    f = example("fast_gyro")
    t = np.linspace(0.0, 0.2, 2)
    with pytest.raises(IntegrationError) as err:
        f.c.integrate(t, FAST_X0, "gauss2_fixed", h=0.01)
    assert err.value.code == 8  # NO_CONVERGENCE: the sweeps diverge at this step
    X, st = f.c.integrate(t, FAST_X0, "gauss2", h=0.01, full_output=True)  # Newton takes it
    assert st["n_newton"] == st["n_steps"] and np.all(np.isfinite(X))
    ref = f.c.integrate(t, FAST_X0, "dop853", rtol=1e-13, atol=1e-13)
    errs = []
    for h in (0.002, 0.001):  # where the sweeps converge slowly: Newton on every step, fewer rhs
        X, st = f.c.integrate(t, FAST_X0, "gauss2", h=h, full_output=True)
        Xf, sf = f.c.integrate(t, FAST_X0, "gauss2_fixed", h=h, full_output=True)
        assert st["n_newton"] == st["n_steps"] and st["n_rhs"] < 0.6 * sf["n_rhs"]
        assert np.max(np.abs(X - Xf)) <= 1e-11 * np.max(np.abs(Xf))
        errs.append(np.max(np.abs(X[-1] - ref[-1])))
    assert 8.0 < errs[0] / errs[1] < 40.0, errs  # order 4


def test_gauss2_newton_time_dependent(example):
    """Kapitza's pendulum (the pivot vibrates at 260 rad/s): Newton's Jacobian and stage times on
    a time-dependent model give the sweeps' solution."""
    k = example("kapitza")
    x0 = np.array([np.pi - 0.1, 0.0])
    t = np.linspace(0.0, 0.3, 2)
    h = 2 * np.pi / k.params["w"] / 8
    Xf = k.c.integrate(t, x0, "gauss2_fixed", h=h, params=k.params)
    Xn, st = k.c.integrate(t, x0, "gauss2", h=h, params=k.params, full_output=True)
    assert st["n_newton"] > 0
    assert np.max(np.abs(Xn - Xf)) <= 1e-11
