"""Random physically valid specs (TOML text), for tests and benchmarks."""
from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

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


# --------------------------------------------------------------------------- the geometry users write
# The exact values users write, which a derivation that takes a shortcut on an exact value gets
# wrong: structural angles 0, ±π/2, ±π (anti-parallel consecutive axes: what ``import`` writes for
# a flipped axis), ±π/4, 3π/4 and numbers of either sign; exact zeros in c and s; inertia tensors
# full, diagonal, symmetric about the joint axis, of a point mass, of a slender rod, and massless
# frames; rotors along the joint axis, anywhere or spinning up; joint offsets (0, a number, π);
# springs, dampers, motor armature, torque expressions of t and the state, controls; gravity or none; a fixed or
# moving platform (its motion written with π) and loads on the bodies.
THETAS = ("0", "pi/2", "-pi/2", "pi", "-pi", "pi/4", "-pi/4", "3*pi/4", "number")
INERTIAS = ("full", "diagonal", "axial", "point", "rod", "massless")
ROTORS = ("none", "axis", "full", "spin")
OFFSETS = ("none", "number", "pi")
BASES = ("fixed", "translate", "rotate", "both")


@dataclass(frozen=True)
class BodyPlan:
    """The choices for one body of ``geometry_spec_text`` (the numbers are drawn from its seed)."""

    theta: str = "number"  # one of THETAS
    inertia: str = "full"  # one of INERTIAS ("massless" is a point mass on the last body)
    zero_c: tuple = (False, False, False)  # exact zeros in c
    zero_s: tuple = (False, False, False)  # exact zeros in s
    rotor: str = "none"  # one of ROTORS
    offset: str = "none"  # one of OFFSETS
    spring: bool = False
    damping: bool = False
    control: bool = False
    torque: bool = False  # a torque expression of t and the state (with π in it)
    armature: bool = False  # a motor's reflected inertia on the joint


@dataclass(frozen=True)
class ChainPlan:
    bodies: tuple  # BodyPlan per body
    seed: int = 0
    base: str = "fixed"  # one of BASES
    loads: bool = False  # forces and moments on the bodies
    gravity: bool = True

    @property
    def general(self) -> bool:
        return self.base != "fixed" or self.loads


def _decimal(x: Fraction) -> str:
    """An exact decimal text of a fraction whose denominator divides a power of ten."""
    sign, x = ("-" if x < 0 else ""), abs(x)
    whole, rest = divmod(x.numerator, x.denominator)
    digits = ""
    while rest:
        rest *= 10
        d, rest = divmod(rest, x.denominator)
        digits += str(d)
        if len(digits) > 40:
            raise ValueError(f"{x} has no short decimal")
    return sign + str(whole) + ("." + digits if digits else "")


def _short(rng: np.random.Generator, lo: float, hi: float, places: int = 2) -> Fraction:
    return Fraction(int(round(rng.uniform(lo, hi) * 10 ** places)), 10 ** places)


def random_plan(rng: np.random.Generator, n: int, general: bool = False) -> ChainPlan:
    """A ChainPlan with every choice drawn (``general``: a moving platform or loads may be drawn)."""
    bodies = []
    for _ in range(n):
        bodies.append(BodyPlan(theta=str(rng.choice(THETAS)), inertia=str(rng.choice(INERTIAS)),
                               zero_c=tuple(bool(b) for b in rng.random(3) < 0.3),
                               zero_s=tuple(bool(b) for b in rng.random(3) < 0.3),
                               rotor=str(rng.choice(ROTORS)), offset=str(rng.choice(OFFSETS)),
                               spring=bool(rng.random() < 0.3), damping=bool(rng.random() < 0.3),
                               control=bool(rng.random() < 0.4), torque=bool(rng.random() < 0.2),
                               armature=bool(rng.random() < 0.25)))
    base = str(rng.choice(BASES)) if general else "fixed"
    return ChainPlan(tuple(bodies), int(rng.integers(2**31)), base, bool(general and rng.random() < 0.5),
                     bool(rng.random() < 0.85))


def random_geometry_spec_text(rng: np.random.Generator, n: int, name: str = "geom", general: bool = False) -> str:
    """A random chain of the geometry users write (``random_plan``, then ``geometry_spec_text``)."""
    return geometry_spec_text(random_plan(rng, n, general), name)


def geometry_spec_text(plan: ChainPlan, name: str = "geom") -> str:
    """The spec text of ``plan``: numbers drawn from its seed, written with few decimals so that
    an exact zero, a point mass's tensor m(|c|²1 − c cᵀ) and a diagonal tensor are exact in the
    spec too (the parallel-axis term computed in fractions)."""
    rng = np.random.default_rng(plan.seed)
    n = len(plan.bodies)
    lines = [f'name = "{name}"', f'description = "random chain of the geometry users write, n = {n}"',
             f"g = {9.81 if plan.gravity else 0}", ""]
    if plan.base != "fixed":
        lines += _base_lines(rng, plan.base in ("translate", "both"), plan.base in ("rotate", "both"))
    for k, b in enumerate(plan.bodies, start=1):
        kind = "point" if b.inertia == "massless" and k == n else b.inertia
        m = Fraction(0) if kind == "massless" else _short(rng, 0.2, 2.0)
        c = [Fraction(0) if z or kind == "massless" else _short(rng, -0.3, 0.3) for z in b.zero_c]
        s = [Fraction(0) if z else _short(rng, -0.4, 0.4) for z in b.zero_s]
        if kind in ("point", "rod") and k == n and c[1] == 0 and c[2] == 0:
            c[1] = _short(rng, 0.05, 0.3)  # the last body's mass off its axis: else M is singular
        A = _inertia(rng, kind, m, c)
        theta = (repr(float(rng.uniform(-np.pi, np.pi))) if b.theta == "number" else
                 "0" if b.theta == "0" else f'"{b.theta}"')
        lines += ["[[body]]", f"theta = {theta}", f"m = {_decimal(m)}", "c = [" + ", ".join(map(_decimal, c)) + "]",
                  "A = [" + ", ".join("[" + ", ".join(row) + "]" for row in A) + "]"]
        if k < n:
            lines.append("s = [" + ", ".join(map(_decimal, s)) + "]")
        if b.rotor == "axis":
            lines.append(f"lambda = [{_decimal(_short(rng, -0.5, 0.5))}, 0, 0]")
        elif b.rotor == "full":
            lines.append("lambda = [" + ", ".join(_decimal(_short(rng, -0.5, 0.5)) for _ in range(3)) + "]")
        elif b.rotor == "spin":  # λ(t): a rotor's motor spinning it up
            lines.append("lambda = [" + ", ".join(f'"{_decimal(_short(rng, -0.3, 0.3))} + {_decimal(_short(rng, -0.2, 0.2))}*t"'
                                                  for _ in range(3)) + "]")
        if b.offset == "number":
            lines.append(f"offset = {_decimal(_short(rng, -3.0, 3.0, 3))}")
        elif b.offset == "pi":
            lines.append('offset = "pi"')
        if b.spring:
            lines += [f"spring = {_decimal(_short(rng, 0.2, 2.0))}", f"rest = {_decimal(_short(rng, -0.5, 0.5))}"]
        if b.damping:
            lines.append(f"damping = {_decimal(_short(rng, 0.01, 0.2))}")
        if b.armature:
            lines.append(f"armature = {_decimal(_short(rng, 0.001, 0.5, 3))}")
        if b.control:
            lines.append("control = true")
        if b.torque:
            lines.append(f'torque = "{_decimal(_short(rng, -0.3, 0.3))}*sin(pi*t) - 0.05*phidot{k}*cos(phi{k} + pi/6)"')
        lines.append("")
        if plan.loads:
            lines += _load_lines(rng, k)
    return "\n".join(lines)


def _inertia(rng: np.random.Generator, kind: str, m: Fraction, c: list) -> list:
    """The rows of A about Oᵏ as texts: a central tensor of ``kind`` plus m(|c|²1 − c cᵀ), exact
    where the central tensor has short decimals (all kinds but "full")."""
    if kind == "massless":
        return [["0"] * 3 for _ in range(3)]
    if kind == "full":  # principal moments meeting the triangle inequality, random axes
        pm = np.sort(rng.uniform(0.002, 0.02, 3))
        pm[2] = min(pm[2], 0.9 * (pm[0] + pm[1]))
        Q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        G = Q @ np.diag(pm) @ Q.T
        AG = [[Fraction(int(round(float(G[max(i, j), min(i, j)]) * 10**9)), 10**9) for j in range(3)] for i in range(3)]
    else:
        if kind == "point":
            d = [Fraction(0)] * 3
        elif kind == "rod":  # a slender rod along a body axis: no moment about it
            d = [_short(rng, 0.002, 0.02, 4)] * 3
            d[int(rng.integers(3))] = Fraction(0)
        elif kind == "axial":  # symmetric about the joint axis
            a, t = _short(rng, 0.002, 0.02, 4), _short(rng, 0.002, 0.02, 4)
            d = [min(a, 2 * t), t, t]
        else:  # diagonal: principal axes along the body's
            d = sorted(_short(rng, 0.002, 0.02, 4) for _ in range(3))
            d[2] = min(d[2], d[0] + d[1])
        AG = [[d[i] if i == j else Fraction(0) for j in range(3)] for i in range(3)]
    cc = sum(x * x for x in c)
    A = [[AG[i][j] + m * ((cc if i == j else 0) - c[i] * c[j]) for j in range(3)] for i in range(3)]
    return [[_decimal(v) for v in row] for row in A]


def _base_lines(rng: np.random.Generator, translate: bool, rotate: bool) -> list:
    out = ["[base]"]
    if translate:
        amp, om = rng.uniform(0.05, 0.3, 3), rng.uniform(0.5, 3.0, 3)
        out.append("position = [" + ", ".join(f'"{amp[i]:.3f}*sin({om[i]:.3f}*pi*t + {i})"' for i in range(3)) + "]")
    if rotate:
        rots = []
        for _ in range(int(rng.integers(1, 4))):
            axis = rng.normal(size=3)
            rots.append("{axis = [" + ", ".join(f"{a:.3f}" for a in axis) + "], angle = "
                        + f'"{rng.uniform(0.1, 0.5):.3f}*sin({rng.uniform(0.5, 2):.3f}*t) + {rng.uniform(-0.5, 0.5):.3f}*t"' + "}")
        out.append("rotation = [" + ", ".join(rots) + "]")
    return out + [""]


def _load_lines(rng: np.random.Generator, k: int) -> list:
    pt, F = rng.uniform(-0.3, 0.3, 3), rng.uniform(-1, 1, 3)
    out = ["[[body.force]]", "point = [" + ", ".join(f"{v:.3f}" for v in pt) + "]",
           "F = [" + ", ".join(f'"{v:.3f}"' for v in F) + "]", f'frame = "{"body" if k % 2 else "fixed"}"', ""]
    if k == 1:
        out += ["[[body.moment]]", 'M = ["0.1*sin(t)", "0.05", "-0.02*phidot1"]', 'frame = "fixed"', ""]
    return out
