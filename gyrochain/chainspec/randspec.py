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
    offsets: bool = False,
) -> str:
    """A chain of n gyrostats with random masses, offsets, full inertia tensors about O^k
    (a random positive definite central tensor that meets the triangle inequality, moved by
    the parallel-axis rule) and, if ``gyro``, random gyrostatic moments.  ``planar`` puts every
    axis parallel to the first (θᵏ = 0 for k > 1) and every c, s in the plane ⟂ e¹.  ``offsets``
    gives every joint a random zero (the field ``offset``), as imported robots have."""
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
        if offsets:
            lines.append(f"offset = {_fmt(rng.uniform(-3.0, 3.0))}")
        lines.append("")
    return "\n".join(lines)


def random_general_spec_text(
    rng: np.random.Generator,
    n: int,
    name: str = "gchain",
    translate: bool = True,
    rotate: bool = True,
    loads: bool = True,
    springs: bool = True,
    spin_up: bool = True,
) -> str:
    """A random chain (as ``random_spec_text``) with the general case's fields: a platform that
    translates and/or turns about one to three random axes, follower and fixed-direction forces,
    moments, joint springs and dampers, a torque expression, and rotors spinning up (λ(t))."""
    text = random_spec_text(rng, n, name=name)
    blocks = text.split("[[body]]")
    head = blocks[0]
    if translate or rotate:
        head += "[base]\n"
        if translate:
            amp, om = rng.uniform(0.05, 0.3, 3), rng.uniform(0.5, 3.0, 3)
            head += "position = [" + ", ".join(f'"{amp[i]:.3f}*sin({om[i]:.3f}*t + {i})"' for i in range(3)) + "]\n"
        if rotate:
            rots = []
            for _ in range(int(rng.integers(1, 4))):
                axis = rng.normal(size=3)
                rots.append("{axis = [" + ", ".join(f"{a:.3f}" for a in axis) + "], angle = "
                            + f'"{rng.uniform(0.1, 0.5):.3f}*sin({rng.uniform(0.5, 2):.3f}*t) + {rng.uniform(-0.5, 0.5):.3f}*t"' + "}")
            head += "rotation = [" + ", ".join(rots) + "]\n"
        head += "\n"
    out = [head]
    for k, body in enumerate(blocks[1:], start=1):
        extra = []
        if spin_up and k % 2 == 1:
            lam = rng.uniform(-0.3, 0.3, 3)
            rate = rng.uniform(-0.2, 0.2, 3)
            body = "\n".join(ln for ln in body.splitlines() if not ln.startswith("lambda"))
            extra.append("lambda = [" + ", ".join(f'"{lam[i]:.3f} + {rate[i]:.3f}*t"' for i in range(3)) + "]")
        if springs:
            extra.append(f"spring = {rng.uniform(0.2, 2.0):.3f}")
            extra.append(f"rest = {rng.uniform(-0.5, 0.5):.3f}")
            extra.append(f"damping = {rng.uniform(0.0, 0.1):.3f}")
            if k == n:
                extra.append(f'torque = "{rng.uniform(-0.3, 0.3):.3f}*sin(2*t) - 0.05*phidot{k}*cos(phi1)"')
        tables = []
        if loads:
            pt = rng.uniform(-0.3, 0.3, 3)
            F = rng.uniform(-1, 1, 3)
            tables.append("[[body.force]]\npoint = [" + ", ".join(f"{v:.3f}" for v in pt) + "]\n"
                          + "F = [" + ", ".join(f'"{v:.3f}"' for v in F) + "]\n"
                          + f'frame = "{"body" if k % 2 else "fixed"}"')
            if k == 1:
                tables.append('[[body.moment]]\nM = ["0.1*sin(t)", "0.05", "-0.02*phidot1"]\nframe = "fixed"')
        out.append("[[body]]" + body.rstrip("\n") + "\n" + "\n".join(extra) + "\n\n" + "\n\n".join(tables) + "\n\n")
    return "".join(out)
