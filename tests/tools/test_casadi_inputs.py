"""`generate --casadi` for a model that reads t and for disturbance torques: t is an input of f and
F (after p and h), a spec's disturbance torques are CasADi's u_dist (their last input), and every
first and second derivative in them is exact: the C's against differences at random points, and
CasADi's own (its AD over jac_ and jac_adj1_) against differences of f and of its gradient.  Two
problems that need them: a minimum-time turn of a gimbal's outer ring on a rolling ship (the times
t_k = k T/N move with the decision T), and estimating a constant torque on the Furuta pendulum's
unactuated joint from a measured motion (u_dist a decision variable)."""
from __future__ import annotations

import numpy as np
import pytest

from gyrochain.spec import parse_spec
from conftest import ROOT, fd_jacobian

casadi = pytest.importorskip("casadi", reason="CasADi is not installed (the test extra installs gyrochain[casadi])")
from gyrochain import casadi as gc  # noqa: E402
from gyrochain.models import pipeline  # noqa: E402


def ship_motor() -> str:
    """The gimbal on a rolling, pitching, heaving ship with a motor on its outer ring."""
    text = (ROOT / "specs" / "ship_gimbal.toml").read_text()
    return text.replace('name = "ship_gimbal"', 'name = "ship_motor"').replace("s = [0.0, 0.0, 0.0]\n", "s = [0.0, 0.0, 0.0]\ncontrol = true\n", 1)


def furuta_disturbed() -> str:
    """The Furuta pendulum with a disturbance torque on the pendulum's joint (body 2)."""
    head, arm, pendulum = (ROOT / "specs" / "furuta.toml").read_text().split("[[body]]")
    return "[[body]]".join([head.replace('name = "furuta"', 'name = "furuta_disturbed"'), arm,
                            pendulum.replace("\n", "\ndisturbance = true\n", 1)])


@pytest.fixture(scope="module")
def built():
    out = {}
    for text in (ship_motor(), furuta_disturbed()):
        spec = parse_spec(text)
        out[spec.name] = (gc.functions(spec), pipeline.compiled(spec, hessian=True)[0], spec)
    return out


def _sym(m, step):
    """(z, the function's output at z): z = (x, u[, h][, t][, u_dist]), CasADi's inputs but p."""
    sizes = [2 * m.n, m.nu] + ([1] if step else []) + ([1] if m.time_dependent else []) + ([m.ndist] if m.ndist else [])
    z = casadi.SX.sym("z", sum(sizes))
    parts = casadi.vertsplit(z, list(np.cumsum([0, *sizes])))
    args = [parts[0], parts[1], m.p0, *parts[2:]]
    return z, (m.F if step else m.f)(*args)


@pytest.mark.parametrize("name", ["ship_motor", "furuta_disturbed"])
def test_every_derivative_in_t_and_u_dist_equals_differences(built, rng, name):
    m, c, spec = built[name]
    assert [a for a in m.f.name_in()] == ["x", "u", "p"] + (["t"] if name == "ship_motor" else ["u_dist"])
    assert m.F.name_in() == ["x", "u", "p", "h"] + (["t"] if name == "ship_motor" else ["u_dist"])
    worst = {"f": 0.0, "jac": 0.0, "hess": 0.0}
    for step in (False, True):
        z, out = _sym(m, step)
        value = casadi.Function("v", [z], [out])
        jac = casadi.Function("j", [z], [casadi.jacobian(out, z)])
        lam = casadi.SX.sym("lam", 2 * m.n)
        lag = casadi.dot(lam, out)
        hess = casadi.Function("h", [z, lam], [casadi.hessian(lag, z)[0]])
        grad = casadi.Function("g", [z, lam], [casadi.gradient(lag, z)])
        for _ in range(5):
            x = np.concatenate([rng.uniform(-np.pi, np.pi, m.n), rng.normal(size=m.n)])
            u, d, t, h = rng.normal(size=m.nu), rng.normal(size=m.ndist), float(rng.uniform(0, 3)), 0.02
            z0 = np.concatenate([x, u] + ([[h]] if step else []) + ([[t]] if m.time_dependent else []) + [d])
            full = np.zeros(len(spec.controls))  # the C's u: controls and disturbances in chain order
            full[[i for i, k in enumerate(spec.controls) if k not in spec.disturbances]] = u
            full[[i for i, k in enumerate(spec.controls) if k in spec.disturbances]] = d
            tt = t if m.time_dependent else 0.0
            want = c.step(x, h, full, t=tt) if step else c.rhs(tt, x, full)
            worst["f"] = max(worst["f"], np.max(np.abs(np.asarray(value(z0)).ravel() - want)))
            J = np.asarray(jac(z0))
            fd = fd_jacobian(lambda v: np.asarray(value(v)).ravel(), z0, h=1e-4)
            worst["jac"] = max(worst["jac"], np.max(np.abs(J - fd)) / max(1.0, np.max(np.abs(fd))))
            lv = rng.normal(size=2 * m.n)
            H = np.asarray(hess(z0, lv))
            fd = fd_jacobian(lambda v: np.asarray(grad(v, lv)).ravel(), z0, h=1e-4)
            worst["hess"] = max(worst["hess"], np.max(np.abs(H - fd)) / max(1.0, np.max(np.abs(fd))))
    print(f"\n{name}: {worst}")
    assert worst["f"] <= 1e-14 and worst["jac"] <= 1e-8 and worst["hess"] <= 1e-7, worst


def test_a_minimum_time_turn_on_a_rolling_ship(built):
    """The outer ring turns 0.5 rad from rest to rest with |u| <= 0.3 N m in least time, the ship
    rolling under it: the times t_k = k T/N of the steps are the decision T's, so IPOPT's exact
    Hessian takes the derivatives in t of the step, first and second.  The optimum, stepped again
    by the C's NAME_step from the same times, is the motion IPOPT found."""
    m, c, _ = built["ship_motor"]
    N = 30
    opti = casadi.Opti()
    X, U, T = opti.variable(4, N + 1), opti.variable(1, N), opti.variable()
    opti.minimize(T)
    opti.subject_to(X[:, 0] == casadi.DM([0.0, 0.3, 0.0, 0.0]))
    opti.subject_to(X[0, N] == 0.5)
    opti.subject_to(X[2, N] == 0.0)
    for k in range(N):
        opti.subject_to(X[:, k + 1] == m.F(X[:, k], U[:, k], m.p0, T / N, k * T / N))
    opti.subject_to(opti.bounded(-0.3, U, 0.3))
    opti.subject_to(opti.bounded(0.2, T, 5.0))
    opti.set_initial(T, 1.0)
    opti.set_initial(X[0, :], np.linspace(0.0, 0.5, N + 1))
    opti.set_initial(X[1, :], 0.3)
    opti.solver("ipopt", {"print_time": False}, {"print_level": 0, "sb": "yes"})
    sol = opti.solve()
    assert sol.stats()["return_status"] == "Solve_Succeeded"
    Tv, Xv, Uv = sol.value(T), sol.value(X), np.atleast_2d(sol.value(U))
    x = Xv[:, 0]
    for k in range(N):
        x = c.step(x, Tv / N, Uv[:, k], t=k * Tv / N)
    assert np.max(np.abs(x - Xv[:, N])) < 1e-8
    print(f"\nminimum time {Tv:.4f} s in {sol.stats()['iter_count']} iterations")
    assert np.max(np.abs(Uv)) > 0.3 - 1e-6  # a bound is active: a bang-bang-like turn


def test_estimating_a_torque_on_an_unactuated_joint(built):
    """A constant torque of 0.004 N m on the Furuta pendulum's joint (no motor there) and a known
    motor torque: from the 41 measured states of 0.4 s, least squares over the start and the
    unknown torque (u_dist a decision variable, IPOPT's exact Hessian) gives it back to 1e-8."""
    m, c, _ = built["furuta_disturbed"]
    h, N, d_true = 0.01, 40, 0.004
    u = 0.05 * np.sin(np.arange(N) * h * 7.0)
    x, meas = np.array([0.0, 0.4, 0.0, 0.0]), []
    for k in range(N + 1):
        meas.append(x)
        if k < N:
            x = c.step(x, h, [u[k], d_true])
    opti = casadi.Opti()
    X0, D = opti.variable(4), opti.variable()
    x, cost = X0, 0
    for k in range(N + 1):
        cost += casadi.sumsqr(x - meas[k])
        if k < N:
            x = m.F(x, u[k], m.p0, h, D)
    opti.minimize(cost)
    opti.solver("ipopt", {"print_time": False}, {"print_level": 0, "sb": "yes", "tol": 1e-14})
    sol = opti.solve()
    assert abs(sol.value(D) - d_true) < 1e-8 and np.max(np.abs(sol.value(X0) - meas[0])) < 1e-8


def test_the_c_of_both_is_strict_c99(tmp_path):
    """NAME_casadi.c of a model that reads t and has a disturbance torque (the heaving Furuta
    pendulum of docs/optimal-control.md): C99, warning-free under -Wall -Wextra -Wpedantic -Werror."""
    import subprocess

    text = furuta_disturbed().replace("g = 9.81\n", 'g = 9.81\n[base]\nposition = ["0.01*sin(30*t)", 0, 0]\n', 1)
    spec = parse_spec(text)
    assert spec.disturbances == (2,)
    files, model = pipeline.derive_and_render(spec, targets=("c", "casadi"))
    assert model.tder
    for k in ("furuta_disturbed_casadi.c", "furuta_disturbed.c", "furuta_disturbed.h"):
        (tmp_path / k).write_text(files[k])
    r = subprocess.run(["cc", "-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-c", "furuta_disturbed_casadi.c",
                        "furuta_disturbed.c"], cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
