"""Robot descriptions in and out, for the commands ``gyrochain import`` and ``gyrochain export``.

    text, summary = exchange.import_text("ur5.urdf", tip=None, locks=["finger=0.02"])

Import reads a URDF (urdf.py), cuts it to the chain (robot.py) and writes a spec; the spec is
parsed again before it is written, so what is written is a spec the other commands accept.
"""
from __future__ import annotations

import math
from pathlib import Path

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
        raise SpecError(str(path), "an MJCF file: import reads URDF (MuJoCo's `compile` tool, or "
                        "mujoco.MjModel.from_xml_path and mj_saveLastXML, cannot write URDF either; export the "
                        "robot's URDF from its source)")
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
