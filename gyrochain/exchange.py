"""Robot descriptions in and out, for the commands ``gyrochain import`` and ``gyrochain export``.

    text, summary = exchange.import_text("ur5.urdf", tip=None, locks=["finger=0.02"])

Import reads a URDF (urdf.py), cuts it to the chain (robot.py) and writes a spec; the spec is
parsed again before it is written, so what is written is a spec the other commands accept.
"""
from __future__ import annotations

import hashlib
import math
from pathlib import Path

import numpy as np

from . import robot, urdf
from .errors import SpecError
from .spec import parse_spec


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
    """A URDF; an MJCF file is named as such (export writes MJCF, import reads URDF)."""
    path = Path(path)
    if path.suffix.lower() == ".xml" or (path.is_file() and b"<mujoco" in path.read_bytes()[:4096]):
        raise SpecError(str(path), "an MJCF file (MuJoCo's format): import reads URDF, which most robots publish "
                        "beside their MJCF (export writes both)")
    return urdf.read(path)


def import_text(path, base: str | None = None, tip: str | None = None, locks=None, name: str | None = None,
                controls: bool = True, g: float = robot.GRAVITY) -> tuple[str, list[str]]:
    """The spec text of the chain in the description at ``path``, and lines that say what was done."""
    desc = read_description(path)
    if name is not None and not robot.spec_name(name) == name:
        raise SpecError(f"--name {name}", "expected a C identifier (letters, digits, _; not starting with a digit)")
    ch = robot.chain(desc, base, tip, locks_of(locks))
    text = robot.spec_text(ch, name, g=g, controls=controls)
    spec = parse_spec(text)  # what is written is a spec the other commands accept
    joints = [b.joint.name for b in ch.bodies]
    lines = [f"imported {spec.name} from {Path(path).name}: {len(joints)} joints from {ch.base} to {ch.tip} "
             f"({', '.join(joints)})"]
    if ch.merged:
        lines.append(f"  merged into their bodies (fixed or locked joints): {', '.join(ch.merged)}")
    if ch.locked:
        lines.append(f"  locked: {', '.join(f'{k} = {v}' for k, v in ch.locked.items())}")
    dropped = [b.joint.name for b in ch.bodies if float(b.joint.friction) != 0]
    if dropped:
        lines.append(f"  dropped: the Coulomb friction of {', '.join(dropped)} (a spec has viscous damping only)")
    return text, lines


FORMATS = {"urdf": ("model.urdf.jinja", ".urdf"), "mjcf": ("model.mjcf.jinja", ".xml")}


def export_text(spec, spec_label: str, to: str, values: dict) -> tuple[str, list[str]]:
    """The spec as a robot description (``to``: urdf or mjcf), and lines that say what it holds."""
    from . import __version__
    from .printers.common import environment

    why = robot.refusals(spec, to)
    if why:
        raise SpecError(f"export --to {to}", why)
    links = robot.links_of(spec, values)
    if to == "mjcf":
        for k, link in enumerate(links, start=1):
            xx, yy, zz, xy, xz, yz = (float(v) for v in link.Ic)
            if np.linalg.eigvalsh(np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]]))[0] <= 1e-15 * max(xx, yy, zz, 1e-300):
                raise SpecError(f"body[{k}].I_c", "MuJoCo's compiler refuses a body whose inertia about its centre of mass "
                                "has a zero principal moment (a point mass, a thin rod): give it a small one")
    g = float(spec.g.subs({p: values[str(p)] for p in spec.params if str(p) in values}))
    rows = [dict(xyz=robot.numbers(link.xyz), rpy=robot.numbers(robot.rpy_of(link.R)), quat=robot.numbers(robot.quat_of(link.R)),
                 c=robot.numbers(link.c), m=robot.numbers([link.m]), I=robot.numbers(link.Ic).split(),
                 damping=robot.numbers([link.damping]) if link.damping else "",
                 spring=robot.numbers([link.spring]) if link.spring else "", rest=robot.numbers([link.rest]))
            for link in links]
    notes = [f"The spec's parameters at: {', '.join(f'{k} = {v:g}' for k, v in values.items())}."] if values else []
    if to == "urdf" and spec.controls:
        notes.append("Every joint takes a torque here; the spec's controls are joints "
                     + ", ".join(map(str, spec.controls)) + ".")
    template, _ = FORMATS[to]
    text = environment().get_template(template).render(
        name=spec.name, version=__version__, spec_label=Path(spec_label).name.replace("--", "- -"),
        spec_sha=hashlib.sha256(spec.source.encode("utf-8")).hexdigest()[:16], g=robot.numbers([g]), links=rows,
        notes=[n.replace("--", "- -") for n in notes], motors=list(spec.controls) if to == "mjcf" else [])
    said = [f"exported {spec.name} as {to.upper()}: {len(links)} joints (joint1..joint{len(links)} = phi1..phi{len(links)})"]
    if to == "urdf" and g != robot.GRAVITY:
        said.append(f"  gravity {g:g} is in a comment only: URDF has no element for it (set it in the simulator)")
    return text, said
