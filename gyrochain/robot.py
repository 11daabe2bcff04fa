"""A robot description as a tree of links and joints (read from URDF by urdf.py), cut down to the
chain the paper's pendulum is, and written as a spec.

    desc = urdf.read(path)                                   # Description: links, joints, numbers as written
    ch = robot.chain(desc, base=None, tip=None, locks={})    # Chain: the revolute joints from base to tip
    text = robot.spec_text(ch, name="ur5", source="ur5.urdf")

The geometry is computed with 40 digits (mpmath) from the decimals as written, at the description's
zero (every joint at 0, a locked one at its value), in the description's world (z up, gravity −z):

- Links joined by ``fixed`` or locked joints are one body: masses add, centres average, inertias
  add about the common centre (the parallel-axis theorem).  The base link's body is the platform.
- Body k's frame has ê^k_1 along joint k's axis, as the paper wants; ê^{k−1}_2 is the common
  perpendicular of axes k−1 and k (for k = 1: of the downward vertical and axis 1), in the sense
  that makes |δᵏ| ≤ π/2.  θᵏ is the angle between the axes, and the offset δᵏ turns body k about its axis from the frame θᵏ alone gives to
  the frame its next axis needs, so that the spec's φᵏ is the description's joint position: same
  zero, same sign.  Where two axes are parallel (or axis 1 vertical) the perpendicular is free, and
  δ = 0 is taken.
- An angle that is a multiple of π/2 rounded to the nine or more decimals it is written with
  (1.57079632679, 1.5707963267948966) is that multiple; one written with fewer (1.5708) is taken
  as written.  Either way the model differs from one built on the decimal by less than 5e-10.
- Numbers are written as the double nearest to the 40-digit value (a decimal that stands as written
  is written as it was); a value within 1e-30 of 0 is 0 and an angle within 1e-30 of a multiple of
  π/2 is written exactly ("pi/2"), so that the generated code folds it.
"""
from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

import mpmath as mp

from .errors import SpecError, did_you_mean
from .spec import IDENT

DIGITS = 40
EXACT = mp.mpf("1e-30")  # below this a computed number is an exact 0 or multiple of pi/2
QUARTER_DIGITS = 9  # an angle that is k·π/2 rounded to this many decimals or more is k·π/2
CHAIN_KINDS = ("revolute", "continuous")
LOCKABLE = ("revolute", "continuous", "prismatic")
KINDS = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar")
GRAVITY = 9.81  # the description's world has none; Pinocchio's and MuJoCo's default


@dataclass(frozen=True)
class Inertial:
    m: object  # mpf
    xyz: tuple  # the centre of mass in the link frame
    rpy: tuple  # the inertia's axes in the link frame
    I: tuple  # (ixx, iyy, izz, ixy, ixz, iyz) about the centre of mass, in those axes


@dataclass(frozen=True)
class Joint:
    name: str
    kind: str
    parent: str
    child: str
    xyz: tuple = (0, 0, 0)
    rpy: tuple = (0, 0, 0)
    axis: tuple = (1, 0, 0)
    damping: object = 0
    friction: object = 0
    limit: dict = field(default_factory=dict)  # lower, upper, effort, velocity as written
    mimic: str | None = None


@dataclass(frozen=True)
class Description:
    name: str
    source: str  # what it was read from, for messages
    links: dict  # name -> Inertial | None
    joints: dict  # name -> Joint, in the file's order


@dataclass(frozen=True)
class Body:
    """Body k of the chain: its joint and its links (the first is the joint's child)."""

    joint: Joint
    links: tuple
    m: object
    com: object  # world, at the zero
    Ic: object  # 3×3 about com, world axes
    O: object  # joint k's origin, world
    u: object  # joint k's unit axis, world


@dataclass(frozen=True)
class Chain:
    desc: Description
    base: str
    tip: str
    bodies: tuple
    locked: dict  # joint name -> value
    merged: tuple  # links joined to a body by fixed or locked joints
    platform: tuple  # the links of the base's body
    left_out: tuple  # links not on the chain (above the base)


def fail(desc: Description, what: str, message: str):
    raise SpecError(f"{desc.source}: {what}" if what else desc.source, message)


# --------------------------------------------------------------------------- 3-vectors, 3×3 in mpmath
def _v(xs) -> mp.matrix:
    return mp.matrix([mp.mpf(x) for x in xs])


def _quarter(a):
    """An angle as written, but a multiple of π/2 rounded to the nine or more decimals it is written
    with (1.57079632679, 3.141592653589793) is that multiple: its cosine is then 0, not 5e-12, and
    the generated code has no terms of that size.  One written with fewer (1.5708) is taken as written."""
    x = mp.mpf(a)
    k = mp.nint(x / (mp.pi / 2))
    text = str(a).lower()
    mantissa, _, exponent = text.partition("e")
    decimals = len(mantissa.partition(".")[2]) - int(exponent or 0)
    if decimals < QUARTER_DIGITS:
        return x
    return k * mp.pi / 2 if abs(x - k * mp.pi / 2) <= mp.mpf(10) ** -decimals / 2 else x


def _rpy(r, p, y) -> mp.matrix:
    """URDF's fixed-axis roll, pitch, yaw: R = Rz(y) Ry(p) Rx(r)."""
    cr, sr, cp, sp_, cy, sy = (f(_quarter(a)) for a in (r, p, y) for f in (mp.cos, mp.sin))
    return mp.matrix([[cy * cp, cy * sp_ * sr - sy * cr, cy * sp_ * cr + sy * sr],
                      [sy * cp, sy * sp_ * sr + cy * cr, sy * sp_ * cr - cy * sr],
                      [-sp_, cp * sr, cp * cr]])


def _about(axis: mp.matrix, q) -> mp.matrix:
    """The turn by q about a unit axis (Rodrigues)."""
    x, y, z = axis
    c, s = mp.cos(q), mp.sin(q)
    C = 1 - c
    return mp.matrix([[c + x * x * C, x * y * C - z * s, x * z * C + y * s],
                      [y * x * C + z * s, c + y * y * C, y * z * C - x * s],
                      [z * x * C - y * s, z * y * C + x * s, c + z * z * C]])


def _cross(a, b) -> mp.matrix:
    return mp.matrix([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _norm(a):
    return mp.sqrt(_dot(a, a))


def _unit(a) -> mp.matrix:
    return a / _norm(a)


def _row(M, i) -> mp.matrix:
    return mp.matrix([M[i, 0], M[i, 1], M[i, 2]])


def _sym6(I) -> mp.matrix:
    xx, yy, zz, xy, xz, yz = (mp.mpf(v) for v in I)
    return mp.matrix([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])


# --------------------------------------------------------------------------- the tree and the chain
def chain(desc: Description, base: str | None = None, tip: str | None = None, locks: dict | None = None) -> Chain:
    """The revolute chain from ``base`` (default: the root) to ``tip`` (needed where the movable
    joints branch), with the ``locks`` {joint: value} fixed.  Everything the paper's chain cannot
    express is one line naming the joint or the links."""
    mp.mp.dps = DIGITS
    locks = dict(locks or {})
    children, root = _tree(desc, locks)
    base = base or root
    for what, link in (("--base", base), ("--tip", tip)):
        if link is not None and link not in desc.links:
            fail(desc, f"{what} {link}", f"no such link; {did_you_mean(link, desc.links)}"
                 f"the links are {', '.join(desc.links)}")
    walk = _Walk(desc, children, locks, base)
    platform, out = walk.cluster(base)
    path, bodies_links = [], []
    while out:
        if len(out) > 1:  # the movable joints branch: one branch is the chain, the others must be locked
            if tip is None:
                fail(desc, "--tip", f"the movable joints branch at {', '.join(j.name for j in out)}: give --tip, "
                     f"one of {', '.join(_ends(children, [j.child for j in out]))}")
            on = [j for j in out if _below(children, j.child, tip)]
            others = [j.name for j in out if not on or j is not on[0]]
            fail(desc, f"joint {others[0]!r}", f"is not on the chain from {base} to {tip}: lock it "
                 f"({' '.join(f'--lock {o}=VALUE' for o in others[:3])}{' …' if len(others) > 3 else ''})")
        j = out[0]
        walk.place(j, 0)
        links, out = walk.cluster(j.child)
        path.append(j)
        bodies_links.append(links)
        if tip is not None and tip in links:
            if out:
                fail(desc, f"joint {out[0].name!r}", f"is past the tip {tip}: lock it with --lock {out[0].name}=VALUE")
            break
    if not path:
        fail(desc, "", f"no revolute or continuous joint below {base}: nothing moves")
    if tip is not None and tip not in bodies_links[-1]:
        fail(desc, f"--tip {tip}", f"is not moved by a joint below {base}")
    bodies = tuple(_body(desc, j, links, walk.pose) for j, links in zip(path, bodies_links))
    above = tuple(name for name in desc.links if name not in walk.pose)
    merged = tuple(x for links in bodies_links for x in links[1:])
    return Chain(desc, base, tip or bodies_links[-1][0], bodies, dict(locks), merged, tuple(platform), above)


def _tree(desc: Description, locks: dict) -> tuple[dict, str]:
    """{link: its child joints} and the root; a joint naming a missing link, a second parent (a
    closed loop), a lock of no joint or of a joint that cannot be locked are one line each."""
    parent_of: dict = {}
    children: dict = {name: [] for name in desc.links}
    for j in desc.joints.values():
        for end in (j.parent, j.child):
            if end not in desc.links:
                fail(desc, f"joint {j.name!r}", f"names the link {end!r}, which the description does not have")
        if j.child in parent_of:
            fail(desc, f"joint {j.name!r}", f"closes a loop: link {j.child!r} is already the child of joint "
                 f"{parent_of[j.child].name!r} (the paper's chain is a tree of one path)")
        parent_of[j.child] = j
        children[j.parent].append(j)
    for name in locks:
        if name not in desc.joints:
            fail(desc, f"--lock {name}", f"no such joint; {did_you_mean(name, desc.joints)}"
                 f"the joints are {', '.join(desc.joints)}")
        if desc.joints[name].kind not in LOCKABLE:
            fail(desc, f"--lock {name}", f"a {desc.joints[name].kind} joint cannot be locked at one value")
    roots = [name for name in desc.links if name not in parent_of]
    if len(roots) != 1:
        fail(desc, "", f"{len(roots)} links have no parent ({', '.join(roots[:5])}): a description is one tree")
    return children, roots[0]


class _Walk:
    """The links' world poses at the zero, placed joint by joint from the base outwards."""

    def __init__(self, desc: Description, children: dict, locks: dict, base: str):
        self.desc, self.children, self.locks = desc, children, locks
        self.pose = {base: (mp.eye(3), mp.matrix([0, 0, 0]))}  # world rotation (columns: link axes), origin

    def moves(self, j: Joint) -> bool:
        """A joint of the chain (True), rigid (False), or one line saying why it can be neither."""
        if j.name in self.locks or j.kind == "fixed":
            return False
        if j.mimic is not None:
            fail(self.desc, f"joint {j.name!r}", f"mimics {j.mimic!r}: the paper's joints are independent "
                 f"(lock it with --lock {j.name}=VALUE)")
        if j.kind not in CHAIN_KINDS:
            hint = f" (lock it with --lock {j.name}=VALUE)" if j.kind in LOCKABLE else ""
            fail(self.desc, f"joint {j.name!r}", f"a {j.kind} joint: the paper's chain has revolute joints only{hint}")
        return True

    def place(self, j: Joint, q) -> None:
        R, p = self.pose[j.parent]
        Rj = R * _rpy(*j.rpy)
        O = p + R * _v(j.xyz)
        a = _unit(_v(j.axis))
        if j.kind == "prismatic":
            self.pose[j.child] = (Rj, O + Rj * (a * mp.mpf(q)))
        else:
            self.pose[j.child] = (Rj * _about(a, mp.mpf(q)) if q else Rj, O)

    def cluster(self, head: str) -> tuple[list, list]:
        """The links rigidly joined to ``head`` (placed), and the chain joints leaving them."""
        links, out, todo = [], [], [head]
        while todo:
            link = todo.pop(0)
            links.append(link)
            for j in self.children[link]:
                if self.moves(j):
                    out.append(j)
                else:
                    self.place(j, self.locks.get(j.name, 0))
                    todo.append(j.child)
        return links, out


def _below(children, head: str, target: str) -> bool:
    todo = [head]
    while todo:
        link = todo.pop()
        if link == target:
            return True
        todo += [j.child for j in children[link]]
    return False


def _ends(children, heads) -> list:
    ends = []
    for head in heads:
        todo = [head]
        while todo:
            link = todo.pop()
            todo += [j.child for j in children[link]]
            if not children[link]:
                ends.append(link)
    return ends


def _body(desc: Description, j: Joint, links: list, pose: dict) -> Body:
    """Body of joint ``j``: its links' masses merged (world axes, at the zero)."""
    m, first = mp.mpf(0), mp.matrix([0, 0, 0])
    parts = []
    for name in links:
        ine = desc.links[name]
        if ine is None or mp.mpf(ine.m) == 0:
            continue
        R, p = pose[name]
        Ri = R * _rpy(*ine.rpy)
        parts.append((mp.mpf(ine.m), p + R * _v(ine.xyz), Ri * _sym6(ine.I) * Ri.T))
        m += parts[-1][0]
        first += parts[-1][0] * parts[-1][1]
    if not m > 0:
        fail(desc, f"link {links[0]!r}", f"joint {j.name!r} turns no mass (its links {', '.join(links)} have none): "
             "the paper's bodies have mass; merge it by locking the joint or give it an <inertial>")
    com = first / m
    Ic = mp.zeros(3, 3)
    for mi, pi, Ii in parts:
        d = pi - com
        Ic += Ii + mi * (_dot(d, d) * mp.eye(3) - d * d.T)
    R, _ = pose[j.child]
    Rp, pp = pose[j.parent]
    return Body(j, tuple(links), m, com, Ic, pp + Rp * _v(j.xyz), R * _unit(_v(j.axis)))


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


def spec_text(ch: Chain, name: str | None = None, g=GRAVITY, controls: bool = True) -> str:
    """The chain as a spec (TOML), with comments saying where every body came from and what was
    merged, locked, left out or dropped."""
    from .printers.common import environment

    name = name or spec_name(ch.desc.name)
    bodies = []
    for k, (b, pb) in enumerate(zip(ch.bodies, paper(ch)), start=1):
        j = b.joint
        fields = [("theta", angle(pb.theta))]
        if angle(pb.offset) != "0.0":
            fields.append(("offset", angle(pb.offset)))
        fields += [("m", number(pb.m)), ("c", _vec(pb.c)), ("I_c", _vec(pb.Ic))]
        if pb.s is not None:
            fields.append(("s", _vec(pb.s)))
        if mp.mpf(j.damping) > 0:
            fields.append(("damping", number(j.damping)))
        if controls:
            fields.append(("control", "true"))
        comments = []
        if len(b.links) > 1:
            comments.append(f"with {', '.join(b.links[1:])} (fixed or locked to {b.links[0]})")
        if j.limit:
            comments.append("limits (not enforced by the model): " + ", ".join(f"{k} {v}" for k, v in j.limit.items()))
        if mp.mpf(j.friction) != 0:
            comments.append(f"dropped: <dynamics friction=\"{j.friction}\"> (Coulomb friction has no field in a spec)")
        bodies.append(dict(joint=j.name, title=f"joint {j.name} ({j.kind}), link {b.links[0]}", fields=fields,
                           comments=comments))
    notes = []
    if ch.locked:
        notes.append("locked: " + ", ".join(f"{k} = {v}" for k, v in ch.locked.items()))
    if ch.platform:
        notes.append(f"the platform (fixed): {', '.join(ch.platform)}")
    if ch.left_out:
        notes.append(f"left out (above the base {ch.base}): {', '.join(ch.left_out)}")
    source = ch.desc.source
    description = f"{ch.desc.name}: {len(bodies)} joints from {ch.base} to {ch.tip}, imported from {Path(source).name}"
    return environment().get_template("imported_spec.toml.jinja").render(
        name=name, source=Path(source).name, robot=ch.desc.name, base=ch.base, tip=ch.tip, bodies=bodies,
        notes=notes, description=json.dumps(description, ensure_ascii=False), g=number(g))


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
                        num(b.rest), b.control))
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
