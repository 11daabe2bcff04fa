"""Optimal control over the exact model against CasADi's own: three problems solved by IPOPT (exact
Hessians, the same start; the UR5 within the limits its URDF states, functions(...).bounds) over
direct multiple shooting with one RK4 step per interval, once over
`generate --casadi`'s external step (gyrochain.casadi.functions: exact Jacobians and exact second
derivatives, jac_adj1_NAME_F) and over the same RK4 written in CasADi SX around Featherstone's
articulated-body algorithm (bench/peers.py, numbers folded in, CasADi's common subexpressions), its
Jacobians and Hessians by CasADi's automatic differentiation: the NLP expanded into SX
(``expand=True``, CasADi's virtual machine) and compiled by CasADi's jit with gcc -O3 (the UR5's only
with --jit-all: gcc takes minutes on its one function).  And a nonlinear MPC balancing the Furuta
pendulum through two strikes, warm-started, its time per control step.  Both models agree to 1e-14
(checked here).  Prints, per problem and model, the IPOPT iterations, the wall time per iteration
(IPOPT's own t_wall_total over its iterations, without the jit's compile) and per evaluation of the
constraints, their Jacobian and the Lagrangian's Hessian; writes bench/results/casadi_ocp.csv.
Usage: python bench/casadi_ocp.py [REPEATS] [--jit-all]"""
from __future__ import annotations

import os
import sys
import tempfile
import time
from pathlib import Path

import casadi as ca
import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "bench"))
from peers import casadi_aba  # noqa: E402
from gyrochain.casadi import functions  # noqa: E402
from gyrochain.derive import reference  # noqa: E402
from gyrochain.spec import load_spec  # noqa: E402

def jit(level: str) -> dict:
    return {"jit": True, "compiler": "shell", "jit_options": {"compiler": "gcc", "flags": [level], "verbose": False}}
# name, spec, N, T, start (phi), goal (phi; None: free), the coordinates left free at the goal
PROBLEMS = [
    ("Furuta swing-up", "furuta", 60, 1.5, [0.0, 0.0], [None, np.pi]),
    ("two-link arm swing-up", "planar2dof", 60, 1.5, [np.pi, 0.0], [0.0, 0.0]),
    ("UR5 point to point within its limits", "ur5", 30, 0.6, [0.0] * 6, [1.0, -0.5, 0.5, 0.3, 0.2, 0.1]),
]


def sx_step(spec):
    """RK4 of Featherstone's ABA in SX: (x, u, h) -> xnext."""
    f = casadi_aba(reference.numeric(spec), f"{spec.name}_sx", torques=True)
    n = spec.n
    x, u, h = ca.SX.sym("x", 2 * n), ca.SX.sym("u", len(spec.controls)), ca.SX.sym("h")

    def rate(y):
        return ca.vertcat(y[n:], f(y, u))
    k1 = rate(x)
    k2 = rate(x + h / 2 * k1)
    k3 = rate(x + h / 2 * k2)
    xn = x + h / 6 * (k1 + 2 * k2 + 2 * k3 + rate(x + h * k3))
    return ca.Function(f"{spec.name}_F_sx", [x, u, h], [xn], {"cse": True})


def solve(step, n: int, nu: int, N: int, T: float, start, goal, opts: dict, bounds=None) -> dict:
    """``bounds``: the spec's limits (functions(...).bounds) on every state and control, where it has them."""
    h = T / N
    opti = ca.Opti()
    X, U = opti.variable(2 * n, N + 1), opti.variable(nu, N)
    opti.minimize(h * ca.sumsqr(U))
    opti.subject_to(X[:, 0] == ca.DM([*start, *[0.0] * n]))
    for i, g in enumerate(goal):
        if g is not None:
            opti.subject_to(X[i, N] == g)
    opti.subject_to(X[n:, N] == 0)
    for k in range(N):
        opti.subject_to(X[:, k + 1] == step(X[:, k], U[:, k], h))
    if bounds is not None:
        lim = np.isfinite(bounds.ubx)  # (a limit of inf is no constraint)
        for k in range(N):
            opti.subject_to(opti.bounded(bounds.lbu, U[:, k], bounds.ubu))
        for k in range(N + 1):
            opti.subject_to(opti.bounded(bounds.lbx[lim], X[np.flatnonzero(lim).tolist(), k], bounds.ubx[lim]))
    for i in range(n):
        g = goal[i] if goal[i] is not None else start[i]
        opti.set_initial(X[i, :], np.linspace(start[i], g, N + 1))
    opti.solver("ipopt", {"print_time": False, "record_time": True, **opts}, {"print_level": 0, "sb": "yes", "tol": 1e-10})
    t0 = time.perf_counter()
    sol = opti.solve()
    took = time.perf_counter() - t0
    st = sol.stats()
    it = st["iter_count"]
    return dict(cost=float(sol.value(opti.f)), iterations=it, per_iteration_ms=1e3 * st["t_wall_total"] / max(it, 1),
                g_us=1e6 * st["t_wall_nlp_g"] / max(st["n_call_nlp_g"], 1),
                jac_g_us=1e6 * st["t_wall_nlp_jac_g"] / max(st["n_call_nlp_jac_g"], 1),
                hess_us=1e6 * st["t_wall_nlp_hess_l"] / max(st["n_call_nlp_hess_l"], 1), setup_s=took - st["t_wall_total"])


def best_of(repeats: int, step, m, N, T, start, goal, opts) -> dict:
    """The run of least time per iteration of ``repeats`` (CasADi's jit writes its files in a
    scratch folder), within the spec's limits where it has them."""
    best = None
    here = os.getcwd()
    with tempfile.TemporaryDirectory() as scratch:
        os.chdir(scratch)
        try:
            for _ in range(repeats):
                r = solve(step, m.n, m.nu, N, T, start, goal, opts, m.bounds if np.isfinite(m.bounds.ubx).any() else None)
                best = r if best is None or r["per_iteration_ms"] < best["per_iteration_ms"] else best
        finally:
            os.chdir(here)
    return best


def nmpc(step, n: int, nu: int, opts: dict, N: int = 25, h: float = 0.02, steps: int = 60) -> dict:
    """Balance the Furuta pendulum upright by NMPC: each control step solves the horizon's OCP (|u|
    bounded, warm-started from the last solution) from the measured state; the plant is the exact
    step; the pendulum is struck (its rate +1, then -1.5 rad/s) at steps 10 and 35.  The solver
    time per control step (the median) and the largest tilt after the strikes."""
    opti = ca.Opti()
    X, U, x0 = opti.variable(2 * n, N + 1), opti.variable(nu, N), opti.parameter(2 * n)
    up = ca.DM([0.0, np.pi, 0.0, 0.0])
    opti.minimize(ca.sumsqr(X[1, :] - np.pi) * 10 + ca.sumsqr(X[2:, :]) * 0.1 + ca.sumsqr(X[0, :]) + 0.1 * ca.sumsqr(U))
    opti.subject_to(X[:, 0] == x0)
    for k in range(N):
        opti.subject_to(X[:, k + 1] == step(X[:, k], U[:, k], h))
    opti.subject_to(opti.bounded(-0.3, U, 0.3))
    opti.solver("ipopt", {"print_time": False, **opts}, {"print_level": 0, "sb": "yes", "tol": 1e-8})
    x = np.array([0.0, np.pi - 0.2, 0.0, 0.0])
    times, tilt, guess = [], 0.0, None
    opti.set_initial(X, ca.repmat(up, 1, N + 1))
    for i in range(steps):
        if i in (10, 35):
            x[3] += 1.0 if i == 10 else -1.5
        opti.set_value(x0, x)
        if guess is not None:
            opti.set_initial(X, guess[0])
            opti.set_initial(U, guess[1])
        t0 = time.perf_counter()
        sol = opti.solve()
        times.append(time.perf_counter() - t0)
        guess = (sol.value(X), sol.value(U))
        u = np.atleast_1d(guess[1])[:1] if nu == 1 else guess[1][:, 0]
        x = np.asarray(step(x, u, h)).ravel()
        tilt = max(tilt, abs(x[1] - np.pi)) if i >= 10 else tilt
    return dict(per_step_ms=1e3 * float(np.median(times)), tilt=tilt, final=abs(x[1] - np.pi))


def main(repeats: int = 3, jit_all: bool = False) -> None:
    rows = []
    for title, name, N, T, start, goal in PROBLEMS:
        spec = load_spec(ROOT / "specs" / f"{name}.toml")
        m = functions(spec)
        sx = sx_step(spec)
        rng = np.random.default_rng(0)
        x, u = rng.uniform(-1, 1, 2 * m.n), rng.uniform(-1, 1, m.nu)
        agree = float(np.max(np.abs(np.asarray(m.F(x, u, m.p0, 0.01)) - np.asarray(sx(x, u, 0.01)))))
        ours = lambda x, u, h: m.F(x, u, m.p0, h)  # noqa: E731
        runs = {"gyrochain external": best_of(repeats, ours, m, N, T, start, goal, {})}
        runs["CasADi SX, expand"] = best_of(repeats, sx, m, N, T, start, goal, {"expand": True})
        if m.n <= 2 or jit_all:  # (the UR5's NLP takes gcc minutes a build)
            try:
                runs["CasADi SX, jit -O3"] = best_of(repeats if m.n <= 2 else 1, sx, m, N, T, start, goal, jit("-O3"))
            except RuntimeError as exc:  # gcc itself may fail on the NLP's one large function
                print(f"{title}: CasADi's jit with gcc -O3 failed ({str(exc).splitlines()[-1][:120]}); -O1 instead", flush=True)
                runs["CasADi SX, jit -O1 (-O3: gcc failed)"] = best_of(1, sx, m, N, T, start, goal, jit("-O1"))
        base = runs["CasADi SX, expand"]
        for label, r in runs.items():
            rows.append(dict(problem=title, model=label, n=m.n, intervals=N, iterations=r["iterations"],
                             cost=f"{r['cost']:.10g}", per_iteration_ms=f"{r['per_iteration_ms']:.3g}",
                             constraints_us=f"{r['g_us']:.3g}", jacobian_us=f"{r['jac_g_us']:.3g}",
                             hessian_us=f"{r['hess_us']:.3g}", setup_s=f"{r['setup_s']:.3g}",
                             ratio=f"{r['per_iteration_ms'] / base['per_iteration_ms']:.3f}",
                             step_agreement=f"{agree:.1e}"))
            print(rows[-1], flush=True)
        for label, r in runs.items():
            print(f"{title}: per iteration, {label} / CasADi SX expand = {r['per_iteration_ms'] / base['per_iteration_ms']:.3f}"
                  f" ({r['iterations']} iterations, cost {r['cost']:.10g})", flush=True)
        if name == "furuta":
            mpc = {"gyrochain external": nmpc(ours, m.n, m.nu, {}), "CasADi SX, expand": nmpc(sx, m.n, m.nu, {"expand": True}),
                   "CasADi SX, jit -O3": nmpc(sx, m.n, m.nu, jit("-O3"))}
            for label, r in mpc.items():
                rows.append(dict(problem="Furuta NMPC, per control step", model=label, n=m.n, intervals=25, iterations="",
                                 cost=f"{r['final']:.2e}", per_iteration_ms=f"{r['per_step_ms']:.3g}", constraints_us="",
                                 jacobian_us="", hessian_us="", setup_s="",
                                 ratio=f"{r['per_step_ms'] / mpc['CasADi SX, expand']['per_step_ms']:.3f}",
                                 step_agreement=f"{agree:.1e}"))
                print(f"Furuta NMPC: {label}: {r['per_step_ms']:.3g} ms per control step (median), largest tilt after "
                      f"the strikes {r['tilt']:.3f} rad, {r['final']:.1e} at the end", flush=True)
    from provenance import write

    write(ROOT / "bench" / "results" / "casadi_ocp.csv", rows, flags="ours cc -O2; CasADi SX expand, or its jit with gcc as the row says")


if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if a != "--jit-all"]
    main(int(args[0]) if args else 3, jit_all="--jit-all" in sys.argv[1:])
