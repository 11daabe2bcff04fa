"""MJCF in: a MuJoCo model compiled by MuJoCo itself, read into a robot.Description.

    desc = mjcf.read("acrobot.xml")     # one line (SpecError) for a model MuJoCo does not compile

Why MuJoCo's compiler rather than our own walk over the XML: MJCF's meaning is in its compiler
(defaults and classes, ``<include>``, inertias from geoms, degrees, ``fromto``, ``euler`` in any
sequence), and the compiled ``mjModel`` is what MuJoCo simulates.  The ``mujoco`` package is an
optional extra (``pip install gyrochain[mujoco]``).

Each body of the model is a link with its mass, centre of mass and inertia; its joints lead to it
from its parent.  A body without joints is fixed to its parent; a hinge is a revolute joint, a
slide a prismatic one, a ball and a free joint are held at the model's pose when off the chain.  A
joint placed away from the body's origin (``pos``), or several joints in one body, become massless
links in between, so that each joint turns about its own axis through its own point, in order, as
MuJoCo composes them.  The model's pose (``qpos0``) is the description's zero.
"""
from __future__ import annotations

import os
from dataclasses import replace
from pathlib import Path

import mpmath as mp

from ..chainspec.errors import SpecError
from .robot import DIGITS, Description, Inertial, Joint
from .robotspec import rpy_of

KIND = {0: "floating", 1: "ball", 2: "prismatic", 3: "revolute"}  # mjtJoint: free, ball, slide, hinge


def _mujoco():
    try:
        import mujoco
    except ImportError:
        raise SpecError("import", "an MJCF file needs MuJoCo's compiler: pip install 'gyrochain[mujoco]' "
                        "(or pip install mujoco)") from None
    return mujoco


def read(path) -> Description:
    """The compiled model at ``path`` as links and joints; what MuJoCo refuses is one line."""
    path = Path(path)
    where = str(path)
    if not path.exists():
        raise SpecError(where, "no such file")
    if not path.is_file():
        raise SpecError(where, "is not a regular file")
    mujoco = _mujoco()
    warned: list = []
    # MuJoCo's warnings (a deprecated attribute) go to the spec's comments, not to stderr and
    # MUJOCO_LOG.TXT in the user's folder
    previous = mujoco.get_mju_user_warning() if hasattr(mujoco, "set_mju_user_warning") else None
    if previous is not None or hasattr(mujoco, "set_mju_user_warning"):
        mujoco.set_mju_user_warning(lambda text: warned.append(" ".join(str(text).split())))
    try:
        model = mujoco.MjModel.from_xml_path(os.fspath(path))
    except ValueError as exc:  # MuJoCo's compiler: "XML Error: ... Element 'x', line 3"
        raise SpecError(where, "MuJoCo does not compile it: " + " ".join(str(exc).split())) from None
    finally:
        if hasattr(mujoco, "set_mju_user_warning"):
            mujoco.set_mju_user_warning(previous)
    desc = describe(model, where)
    return replace(desc, notes=desc.notes + tuple(f"MuJoCo's compiler warned: {w}" for w in dict.fromkeys(warned)))


def _s(x) -> str:
    return repr(float(x))


def _rot(q) -> mp.matrix:
    """The rotation of a unit quaternion (w, x, y, z)."""
    w, x, y, z = (mp.mpf(float(v)) for v in q)
    n = mp.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w / n, x / n, y / n, z / n
    return mp.matrix([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                      [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                      [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def _rpy(q) -> tuple:
    return tuple(mp.nstr(a, 20) for a in rpy_of(_rot(q)))


class _Names:
    """Unique names: MuJoCo's where given, else ``fallback``, with _2, _3 … where two would meet."""

    def __init__(self):
        self.taken: set = set()

    def __call__(self, name: str, fallback: str) -> str:
        name = name or fallback
        out, k = name, 2
        while out in self.taken:
            out, k = f"{name}_{k}", k + 1
        self.taken.add(out)
        return out


def _text(xs) -> tuple:
    return tuple(x if isinstance(x, str) else mp.nstr(x, 20) for x in xs)


GRAVITY_TILT = 1e-4  # gravity whose horizontal part is at most this fraction of it: along -z, the part left out said


def describe(model, where: str) -> Description:
    """A compiled ``mjModel`` as a Description (links named after the bodies, joints after the joints)."""
    mp.mp.dps = DIGITS
    off = _disabled(model)
    g = [0.0, 0.0, 0.0] if "gravity" in off else [float(x) for x in model.opt.gravity]
    tilt = (g[0] ** 2 + g[1] ** 2) ** 0.5
    if g[2] > 0 or tilt > GRAVITY_TILT * (tilt ** 2 + g[2] ** 2) ** 0.5:
        raise SpecError(f"{where}: <option gravity>", f"({' '.join(f'{x:g}' for x in g)}) is not along -z: the spec's "
                        "gravity acts along the model's -z (--g sets only its magnitude); turn the model so that "
                        "gravity is along -z, or write <option gravity=\"0 0 -g\"/>")
    link_name, joint_name = _Names(), _Names()
    bodies = [link_name(model.body(i).name, f"body{i}") for i in range(model.nbody)]
    links: dict = {}
    joints: dict = {}
    for i, name in enumerate(bodies):
        m = float(model.body_mass[i])
        links[name] = Inertial(_s(m), tuple(_s(x) for x in model.body_ipos[i]), _rpy(model.body_iquat[i]),
                               tuple(_s(x) for x in model.body_inertia[i]) + ("0", "0", "0")) if m > 0 else None
        if i > 0:
            _joints_of(model, i, bodies, where, links, joints, link_name, joint_name)
    notes = [f"gravity ({' '.join(f'{x:g}' for x in g)}) read as {-g[2]:g} along -z: its horizontal part, "
             f"{tilt / abs(g[2]):.1g} of it, left out"] if tilt else []
    notes += [f"ignored: the medium's {what} ({float(value):g}): its drag has no field in a spec"
             for what, value in (("density", model.opt.density), ("viscosity", model.opt.viscosity)) if float(value) != 0]
    if any(float(x) != 0 for x in model.body_gravcomp):
        notes.append("ignored: gravity compensation (gravcomp) of some bodies")
    if model.ntendon:
        notes.append(f"ignored: {model.ntendon} tendon(s)")
    if model.neq:
        notes.append(f"ignored: {model.neq} equality constraint(s)")
    title = model.names[:model.names.index(b"\0")].decode() if model.names[:1] != b"\0" else Path(where).stem
    if "gravity" in off:  # <flag gravity="disable"/>: the model's gravity vector stays, MuJoCo applies none
        notes.append("gravity 0: the model disables it (<flag gravity=\"disable\"/>)")
    for what, field in (("spring", "spring"), ("damper", "damping")):
        if what in off and any(float(getattr(j, field)) != 0 for j in joints.values()):
            notes.append(f"no joint {field}: the model disables its {what}s (<flag {what}=\"disable\"/>)")
            joints = {k: replace(j, **{field: "0"}) for k, j in joints.items()}
    return Description(title, where, links, joints, tuple(notes), -g[2] if g[2] else 0.0)


def _disabled(model) -> set:
    """What the model's <option><flag .../> switches off of what the chain's equations hold."""
    import mujoco

    flags, bits = int(model.opt.disableflags), mujoco.mjtDisableBit
    out = {name for name in ("gravity", "spring", "damper")
           if hasattr(bits, f"mjDSBL_{name.upper()}") and flags & int(getattr(bits, f"mjDSBL_{name.upper()}"))}
    if hasattr(bits, "mjDSBL_PASSIVE") and flags & int(bits.mjDSBL_PASSIVE):  # MuJoCo before 3.1: one flag for both
        out |= {"spring", "damper"}
    return out


def _joints_of(model, i: int, bodies: list, where: str, links: dict, joints: dict, link_name, joint_name) -> None:
    """The joints from body i's parent to body i: a weld where it has none; else each joint about
    its axis through its point, in order, with massless links between."""
    name, parent = bodies[i], bodies[model.body_parentid[i]]
    pos, R = model.body_pos[i], _rot(model.body_quat[i])
    rpy = tuple(mp.nstr(a, 20) for a in rpy_of(R))
    adr, num = int(model.body_jntadr[i]), int(model.body_jntnum[i])
    if num == 0:
        jn = joint_name("", f"{name}_weld")
        joints[jn] = Joint(jn, "fixed", parent, name, tuple(_s(x) for x in pos), rpy)
        return
    prev = None
    for k in range(adr, adr + num):
        kind = KIND[int(model.jnt_type[k])]
        jn = joint_name(model.joint(k).name, f"joint{k}")
        p = [mp.mpf(float(x)) for x in model.jnt_pos[k]]
        if prev is None:  # the first joint: at the body's place, turned as the body is
            xyz, rot = [mp.mpf(float(pos[r])) + sum(R[r, c] * p[c] for c in range(3)) for r in range(3)], rpy
        else:  # the next ones: from the previous joint's point, in the body's axes
            xyz, rot = [p[r] - prev[r] for r in range(3)], ("0", "0", "0")
        last, at_origin = k == adr + num - 1, all(x == 0 for x in p)
        child = name if last and at_origin else link_name("", f"{name}__{jn}")
        if child != name:
            links[child] = None
        dof, qadr = int(model.jnt_dofadr[k]), int(model.jnt_qposadr[k])
        hinge_or_slide = kind in ("revolute", "prismatic")
        limit = {"lower": _s(model.jnt_range[k][0]), "upper": _s(model.jnt_range[k][1])} if model.jnt_limited[k] else {}
        if getattr(model, "jnt_actfrclimited", None) is not None and model.jnt_actfrclimited[k]:  # actuatorfrcrange
            limit["effort"] = _s(max(abs(float(x)) for x in model.jnt_actfrcrange[k]))
        joints[jn] = Joint(jn, kind, parent, child, _text(xyz), rot,
                           tuple(_s(x) for x in model.jnt_axis[k]) if hinge_or_slide else ("1", "0", "0"),
                           _s(model.dof_damping[dof]), _s(model.dof_frictionloss[dof]), limit,
                           armature=_s(model.dof_armature[dof]), spring=_s(model.jnt_stiffness[k]),
                           rest=_s(model.qpos_spring[qadr]) if hinge_or_slide else "0",
                           ref=_s(model.qpos0[qadr]) if hinge_or_slide else "0")
        parent, prev = child, p
    if not all(x == 0 for x in prev):
        jn = joint_name("", f"{name}_at")
        joints[jn] = Joint(jn, "fixed", parent, name, _text([-x for x in prev]))
