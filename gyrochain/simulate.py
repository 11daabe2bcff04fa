"""``simulate``: a trajectory of a spec as the rows of a CSV: t, φ¹…φⁿ, φ̇¹…φ̇ⁿ and the energy
(23), by the emitted C's integrators (DOP853 with dense output at the asked times by default) or,
with ``reference``, by the independent numpy model and scipy's DOP853; and what every command
that runs a motion shares: the initial state (``initial_state``), the check that the mass matrix
is positive definite where the motion starts (``check_start``) and the C integration with a failure
as one line (``motion``)."""
from __future__ import annotations

import math

import numpy as np

from . import reference
from .errors import SpecError
from .physical import run_values

METHODS = ("dop853", "rk4", "gauss2", "gauss2_symplectic")


def initial_state(spec, phi=None, phidot=None) -> list:
    """x₀ = (φ, φ̇): the given values, else the spec's [initial], else zero; the counts checked."""
    n, init = spec.n, spec.initial or {}
    out = []
    for what, given, key in (("--phi", phi, "phi"), ("--phidot", phidot, "phidot")):
        vals = list(given) if given is not None else list(init.get(key, [0.0] * n))
        if len(vals) != n:
            raise SpecError(what, f"expected {n} comma-separated numbers, got {len(vals)}")
        if not all(math.isfinite(v) for v in vals):
            raise SpecError(what, "expected finite numbers")
        out += vals
    return out


def torques(spec, u) -> list | None:
    """The controlled joints' constant torques: the given ones (counted), else zero; None without controls."""
    if not spec.controls:
        if u:
            raise SpecError("--u", "the spec has no controlled joint")
        return None
    u = list(u) if u is not None else [0.0] * len(spec.controls)
    if len(u) != len(spec.controls):
        raise SpecError("--u", f"expected {len(spec.controls)} comma-separated numbers (the controlled joints "
                               f"{', '.join(map(str, spec.controls))}), got {len(u)}")
    if not all(math.isfinite(v) for v in u):
        raise SpecError("--u", "expected finite numbers")
    return u


def columns(n: int) -> list[str]:
    return ["t", *[f"phi{k}" for k in range(1, n + 1)], *[f"phidot{k}" for k in range(1, n + 1)], "energy"]


def check_start(M: np.ndarray, what: str = "state") -> None:
    """A motion starts only where the mass matrix is positive definite (otherwise φ̈ is not defined
    or the values are not a body's): the same words as the C's SINGULAR."""
    try:
        np.linalg.cholesky(M)
    except np.linalg.LinAlgError:
        ev = np.linalg.eigvalsh((M + M.T) / 2)
        raise SpecError(what, f"SINGULAR (M is not positive definite) at the start: its smallest eigenvalue is {ev[0]:.3g}") from None


def motion(model, times: np.ndarray, x0, u=None, params=None, method: str = "dop853", h: float = 0.0,
           rtol: float = 1e-10, atol: float = 1e-12) -> np.ndarray:
    """The states at ``times`` by the emitted C's integrator (DOP853: dense output between its
    steps); a failure is a one-line error naming where it stopped."""
    from .build import IntegrationError, ModelError

    check_start(model.mass_matrix(x0[: model.n], params=params or None))
    t = np.concatenate([[0.0], times]) if times[0] > 0 else times
    try:
        X = model.integrate(t, x0, method, h=h, rtol=rtol, atol=atol, u=u, params=params or None)
    except IntegrationError as exc:
        why = str(exc.args[0]).split(": ", 1)[-1].split(" at t =")[0]
        raise SpecError("motion", f"the integrator stopped at t = {exc.t:.6g} s: {why}") from None
    except ModelError as exc:
        raise SpecError("motion", str(exc)) from None
    return X[len(t) - len(times):]


def check_options(t1: float, steps: int, method: str, h: float, rtol: float, atol: float) -> None:
    if not (math.isfinite(t1) and t1 > 0):
        raise SpecError("--t1", f"must be a positive number of seconds, got {t1:g}")
    if not 1 <= steps <= 10_000_000:
        raise SpecError("--steps", f"must be a whole number of output intervals from 1 to 10⁷, got {steps}")
    if method not in METHODS:
        raise SpecError("--method", f"expected one of {', '.join(METHODS)}, got {method!r}")
    if not (math.isfinite(h) and h >= 0):
        raise SpecError("--h", f"must be a step in seconds >= 0 (0: automatic), got {h:g}")
    for name, tol in (("--rtol", rtol), ("--atol", atol)):
        if not (math.isfinite(tol) and tol >= 0):
            raise SpecError(name, f"must be a finite tolerance >= 0, got {tol:g}")
    if atol == 0:  # a component at (or through) zero would ask a purely relative tolerance for endless steps
        raise SpecError("--atol", "must be > 0: a state component at zero makes a purely relative tolerance unreachable")


def run(spec, x0, t1: float, steps: int, u=None, params: dict | None = None, method: str = "dop853", h: float = 0.0,
        rtol: float = 1e-10, atol: float = 1e-12, use_reference: bool = False) -> np.ndarray:
    """The states at steps + 1 equal intervals of [0, t1], with the energy (23) in the last column.
    A fixed-step method without ``h`` takes 10 steps per output interval."""
    check_options(t1, steps, method, h, rtol, atol)
    values = run_values(spec, params)
    u = torques(spec, u)
    t = np.linspace(0.0, t1, steps + 1)
    if use_reference:
        if method != "dop853":
            raise SpecError("--method", "the reference model integrates with scipy's DOP853 only")
        ch = reference.numeric(spec, values)
        check_start(reference.mass_matrix(ch, x0[: spec.n]))
        X = reference.simulate(ch, list(x0), t, u=u, rtol=rtol, atol=atol)
        return np.array([[ti, *xi, reference.energy(ch, xi, ti)] for ti, xi in zip(t, X)])
    from . import pipeline

    model, _ = pipeline.compiled(spec)
    if method != "dop853" and h == 0:
        h = t1 / steps / 10
    if method == "gauss2_symplectic" and not model.has_canonical:
        raise SpecError("--method", "gauss2_symplectic needs Hamilton's variables: a fixed base and no time-dependent field")
    X = motion(model, t, x0, u=u, params=values, method=method, h=h, rtol=rtol, atol=atol)
    p = values or None
    return np.array([[ti, *xi, model.energy(xi, params=p, t=ti)] for ti, xi in zip(t, X)])
