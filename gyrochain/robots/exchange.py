"""Robot descriptions in and out, for the commands ``gyrochain import`` and ``gyrochain export``.

    text, summary = exchange.import_text("ur5.urdf", tip=None, locks=["finger=0.02"])

Import reads a URDF (urdf.py), cuts it to the chain (robot.py) and writes a spec; the spec is
parsed again before it is written, so what is written is a spec the other commands accept.
"""
from __future__ import annotations

import hashlib
import math
import re
from dataclasses import replace
from pathlib import Path

import numpy as np

from . import robot, robotspec, urdf
from ..chainspec.errors import SpecError
from ..chainspec.spec import parse_spec


def locks_of(items) -> dict:
    """--lock NAME=VALUE options: {joint: the value as written}."""
    out: dict = {}
    for item in items or []:
        key, eq, val = item.partition("=")
        key, val = key.strip(), val.strip()
        if not (eq and key) or not urdf.DECIMAL.fullmatch(val) or not math.isfinite(float(val)):
            raise SpecError(f"--lock {item}", "expected joint=number (radians for a revolute joint, metres for a prismatic one)")
        if key in out:
            raise SpecError(f"--lock {key}", "given twice")
        out[key] = val
    return out


def read_description(path) -> robot.Description:
    """A URDF, or an MJCF model (through MuJoCo's compiler), told apart by the root element."""
    path = Path(path)
    head = b""
    try:
        with open(path, "rb") as fh:
            head = fh.read(1 << 16)
    except OSError:
        pass  # urdf.read says what is wrong with the path
    text = re.sub(rb"<!--.*?-->|<\?.*?\?>", b"", head, flags=re.S)
    root = re.search(rb"<([A-Za-z_][\w:.-]*)", text)
    if root is not None and root.group(1) == b"mujoco":
        from . import mjcf

        return mjcf.read(path)
    return urdf.read(path)


def tree_text(path, base: str | None = None) -> str:
    """The tree of the description at ``path`` (``import --list``)."""
    return robot.tree_text(read_description(path), base)


def import_text(path, base: str | None = None, tip: str | None = None, locks=None, name: str | None = None,
                controls: bool = True, g: float | None = None) -> tuple[str, list[str]]:
    """The spec text of the chain in the description at ``path``, and lines that say what was done
    (``g``: the gravity along the description's −z; default the description's own, else 9.81)."""
    if g is not None and not g >= 0:
        raise SpecError(f"--g {g:g}", "gravity's magnitude along the model's -z: expected 0 or more")
    desc = read_description(path)
    if g is not None and desc.g is not None:  # the file's gravity (or its disabling) replaced by --g
        desc = replace(desc, notes=tuple(f"gravity {g:g} (--g), where the file has {desc.g:g}" if n.startswith("gravity ")
                                         else n for n in desc.notes))
    g = g if g is not None else desc.g if desc.g is not None else robot.GRAVITY
    if name is not None and not robotspec.spec_name(name) == name:
        raise SpecError(f"--name {name}", "expected a C identifier (letters, digits, _; not starting with a digit)")
    ch = robot.chain(desc, base, tip, locks_of(locks))
    text = robotspec.spec_text(ch, name, g=g, controls=controls)
    try:
        spec = parse_spec(text)  # what is written is a spec the other commands accept
    except SpecError as exc:  # said of what the user gave: the file's joint, or --name
        field, _, why = str(exc).partition(": ")
        k = re.match(r"body\[(\d+)\]", field)
        if k:
            raise SpecError(f"{path}: joint {ch.bodies[int(k[1]) - 1].joint.name!r}", why) from None
        if field == "name":
            raise SpecError(f"--name {name}" if name else f"{path}: robot name {ch.desc.name!r}",
                            why + ("" if name else " (give --name NAME)")) from None
        raise
    joints = [b.joint.name for b in ch.bodies]
    lines = [f"imported {spec.name} from {Path(path).name}: {len(joints)} joint{'s' if len(joints) > 1 else ''} from {ch.base} to {ch.tip} "
             f"({', '.join(joints)})"]
    if ch.merged:
        lines.append(f"  merged into their bodies (fixed or locked joints): {_few(ch.merged)}")
    if ch.locked:
        lines.append(f"  locked at the values given: {', '.join(f'{k} = {v}' for k, v in ch.locked.items())}")
    if ch.auto_locked:
        lines.append(f"  locked at their zero (off the chain, or sliding): {_few(robot.posed(ch.desc, ch.auto_locked))}")
    if ch.held:
        lines.append(f"  held at their zero (between the root and the base): {_few(robot.posed(ch.desc, ch.held))}")
    lines += [f"  {line}" for line in ch.repairs]
    dropped = [b.joint.name for b in ch.bodies if float(b.joint.friction) != 0]
    if dropped:
        lines.append(f"  dropped: the Coulomb friction of {', '.join(dropped)} (a spec has viscous damping only)")
    return text, lines


def _limit_attributes(lim: dict) -> dict:
    """A joint's limits as the templates write them: MJCF's ``range`` (lower upper) where both are
    given and its ``effort``; URDF's joint type (revolute with a range, else continuous) and the
    attributes of its <limit> (0 for an effort or a velocity the spec does not give: URDF's "none")."""
    both = "lower" in lim and "upper" in lim
    num = lambda key: robotspec.numbers([lim[key]]) if key in lim else "0"  # noqa: E731
    urdf = " ".join(f'{k}="{num(k)}"' for k in (("lower", "upper") if both else ()) + ("effort", "velocity"))
    return dict(range=robotspec.numbers([lim["lower"], lim["upper"]]) if both else "",
                effort=robotspec.numbers([lim["effort"]]) if "effort" in lim else "",
                urdf_type="revolute" if both else "continuous",
                urdf_limit=urdf if both or "effort" in lim or "velocity" in lim else "")


def _few(names, most: int = 8) -> str:
    """A list of names for a line on the terminal: the first ``most``, then how many more (the spec lists all)."""
    names = list(names)
    return ", ".join(names[:most]) + (f" and {len(names) - most} more (listed in the spec)" if len(names) > most else "")


FORMATS = {"urdf": ("model.urdf.jinja", ".urdf"), "mjcf": ("model.mjcf.jinja", ".xml")}


def export_text(spec, spec_label: str, to: str, values: dict) -> tuple[str, list[str]]:
    """The spec as a robot description (``to``: urdf or mjcf), and lines that say what it holds."""
    from .. import __version__
    from ..printers.common import environment

    why = robotspec.refusals(spec, to)
    if why:
        raise SpecError(f"export --to {to}", why)
    links = robotspec.links_of(spec, values)
    if to == "mjcf":
        for k, link in enumerate(links, start=1):
            xx, yy, zz, xy, xz, yz = (float(v) for v in link.Ic)
            if np.linalg.eigvalsh(np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]]))[0] <= 1e-15 * max(xx, yy, zz, 1e-300):
                raise SpecError(f"body[{k}].I_c", "MuJoCo's compiler refuses a body whose inertia about its centre of mass "
                                "has a zero principal moment (a point mass, a thin rod): give it a small one")
    g = float(spec.g.subs({p: values[str(p)] for p in spec.params if str(p) in values}))
    rows = [dict(xyz=robotspec.numbers(link.xyz), rpy=robotspec.numbers(robotspec.rpy_of(link.R)), quat=robotspec.numbers(robotspec.quat_of(link.R)),
                 c=robotspec.numbers(link.c), m=robotspec.numbers([link.m]), I=robotspec.numbers(link.Ic).split(),
                 damping=robotspec.numbers([link.damping]) if link.damping else "",
                 spring=robotspec.numbers([link.spring]) if link.spring else "", rest=robotspec.numbers([link.rest]),
                 armature=robotspec.numbers([link.armature]) if link.armature else "",
                 **_limit_attributes(dict(link.limits)))
            for link in links]
    notes = [f"The spec's parameters at: {', '.join(f'{k} = {v:g}' for k, v in values.items())}."] if values else []
    if to == "urdf" and spec.controls:
        notes.append("Every joint takes a torque here; the spec's controls are joints "
                     + ", ".join(map(str, spec.controls)) + ".")
    template, _ = FORMATS[to]
    text = environment().get_template(template).render(
        name=spec.name, version=__version__, spec_label=Path(spec_label).name.replace("--", "- -"),
        spec_sha=hashlib.sha256(spec.source.encode("utf-8")).hexdigest()[:16], g=robotspec.numbers([g]), links=rows,
        notes=[n.replace("--", "- -") for n in notes], motors=list(spec.controls) if to == "mjcf" else [])
    said = [f"exported {spec.name} as {to.upper()}: {len(links)} joints (joint1..joint{len(links)} = phi1..phi{len(links)})"]
    if to == "mjcf" and any("velocity" in dict(link.limits) for link in links):
        said.append("  dropped: the joints' velocity limits (MJCF has no element for them)")
    if to == "urdf" and g != robot.GRAVITY:
        said.append(f"  gravity {g:g} is in a comment only: URDF has no element for it (set it in the simulator)")
    return text, said
