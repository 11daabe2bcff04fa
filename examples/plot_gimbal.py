"""Nikolai's gyroscope in a Cardan suspension (specs/gimbal.toml, its [initial] state): φ(t) and
ψ(t) from the quadratures (30) over an ODE solution of the generated equations, and the phase
curve.  Writes docs/img/gimbal_quadrature.png; run by `make plot`."""
from __future__ import annotations

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from scipy.integrate import solve_ivp  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
from gyrochain.build import load  # noqa: E402
from gyrochain.spec import load_spec  # noqa: E402


def main(out: Path) -> None:
    spec = load_spec(ROOT / "specs" / "gimbal.toml")
    model = load(ROOT / "generated" / "gimbal", "gimbal")
    x0 = np.array([*spec.initial["phi"], *spec.initial["phidot"]])
    info = model.quad_motion(x0)
    T = info["period"]
    t = np.linspace(0.0, 3.0 * T, 600)
    Xq = model.quad_state(t, x0)
    t_ode = np.linspace(0.0, 3.0 * T, 61)
    Xo = solve_ivp(lambda s, x: model.rhs(s, x), (0.0, t[-1]), x0, method="DOP853", rtol=1e-12, atol=1e-12,
                   t_eval=t_ode).y.T
    err = np.max(np.abs(model.quad_state(t_ode, x0) - Xo)[:, :2])

    fig = plt.figure(figsize=(8.0, 6.6))  # two panels over the phase curve: legible at a page's 672 px
    grid = fig.add_gridspec(2, 2)
    ax = [fig.add_subplot(grid[0, 0]), fig.add_subplot(grid[0, 1]), fig.add_subplot(grid[1, :])]
    ax[0].plot(t, Xq[:, 1], label="quadrature (30)")
    ax[0].plot(t_ode, Xo[:, 1], "o", ms=3, label="ODE (DOP853, 1e-12)")
    for k in range(4):
        ax[0].axvline(k * T, color="0.85", lw=0.8, zorder=0)
    ax[0].axhline(info["phi_min"], color="0.6", ls=":", lw=0.8)
    ax[0].axhline(info["phi_max"], color="0.6", ls=":", lw=0.8)
    ax[0].set(xlabel="t [s]", ylabel="φ = φ² [rad]", title=f"inner ring: libration,\nperiod {T:.6f} s")
    ax[1].plot(t, Xq[:, 0], label="quadrature (30)")
    ax[1].plot(t_ode, Xo[:, 0], "o", ms=3, label="ODE")
    ax[1].set(xlabel="t [s]", ylabel="ψ = φ¹ [rad]", title=f"outer ring: +{info['psi_advance']:.4f} rad per period")
    ax[2].plot(Xq[:, 1], Xq[:, 3], label="quadrature")
    ax[2].plot(Xo[:, 1], Xo[:, 3], "o", ms=3, label="ODE")
    ax[2].set(xlabel="φ [rad]", ylabel="φ̇ [rad/s]", title="phase curve (turning points dotted)")
    for a in ax:
        a.legend(fontsize=8, loc="best")
        a.grid(alpha=0.3)
    ax[2].axvline(info["phi_min"], color="0.6", ls=":", lw=0.8)
    ax[2].axvline(info["phi_max"], color="0.6", ls=":", lw=0.8)
    fig.suptitle(f"gimbal: x0 = {x0.tolist()},\nmax |quadrature − ODE| over 3 periods = {err:.1e} rad", fontsize=10)
    fig.tight_layout()
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=110, metadata={"Software": None})
    print(f"wrote {out}: period {T:.12g} s, max |quadrature - ODE| {err:.2e} rad")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "docs" / "gimbal_quadrature.png")
