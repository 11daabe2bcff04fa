"""`generate --casadi`: the model as CasADi external functions.  f and its Jacobian equal NAME_rhs
and NAME_linearize for every example with a control, the Jacobian is CasADi's own finite
differences' and has the true sparsity, the RK4 step's Jacobian is its central differences', and
the Furuta pendulum's f equals an independent model typed from the literature in CasADi SX
(Cazzolato & Prime 2011): so does its swing-up's optimum.  Bad input is one line."""
from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from gyrochain.spec import load_spec
from conftest import EXAMPLES, FURUTA_SYM_PARAMS, ROOT, example_params, example_script, tiered

casadi = pytest.importorskip("casadi", reason="CasADi is not installed (the test extra installs gyrochain[casadi])")
from gyrochain import casadi as gc  # noqa: E402
from gyrochain.models import pipeline  # noqa: E402

CONTROLLED = [e for e in EXAMPLES if load_spec(ROOT / "specs" / f"{e}.toml").controls]
# make test checks two of them (a planar arm and a 6-joint arm); the rest, a library build each, are the extended tier's
EVERY_CONTROLLED = tiered(CONTROLLED, {"furuta", "ur5"})


@pytest.fixture(scope="module")
def models(example):
    built = {}

    def get(name):
        if name not in built:
            built[name] = (gc.functions(ROOT / "specs" / f"{name}.toml"), example(name).c)
        return built[name]
    return get


def _points(m, rng, k=100):
    X = np.concatenate([rng.uniform(-np.pi, np.pi, (k, m.n)), rng.normal(size=(k, m.n))], axis=1)
    return X, rng.normal(size=(k, m.nu))


@pytest.mark.parametrize("name", EVERY_CONTROLLED)
def test_f_and_its_jacobian_are_rhs_and_linearize(name, models, rng):
    m, cm = models(name)
    jac = m.f.jacobian()
    prm = example_params(name)
    worst = 0.0
    for x, u in zip(*_points(m, rng)):
        xdot = np.asarray(m.f(x, u, m.p0)).ravel()
        ref = cm.rhs(0.0, x, u, prm)
        A, B = cm.linearize(x, u, prm)
        Jx, Ju, Jp = (np.asarray(casadi.DM(b).full()) for b in jac(x, u, m.p0, xdot))
        scale = max(1.0, np.max(np.abs(A)), np.max(np.abs(B)))
        worst = max(worst, np.max(np.abs(xdot - ref)) / max(1.0, np.max(np.abs(ref))),
                    np.max(np.abs(Jx - A)) / scale, np.max(np.abs(Ju - B)) / scale)
        assert Jp.shape == (2 * m.n, len(m.params))
        if m.params:  # d/dp: NAME_param_derivatives under phidot's zero rows
            assert not Jp[:m.n].any() and np.allclose(Jp[m.n:], cm.param_derivatives(x, u, prm)[1], rtol=1e-14, atol=1e-14)
    assert worst <= 1e-14, worst


def test_the_derivatives_in_p_are_exact_and_a_second_one_never_a_silent_zero(models, rng):
    """The parameters' first derivatives are emitted: CasADi's jacobian of f and of the RK4 step F
    in p equals central differences in every parameter (to 1e-7); the second derivatives in p are
    not: CasADi's Hessian in p is NaN (a zero would say the dynamics do not depend on the masses).
    M and E, which have no derivatives, CasADi refuses to differentiate, naming them; the
    derivatives in x and u and IPOPT's Hessian in them (NAME_rhs_hessian's, exact) are what they were."""
    m, cm = models("furuta_sym")
    x, u, p = casadi.MX.sym("x", 2 * m.n), casadi.MX.sym("u", m.nu), casadi.MX.sym("p", len(m.params))
    q = casadi.MX.sym("q", m.n)
    for _ in range(5):
        xv, uv = np.concatenate([rng.uniform(-np.pi, np.pi, 2), rng.normal(size=2)]), rng.normal(size=1)
        for out in (m.f(x, u, p), m.F(x, u, p, 0.01)):
            value = casadi.Function("v", [x, u, p], [out])
            Jp = np.asarray(casadi.Function("Jp", [x, u, p], [casadi.jacobian(out, p)])(xv, uv, m.p0).full())
            fd = np.array([(np.asarray(value(xv, uv, m.p0 + e)).ravel() - np.asarray(value(xv, uv, m.p0 - e)).ravel())
                           / (2 * e[j]) for j, e in enumerate(np.diag(1e-5 * np.abs(m.p0)))]).T
            assert np.max(np.abs(Jp - fd)) <= 1e-7 * np.max(np.abs(fd)), np.max(np.abs(Jp - fd))
    for fn, args in (("M", (q, p)), ("E", (x, p))):
        with pytest.raises(RuntimeError, match=f"Derivatives cannot be calculated for furuta_sym_{fn}"):
            casadi.jacobian(getattr(m, fn)(*args), p)
    xv, uv = np.array([0.3, -0.7, 0.2, 1.1]), np.array([0.4])
    Jx = casadi.Function("Jx", [x, u, p], [casadi.jacobian(m.f(x, u, p), x)])(xv, uv, m.p0).full()
    A, _ = cm.linearize(xv, uv, FURUTA_SYM_PARAMS)
    assert np.max(np.abs(Jx - A)) <= 1e-14 * np.max(np.abs(A))
    lam = np.array([0.2, -0.1, 0.5, 0.3])
    H = casadi.Function("H", [x, u, p], [casadi.hessian(casadi.dot(lam, m.f(x, u, p)), x)[0]])(xv, uv, m.p0).full()
    want = pipeline.compiled(load_spec(ROOT / "specs" / "furuta_sym.toml"), hessian=True)[0].rhs_hessian(
        xv, lam, uv, FURUTA_SYM_PARAMS)[:4, :4]
    assert np.all(np.isfinite(H)) and np.array_equal(H, H.T) and np.allclose(H, want, rtol=1e-14, atol=1e-14)
    Hp = casadi.Function("Hp", [x, u, p], [casadi.hessian(casadi.dot(lam, m.f(x, u, p)), p)[0]])(xv, uv, m.p0).full()
    assert np.all(np.isnan(Hp))  # in p: not emitted, NaN


@pytest.mark.parametrize("name", EVERY_CONTROLLED)
def test_the_jacobian_is_casadi_s_finite_differences(name, models, rng):
    """CasADi's own central differences of f (the external loaded without our Jacobian) agree with
    our Jacobian in x and u to 1e-6 of its scale."""
    m, _ = models(name)
    fd = casadi.external(f"{name}_f", str(m.library), dict(enable_fd=True, enable_jacobian=False, enable_forward=False,
                                                          enable_reverse=False, fd_method="central")).forward(1)
    jac = m.f.jacobian()
    d = 2 * m.n
    for xv, uv in zip(*_points(m, rng, 10)):
        xdot = np.asarray(m.f(xv, uv, m.p0)).ravel()
        a = np.hstack([casadi.DM(b).full() for b in jac(xv, uv, m.p0, xdot)[:2]])
        seeds = np.eye(d + m.nu)  # one forward direction of CasADi's differences per column of (x, u)
        b = np.column_stack([np.asarray(fd(xv, uv, m.p0, xdot, e[:d], e[d:], np.zeros(len(m.params)))).ravel()
                             for e in seeds])
        assert np.max(np.abs(a - b)) < 1e-6 * max(1.0, np.max(np.abs(a))), np.max(np.abs(a - b))


def test_the_jacobian_has_the_true_sparsity(models):
    """The stored pattern of df/dx leaves out exactly the entries the derivative has structurally
    zero: the Furuta arm's angle, which no force depends on (8 entries of 16)."""
    m, _ = models("furuta")
    sp = m.f.jacobian().sparsity_out(0)
    stored = set(zip(sp.row(), sp.get_col()))
    assert stored == {(2, 1), (3, 1), (0, 2), (2, 2), (3, 2), (1, 3), (2, 3), (3, 3)}, sorted(stored)


@pytest.mark.parametrize("name", ["furuta", "ur5"])
def test_the_rk4_step_and_its_jacobian(name, models, rng):
    m, cm = models(name)
    prm = example_params(name)
    jac = m.F.jacobian()
    h, eps = 0.01, 1e-6
    for x, u in zip(*_points(m, rng, 5)):
        k1 = cm.rhs(0, x, u, prm)
        k2 = cm.rhs(0, x + h / 2 * k1, u, prm)
        k3 = cm.rhs(0, x + h / 2 * k2, u, prm)
        k4 = cm.rhs(0, x + h * k3, u, prm)
        xn = np.asarray(m.F(x, u, m.p0, h)).ravel()
        assert np.max(np.abs(xn - (x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)))) < 1e-14 * max(1.0, np.max(np.abs(xn)))
        Jx, Ju, Jp, Jh = (np.asarray(casadi.DM(b).full()) for b in jac(x, u, m.p0, h, xn))

        def step(dx=0.0, du=0.0, dh=0.0):
            return np.asarray(m.F(x + dx, u + du, m.p0, h + dh)).ravel()
        fd = [(step(dx=e) - step(dx=-e)) / (2 * eps) for e in np.eye(2 * m.n) * eps]
        fd += [(step(du=e) - step(du=-e)) / (2 * eps) for e in np.eye(m.nu) * eps]
        fd += [(step(dh=eps) - step(dh=-eps)) / (2 * eps)]
        J = np.hstack([Jx, Ju, Jh])
        assert J.shape == (2 * m.n, 2 * m.n + m.nu + 1) and Jp.size == 0 == len(m.params)
        err = np.max(np.abs(np.array(fd).T - J)) / max(1.0, np.max(np.abs(J)))
        assert err < 1e-7, (name, err)


# --------------------------------------------------------------------------- an independent model
def cazzolato_prime(spec_values=None):
    """The Furuta pendulum of specs/furuta.toml typed into CasADi SX from the literature: Cazzolato &
    Prime, "On the dynamics of the Furuta pendulum", J. Control Sci. Eng. 2011, the full model of
    principal inertias without friction, with the arm's angle theta1 (positive the other way from
    this tool's phi1, so u = -tau1) and the pendulum's theta2 = phi2 (0 hanging).  The spec's inertias
    about the hinge points A give the paper's: the arm about its vertical axis J0 = A1_11 + m2 L1^2, the
    pendulum about the two axes across it J2 = A2_11 = A2_22 and about its length J2x = A2_33."""
    g, m2, L1, l2 = 9.81, 0.1, 0.2, 0.15
    J0, J2, J2x = 0.0042 + m2 * L1 ** 2, 0.003, 0.00001
    x, u = casadi.SX.sym("x", 4), casadi.SX.sym("u", 1)
    th2, dth1, dth2, tau1 = x[1], -x[2], x[3], -u[0]
    s, c = casadi.sin(th2), casadi.cos(th2)
    M = casadi.vertcat(casadi.horzcat(J0 + J2 * s ** 2 + J2x * c ** 2, m2 * L1 * l2 * c),
                       casadi.horzcat(m2 * L1 * l2 * c, J2))
    dM11 = (J2 - J2x) * 2 * s * c  # d M11 / d theta2
    rhs = casadi.vertcat(tau1 - dM11 * dth1 * dth2 + m2 * L1 * l2 * s * dth2 ** 2,
                         0.5 * dM11 * dth1 ** 2 - g * m2 * l2 * s)
    dd = casadi.solve(M, rhs)
    xdot = casadi.vertcat(x[2], x[3], -dd[0], dd[1])
    return casadi.Function("furuta_sx", [x, u], [xdot])


def test_f_is_the_literature_s_furuta_pendulum(models, rng):
    """Our external f and its Jacobian equal the SX model of Cazzolato & Prime at random points
    (to 1e-13 of their scale)."""
    m, _ = models("furuta")
    sx = cazzolato_prime()
    x, u = casadi.SX.sym("x", 4), casadi.SX.sym("u", 1)
    J_sx = casadi.Function("J", [x, u], [casadi.jacobian(sx(x, u), casadi.vertcat(x, u))])
    J_us = casadi.Function("J", [x, u], [casadi.jacobian(m.f(x, u, m.p0), casadi.vertcat(x, u))])
    worst = 0.0
    for xv, uv in zip(*_points(m, rng)):
        a, b = np.asarray(m.f(xv, uv, m.p0)).ravel(), np.asarray(sx(xv, uv)).ravel()
        A, B = J_us(xv, uv).full(), J_sx(xv, uv).full()
        worst = max(worst, np.max(np.abs(a - b)) / max(1.0, np.max(np.abs(b))), np.max(np.abs(A - B)) / max(1.0, np.max(np.abs(B))))
    assert worst < 1e-13, worst


def test_the_hessians_are_the_literature_model_s(models, rng):
    """CasADi's Hessian of λ·f and of λ·F (one RK4 step, in x, u and h) through our external
    functions (jac_adj1_: NAME_rhs_hessian, NAME_step_hessian) equals CasADi's exact Hessian of the
    SX model of Cazzolato & Prime at 100 random points, to 1e-12 of its scale."""
    m, _ = models("furuta")
    sx = cazzolato_prime()

    def rk4(f, x, u, h):
        k1 = f(x, u)
        k2 = f(x + h / 2 * k1, u)
        k3 = f(x + h / 2 * k2, u)
        return x + h / 6 * (k1 + 2 * k2 + 2 * k3 + f(x + h * k3, u))

    def hessians(sym, f, F):
        x, u, h, lam = sym.sym("x", 4), sym.sym("u", 1), sym.sym("h"), sym.sym("lam", 4)
        return (casadi.Function("Hf", [x, u, lam], [casadi.hessian(casadi.dot(lam, f(x, u)), casadi.vertcat(x, u))[0]]),
                casadi.Function("HF", [x, u, h, lam], [casadi.hessian(casadi.dot(lam, F(x, u, h)), casadi.vertcat(x, u, h))[0]]))
    ours = hessians(casadi.MX, lambda x, u: m.f(x, u, m.p0), lambda x, u, h: m.F(x, u, m.p0, h))
    theirs = hessians(casadi.SX, sx, lambda x, u, h: rk4(sx, x, u, h))
    worst = [0.0, 0.0]
    for x, u in zip(*_points(m, rng)):
        lam, h = rng.normal(size=4), 10.0 ** rng.uniform(-3, -1)
        for k, args in enumerate(((x, u, lam), (x, u, h, lam))):
            A, B = ours[k](*args).full(), theirs[k](*args).full()
            worst[k] = max(worst[k], np.max(np.abs(A - B)) / max(1.0, np.max(np.abs(B))))
    print(f"\nHessians against the SX model: f {worst[0]:.1e}, F {worst[1]:.1e}")
    assert max(worst) <= 1e-12, worst


def test_the_ur5_s_hessians_are_its_c_functions(models, rng):
    """For a 6-joint arm (nu = 6), each block of jac_adj1_ur5_F and jac_adj1_ur5_f lands where
    CasADi reads it: its Hessians equal NAME_step_hessian and NAME_rhs_hessian."""
    m, _ = models("ur5")
    c = pipeline.compiled(load_spec(ROOT / "specs" / "ur5.toml"), hessian=True)[0]
    x, u, h, lam = casadi.MX.sym("x", 12), casadi.MX.sym("u", 6), casadi.MX.sym("h"), casadi.MX.sym("lam", 12)
    Hf = casadi.Function("Hf", [x, u, lam], [casadi.hessian(casadi.dot(lam, m.f(x, u, m.p0)), casadi.vertcat(x, u))[0]])
    HF = casadi.Function("HF", [x, u, h, lam], [casadi.hessian(casadi.dot(lam, m.F(x, u, m.p0, h)), casadi.vertcat(x, u, h))[0]])
    for xv, uv in zip(*_points(m, rng, 3)):
        lv = rng.normal(size=12)
        assert np.allclose(Hf(xv, uv, lv).full(), c.rhs_hessian(xv, lv, uv), rtol=0, atol=1e-12 * np.max(np.abs(c.rhs_hessian(xv, lv, uv))))
        want = c.step_hessian(xv, 0.01, lv, uv)
        assert np.allclose(HF(xv, uv, 0.01, lv).full(), want, rtol=0, atol=1e-12 * np.max(np.abs(want)))


def test_the_swing_up_s_optimum_is_the_literature_model_s(models):
    """The same optimal control problem over our RK4 step (its exact Hessian: jac_adj1_furuta_F) and
    over the SX model's RK4 (CasADi's exact Hessian) from the same initial guess: the same cost to
    1e-8, the same torques and motion to 1e-6, in the same number of IPOPT iterations."""
    m, _ = models("furuta")
    sx = cazzolato_prime()

    def rk4(x, u, h):
        k1 = sx(x, u)
        k2 = sx(x + h / 2 * k1, u)
        k3 = sx(x + h / 2 * k2, u)
        return x + h / 6 * (k1 + 2 * k2 + 2 * k3 + sx(x + h * k3, u))
    swing_up = example_script("furuta_swing_up").swing_up  # the docs' problem (examples/furuta_swing_up.py)
    ours = swing_up(lambda x, u, h: m.F(x, u, m.p0, h), tol=1e-12)
    theirs = swing_up(rk4, tol=1e-12)
    print(f"\nswing-up: cost {ours['cost']!r} (ours, {ours['iterations']} iterations), {theirs['cost']!r} "
          f"(SX, {theirs['iterations']} iterations)")
    assert abs(ours["cost"] - theirs["cost"]) <= 1e-8 * abs(theirs["cost"])
    assert np.max(np.abs(ours["X"] - theirs["X"])) < 1e-6
    assert np.max(np.abs(ours["U"] - theirs["U"])) < 1e-6 * max(1.0, np.max(np.abs(theirs["U"])))
    assert ours["iterations"] == theirs["iterations"]


# --------------------------------------------------------------------------- bad input
def _generate(tmp_path, spec, *extra):
    out = tmp_path / "out"
    res = subprocess.run([sys.executable, "-m", "gyrochain", "generate", str(spec), "--casadi", "-q", "-o", str(out), *extra],
                         capture_output=True, text=True, timeout=300, cwd=tmp_path)
    return res, out


def test_generate_casadi_refuses_in_one_line_and_writes_nothing(tmp_path):
    disturbed = tmp_path / "disturbed.toml"  # a disturbance torque is an input, but no control
    disturbed.write_text((ROOT / "specs" / "kapitza.toml").read_text().replace("m = 0.1\n", "m = 0.1\ndisturbance = true\n", 1))
    for spec, extra, why in ((ROOT / "specs" / "double_pendulum.toml", (), "no control torque"),
                             (ROOT / "specs" / "furuta.toml", ("--real", "float"), "double"),
                             (disturbed, (), "no control torque")):
        res, out = _generate(tmp_path, spec, *extra)
        assert res.returncode == 2 and res.stderr.count("\n") == 1, res.stderr
        assert res.stderr.startswith("error: --casadi:") and why in res.stderr, res.stderr
        assert not out.exists()


def test_a_folder_generate_wrote_gives_the_same_functions(tmp_path, models):
    res, out = _generate(tmp_path, ROOT / "specs" / "furuta.toml", "--no-build")
    assert res.returncode == 0, res.stderr
    assert (out / "furuta_casadi.c").exists()
    m, _ = models("furuta")
    mf = gc.functions(out)
    assert mf.library == m.library  # the same sources: the same library
    from gyrochain.chainspec.errors import SpecError

    with pytest.raises(SpecError, match="no NAME_casadi.c"):
        gc.functions(tmp_path)


LIMITED = (ROOT / "specs" / "furuta.toml").read_text().replace(
    "control = true           # motor torque on the arm", 'control = true\nlimits = {lower = "-pi/2", upper = 1.5, effort = 0.8}') + \
    'limits = {velocity = 12}\n'


def test_the_spec_s_limits_reach_the_header_the_manifest_and_the_bounds(tmp_path):
    """A spec's joint limits, as data: the header's initializers (HUGE_VAL where a joint has none,
    compiled as a user's C99 would use them), MANIFEST.json, the Python module, and the CasADi
    model's box bounds on x and u, from the spec and from the folder generate wrote alike."""
    import json

    spec_path = tmp_path / "furuta.toml"
    spec_path.write_text(LIMITED)
    res, out = _generate(tmp_path, spec_path, "--no-build")
    assert res.returncode == 0, res.stderr
    header = (out / "furuta.h").read_text()
    for line in ("#define FURUTA_HAS_LIMITS 1", "#define FURUTA_PHI_LOWER {-1.5707963267948966, -HUGE_VAL}",
                 "#define FURUTA_PHI_UPPER {1.5, HUGE_VAL}", "#define FURUTA_PHIDOT_MAX {HUGE_VAL, 12.0}",
                 "#define FURUTA_EFFORT_MAX {0.8, HUGE_VAL}"):
        assert line + "\n" in header, line
    assert json.loads((out / "MANIFEST.json").read_text())["limits"] == [
        {"joint": 1, "lower": -np.pi / 2, "upper": 1.5, "effort": 0.8}, {"joint": 2, "velocity": 12.0}]
    assert "LIMITS = {'lower': [-1.5707963267948966, None], 'upper': [1.5, None], 'velocity': [None, 12.0], " \
           "'effort': [0.8, None]}" in (out / "furuta.py").read_text()
    user = tmp_path / "user.c"
    user.write_text('#include <math.h>\n#include "furuta.h"\nint main(void)\n{\n    static const double lo[FURUTA_N] = FURUTA_PHI_LOWER;\n'
                    "    static const double hi[FURUTA_N] = FURUTA_PHI_UPPER;\n    return lo[0] < hi[0] && isinf(lo[1]) ? 0 : 1;\n}\n")
    cc = subprocess.run(["cc", "-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-I", str(out), str(user), "-o",
                         str(tmp_path / "user"), "-lm"], capture_output=True, text=True)
    assert cc.returncode == 0, cc.stderr
    assert subprocess.run([str(tmp_path / "user")]).returncode == 0
    inf = np.inf
    for m in (gc.functions(spec_path), gc.functions(out)):
        b = m.bounds
        assert np.array_equal(b.lbx, [-np.pi / 2, -inf, -inf, -12.0]) and np.array_equal(b.ubx, [1.5, inf, inf, 12.0])
        assert np.array_equal(b.lbu, [-0.8]) and np.array_equal(b.ubu, [0.8])


def test_a_parameter_without_a_value_and_no_casadi_are_one_line(tmp_path, monkeypatch):
    from gyrochain.chainspec.errors import SpecError

    text = (ROOT / "specs" / "furuta_sym.toml").read_text()
    bare = tmp_path / "bare.toml"
    bare.write_text(text.split("[values]")[0])
    with pytest.raises(SpecError, match="no value for") as err:
        gc.functions(bare)
    assert "\n" not in str(err.value)
    m = gc.functions(bare, params=dict(zip(["g0", "m1", "r", "J1", "J1z", "m2", "l", "J2", "J2z"],
                                           [9.81, 0.3, 0.2, 0.004, 0.0002, 0.1, 0.15, 0.00075, 1e-5])))
    assert list(m.params) == ["g0", "m1", "r", "J1", "J1z", "m2", "l", "J2", "J2z"] and m.p0[0] == 9.81
    with pytest.raises(SpecError, match="--param m1: nan is not a finite number"):
        gc.functions(ROOT / "specs" / "furuta_sym.toml", params={"m1": float("nan")})
    with pytest.raises(SpecError, match="--param mass: unknown parameter"):
        gc.functions(ROOT / "specs" / "furuta_sym.toml", params={"mass": 1.0})
    monkeypatch.setitem(sys.modules, "casadi", None)  # as where CasADi is not installed
    with pytest.raises(gc.CasadiUnavailable, match=r"pip install 'gyrochain\[casadi\]'"):
        gc.functions(ROOT / "specs" / "furuta.toml")


DRIVER = r"""
#include <math.h>
#include <stdio.h>
#define casadi_int long long int
int NAME_f(const double **arg, double **res, casadi_int *iw, double *w, int mem);
int jac_NAME_f(const double **arg, double **res, casadi_int *iw, double *w, int mem);
int NAME_F(const double **arg, double **res, casadi_int *iw, double *w, int mem);
int jac_NAME_F(const double **arg, double **res, casadi_int *iw, double *w, int mem);
const casadi_int *jac_NAME_f_sparsity_out(casadi_int i);
#define SECOND(F) int F(const double **arg, double **res, casadi_int *iw, double *w, int mem); \
    casadi_int F##_n_out(void); const casadi_int *F##_sparsity_out(casadi_int i);
SECOND(adj1_NAME_f) SECOND(jac_adj1_NAME_f) SECOND(adj1_NAME_F) SECOND(jac_adj1_NAME_F)
static double buf[1 << 16];

/* every output of a second-order function, each in its own slice of buf; 1 if one is not finite */
static int second(int (*fn)(const double **, double **, casadi_int *, double *, int), casadi_int nout,
                  const casadi_int *(*sp)(casadi_int), const double **arg)
{
    double *res[32];
    casadi_int i, k, off = 0, nnz[32];
    int bad;
    for (i = 0; i < nout; ++i) {
        const casadi_int *s = sp(i);
        nnz[i] = s[2] == 1 && s[1] > 0 ? s[0] * s[1] : s[2 + s[1]];  /* dense (nrow, ncol, 1) or compressed */
        res[i] = buf + off;
        off += nnz[i];
    }
    bad = fn(arg, res, 0, 0, 0) != 0;
    for (i = 0; i < nout; ++i) {
        for (k = 0; k < nnz[i]; ++k) bad |= !isfinite(res[i][k]);
    }
    return bad;
}

int main(void)
{
    double x[2 * DRV_N], u[DRV_NU], h = 0.01, xdot[2 * DRV_N], xn[2 * DRV_N], Jx[4 * DRV_N * DRV_N], Ju[2 * DRV_N * DRV_NU], Jh[2 * DRV_N], Jfx[4 * DRV_N * DRV_N], Jfu[2 * DRV_N * DRV_NU];
    const double *a[5] = {x, u, 0, &h, 0};  /* p NULL: CasADi's zero input */
    double *r1[1] = {xdot}, *r2[1] = {xn}, *rj[4] = {Jx, Ju, 0, Jh}, *rf[3] = {Jfx, Jfu, 0};
    int i, bad = 0;
    for (i = 0; i < 2 * DRV_N; ++i) x[i] = 0.1 * (i + 1);
    for (i = 0; i < DRV_NU; ++i) u[i] = 0.05 * (i + 1);
    bad |= NAME_f(a, r1, 0, 0, 0) | NAME_F(a, r2, 0, 0, 0) | jac_NAME_F(a, rj, 0, 0, 0) | jac_NAME_f(a, rf, 0, 0, 0);
    for (i = 0; i < 2 * DRV_N; ++i) bad |= !isfinite(xdot[i]) || !isfinite(xn[i]) || !isfinite(Jh[i]);
    for (i = 0; i < 4 * DRV_N * DRV_N; ++i) bad |= !isfinite(Jx[i]);
    {
        double lam[2 * DRV_N];
        const double *af[8] = {x, u, 0, 0, lam, 0, 0, 0}, *aF[10] = {x, u, 0, &h, 0, lam, 0, 0, 0, 0};
        for (i = 0; i < 2 * DRV_N; ++i) lam[i] = 0.3 - 0.1 * i;
        bad |= 2 * second(adj1_NAME_f, adj1_NAME_f_n_out(), adj1_NAME_f_sparsity_out, af);
        bad |= 2 * second(jac_adj1_NAME_f, jac_adj1_NAME_f_n_out(), jac_adj1_NAME_f_sparsity_out, af);
        bad |= 2 * second(adj1_NAME_F, adj1_NAME_F_n_out(), adj1_NAME_F_sparsity_out, aF);
        bad |= 2 * second(jac_adj1_NAME_F, jac_adj1_NAME_F_n_out(), jac_adj1_NAME_F_sparsity_out, aF);
    }
    a[0] = 0;  /* x all zeros, given as NULL */
    bad |= NAME_f(a, r1, 0, 0, 0);
    printf("%d %lld\n", bad, jac_NAME_f_sparsity_out(0)[2 + 2 * DRV_N]);
    return bad;
}
"""


@pytest.mark.extended
@pytest.mark.parametrize("name", ["furuta", "planar2dof"])  # (the UR5's 2 MB of C with its Hessian: gcc's ASan build ran out of memory)
def test_the_c_is_strict_c99_and_clean_under_the_sanitizers(name, models, tmp_path):
    """NAME_casadi.c by C alone, as acados or a user's own solver calls it (no CasADi): -std=c99
    -Wall -Wextra -Wpedantic -Werror, and every function run under ASan and UBSan, a NULL input
    read as zeros."""

    files, _ = pipeline.derive_and_render(load_spec(ROOT / "specs" / f"{name}.toml"), targets=("c", "casadi"))
    for k in (f"{name}_casadi.c", f"{name}.c", f"{name}.h"):
        (tmp_path / k).write_text(files[k])
    m, _ = models(name)
    (tmp_path / "main.c").write_text(DRIVER.replace("NAME", name))
    res = subprocess.run(["cc", "-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-g", "-O1",
                          "-fsanitize=address,undefined", "-fno-sanitize-recover=all", f"-DDRV_N={m.n}", f"-DDRV_NU={m.nu}",
                          "main.c", f"{name}_casadi.c", f"{name}.c", "-lm", "-o", "run"], cwd=tmp_path, capture_output=True,
                         text=True)
    assert res.returncode == 0, res.stderr
    res = subprocess.run(["./run"], cwd=tmp_path, capture_output=True, text=True, timeout=60)
    assert res.returncode == 0 and not res.stderr, (res.stdout, res.stderr)
    nnz = int(res.stdout.split()[1])
    assert 0 < nnz < 4 * m.n * m.n  # the stored entries of df/dx: fewer than dense
