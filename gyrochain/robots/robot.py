"""A robot description as a tree of links and joints (read from URDF by urdf.py), cut down to the
chain the paper's pendulum is, and written as a spec.

    desc = urdf.read(path)                                   # Description: links, joints, numbers as written
    ch = robot.chain(desc, base=None, tip=None, locks={})    # Chain: the revolute joints from base to tip
    text = robotspec.spec_text(ch, name="ur5")                # robotspec.py

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

from dataclasses import dataclass, field
from pathlib import Path

import mpmath as mp

from ..chainspec.errors import SpecError, did_you_mean

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
    armature: object = 0  # MJCF: a rotor's inertia added to the joint's diagonal of M
    spring: object = 0  # MJCF: the joint's stiffness, about ``rest``
    rest: object = 0
    ref: object = 0  # MJCF: the joint's value in the pose the file writes (its zero is that pose turned by −ref)


@dataclass(frozen=True)
class Description:
    name: str
    source: str  # what it was read from, for messages
    links: dict  # name -> Inertial | None
    joints: dict  # name -> Joint, in the file's order
    notes: tuple = ()  # what the reader left out, a line each (for the spec's comments)
    g: object = None  # the gravity the description states (MJCF); None where the format has none (URDF)


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
    auto_locked: tuple = ()  # joints off the chain, locked at their zero
    repairs: tuple = ()  # inertias made possible (round-off), a line each
    held: tuple = ()  # joints between the root and the base, held at their zero (the base's attitude)


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
    joints branch), with the ``locks`` {joint: value} fixed.  Given a tip, every joint off the path
    from the base to it is locked too: at its ``locks`` value, or else at its zero.  Everything the
    paper's chain cannot express is one line naming the joint or the links."""
    mp.mp.dps = DIGITS
    locks = dict(locks or {})
    children, parent_of, roots = _tree(desc, locks)
    for what, link in (("--base", base), ("--tip", tip)):
        if link is not None and link not in desc.links:
            fail(desc, f"{what} {link}", f"no such link; {did_you_mean(link, desc.links)}"
                 f"`import {Path(desc.source).name} --list` shows the tree")
    if base is None:
        if len(roots) != 1:
            fail(desc, "", f"{len(roots)} links have no parent ({', '.join(roots[:5])}{' …' if len(roots) > 5 else ''}): "
                 "a description is one tree; give --base LINK to import from one of them")
        base = roots[0]
    path = None
    if tip is not None:
        if not _below(children, base, tip):
            fail(desc, f"--tip {tip}", f"is not below the base {base}: `import {Path(desc.source).name} --list` "
                 "shows the tree")
        path, link = set(), tip
        while link != base:
            path.add(parent_of[link].name)
            link = parent_of[link].parent
    walk = _Walk(desc, children, locks, base, path)
    walk.pose[base], held = _attitude(desc, parent_of, base, locks, walk.used)
    platform, out = walk.cluster(base)
    chain_joints, bodies_links = [], []
    while out:
        if len(out) > 1:  # the movable joints branch (no tip given): the user picks the chain
            fail(desc, "--tip", f"the movable joints branch at {', '.join(j.name for j in out)}: give --tip, "
                 f"one of {', '.join(_ends(children, [j.child for j in out]))} (`import "
                 f"{Path(desc.source).name} --list` shows the tree)")
        j = out[0]
        walk.place(j, 0)
        links, out = walk.cluster(j.child)
        chain_joints.append(j)
        bodies_links.append(links)
    unused = [name for name in locks if name not in walk.used]
    if unused:
        fail(desc, f"--lock {unused[0]}", f"the joint is neither below the base {base} nor between it and the root: "
             "it is not part of the model")
    if not chain_joints:
        fail(desc, f"--tip {tip}" if tip else "", f"no revolute or continuous joint below {base}"
             f"{f' on the way to {tip}' if tip else ''}: nothing moves")
    bodies = tuple(_body(desc, j, links, walk) for j, links in zip(chain_joints, bodies_links))
    if bodies[-1].m == 0 and all(x == 0 for x in bodies[-1].Ic):
        fail(desc, f"link {bodies[-1].links[0]!r}", f"joint {bodies[-1].joint.name!r} turns no mass (its links "
             f"{', '.join(bodies[-1].links)} have none): give --tip a link further out, or give it an <inertial>")
    above = tuple(name for name in desc.links if name not in walk.pose)
    merged = tuple(x for links in bodies_links for x in links[1:])
    return Chain(desc, base, tip or bodies_links[-1][0], bodies, {k: locks[k] for k in locks}, merged,
                 tuple(platform), above, tuple(walk.auto), tuple(walk.repairs), tuple(held))


def _tree(desc: Description, locks: dict) -> tuple[dict, dict, list]:
    """{link: its child joints}, {link: its parent joint} and the roots; a joint naming a missing
    link, a second parent (a closed loop), a lock of no joint, of a joint that cannot be locked or
    outside the joint's limits are one line each."""
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
    for name, value in locks.items():
        if name not in desc.joints:
            fail(desc, f"--lock {name}", f"no such joint; {did_you_mean(name, desc.joints)}"
                 f"`import {Path(desc.source).name} --list` shows the tree")
        j = desc.joints[name]
        if j.kind not in LOCKABLE:
            fail(desc, f"--lock {name}", f"a {j.kind} joint cannot be locked at one value")
        lo, hi = j.limit.get("lower"), j.limit.get("upper")
        if j.kind != "continuous" and lo is not None and hi is not None and mp.mpf(lo) <= mp.mpf(hi) \
                and not mp.mpf(lo) <= mp.mpf(value) <= mp.mpf(hi):
            unit = "m" if j.kind == "prismatic" else "rad"
            fail(desc, f"--lock {name}={value}", f"outside the joint's limits, {lo} to {hi} {unit}")
    roots = [name for name in desc.links if name not in parent_of]
    if _cycle_free_count(children, roots) != len(desc.links):
        fail(desc, "", "its joints form a loop with no root: a description is a tree")
    return children, parent_of, roots


def _attitude(desc: Description, parent_of: dict, base: str, locks: dict, used: set) -> tuple:
    """The base link's world pose at the zero: the joints from the root to it at their --lock
    values or their zero (a floating or planar one at its origin), so that gravity stays along the
    world's −z whatever link the chain starts from."""
    up, link = [], base
    while link in parent_of:
        up.append(parent_of[link])
        link = parent_of[link].parent
    pose, held = (mp.eye(3), mp.matrix([0, 0, 0])), []
    for j in reversed(up):
        used.update([j.name] if j.name in locks else [])
        if j.kind != "fixed" and j.name not in locks:
            held.append(j.name)
        pose = _placed(pose, j, locks.get(j.name))
    return (pose[0], mp.matrix([0, 0, 0])), held


def posed(desc: Description, names) -> list[str]:
    """Joints held where the file puts them: each name, with its ref where that is not 0."""
    return [n if mp.mpf(desc.joints[n].ref) == 0 else f"{n} (at its ref {desc.joints[n].ref})" for n in names]


def _placed(parent: tuple, j: Joint, q) -> tuple:
    """The child link's pose (rotation, origin) from its parent's, with the joint at ``q`` (a
    floating or planar joint, which cannot be locked at one value, at its origin; q None: as the
    file writes it).  The file writes the pose at the joint's ``ref``: q is measured from ref's
    turn back."""
    R, p = parent
    Rj, O, q = R * _rpy(*j.rpy), p + R * _v(j.xyz), (mp.mpf(q) - mp.mpf(j.ref) if q is not None else mp.mpf(0))
    if q == 0 or j.kind not in LOCKABLE:
        return Rj, O
    if j.kind == "prismatic":
        return Rj, O + Rj * (_unit(_v(j.axis)) * q)
    return Rj * _about(_unit(_v(j.axis)), q), O


def _cycle_free_count(children: dict, roots: list) -> int:
    seen, todo = 0, list(roots)
    while todo:
        link = todo.pop()
        seen += 1
        todo += [j.child for j in children[link]]
    return seen


class _Walk:
    """The links' world poses at the zero, placed joint by joint from the base outwards.  With a
    ``path`` (the joints from the base to the tip) every other joint is rigid: locked at its value
    or its zero."""

    def __init__(self, desc: Description, children: dict, locks: dict, base: str, path: set | None):
        self.desc, self.children, self.locks, self.path = desc, children, locks, path
        self.pose = {base: (mp.eye(3), mp.matrix([0, 0, 0]))}  # world rotation (columns: link axes), origin
        self.used: set = set()  # the locks applied
        self.auto: list = []  # joints off the chain locked at their zero
        self.repairs: list = []  # inertias made possible (round-off), one line each

    def moves(self, j: Joint) -> bool:
        """A joint of the chain (True), rigid (False), or one line saying why it can be neither."""
        if j.name in self.locks:
            self.used.add(j.name)
            return False
        if j.kind == "fixed":
            return False
        if self.path is not None and (j.name not in self.path or j.kind == "prismatic"):  # off the chain, or a slide
            self.auto.append(j.name)
            return False
        if j.mimic is not None:
            fail(self.desc, f"joint {j.name!r}", f"mimics {j.mimic!r}: the paper's joints are independent "
                 f"(lock it with --lock {j.name}=VALUE)")
        if j.kind not in CHAIN_KINDS:
            name, ends = Path(self.desc.source).name, _ends(self.children, [j.child])
            turns = _turning_below(self.children, j.child)
            hint = (f" (lock it with --lock {j.name}=VALUE)" if j.kind in LOCKABLE
                    else f" (nothing turns below it: --tip LINK takes a chain that avoids it; `import {name} --list` "
                    "shows the leaves)" if not turns
                    else f" (the chain starts below it: `import {name} --base {j.child}"
                    + (f" --tip LINK`, LINK one of {', '.join(ends[:6])}{' …' if len(ends) > 6 else ''})" if len(ends) > 1
                       else "`)"))
            fail(self.desc, f"joint {j.name!r}", f"a {j.kind} joint: the paper's chain has revolute joints only{hint}")
        return True

    def place(self, j: Joint, q) -> None:
        self.pose[j.child] = _placed(self.pose[j.parent], j, q)

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
                    self.place(j, self.locks.get(j.name))
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


def _turning_below(children, head: str) -> bool:
    """Whether a revolute or continuous joint (not a mimic) lies below ``head``."""
    todo = [head]
    while todo:
        for j in children[todo.pop()]:
            if j.kind in CHAIN_KINDS and j.mimic is None:
                return True
            todo.append(j.child)
    return False


def _joint_to(desc: Description, link: str) -> str:
    return next(j.name for j in desc.joints.values() if j.child == link)


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


DOF = {"revolute": 1, "continuous": 1, "prismatic": 1, "planar": 3, "ball": 3, "floating": 6}


def tree_text(desc: Description, base: str | None = None) -> str:
    """The description as a tree, a link a line under the joint that leads to it, and the leaves a
    chain can end at (reached from the base by at least one revolute or continuous joint)."""
    children, _, roots = _tree(desc, {})
    if base is not None and base not in desc.links:
        fail(desc, f"--base {base}", f"no such link; {did_you_mean(base, desc.links)}the tree has "
             f"{len(desc.links)} links")
    kinds: dict = {}
    for j in desc.joints.values():
        kinds[j.kind] = kinds.get(j.kind, 0) + 1
    dof = sum(DOF.get(j.kind, 0) for j in desc.joints.values() if j.mimic is None)
    mimics = sum(1 for j in desc.joints.values() if j.mimic is not None)
    lines = [f"{Path(desc.source).name}: robot {desc.name!r}, {len(desc.links)} links, {len(desc.joints)} joints ("
             + ", ".join(f"{v} {k}" for k, v in sorted(kinds.items(), key=lambda kv: -kv[1]))
             + f"); {dof} degree{'s' if dof != 1 else ''} of freedom"
             + (f" and {mimics} mimic joint{'s' if mimics != 1 else ''}" if mimics else "")]
    leaves = []
    for top in ([base] if base else roots):
        todo = [(top, None, "", 0, None)]
        while todo:
            link, j, indent, turning, below = todo.pop()  # below: the link under the last joint no chain can hold
            what = "" if j is None else f"  ({j.name}: {j.kind}" + (f", mimics {j.mimic}" if j.mimic else "") + ")"
            lines.append(f"  {indent}{link}{what}")
            kids = children[link]
            if not kids and turning:
                leaves.append((link, turning, below))
            for k in reversed(kids):
                if k.kind in LOCKABLE or k.kind == "fixed":
                    todo.append((k.child, k, indent + "  ", turning + (k.kind in CHAIN_KINDS and k.mimic is None), below))
                else:  # a floating, planar or ball joint: a chain starts below it (--base)
                    todo.append((k.child, k, indent + "  ", 0, k.child))
    name = Path(desc.source).name
    bases = {below for *_, below in leaves}
    if leaves and len(bases) == 1:
        (below,) = bases
        start = below or base or (roots[0] if len(roots) == 1 else "its root")
        lines.append(f"leaves a chain can end at (`import {name} {f'--base {below} ' if below else ''}--tip LINK`"
                     + (f", the chain below the {desc.joints[_joint_to(desc, below)].kind} joint" if below else "")
                     + f"; the number of revolute joints from {start}):")
        lines += [f"  {leaf} ({n})" for leaf, n, _ in leaves]
    elif leaves:
        lines.append(f"leaves a chain can end at (`import {name} [--base BASE] --tip LINK`; the number of revolute joints "
                     "from the base, and the --base it needs below a floating, planar or ball joint):")
        lines += [f"  {leaf} ({n}{f'; --base {below}' if below else ''})" for leaf, n, below in leaves]
    else:
        lines.append("no leaf is reached by a revolute or continuous joint: nothing for a chain to turn")
    return "\n".join(lines)


ROUND_OFF = 1e-9  # a principal moment this far (relative) outside the possible is round-off, and repaired
TINY = mp.mpf("1e-20")  # kg m²: an inertia below this is a point's, whatever its written round-off


def _outside(I: mp.matrix) -> tuple:
    """How far a central inertia lies outside the possible ones (0 inside), its principal moments
    in increasing order, their axes' indices in that order and the axes (columns of Q)."""
    E, Q = mp.eigsy(I)
    order = sorted(range(3), key=lambda i: E[i])
    l0, l1, l2 = (E[i] for i in order)
    return max(-l0, l2 - l0 - l1, mp.mpf(0)), (l0, l1, l2), order, Q


def _moments(ls) -> str:
    return ", ".join(mp.nstr(x, 6) for x in ls)


def _possible(desc: Description, j: Joint, links: list, Ic: mp.matrix, impossible: list, walk: _Walk) -> mp.matrix:
    """The body's inertia about its centre of mass as a body can have it: as computed; the nearest
    possible tensor where it is outside only by round-off (with a line saying so); else one line
    naming the links whose own inertia is impossible."""
    outside, (l0, l1, l2), order, Q = _outside(Ic)
    if outside == 0:
        return Ic
    scale = max(abs(l0), abs(l2))
    if outside > ROUND_OFF * scale + TINY:
        culprits = f" (of its links, {', '.join(impossible)} alone {'is' if len(impossible) == 1 else 'are'} not)" \
            if impossible else ""
        fail(desc, f"link {impossible[0] if impossible else links[0]!r}", f"<inertia>: the body of joint {j.name!r} is not "
             f"physically possible{culprits}: principal moments {_moments((l0, l1, l2))} about its centre of mass; each "
             "must be ≥ 0 and at most the sum of the others")
    l0 = max(l0, mp.mpf(0))  # the nearest possible moments: clip at 0, then onto l2 = l0 + l1
    d = max(l2 - l0 - l1, mp.mpf(0)) / 3
    fixed = {order[0]: l0 + d, order[1]: l1 + d, order[2]: l2 - d}
    walk.repairs.append(f"the body of joint {j.name}: inertia repaired to the nearest possible (principal moments "
                        f"{_moments((l0, l1, l2))}, outside by round-off)")
    return Q * mp.diag([fixed[i] for i in range(3)]) * Q.T


def _body(desc: Description, j: Joint, links: list, walk: _Walk) -> Body:
    """Body of joint ``j``: its links' masses merged (world axes, at the zero).  A link with no mass
    but an inertia (real files have them) adds its inertia."""
    pose = walk.pose
    m, first = mp.mpf(0), mp.matrix([0, 0, 0])
    parts, impossible = [], []
    for name in links:
        ine = desc.links[name]
        if ine is None or (mp.mpf(ine.m) == 0 and all(mp.mpf(v) == 0 for v in ine.I)):
            continue
        if mp.mpf(ine.m) < 0:
            fail(desc, f"link {name!r}", f"<mass value>: a negative mass ({ine.m}); it is part of the body of joint {j.name!r}")
        R, p = pose[name]
        Ri = R * _rpy(*ine.rpy)
        I = _sym6(ine.I)
        outside, ls, _, _ = _outside(I)
        if outside > ROUND_OFF * max(abs(ls[0]), abs(ls[2])) + TINY:
            impossible.append(name)
            walk.repairs.append(f"the inertia of link {name} alone is not physically possible (principal moments "
                                f"{_moments(ls)}); the body of joint {j.name} it is part of is, and the model uses the body")
        parts.append((mp.mpf(ine.m), p + R * _v(ine.xyz), Ri * I * Ri.T))
        m += parts[-1][0]
        first += parts[-1][0] * parts[-1][1]
    if 0 < m < EXACT:
        fail(desc, f"link {links[0]!r}", f"the body of joint {j.name!r} has a mass of {mp.nstr(m, 6)} kg, too small "
             f"to be written (below {mp.nstr(EXACT, 1)} kg): give its links their masses")
    R, _ = pose[j.child]
    Rp, pp = pose[j.parent]
    O = pp + Rp * _v(j.xyz)
    com = first / m if m > 0 else O  # a massless frame between two joints (a ball joint of revolute ones)
    Ic = mp.zeros(3, 3)
    for mi, pi, Ii in parts:
        d = pi - com
        Ic += Ii + mi * (_dot(d, d) * mp.eye(3) - d * d.T)
    Ic = _possible(desc, j, links, Ic, impossible, walk)
    return Body(j, tuple(links), m, com, Ic, O, R * _unit(_v(j.axis)))
