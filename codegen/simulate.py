"""``simulate``: a trajectory of a spec by the independent reference model (reference.py), as
the rows of a CSV: t, φ¹…φⁿ, φ̇¹…φ̇ⁿ and the energy; and the initial state every command starts
from (``initial_state``)."""
from __future__ import annotations

import numpy as np

from . import reference
from .spec import SpecError


def initial_state(spec, phi=None, phidot=None) -> list:
    """x₀ = (φ, φ̇): the given values, else the spec's [initial], else zero; the counts checked."""
    n, init = spec.n, spec.initial or {}
    out = []
    for what, given, key in (("--phi", phi, "phi"), ("--phidot", phidot, "phidot")):
        vals = list(given) if given is not None else list(init.get(key, [0.0] * n))
        if len(vals) != n:
            raise SpecError(what, f"expected {n} comma-separated numbers, got {len(vals)}")
        out += vals
    return out


def columns(n: int) -> list[str]:
    return ["t", *[f"phi{k}" for k in range(1, n + 1)], *[f"phidot{k}" for k in range(1, n + 1)], "energy"]


def run(spec, x0, t1: float, steps: int, u=None, params: dict | None = None) -> np.ndarray:
    """The states at steps + 1 equal intervals of [0, t1], with the energy (23) in the last column."""
    try:
        ch = reference.numeric(spec, params or {})
    except ValueError as exc:
        raise SpecError("--param", str(exc)) from None
    t = np.linspace(0.0, t1, steps + 1)
    X = reference.simulate(ch, list(x0), t, u=u)
    return np.array([[ti, *xi, reference.energy(ch, xi, ti)] for ti, xi in zip(t, X)])
