"""The picture of the frames and angles in docs/spec.md: body k−1's frame, the axis lᵏ at θᵏ from
lᵏ⁻¹ about the common perpendicular ê^{k−1}_2, body k's frame turned by φᵏ about eᵏ, and the
vectors s and c of body k.  The frames are computed with the convention the generator uses,
α^{k,k−1} = R₁(φᵏ) R₂(θᵏ) (rows: ê^k_i in frame k−1), not drawn by hand.

    python examples/frames_figure.py docs/img/frames.png        (run by `make plot`)
"""
from __future__ import annotations

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def R1(phi: float) -> np.ndarray:
    c, s = np.cos(phi), np.sin(phi)
    return np.array([[1, 0, 0], [0, c, s], [0, -s, c]])


def R2(theta: float) -> np.ndarray:
    c, s = np.cos(theta), np.sin(theta)
    return np.array([[c, 0, -s], [0, 1, 0], [s, 0, c]])


def _arc(a: np.ndarray, b: np.ndarray, r: float, n: int = 40) -> np.ndarray:
    """Points at radius r on the arc from the direction a to the direction b."""
    w = b - (b @ a) * a
    w /= np.linalg.norm(w)
    ang = np.arccos(np.clip(a @ b, -1.0, 1.0))
    return np.array([r * (np.cos(x) * a + np.sin(x) * w) for x in np.linspace(0.0, ang, n)])


def main(out: str) -> None:
    theta, phi = np.radians(55.0), np.radians(40.0)
    alpha = R1(phi) @ R2(theta)  # rows: ê^k_i in frame k−1
    zero = R2(theta)  # body k's frame at φᵏ = 0
    s_k = alpha.T @ np.array([0.0, -0.7, 1.1])  # s^k = O^k O^{k+1}: (0, -0.7, 1.1) in body k axes
    E = np.eye(3)
    fig = plt.figure(figsize=(6.0, 5.6), dpi=120)
    ax = fig.add_subplot(projection="3d", proj_type="ortho")
    grey, blue, orange = "#666666", "#0072B2", "#D55E00"

    def line(p, q, col, lw=1.6, ls="-", alpha_=1.0):
        ax.plot(*zip(p, q), color=col, lw=lw, ls=ls, alpha=alpha_)

    def text(p, label, col, size=11, **kw):
        ax.text(*p, label, color=col, fontsize=size, **kw)

    # frame k−1 (grey) and its axis l^{k−1} along ê^{k−1}_1
    line(-1.5 * E[0], 1.5 * E[0], grey, lw=5, alpha_=0.3)
    text(-1.75 * E[0], "$l^{k-1}$", grey)
    for i, lab in enumerate(("$\\hat e^{k-1}_1$", "$\\hat e^{k-1}_2$", "$\\hat e^{k-1}_3$")):
        line(np.zeros(3), 1.1 * E[i], grey)
        text(1.2 * E[i], lab, grey)
    # body k's axis l^k along e^k = ê^k_1, at θ^k from l^{k−1} about ê^{k−1}_2 (the common perpendicular)
    line(-1.5 * alpha[0], 1.5 * alpha[0], blue, lw=5, alpha_=0.35)
    text(1.62 * alpha[0], "$l^k$, along $e^k = \\hat e^k_1$", blue)
    arc = _arc(E[0], alpha[0], 0.55)
    ax.plot(*arc.T, color="k", lw=1.2)
    text(0.68 * arc[len(arc) // 2] / np.linalg.norm(arc[len(arc) // 2]), "$\\theta^k$", "k", 13)
    # ê^k_2, ê^k_3 turned by φ^k about e^k from where θ^k alone puts them (dotted)
    for i, lab in ((1, "$\\hat e^k_2$"), (2, "$\\hat e^k_3$")):
        line(np.zeros(3), 1.0 * alpha[i], blue)
        text(1.1 * alpha[i], lab, blue)
        line(np.zeros(3), 1.0 * zero[i], blue, lw=1.0, ls=":")
    arc = _arc(zero[2], alpha[2], 0.8)
    ax.plot(*arc.T, color=blue, lw=1.2)
    text(0.93 * arc[len(arc) // 2] / np.linalg.norm(arc[len(arc) // 2]), "$\\varphi^k$", blue, 13)
    # s^k from O^k to O^{k+1}, in body k's axes
    line(np.zeros(3), s_k, orange, lw=2.4)
    ax.scatter(*s_k, color=orange, s=20)
    text(s_k * 1.08, "$O^{k+1}$", orange)
    text(0.55 * s_k + np.array([0.0, 0.08, 0.0]), "$s^k$", orange, 12)
    ax.scatter(0, 0, 0, color="k", s=20)
    text(np.array([0.0, -0.05, -0.22]), "$O^k$", "k")
    ax.set_title("body $k$ relative to body $k-1$:  $\\alpha^{k,k-1} = R_1(\\varphi^k)\\,R_2(\\theta^k)$\n"
                 "(for $k = 1$, body 0 is the fixed frame, whose $\\hat e^0_1$ points down)", fontsize=10)
    ax.set_box_aspect((1, 1, 1))
    for setlim in (ax.set_xlim, ax.set_ylim, ax.set_zlim):
        setlim(-1.15, 1.15)
    ax.view_init(elev=20, azim=-130, roll=0)
    ax.set_axis_off()
    fig.tight_layout()
    fig.savefig(out)
    print(f"wrote {out}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "docs/img/frames.png")
