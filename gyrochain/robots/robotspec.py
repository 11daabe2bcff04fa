"""The chain in the paper's terms, both ways: a robot.Chain written as a spec (θᵏ, δᵏ and every
body's data in the frames of robot.py's docstring, with comments saying where each body came
from and what the import did), and a spec's bodies as the links of a robot description (export).

    text = robotspec.spec_text(robot.chain(desc), name="ur5")
    links = robotspec.links_of(spec, values)
"""
from __future__ import annotations

import json
import textwrap
from dataclasses import dataclass
from pathlib import Path

import mpmath as mp

from .robot import DIGITS, EXACT, GRAVITY, Chain, _cross, _dot, _norm, _row, _unit, posed
from ..chainspec.spec import IDENT


# --------------------------------------------------------------------------- the paper's frames
@dataclass(frozen=True)
class PaperBody:
    """Body k in the paper's terms: every vector in its frame at the description's zero."""

    theta: object
    offset: object
    m: object
    c: tuple
    Ic: tuple  # (xx, yy, zz, xy, xz, yz)
    s: tuple | None


def paper(ch: Chain) -> list[PaperBody]:
    """θᵏ, δᵏ and the body data in the frames of the module docstring."""
    mp.mp.dps = DIGITS
    down = mp.matrix([0, 0, -1])
    us = [b.u for b in ch.bodies]
    n = len(us)

    def perpendicular(a, b, fallback):
        w = _cross(a, b)
        return _unit(w) if _norm(w) > EXACT else fallback

    # the fixed frame: ê⁰₁ down, ê⁰₂ along ê⁰₁ × e¹ (free when e¹ is vertical: then along e¹ × e²)
    e2 = perpendicular(down, us[0], None)
    if e2 is None:
        e2 = perpendicular(us[0], us[1], None) if n > 1 else None
        e2 = e2 if e2 is not None else perpendicular(down, mp.matrix([1, 0, 0]), None)
    F = _frame(down, e2)
    out = []
    for k in range(n):
        u = us[k]
        a1, a2 = _row(F, 0), _row(F, 1)
        theta = mp.atan2(_dot(_cross(a1, u), a2), _dot(a1, u))
        G = _frame(u, a2)  # R₂(θ) F: the second axis kept
        want = perpendicular(u, us[k + 1], _row(G, 1)) if k + 1 < n else _row(G, 1)
        g2, g3 = _row(G, 1), _row(G, 2)
        delta = mp.atan2(_dot(want, g3), _dot(want, g2))
        if abs(delta) > mp.pi / 2 + EXACT:  # the perpendicular's other sense: the smaller turn (θᵏ⁺¹ < 0 then)
            want = -want
            delta = mp.atan2(_dot(want, g3), _dot(want, g2))
        F = _frame(u, want)
        b = ch.bodies[k]
        c = F * (b.com - b.O)
        Ic = F * b.Ic * F.T
        s = F * (ch.bodies[k + 1].O - b.O) if k + 1 < n else None
        out.append(PaperBody(theta, delta, b.m, tuple(c), (Ic[0, 0], Ic[1, 1], Ic[2, 2], Ic[0, 1], Ic[0, 2], Ic[1, 2]),
                             tuple(s) if s is not None else None))
    return out


def _frame(e1, e2) -> mp.matrix:
    """Rows ê₁, ê₂, ê₃ = ê₁ × ê₂ (e2 made exactly orthogonal to e1)."""
    e2 = _unit(e2 - _dot(e2, e1) * e1)
    e3 = _cross(e1, e2)
    return mp.matrix([[e1[0], e1[1], e1[2]], [e2[0], e2[1], e2[2]], [e3[0], e3[1], e3[2]]])


# --------------------------------------------------------------------------- numbers as written in a spec
def number(x) -> str:
    """The double nearest to x as TOML (a decimal that stood as written is written as it was)."""
    x = mp.mpf(x)
    return "0.0" if abs(x) < EXACT else repr(float(x))


def angle(x) -> str:
    """An angle: an exact multiple of π/2 as a string ("pi/2"), any other the nearest double."""
    x = mp.mpf(x)
    quarters = mp.nint(x / (mp.pi / 2))
    if abs(x - quarters * mp.pi / 2) < EXACT:
        q = int(quarters)
        return {0: "0.0", 1: '"pi/2"', -1: '"-pi/2"', 2: '"pi"', -2: '"-pi"'}.get(q, f'"{q}*pi/2"')
    return number(x)


def spec_name(text: str) -> str:
    """A C identifier from a robot's name ("ur5", "panda_arm"); "robot" when nothing is left."""
    out = "".join(ch if ch.isalnum() or ch == "_" else "_" for ch in text).strip("_") or "robot"
    out = out if not out[0].isdigit() else f"robot_{out}"
    return out if IDENT.fullmatch(out) else "robot"


def limits_kept(j) -> dict:
    """The joint's limits a spec holds, in tables.KEYS' order: a range where lower < upper (not for
    a continuous joint), a speed and an effort where positive (URDF writes 0 for "none")."""
    lim = {k: mp.mpf(v) for k, v in j.limit.items()}
    out = {}
    if j.kind != "continuous" and "lower" in lim and "upper" in lim and lim["lower"] < lim["upper"]:
        out.update(lower=lim["lower"], upper=lim["upper"])
    out.update({k: lim[k] for k in ("velocity", "effort") if k in lim and lim[k] > 0})
    return out


def spec_text(ch: Chain, name: str | None = None, g=GRAVITY, controls: bool = True) -> str:
    """The chain as a spec (TOML), with comments saying where every body came from and what was
    merged, locked, left out or dropped."""
    from ..printers.common import environment

    name = name or spec_name(ch.desc.name)
    bodies = []
    for k, (b, pb) in enumerate(zip(ch.bodies, paper(ch)), start=1):
        j, comments = b.joint, []
        fields = [("theta", angle(pb.theta))]
        if angle(pb.offset) != "0.0":
            fields.append(("offset", angle(pb.offset)))
        fields += [("m", number(pb.m)), ("c", _vec(pb.c)), ("I_c", _vec(pb.Ic))]
        if pb.s is not None:
            fields.append(("s", _vec(pb.s)))
        if mp.mpf(j.damping) > 0:
            fields.append(("damping", number(j.damping)))
        if mp.mpf(j.armature) != 0:
            fields.append(("armature", number(j.armature)))
        if mp.mpf(j.spring) != 0:
            fields.append(("spring", number(j.spring)))
            if mp.mpf(j.rest) != 0:
                fields.append(("rest", number(j.rest)))
        kept = limits_kept(j)
        if kept:
            fields.append(("limits", "{" + ", ".join(f"{k} = {number(v)}" for k, v in kept.items()) + "}"))
            comments.append("limits: data for an optimiser or a controller; the model does not enforce them")
        if set(kept) != set(j.limit):
            comments.append("limits as written: " + ", ".join(f"{k} {v}" for k, v in j.limit.items())
                            + " (" + ("a continuous joint has no range; " if j.kind == "continuous" else "")
                            + "an empty range, or a zero speed or effort, means none)")
        if controls:
            fields.append(("control", "true"))
        if len(b.links) > 1:
            comments.append(f"with {', '.join(b.links[1:])} (fixed or locked to {b.links[0]})")
        if mp.mpf(j.ref) != 0:
            comments.append(f"ref {j.ref}: the angle is MuJoCo's qpos (the file writes the pose at qpos = {j.ref})")
        if mp.mpf(j.friction) != 0:
            comments.append(f"dropped: <dynamics friction=\"{j.friction}\"> (Coulomb friction has no field in a spec)")
        bodies.append(dict(joint=j.name, title=f"joint {j.name} ({j.kind}), link {b.links[0]}", fields=fields,
                           comments=comments))
    notes = []
    for line in facts(ch):
        notes += textwrap.wrap(line, 96, subsequent_indent="  ", break_on_hyphens=False, break_long_words=False)
    n, source = len(bodies), Path(ch.desc.source).name
    count = f"{n} joint{'s' if n > 1 else ''}"
    angles = (f"angles phi1..phi{n} are the description's joint positions" if n > 1
              else "angle phi1 is the description's joint position")
    description = f"{ch.desc.name}: {count} from {ch.base} to {ch.tip}, imported from {source}"
    return environment().get_template("imported_spec.toml.jinja").render(
        count=count, angles=angles, name=name, source=source, robot=ch.desc.name, base=ch.base, tip=ch.tip,
        bodies=bodies, notes=notes, description=json.dumps(description, ensure_ascii=False), g=number(g))


def facts(ch: Chain) -> list[str]:
    """What the import did beyond the chain's own links: locks, repairs, the platform, what was left out."""
    out = list(ch.desc.notes)
    if ch.locked:
        out.append("locked at the values given: " + ", ".join(f"{k} = {v}" for k, v in ch.locked.items()))
    if ch.auto_locked:
        out.append(f"locked at their zero (off the chain from {ch.base} to {ch.tip}, or sliding): "
                   + ", ".join(posed(ch.desc, ch.auto_locked)))
    if ch.held:
        out.append(f"held at their zero (between the root and the base {ch.base}, so the platform): " + ", ".join(posed(ch.desc, ch.held)))
    out += list(ch.repairs)
    if ch.platform:
        out.append(f"the platform (fixed): {', '.join(ch.platform)}")
    if ch.left_out:
        out.append(f"left out (not below the base {ch.base}): {', '.join(ch.left_out)}")
    return out


def _vec(xs) -> str:
    return "[" + ", ".join(number(x) for x in xs) + "]"


# --------------------------------------------------------------------------- a spec as links (export)
# the spec's fixed frame in a description's world (z up, gravity −z): ê⁰₁ = −z, ê⁰₂ = x, ê⁰₃ = −y
FIXED_IN_WORLD = ((0, 0, -1), (1, 0, 0), (0, -1, 0))


@dataclass(frozen=True)
class Link:
    """Link k of an exported description: its joint's origin in the parent link's frame (xyz and
    the rotation R, columns the child's axes), and its body's data in its own frame (ê^k at φᵏ = 0)."""

    xyz: tuple
    R: object
    m: object
    c: tuple
    Ic: tuple  # (xx, yy, zz, xy, xz, yz) about the centre of mass
    damping: object
    spring: object
    rest: object
    control: bool
    armature: object = 0
    limits: tuple = ()  # the spec's ((key, value), ...)


def refusals(spec, to: str) -> str | None:
    """Why the spec cannot be written as ``to`` ("urdf" or "mjcf"), naming the field; None if it can."""
    import sympy as sp

    if spec.base is not None:
        return ("base: a moving platform has no element in a robot description (its motion is prescribed, not a "
                "joint's); export the chain on a fixed base")
    for k, b in enumerate(spec.bodies, start=1):
        at = f"body[{k}]"
        if any(sp.sympify(x) != 0 for x in b.lam):
            return (f"{at}.lambda: a rotor's relative angular momentum has no element in URDF or MJCF, and a body of "
                    "its own on a free joint would be one more degree of freedom, whose spin the chain's motion "
                    "changes: not the gyrostat's constant relative momentum")
        for key, what in (("torque", b.torque), ("force", b.forces), ("moment", b.moments)):
            if what:
                return f"{at}.{key}: a load has no element in a robot description"
        if b.spring is not None and to == "urdf":
            return f"{at}.spring: URDF has no joint stiffness (MJCF has: --to mjcf)"
        if b.armature != 0 and to == "urdf":
            return f"{at}.armature: URDF has no motor armature (MJCF has: --to mjcf)"
    return None


def links_of(spec, values: dict) -> list[Link]:
    """The spec's bodies as links, every number with 40 digits (parameters at ``values``)."""
    import sympy as sp

    mp.mp.dps = DIGITS
    subs = {p: sp.Float(values[str(p)], 17) for p in spec.params if str(p) in values}

    def num(x):
        return mp.mpf(str(sp.N(sp.sympify(x).subs(subs), DIGITS)))

    prev_s = mp.matrix([0, 0, 0])
    out = []
    for k, b in enumerate(spec.bodies, start=1):
        th, de = num(b.theta), num(b.offset)
        ct, st, cd, sd = mp.cos(th), mp.sin(th), mp.cos(de), mp.sin(de)
        alpha = (mp.matrix([[1, 0, 0], [0, cd, sd], [0, -sd, cd]])  # R₁(δ) R₂(θ): rows ê^k in frame k−1
                 * mp.matrix([[ct, 0, -st], [0, 1, 0], [st, 0, ct]]))
        R = alpha.T if k > 1 else mp.matrix(FIXED_IN_WORLD).T * alpha.T
        m = num(b.m)
        c = mp.matrix([num(x) for x in b.c])
        A = mp.matrix([[num(x) for x in row] for row in b.A])
        Ic = A - m * (_dot(c, c) * mp.eye(3) - c * c.T)
        out.append(Link(tuple(prev_s), R, m, tuple(c), (Ic[0, 0], Ic[1, 1], Ic[2, 2], Ic[0, 1], Ic[0, 2], Ic[1, 2]),
                        num(b.damping) if b.damping is not None else 0, num(b.spring) if b.spring is not None else 0,
                        num(b.rest), b.control, num(b.armature), b.limits))
        prev_s = mp.matrix([num(x) for x in b.s])
    return out


def rpy_of(R) -> tuple:
    """URDF's roll, pitch, yaw of a rotation (R = Rz(y) Ry(p) Rx(r)); at p = ±π/2, r = 0."""
    p = mp.atan2(-R[2, 0], mp.sqrt(R[0, 0] ** 2 + R[1, 0] ** 2))
    if mp.sqrt(R[0, 0] ** 2 + R[1, 0] ** 2) < EXACT:
        return (mp.mpf(0), p, mp.atan2(-R[0, 1], R[1, 1]))
    return (mp.atan2(R[2, 1], R[2, 2]), p, mp.atan2(R[1, 0], R[0, 0]))


def quat_of(R) -> tuple:
    """The unit quaternion (w, x, y, z) of a rotation, w ≥ 0 (MJCF's quat)."""
    t = R[0, 0] + R[1, 1] + R[2, 2]
    if t > 0:
        w = mp.sqrt(1 + t) / 2
        q = (w, (R[2, 1] - R[1, 2]) / (4 * w), (R[0, 2] - R[2, 0]) / (4 * w), (R[1, 0] - R[0, 1]) / (4 * w))
    else:
        i = max(range(3), key=lambda j: R[j, j])
        j, k = (i + 1) % 3, (i + 2) % 3
        r = mp.sqrt(1 + R[i, i] - R[j, j] - R[k, k])
        v = [0, 0, 0]
        v[i], v[j], v[k] = r / 2, (R[j, i] + R[i, j]) / (2 * r), (R[k, i] + R[i, k]) / (2 * r)
        q = ((R[k, j] - R[j, k]) / (2 * r), *v)
    return tuple(-x for x in q) if q[0] < 0 else q


def numbers(xs) -> str:
    """Space-separated, as XML attributes want them."""
    return " ".join("0" if abs(mp.mpf(x)) < EXACT else repr(float(x)) for x in xs)
