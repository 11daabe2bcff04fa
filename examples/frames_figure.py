"""The picture of the frames and angles in docs/spec.md: body k−1's frame, the axis l^k at θ^k from
l^{k−1} about their common perpendicular ê^{k−1}_2, body k's frame turned by φ^k about e^k, and the
vector s^k from O^k to O^{k+1}.  The frames are computed with the convention the generator uses,
α^{k,k−1} = R₁(φ^k) R₂(θ^k) (rows: ê^k_i in frame k−1), not drawn by hand; the three-dimensional
points are projected orthographically onto the page, and each vector is an arrow with its label
beyond its head.

    python examples/frames_figure.py docs/img/frames.png        (run by `make plot`)
"""
from __future__ import annotations

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.patches import FancyArrowPatch  # noqa: E402


def R1(phi: float) -> np.ndarray:
    c, s = np.cos(phi), np.sin(phi)
    return np.array([[1, 0, 0], [0, c, s], [0, -s, c]])


def R2(theta: float) -> np.ndarray:
    c, s = np.cos(theta), np.sin(theta)
    return np.array([[c, 0, -s], [0, 1, 0], [s, 0, c]])


def view(azimuth: float, elevation: float) -> np.ndarray:
    """The orthographic projection onto the page: rows are the page's right and up, in frame k−1."""
    a, e = np.radians(azimuth), np.radians(elevation)
    right = np.array([-np.sin(a), np.cos(a), 0.0])
    up = np.array([-np.cos(a) * np.sin(e), -np.sin(a) * np.sin(e), np.cos(e)])
    return np.array([right, up])


def arc(a: np.ndarray, b: np.ndarray, r: float, n: int = 48) -> np.ndarray:
    """Points at radius r on the arc from the direction a to the direction b."""
    w = b - (b @ a) * a
    w /= np.linalg.norm(w)
    ang = np.arccos(np.clip(a @ b, -1.0, 1.0))
    return np.array([r * (np.cos(x) * a + np.sin(x) * w) for x in np.linspace(0.0, ang, n)])


def main(out: str, azimuth: float = -140.0, elevation: float = 25.0, phi_deg: float = 70.0) -> None:
    theta, phi = np.radians(50.0), np.radians(phi_deg)
    alpha = R1(phi) @ R2(theta)  # rows: ê^k_i in frame k−1
    zero = R2(theta)  # body k's frame at φ^k = 0
    s_k = alpha.T @ np.array([0.25, -0.55, 0.75])  # O^k O^{k+1} = s^k, given in body k's axes
    E = np.eye(3)
    P = view(azimuth=azimuth, elevation=elevation)
    grey, blue, orange = "#555555", "#0072B2", "#D55E00"

    fig, ax = plt.subplots(figsize=(6.4, 4.6), dpi=130)
    ax.set_aspect("equal")
    ax.set_axis_off()

    def p2(v):
        return P @ np.asarray(v, dtype=float)

    def arrow(tip, col, lw=1.8, start=(0, 0, 0), ls="-"):
        ax.add_patch(FancyArrowPatch(p2(start), p2(tip), arrowstyle="-|>", mutation_scale=14, color=col, lw=lw,
                                     linestyle=ls, shrinkA=0, shrinkB=0))

    def label(tip, text, col, size=13, gap=0.13, nudge=(0.0, 0.0)):
        d = p2(tip)
        d = d / (np.linalg.norm(d) or 1.0)
        x, y = p2(tip) + gap * d + np.asarray(nudge)
        ax.text(x, y, text, color=col, fontsize=size, ha="center", va="center")

    # the axis l^{k-1} of joint k−1 along ê^{k−1}_1, and frame k−1's other two vectors
    a0, a1 = p2(-1.3 * E[0]), p2(1.45 * E[0])
    ax.plot(*zip(a0, a1), color=grey, lw=6, alpha=0.18, solid_capstyle="round")
    arrow(1.45 * E[0], grey)
    label(1.45 * E[0], "$l^{k-1}$ along $\\hat e^{k-1}_1$", grey, gap=0.34)
    arrow(E[1], grey)
    label(E[1], "$\\hat e^{k-1}_2$", grey)
    arrow(E[2], grey)
    label(E[2], "$\\hat e^{k-1}_3$", grey)
    # the axis l^k of joint k along e^k = ê^k_1, at θ^k from l^{k−1} about ê^{k−1}_2
    b0, b1 = p2(-1.3 * alpha[0]), p2(1.45 * alpha[0])
    ax.plot(*zip(b0, b1), color=blue, lw=6, alpha=0.18, solid_capstyle="round")
    arrow(1.45 * alpha[0], blue)
    label(1.45 * alpha[0], "$l^k$ along $e^k = \\hat e^k_1$", blue, gap=0.32)
    th = np.array([p2(q) for q in arc(E[0], alpha[0], 0.62)])
    ax.plot(*th.T, color="k", lw=1.3)
    label(arc(E[0], alpha[0], 0.62)[len(th) // 2], "$\\theta^k$", "k", gap=0.13)
    # ê^k_2, ê^k_3: turned by φ^k about e^k from where θ^k alone puts them (dotted)
    for i, text in ((1, "$\\hat e^k_2$"), (2, "$\\hat e^k_3$")):
        ax.plot(*zip(p2(np.zeros(3)), p2(zero[i])), color=blue, lw=1.1, ls=(0, (2, 2)))
        arrow(alpha[i], blue)
        label(alpha[i], text, blue)
    ph3 = arc(zero[2], alpha[2], 0.8)
    ph = np.array([p2(q) for q in ph3])
    ax.plot(*ph.T, color=blue, lw=1.3)
    label(ph3[len(ph3) // 2], "$\\varphi^k$", blue, gap=0.13)
    # s^k from O^k to O^{k+1}
    arrow(s_k, orange, lw=2.4)
    ax.plot(*p2(s_k), "o", color=orange, ms=5)
    label(s_k, "$O^{k+1}$", orange, gap=0.2)
    d = p2(s_k) / np.linalg.norm(p2(s_k))
    mid = p2(0.55 * s_k) + 0.13 * np.array([-d[1], d[0]]) * (1 if d[0] < 0 else -1)  # beside it, away from l^k
    ax.text(*mid, "$s^k$", color=orange, fontsize=13, ha="center", va="center")
    ax.plot(0, 0, "o", color="k", ms=5)
    ax.text(-0.1, -0.16, "$O^k$", fontsize=13, ha="center", va="center")
    ax.autoscale_view()
    fig.savefig(out, bbox_inches="tight", pad_inches=0.08)
    print(f"wrote {out}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "docs/img/frames.png")
