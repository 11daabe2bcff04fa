"""The nonlinear normal modes of the double pendulum of point masses (specs/double_pendulum_point.toml,
1 kg and 1 m each): both branches continued by `gyrochain orbits` from their linear modes
ω² = (g/l)(2 ∓ √2) up to the energy that lifts the lower bob to the level of the pivot's
(E − E₀ = 2mgl), the period against the energy with the linear periods marked, the orbits' shapes
at a few energies, and where the multipliers leave the unit circle.  Writes
docs/img/nnm_periods.png; run by `make plot`."""
from __future__ import annotations

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
from gyrochain import orbits, pipeline  # noqa: E402
from gyrochain.spec import load_spec  # noqa: E402

G, L, M = 9.81, 1.0, 1.0


def main(out: Path) -> None:
    cm, _ = pipeline.compiled(load_spec(ROOT / "specs" / "double_pendulum_point.toml"))
    energies = np.linspace(0.05, 2 * M * G * L, 80)
    fams = orbits.normal_modes(cm, np.zeros(2), energies)
    fig, (ax, ay) = plt.subplots(1, 2, figsize=(9.0, 5.2), dpi=100, gridspec_kw={"width_ratios": (1.25, 1)})
    for k, (fam, sign, colour) in enumerate(zip(fams, (-1, 1), ("tab:blue", "tab:red")), start=1):
        E = np.array([o.value for o in fam.orbits])
        T = np.array([o.period for o in fam.orbits])
        stable = np.array([o.verdict == "linearly stable" for o in fam.orbits])
        T_lin = 2 * np.pi / np.sqrt(G / L * (2 + sign * np.sqrt(2)))
        ax.plot(E, T, "-", color=colour, label=f"mode {k}" + ("" if not fam.stopped else " (continuation stopped)"))
        ax.plot(E[~stable], T[~stable], "x", color=colour, ms=5, label=f"mode {k}: unstable orbits" if (~stable).any() else None)
        ax.plot([0.0], [T_lin], "o", color=colour, mfc="white", label=f"linear: $2\\pi/\\omega$, $\\omega^2 = (g/l)(2 {'-' if sign < 0 else '+'} \\sqrt{{2}})$")
        for o in fam.orbits[:: max(1, len(fam.orbits) // 4)]:
            X = cm.integrate(np.linspace(0.0, o.period, 200), o.x0, rtol=1e-10, atol=1e-10)
            ay.plot(X[:, 0], X[:, 1], "-", color=colour, lw=0.9, alpha=0.8)
        print(f"mode {k}: {len(fam.orbits)} orbits, E - E0 up to {E[-1]:.4g} J, period {T[0]:.6g} .. {T[-1]:.6g} s, "
              f"{int((~stable).sum())} unstable" + (f"; stopped: {fam.stopped}" if fam.stopped else ""))
    ax.set_xlabel("energy above the hanging equilibrium, $E - E_0$ (J)", fontsize=12)
    ax.set_ylabel("period (s)", fontsize=12)
    ax.set_title("period against energy", fontsize=12)
    fig.legend(*ax.get_legend_handles_labels(), loc="lower center", ncol=2, fontsize=11, frameon=False)
    ay.set_xlabel("$\\varphi^1$ (rad)", fontsize=12)
    ay.set_ylabel("$\\varphi^2$ (rad)", fontsize=12)
    ay.set_title("orbits (mode 1 blue, mode 2 red)", fontsize=12)
    for a in (ax, ay):
        a.tick_params(labelsize=11)
    ay.set_aspect("equal", adjustable="datalim")
    fig.tight_layout(rect=(0, 0.15, 1, 1))
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, bbox_inches="tight", pad_inches=0.05)
    print(f"wrote {out}")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "docs" / "img" / "nnm_periods.png")
