"""Swinging the Furuta pendulum (specs/furuta.toml) up from hanging to upright at least effort, by
direct multiple shooting over the exact model: `generate --casadi`'s RK4 step and its exact
Jacobian (gyrochain.casadi.functions), CasADi's Opti and IPOPT.  Twice: with the torque free, and
with the torque bounded to 0.2 N m and the arm to ±1 rad (which takes longer: 2.5 s).
`make plot` writes docs/img/furuta_swing_up.png (a few seconds).
"""
from __future__ import annotations

import sys
from pathlib import Path

import casadi
import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
from gyrochain.casadi import functions  # noqa: E402


def swing_up(step, N: int = 60, T: float = 1.5, umax: float | None = None, arm: float | None = None,
             tol: float = 1e-8) -> dict:
    """From rest hanging (x = 0) to rest upright (phi2 = pi, the arm's angle free) in T seconds,
    minimising the integral of u^2, over N steps of ``step(x, u, h)`` (the external RK4 step:
    ``lambda x, u, h: m.F(x, u, m.p0, h)``); IPOPT's solution and its iterations."""
    h = T / N
    opti = casadi.Opti()
    X, U = opti.variable(4, N + 1), opti.variable(1, N)
    opti.minimize(h * casadi.sumsqr(U))
    opti.subject_to(X[:, 0] == 0)
    opti.subject_to(X[1:, N] == casadi.DM([np.pi, 0.0, 0.0]))
    for k in range(N):
        opti.subject_to(X[:, k + 1] == step(X[:, k], U[:, k], h))
    if umax is not None:
        opti.subject_to(opti.bounded(-umax, U, umax))
    if arm is not None:
        opti.subject_to(opti.bounded(-arm, X[0, :], arm))
    opti.set_initial(X[1, :], np.linspace(0.0, np.pi, N + 1))
    opti.solver("ipopt", {"print_time": False}, {"print_level": 0, "sb": "yes", "tol": tol})
    sol = opti.solve()
    return dict(t=np.linspace(0.0, T, N + 1), X=sol.value(X), U=np.atleast_1d(sol.value(U)), cost=sol.value(opti.f),
                iterations=sol.stats()["iter_count"])


def main(out: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    m = functions(ROOT / "specs" / "furuta.toml")
    step = lambda x, u, h: m.F(x, u, m.p0, h)  # noqa: E731
    free = swing_up(step)
    held = swing_up(step, N=100, T=2.5, umax=0.2, arm=1.0)
    fig, axes = plt.subplots(2, 1, figsize=(7.0, 5.4), dpi=130, sharex=True)
    for run, style, label in ((free, "-", "torque free, 1.5 s"), (held, "--", "|u| ≤ 0.2 N m, |φ¹| ≤ 1 rad, 2.5 s")):
        axes[0].plot(run["t"], run["X"][1], "C0" + style, label=f"pendulum φ² ({label})")
        axes[0].plot(run["t"], run["X"][0], "C1" + style, label=f"arm φ¹ ({label})")
        axes[1].step(run["t"][:-1], run["U"], "C2" + style, where="post",
                     label=f"{label}: ∫u² dt = {run['cost']:.4g}, {run['iterations']} IPOPT iterations")
    axes[0].axhline(np.pi, color="0.6", lw=0.8)
    axes[0].set_ylabel("angle (rad)")
    axes[1].set_ylabel("motor torque u (N m)")
    axes[1].set_xlabel("t (s)")
    axes[0].legend(fontsize=7, loc="lower right")
    axes[1].legend(fontsize=7, loc="upper right")
    axes[0].set_title("Furuta pendulum: swing-up at least effort over the exact model (CasADi + IPOPT)", fontsize=9)
    fig.tight_layout()
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out)
    print(f"wrote {out}: cost {free['cost']:.6g} (free), {held['cost']:.6g} (bounded)")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "docs" / "img" / "furuta_swing_up.png")
