r"""``simulate``: a trajectory of a spec as the rows of a CSV: t, $\varphi^1 \dots \varphi^n$, $\dot\varphi^1 \dots \dot\varphi^n$ and the energy
(23), by the emitted C's integrators (DOP853 with dense output at the asked times by default) or,
with ``reference``, by the independent numpy model and scipy's DOP853; and what every command
that runs a motion shares: the initial state (``initial_state``), the check that the mass matrix
is positive definite where the motion starts (``check_start``) and the C integration with a failure
as one line (``motion``)."""
from __future__ import annotations

import math

import numpy as np

from ..derive import reference
from ..chainspec.errors import SpecError
from ..chainspec.physical import run_values

METHODS = ("dop853", "rk4", "gauss2", "gauss2_symplectic")


def initial_state(spec, phi=None, phidot=None) -> list:
    r"""$x_0 = (\varphi, \dot\varphi)$: the given values, else the spec's [initial], else zero; the counts checked."""
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
           rtol: float = 1e-10, atol: float = 1e-12, max_steps: int = 0) -> np.ndarray:
    """The states at ``times`` by the emitted C's integrator (DOP853: dense output between its
    steps); a failure is a one-line error naming where it stopped."""
    from ..models.build import IntegrationError, ModelError

    check_start(model.mass_matrix(x0[: model.n], params=params or None))
    t = np.concatenate([[0.0], times]) if times[0] > 0 else times
    try:
        X = model.integrate(t, x0, method, h=h, rtol=rtol, atol=atol, u=u, params=params or None, max_steps=max_steps)
    except IntegrationError as exc:
        why = str(exc.args[0]).split(": ", 1)[-1].split(" at t =")[0]
        budget = (f" (its budget of {max_steps:.0e} steps; a shorter --t1, a looser --rtol, or --yes for 1e+08)"
                  if max_steps and "step" in why.lower() else "")
        raise SpecError("motion", f"the integrator stopped at t = {exc.t:.6g} s: {why}{budget}") from None
    except ModelError as exc:
        raise SpecError("motion", str(exc)) from None
    return X[len(t) - len(times):]


FIXED_STEP = ("rk4", "gauss2", "gauss2_symplectic")
MAX_CSV_BYTES = 200 << 20  # simulate's output past which it asks for --yes
MAX_FIXED_STEPS = 10**8  # steps of a fixed-step method past which simulate asks for --yes
MAX_ADAPTIVE_STEPS = 10**7  # DOP853's budget of steps in simulate (seconds of work); --yes lifts it to the C's 10⁸
MAX_T1 = 1e9
RK4_STABLE = 2.785  # h |lambda| on the imaginary axis where classical RK4 stops being stable (2 sqrt 2)


def check_applies(method: str, given: dict) -> None:
    """One meaning per option: --h belongs to the fixed-step methods, --rtol and --atol to DOP853
    (``given``: the options the user typed, by name)."""
    if method == "dop853" and given.get("--h") is not None:
        raise SpecError("--h", "dop853 chooses its own steps; --h is the step of rk4, gauss2 and gauss2_symplectic "
                               "(give --method, or drop --h)")
    for name in ("--rtol", "--atol"):
        if method in FIXED_STEP and given.get(name) is not None:
            raise SpecError(name, f"{method} takes fixed steps --h and has no tolerance; {name} is dop853's")


def check_size(n: int, t1: float, steps: int, method: str, h: float) -> None:
    """The work and output a run asks for, refused (SpecError, so the user can pass --yes) past
    MAX_CSV_BYTES of CSV or MAX_FIXED_STEPS fixed steps."""
    rows, cols = steps + 1, 2 * n + 2
    csv = rows * cols * 24
    if csv > MAX_CSV_BYTES:
        raise SpecError("--steps", f"{rows} rows of {cols} numbers are about {csv / 2**20:.0f} MiB of CSV (more than "
                                   f"{MAX_CSV_BYTES >> 20} MiB); fewer --steps, or --yes to write them")
    if method in FIXED_STEP and h > 0 and t1 / h > MAX_FIXED_STEPS:
        raise SpecError("--h", f"{t1 / h:.3g} steps of {h:g} s over {t1:g} s (more than {MAX_FIXED_STEPS:.0e}); a longer "
                               "--h, or --yes to take them")


def check_stability(model, x0, u, params, method: str, h: float) -> None:
    """RK4 with a step beyond its stability at the start state (h |λ|max > 2.785, λ the
    linearisation's eigenvalues) blows up: refused with the number and the step that would do."""
    if method != "rk4" or h <= 0:
        return
    try:
        A, _ = model.linearize(x0, u, params or None)
    except ArithmeticError:
        return
    lam = float(np.max(np.abs(np.linalg.eigvals(A))))
    if h * lam > RK4_STABLE:
        raise SpecError("--h", f"{h:g} s is beyond RK4's stability at the start: h |lambda|max = {h * lam:.3g} > "
                               f"{RK4_STABLE} (|lambda|max = {lam:.4g} /s), so the solution would blow up; take --h "
                               f"below {RK4_STABLE / lam:.3g} s, or --yes")


def check_options(t1: float, steps: int, method: str, h: float, rtol: float, atol: float) -> None:
    if not (math.isfinite(t1) and t1 > 0):
        raise SpecError("--t1", f"must be a positive number of seconds, got {t1:g}")
    if t1 > MAX_T1:
        raise SpecError("--t1", f"{t1:g} s is more than {MAX_T1:g} s (about 30 years) of motion: no integrator's budget of "
                                "steps reaches that; a shorter --t1")
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
    if rtol >= 1:
        raise SpecError("--rtol", f"{rtol:g} allows errors as large as the state itself; take a tolerance below 1 "
                                  "(the default is 1e-10)")


def run(spec, x0, t1: float, steps: int, u=None, params: dict | None = None, method: str = "dop853", h: float = 0.0,
        rtol: float = 1e-10, atol: float = 1e-12, use_reference: bool = False, yes: bool = False) -> np.ndarray:
    """The states at steps + 1 equal intervals of [0, t1], with the energy (23) in the last column.
    A fixed-step method without ``h`` takes 10 steps per output interval."""
    check_options(t1, steps, method, h, rtol, atol)
    values = run_values(spec, params)
    u = torques(spec, u)
    # the output times k t1/steps rounded to 15 digits: 0.1, not 0.09999999999999999, where that is what was meant
    t = np.array([float(f"{k * t1 / steps:.15g}") for k in range(steps + 1)])
    if use_reference:
        if method != "dop853":
            raise SpecError("--method", "the reference model integrates with scipy's DOP853 only")
        ch = reference.numeric(spec, values)
        check_start(reference.mass_matrix(ch, x0[: spec.n]))
        X = reference.simulate(ch, list(x0), t, u=u, rtol=rtol, atol=atol)
        return np.array([[ti, *xi, reference.energy(ch, xi, ti)] for ti, xi in zip(t, X)])
    from ..models import pipeline

    model, _ = pipeline.compiled(spec)
    if method != "dop853" and h == 0:
        h = t1 / steps / 10
    if not yes:
        check_size(spec.n, t1, steps, method, h)
        check_stability(model, np.asarray(x0, float), u, values, method, h)
    if method == "gauss2_symplectic" and not model.has_canonical:
        raise SpecError("--method", "gauss2_symplectic needs Hamilton's variables: a fixed base and no time-dependent field")
    X = motion(model, t, x0, u=u, params=values, method=method, h=h, rtol=rtol, atol=atol,
               max_steps=0 if yes or method != "dop853" else MAX_ADAPTIVE_STEPS)
    p = values or None
    return np.array([[ti, *xi, model.energy(xi, params=p, t=ti)] for ti, xi in zip(t, X)])
