"""The stability chart of Kapitza's pendulum held upright (specs/kapitza.toml, φ = π): the largest
Floquet multiplier over the pivot's amplitude a and frequency ω by `gyrochain sweep --measure
floquet`, the stable region shaded, with the transition curves of the Mathieu equation drawn over
it in the same units (the Ince–Strutt diagram: α = −4g/(lω²) = a₀(q) and b₁(q), q = 2a/l, from
scipy.special) and the averaged criterion a²ω² = 2gl of Kapitza's effective potential.
Writes docs/img/kapitza_chart.png; run by `make plot` (about a minute on two cores; on a GPU where
one is there)."""
from __future__ import annotations

import shutil
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import ListedColormap, LogNorm  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402
from scipy.optimize import brentq  # noqa: E402
from scipy.special import mathieu_a, mathieu_b  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
from gyrochain import sweep  # noqa: E402
from gyrochain.floquet import MU_TOL  # noqa: E402
from gyrochain.plot import STABLE  # noqa: E402

G, L = 9.81, 0.2  # the example's gravity and bob distance (a point bob: l = A/(m c))
A_MAX, W_MIN, W_MAX = 0.12, 20.0, 400.0


def mathieu_curve(edge, omegas):
    """The amplitude a(ω) where α = −4g/(lω²) equals the characteristic value edge(q), q = 2a/l
    (the root in q of edge(q) − α on the branch that starts at the origin for a₀, at q ≈ 0.9 for b₁)."""
    out = []
    for w in omegas:
        alpha = -4 * G / (L * w * w)
        lo, hi = (1e-9, 3.0)
        f = lambda q, alpha=alpha: edge(q) - alpha  # noqa: E731
        out.append(brentq(f, lo, hi) * L / 2 if f(lo) * f(hi) < 0 else np.nan)
    return np.array(out)


def main(out: Path, store: Path = ROOT / "build" / "kapitza_floquet.zarr", na: int = 121, nw: int = 96) -> None:
    shutil.rmtree(store, ignore_errors=True)
    sw = sweep.Sweep(spec_text=(ROOT / "specs" / "kapitza.toml").read_text(),
                     vary=[("a", 0.0, A_MAX, na), ("w", W_MIN, W_MAX, nw)], t1=1.0, measures=["floquet"],
                     phi=[float(np.pi)], phidot=[0.0])
    sweep.run(sw, store, progress=False, device="auto")  # on a GPU where one can run it
    data = sweep.read(store)
    a, w, mu = data["coords"]["a"], data["coords"]["w"], data["floquet"]
    stable = np.isfinite(mu) & (mu <= 1 + MU_TOL)

    fig, ax = plt.subplots(figsize=(7.0, 5.2), dpi=130)
    ax.pcolormesh(a, w, np.ma.masked_where(~stable.T, np.ones_like(mu.T)), shading="nearest", cmap=ListedColormap([STABLE]))
    unstable = np.ma.masked_where(stable.T | ~np.isfinite(mu.T), mu.T)
    art = ax.pcolormesh(a, w, unstable, shading="nearest", cmap="OrRd", norm=LogNorm(vmin=1.0, vmax=float(np.nanmax(mu))))
    fig.colorbar(art, ax=ax, label="largest Floquet multiplier |μ| (unstable)")
    ws = np.linspace(W_MIN, W_MAX, 400)
    ax.plot(mathieu_curve(lambda q: mathieu_a(0, q), ws), ws, "k-", lw=1.2)
    ax.plot(mathieu_curve(lambda q: mathieu_b(1, q), ws), ws, "k-", lw=1.2)
    ax.plot(np.sqrt(2 * G * L) / ws, ws, "--", color="tab:blue", lw=1.2)
    ax.set_xlim(0.0, A_MAX)
    ax.set_ylim(W_MIN, W_MAX)
    ax.set_xlabel("amplitude of the pivot a (m)")
    ax.set_ylabel("frequency of the pivot ω (rad/s)")
    ax.set_title("Kapitza's pendulum upright (l = 0.2 m): Floquet multipliers of the generated model\n"
                 "against the Mathieu transition curves", fontsize=9)
    ax.legend(handles=[Patch(facecolor=STABLE, edgecolor="0.4", label=f"stable: every |μ| ≤ 1 ({int(stable.sum())} of {mu.size} points)"),
                       Line2D([], [], color="k", label="Mathieu: α = a₀(q) and α = b₁(q) (scipy)"),
                       Line2D([], [], color="tab:blue", ls="--", label="averaged: a²ω² = 2gl")],
              loc="upper right", fontsize=8, framealpha=0.95)
    fig.tight_layout()
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out)
    print(f"wrote {out}: {int(stable.sum())} of {mu.size} points stable")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "docs" / "img" / "kapitza_chart.png")
