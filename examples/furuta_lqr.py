"""Balancing the Furuta pendulum (specs/furuta.toml) upright with an LQR gain from the emitted
linearisation.

furuta_linearize gives A, B at the upright equilibrium (φ² = π, found by `gyrochain steady`); the
gain is the discrete-time LQR of their zero-order-hold discretisation at the 1 kHz control rate
(scipy's Riccati solver); the closed loop runs the emitted C integrator (RK4, one 1 ms step per
control period, the motor torque held in between) from 0.2 rad off upright.  Without the
controller the pendulum falls.  `make plot` writes docs/img/furuta_lqr.png.
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from scipy.linalg import expm, solve_discrete_are

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
from gyrochain.build import load  # noqa: E402

RATE = 1000.0  # Hz
UPRIGHT = np.array([0.0, np.pi, 0.0, 0.0])
Q = np.diag([1.0, 10.0, 0.1, 0.1])  # arm angle, pendulum angle, their rates
R = np.array([[10.0]])  # motor torque


def gain(model, dt: float = 1.0 / RATE) -> np.ndarray:
    """The discrete LQR gain K (u = −K (x − x*)) from furuta_linearize at the upright position."""
    A, B = model.linearize(UPRIGHT, u=np.zeros(1))
    n, m = A.shape[0], B.shape[1]
    big = expm(np.block([[A, B], [np.zeros((m, n + m))]]) * dt)  # zero-order hold
    Ad, Bd = big[:n, :n], big[:n, n:]
    P = solve_discrete_are(Ad, Bd, Q, R)
    return np.linalg.solve(R + Bd.T @ P @ Bd, Bd.T @ P @ Ad)


def run(model, K=None, t1: float = 4.0, offset: float = 0.2, dt: float = 1.0 / RATE):
    """Closed loop (or open loop with K None) from the upright position tilted by ``offset``:
    times, states, torques."""
    x = UPRIGHT + np.array([0.0, -offset, 0.0, 0.0])
    steps = int(round(t1 / dt))
    T, X, U = np.arange(steps + 1) * dt, [x], []
    for k in range(steps):
        err = x - UPRIGHT
        err[:2] = (err[:2] + np.pi) % (2 * np.pi) - np.pi
        u = np.zeros(1) if K is None else -K @ err
        x = model.integrate([T[k], T[k + 1]], x, method="rk4", h=dt, u=u)[-1]
        X.append(x)
        U.append(u[0])
    return T, np.array(X), np.array(U + [U[-1]])


def main(out: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    model = load(ROOT / "generated" / "furuta", "furuta")
    K = gain(model)
    T, X, U = run(model, K)
    To, Xo, _ = run(model, None, t1=1.5)
    fig, ax = plt.subplots(1, 2, figsize=(8.0, 3.8))  # legible at a page's 672 px
    ax[0].plot(T, X[:, 1] - np.pi, label="pendulum φ² − π (LQR)")
    ax[0].plot(T, X[:, 0], label="arm φ¹ (LQR)")
    ax[0].plot(To, Xo[:, 1] - np.pi, "--", label="pendulum, no controller")
    ax[0].set_ylim(-1.5, 1.5)
    ax[0].set_xlabel("t (s)")
    ax[0].set_ylabel("rad")
    ax[0].legend(fontsize=8)
    ax[0].set_title("Furuta pendulum from 0.2 rad\noff upright, LQR at 1 kHz", fontsize=10)
    ax[1].plot(T, U)
    ax[1].set_xlabel("t (s)")
    ax[1].set_ylabel("motor torque (N m)")
    ax[1].set_title("K = " + np.array2string(K[0], precision=3), fontsize=10)
    fig.tight_layout()
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=110)
    print(f"gain K = {K[0]}; |phi2 - pi| at t = {T[-1]:.1f} s: {abs(X[-1, 1] - np.pi):.2e} rad; wrote {out}")


if __name__ == "__main__":
    main(Path(sys.argv[1] if len(sys.argv) > 1 else ROOT / "docs" / "furuta_lqr.png"))
