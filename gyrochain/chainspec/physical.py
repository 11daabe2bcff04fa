"""What numbers must obey to describe a body: an inertia tensor that a body can have, a positive
mass, a spring that stores energy; and the values of a run's symbolic parameters (the spec's
[values], overridden by ``--param``), checked the same way as the numbers written in a spec.

``check_physical`` is called by the spec parser on numeric fields; ``run_values`` by every command
that runs a model.  Both raise SpecError naming the field (and, for a value, the parameter)."""
from __future__ import annotations

import math

import numpy as np
import sympy as sp

from .errors import SpecError

PSD_TOL = 1e-12  # a principal moment above −PSD_TOL × the largest is zero (a point mass, a thin rod)
TRIANGLE_TOL = 1e-9


def check_physical(where: str, m, c, A) -> None:
    """A minus the parallel-axis term must be a possible central inertia tensor: positive
    semidefinite (a point mass has all three principal moments zero, a slender rod one) and the
    principal moments obeying the triangle inequality.  Only decidable when m, c and A are numbers;
    with symbolic entries it is done on the run's values (``check_values``)."""
    if not all(x.is_number for x in (m, *c, *(a for row in A for a in row))):
        return
    _check_tensor(where, float(m), np.array([float(x) for x in c]), np.array([[float(a) for a in row] for row in A]))


def _check_tensor(where: str, m: float, c: np.ndarray, A: np.ndarray, label: str = "") -> None:
    with np.errstate(all="ignore"):
        AG = A - m * (c @ c * np.eye(3) - np.outer(c, c))
    if not np.all(np.isfinite(AG)):
        raise SpecError(where, "too large: the inertia about the centre of mass A − m(|c|²1 − c cᵀ) "
                               f"overflows double precision (m = {m:g}, |c| = {math.hypot(*c):g}){label}")
    ev = np.linalg.eigvalsh(AG)
    scale = max(abs(ev).max(), abs(A).max(), 1e-300)
    moments = ", ".join(f"{e:.6g}" for e in ev)
    if ev[0] < -PSD_TOL * scale:
        raise SpecError(where, "not physically possible: the inertia about the centre of mass (A − m(|c|²1 − c cᵀ)) "
                               f"has a negative principal moment (principal moments {moments}){label}")
    if ev[2] > ev[0] + ev[1] + TRIANGLE_TOL * scale:
        raise SpecError(where, "not physically possible: the central principal moments violate the triangle inequality "
                               f"({ev[2]:.6g} > {ev[0]:.6g} + {ev[1]:.6g}){label}")


def _number(expr, subs: dict, where: str, label: str) -> float:
    try:
        v = complex(expr.subs(subs) if subs else expr)
    except (TypeError, ValueError, ZeroDivisionError, OverflowError):
        v = complex(math.nan)
    if v.imag != 0 or not math.isfinite(v.real):
        raise SpecError(where, f"is not a finite real number{label}")
    return v.real


def check_values(spec, values: dict, label: str = "") -> None:
    """The spec's constant fields with these parameter values, checked like the numbers of a spec
    (``label`` says where the values came from, for the message)."""
    subs = {p: sp.Float(values[str(p)], 17) for p in spec.params if str(p) in values}
    num = lambda e, where: _number(e, subs, where, label)  # noqa: E731
    g = num(spec.g, "g")
    if g < 0:
        raise SpecError("g", f"gravity magnitude must not be negative, got {g:g}{label}")
    for k, b in enumerate(spec.bodies, start=1):
        at = f"body[{k}]"
        num(b.theta, f"{at}.theta")
        num(b.offset, f"{at}.offset")
        m = num(b.m, f"{at}.m")
        if m < 0 or (m == 0 and not b.m.is_number):  # a massless frame is written m = 0, where the derivation checks it
            raise SpecError(f"{at}.m", f"mass must be positive, got {m:g}{label}"
                                       + (" (or 0: a massless frame between two joints)" if m < 0 else
                                          " (a massless frame between two joints is written m = 0 in the spec)"))
        c = np.array([num(x, f"{at}.c") for x in b.c])
        A = np.array([[num(x, f"{at}.A") for x in row] for row in b.A])
        for x in b.s:
            num(x, f"{at}.s")
        for key, what in (("spring", "stiffness"), ("damping", "damping coefficient")):
            e = getattr(b, key)
            if e is not None and num(e, f"{at}.{key}") < 0:
                raise SpecError(f"{at}.{key}", f"a negative {what} would feed energy into the joint{label}")
        num(b.rest, f"{at}.rest")
        if num(b.armature, f"{at}.armature") < 0:
            raise SpecError(f"{at}.armature", f"a motor's reflected inertia is not negative, got "
                                              f"{num(b.armature, f'{at}.armature'):g}{label}")
        _check_tensor(f"{at}.A", m, c, A, label)


def run_values(spec, given: dict | None, what: str = "--param", needed=None) -> dict:
    """The values of a run: the spec's [values] overridden by ``given`` (the command's --param),
    every name a parameter of the spec, every parameter in ``needed`` (default: all) with a finite
    value, and the spec's numbers with these values physically possible.  {} for a numeric spec."""
    given = dict(given or {})
    names = [str(p) for p in spec.params]
    for key in given:
        if key not in names:
            raise SpecError(f"{what} {key}", "unknown parameter (the spec's are: " + (", ".join(names) or "none") + ")")
    for key, v in given.items():
        if not math.isfinite(v):
            raise SpecError(f"{what} {key}", f"{v} is not a finite number")
    values = {**(getattr(spec, "values", None) or {}), **given}
    needed = names if needed is None else list(needed)
    missing = [p for p in needed if p not in values]
    if missing:
        raise SpecError(what, "no value for " + ", ".join(missing) + " (give " + " ".join(f"{what} {p}=…" for p in missing)
                        + ", or a [values] table in the spec)")
    values = {p: float(values[p]) for p in names if p in values}
    if len(values) == len(names):
        said = [f"{what} {k}={v:g}" for k, v in given.items()]
        rest = " and the spec's [values]" if len(given) < len(names) and said else ""
        check_values(spec, values, (" with " + ", ".join(said) + rest) if said else " with the spec's [values]")
    return values
