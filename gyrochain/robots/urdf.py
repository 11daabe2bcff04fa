"""URDF in: the file read into a robot.Description, with every number kept as the decimal written.

    desc = urdf.read("ur5_robot.urdf")      # one line (SpecError) for a file that is not a URDF we can use

Why our own walk over the XML rather than a URDF library (yourdfpy, urdfdom through Pinocchio):
those turn every number into a double at once, while the spec keeps the decimals as written (exact
rationals); they accept and repair what we must refuse with a line naming the element (a NaN, a
second parent, a negative mass); and they pull in meshes and scene libraries the dynamics does not
need.  The XML itself is read by the standard library with document type declarations refused (no
entity expansion), and only the elements the dynamics reads are looked at: ``link/inertial``,
``joint`` with its ``parent``, ``child``, ``origin``, ``axis``, ``limit``, ``dynamics`` and
``mimic``.  Visuals, collisions, transmissions and plugins are skipped.
"""
from __future__ import annotations

import math
import os
import re
import stat
import xml.etree.ElementTree as ET
from pathlib import Path

import mpmath as mp

from ..chainspec.errors import SpecError
from .robot import KINDS, Description, Inertial, Joint

MAX_BYTES = 32 << 20  # a URDF with meshes inline is still far below this
AXISLESS = ("fixed", "floating")  # joints whose <axis> the format ignores
DECIMAL = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?")


def read(path) -> Description:
    """The description in ``path``: its links' inertials and its joints."""
    path = Path(path)
    where = str(path)
    try:
        mode = os.stat(path).st_mode
        if not stat.S_ISREG(mode):
            raise SpecError(where, "is not a regular file")
        with open(path, "rb") as fh:
            data = fh.read(MAX_BYTES + 1)
    except FileNotFoundError:
        raise SpecError(where, "no such file") from None
    except OSError as exc:
        raise SpecError(where, f"cannot read: {exc.strerror or exc}") from None
    if len(data) > MAX_BYTES:
        raise SpecError(where, f"larger than {MAX_BYTES >> 20} MB: not a robot description")
    return parse(data, where)


def parse(data: bytes, where: str = "<urdf>") -> Description:
    head = data.lstrip(b"\xef\xbb\xbf \t\r\n")[:1]
    if head != b"<":
        what = "a spec (TOML) perhaps, " if where.endswith(".toml") else ""
        raise SpecError(where, f"not a URDF: {what}not XML (a robot description starts with '<')")
    if b"<!DOCTYPE" in data or b"<!ENTITY" in data:
        raise SpecError(where, "has a document type declaration: entities are not expanded in a robot description")
    try:
        root = ET.fromstring(data)
    except ET.ParseError as exc:
        raise SpecError(where, f"not well-formed XML ({exc})") from None
    except LookupError as exc:  # <?xml encoding="…"?> that Python does not know
        raise SpecError(where, f"cannot read: {exc}") from None
    except ValueError as exc:  # bytes that are not the declared encoding
        raise SpecError(where, f"cannot read: {' '.join(str(exc).split())}") from None
    if root.tag != "robot":
        raise SpecError(where, f"the root element is <{root.tag}>, not <robot>: not a URDF")
    name = root.get("name") or Path(where).stem
    links: dict = {}
    for el in root.findall("link"):
        lname = _required(el, "name", where, "<link>")
        if lname in links:
            raise SpecError(where, f"link {lname!r}: defined twice")
        links[lname] = _inertial(el, f"{where}: link {lname!r}")
    joints: dict = {}
    for el in root.findall("joint"):
        jname = _required(el, "name", where, "<joint>")
        at = f"{where}: joint {jname!r}"
        if jname in joints:
            raise SpecError(at, "defined twice")
        kind = _required(el, "type", at, "<joint>")
        if kind not in KINDS:
            raise SpecError(at, f"type {kind!r} is not a URDF joint type ({', '.join(KINDS)})")
        parent, child = (_required(_one(el, tag, at, True), "link", at, f"<{tag}>") for tag in ("parent", "child"))
        xyz, rpy = _origin(el, at)
        axis_el = _one(el, "axis", at) if kind not in AXISLESS else None  # the format ignores a fixed joint's axis
        axis = _numbers(axis_el.get("xyz"), 3, f"{at}: <axis xyz>") if axis_el is not None else ("1", "0", "0")
        if all(mp.mpf(a) == 0 for a in axis):
            raise SpecError(f"{at}: <axis xyz>", "a zero axis has no direction")
        dyn = _one(el, "dynamics", at)
        damping = _attr_number(dyn, "damping", f"{at}: <dynamics damping>") if dyn is not None else 0
        friction = _attr_number(dyn, "friction", f"{at}: <dynamics friction>") if dyn is not None else 0
        if mp.mpf(damping) < 0:
            raise SpecError(f"{at}: <dynamics damping>", f"a negative damping ({damping}) feeds energy into the joint")
        lim = _one(el, "limit", at)
        limit = {k: lim.get(k) for k in ("lower", "upper", "effort", "velocity") if lim is not None and lim.get(k) is not None}
        for k, v in limit.items():
            _numbers(v, 1, f"{at}: <limit {k}>")
        mimic = _one(el, "mimic", at)
        joints[jname] = Joint(jname, kind, parent, child, xyz, rpy, axis, damping, friction, limit,
                              _required(mimic, "joint", at, "<mimic>") if mimic is not None else None)
    if not links:
        raise SpecError(where, "has no <link>")
    return Description(name, where, links, joints)


def _one(el, tag: str, at: str, required: bool = False):
    found = el.findall(tag)
    if len(found) > 1:
        raise SpecError(at, f"has {len(found)} <{tag}> elements; one is allowed")
    if required and not found:
        raise SpecError(at, f"has no <{tag}>")
    return found[0] if found else None


def _required(el, attr: str, at: str, tag: str) -> str:
    value = el.get(attr)
    if value is None or not value.strip():
        raise SpecError(at, f"{tag} has no {attr}")
    if any(ord(ch) < 32 or ord(ch) == 127 for ch in value):
        raise SpecError(at, f"{tag} {attr}: a name with a control character")
    return value.strip()


def _numbers(text, count: int, at: str) -> tuple:
    """``count`` decimals as written (strings), each finite."""
    parts = (text or "").split()
    if len(parts) != count:
        raise SpecError(at, f"expected {count} number{'s' if count > 1 else ''}, got {text!r}")
    for p in parts:
        if not DECIMAL.fullmatch(p) or not math.isfinite(float(p)):
            raise SpecError(at, f"{p!r} is not a finite number")
    return tuple(parts)


def _attr_number(el, attr: str, at: str, default: str = "0"):
    value = el.get(attr)
    return default if value is None else _numbers(value, 1, at)[0]


def _origin(el, at: str) -> tuple:
    o = _one(el, "origin", at)
    if o is None:
        return ("0", "0", "0"), ("0", "0", "0")
    xyz = _numbers(o.get("xyz"), 3, f"{at}: <origin xyz>") if o.get("xyz") is not None else ("0", "0", "0")
    rpy = _numbers(o.get("rpy"), 3, f"{at}: <origin rpy>") if o.get("rpy") is not None else ("0", "0", "0")
    return xyz, rpy


def _inertial(link, at: str) -> Inertial | None:
    el = _one(link, "inertial", at)
    if el is None:
        return None
    xyz, rpy = _origin(el, f"{at}: <inertial>")
    mass = _one(el, "mass", at, True)
    m = _numbers(mass.get("value"), 1, f"{at}: <mass value>")[0]
    ine = _one(el, "inertia", at, True)
    I = tuple(_numbers(ine.get(k), 1, f"{at}: <inertia {k}>")[0] for k in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz"))
    return Inertial(m, xyz, rpy, I)  # checked where it enters a body of the chain (robot.py)
