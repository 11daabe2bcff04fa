"""The spec's tables of plain numbers: [values], [initial], and a joint's ``limits``.

A joint's limits are data: its range, its speed and its effort, as the robot's author wrote
them.  The model does not enforce them (a limit is a constraint of the motion, not a term of
the chain's equations); the header, MANIFEST.json and the CasADi model carry them to the
optimiser and the controller, and ``excite`` reads them.

Each parser takes ``scalar(value, where)``, the spec's reader of one entry (a number or an
expression of numbers, such as "-pi/2"), and returns floats."""
from __future__ import annotations

import math

from .errors import SpecError, did_you_mean

KEYS = ("lower", "upper", "velocity", "effort")  # rad, rad, rad/s (|φ̇| at most), N·m (|torque| at most)


def parse_limits(value, where: str, scalar) -> tuple:
    """A body's ``limits`` table as ((key, float), …) in KEYS' order; ``scalar(value, where)``
    reads one entry (a number or an expression of numbers, such as "-pi/2")."""
    if not isinstance(value, dict):
        raise SpecError(where, "expected a table {lower = …, upper = …, velocity = …, effort = …} (any of them)")
    for key in value:
        if key not in KEYS:
            raise SpecError(f"{where}.{key}", f"unknown field ({did_you_mean(key, KEYS)}expected one of {', '.join(KEYS)})")
    out = {}
    for key in (k for k in KEYS if k in value):
        x = scalar(value[key], f"{where}.{key}")
        if not x.is_number or not math.isfinite(float(x)):
            raise SpecError(f"{where}.{key}", "expected a finite number (limits are data: no parameters, no t; "
                            "leave a bound out where there is none)")
        out[key] = float(x)
    if "lower" in out and "upper" in out and not out["lower"] < out["upper"]:
        raise SpecError(f"{where}.upper", f"{out['upper']:g} is not above lower = {out['lower']:g}")
    for key in ("velocity", "effort"):
        if key in out and not out[key] > 0:
            raise SpecError(f"{where}.{key}", f"a bound on the {'speed' if key == 'velocity' else 'torque'}'s size must be "
                            f"positive, got {out[key]:g}")
    return tuple(out.items())


def spec_limits(spec) -> dict:
    """{key: n values, None where that joint has no such bound} for each key some joint has; {}
    when no joint has limits."""
    tables = [dict(b.limits) for b in spec.bodies]
    return {key: [t.get(key) for t in tables] for key in KEYS if any(key in t for t in tables)}


def parse_values(raw, params: tuple, scalar) -> dict:
    """[values]: a number (or an expression of numbers) for some or all symbolic parameters, in the
    spec's order of parameters."""
    if not isinstance(raw, dict):
        raise SpecError("values", "expected a table of parameter = number")
    names = [str(p) for p in params]
    out = {}
    for key, v in raw.items():
        if key not in names:
            raise SpecError(f"values.{key}", "not a parameter of the spec (its parameters are: " + (", ".join(names) or "none") + ")")
        if isinstance(v, (list, dict)):
            raise SpecError(f"values.{key}", "expected a number")
        e = scalar(v, f"values.{key}")
        if e.free_symbols:
            raise SpecError(f"values.{key}", "must be a number (not an expression of parameters)")
        out[key] = float(e)
    return {k: out[k] for k in names if k in out}


def parse_initial(raw, n: int, scalar) -> dict:
    """[initial]: phi and phidot, n numbers each."""
    if not isinstance(raw, dict):
        raise SpecError("initial", "expected a table with phi and phidot")
    for key in raw:
        if key not in ("phi", "phidot"):
            raise SpecError(f"initial.{key}", f"unknown field ({did_you_mean(key, ('phi', 'phidot'))}expected phi, phidot)")
    for key in ("phi", "phidot"):
        if key not in raw:
            raise SpecError(f"initial.{key}", "missing field")
    out = {}
    for key in ("phi", "phidot"):
        v = raw[key]
        if not isinstance(v, list) or len(v) != n:
            raise SpecError(f"initial.{key}", f"expected a list of {n} numbers")
        vals = []
        for i, x in enumerate(v):
            e = scalar(x, f"initial.{key}[{i + 1}]")
            if e.free_symbols:
                raise SpecError(f"initial.{key}[{i + 1}]", "must be a number")
            vals.append(float(e))
        out[key] = tuple(vals)
    return out
