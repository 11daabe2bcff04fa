"""Random physically valid specs (TOML text), for tests and benchmarks."""
from __future__ import annotations

import numpy as np


def _fmt(x: float) -> str:
    return repr(float(x))


def random_spec_text(
    rng: np.random.Generator,
    n: int,
    name: str = "chain",
    planar: bool = False,
    gyro: bool = True,
    controls: tuple = (),
    theta1: float | None = None,
) -> str:
    """A chain of n gyrostats with random masses, offsets, full inertia tensors about O^k
    (a random positive definite central tensor that meets the triangle inequality, moved by
    the parallel-axis rule) and, if ``gyro``, random gyrostatic moments.  ``planar`` puts every
    axis parallel to the first (θᵏ = 0 for k > 1) and every c, s in the plane ⟂ e¹."""
    lines = [f'name = "{name}"', f'description = "random {"planar" if planar else "spatial"} chain, n = {n}"', "g = 9.81", ""]
    for k in range(1, n + 1):
        if k == 1:
            theta = rng.uniform(0.3, 2.8) if theta1 is None else theta1
        else:
            theta = 0.0 if planar else rng.uniform(0.3, 2.8)
        m = rng.uniform(0.3, 2.0)
        c = rng.uniform(-0.3, 0.3, 3)
        s = rng.uniform(-0.5, 0.5, 3)
        if planar:
            c[0] = s[0] = 0.0
        # central inertia: principal moments meeting the triangle inequality, random axes
        pm = np.sort(rng.uniform(0.02, 0.1, 3))
        pm[2] = min(pm[2], 0.9 * (pm[0] + pm[1]))
        Q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        AG = Q @ np.diag(pm) @ Q.T
        A = AG + m * (c @ c * np.eye(3) - np.outer(c, c))
        A = 0.5 * (A + A.T)
        lam = rng.uniform(-0.5, 0.5, 3) if gyro else np.zeros(3)
        if planar and gyro:
            lam[1:] = 0.0  # a rotor along the joint axis keeps the motion planar
        lines += [
            "[[body]]",
            f"theta = {_fmt(theta)}",
            f"m = {_fmt(m)}",
            "c = [" + ", ".join(_fmt(v) for v in c) + "]",
            "A = [" + ", ".join("[" + ", ".join(_fmt(v) for v in row) + "]" for row in A) + "]",
        ]
        if k < n:
            lines.append("s = [" + ", ".join(_fmt(v) for v in s) + "]")
        lines.append("lambda = [" + ", ".join(_fmt(v) for v in lam) + "]")
        if k in controls:
            lines.append("control = true")
        lines.append("")
    return "\n".join(lines)
