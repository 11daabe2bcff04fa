"""The emitted model held to the independent one before anything is written.

``generate`` derives a model symbolically and prints it; the independent model of
derive/reference.py (Newton–Euler in numpy, rotation matrices straight from the structural angles,
no symbolic algebra, no shortcut on exact values) shares nothing with that route but the spec.
Before the files are moved into place, the emitted model itself — the compiled C through cffi when
the command builds it, and the Python mirror — is evaluated at a few random states and compared
with the independent model (and every other command that runs a model checks its compiled C so,
once per process: pipeline.checked):

- the mass matrix M and the forces f of M φ̈ = f, entry by entry, relative to their size (a torque's
  size at least ‖M‖ times 1 rad/s², so that a torque zero by the chain's shape is zero to rounding);
- φ̈ by its residual M φ̈ − f with the independent M and f, relative to ‖M‖‖φ̈‖ + ‖f‖ (the backward
  error of the solve: a badly conditioned M does not make a correct model fail);
- NAME_rhs and NAME_linearize against NAME_qdd and NAME_qdd_derivatives of the same code;
- ∂φ̈/∂(φ, φ̇, u) along a random direction d, by the same residual of the differentiated equation,
  M (∂φ̈ d) − (∂f d − (∂M d) φ̈), with ∂f d and ∂M d from differences of the independent model;
- the energy T − U and, where emitted, the momentum (27); the regressor's torque Y π + τ₀, where
  emitted, against the independent inverse dynamics; one RK4 step of the C's integrator; the state
  the quadratures (30) give, where emitted, against the independent model integrated by scipy.

The states are drawn from a fixed seed (the same spec is checked at the same states by every
run): φ uniform in [−π, π], φ̇ and u standard normal, t uniform in [0, 3] for a model that depends
on it; a symbolic parameter the spec gives no value is drawn from [0.5, 1.5] (a state where the
drawn values make M indefinite checks M and f only).  Any difference beyond ``TOL`` (``FLOAT_TOL``
for a model in single precision) is an ``EmittedModelError`` naming the function, the state and
the difference; ``generate`` then writes nothing, and no command runs the model.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..derive import reference

STATES = 3  # random states per check
SEED = 20261128
TOL = 1e-9  # relative, double precision
FLOAT_TOL = 2e-3  # relative, single precision (about 1e4 of its rounding unit: M, f and the solve each add some)
DERIVATIVE_FACTOR = 1e3  # the derivatives' tolerance over TOL: the differences of the independent model (O(h⁴), h = 1e-3)
# the RK4 step checked: long enough that its increment stands above float's rounding of the state,
# short enough that it moves the state by STEP_MOVE at most (a stiff chain's stages stay near it)
STEP, STEP_MOVE = 1e-2, 1e-3
QUAD_T = 0.7  # the time the quadratures' state is checked at


def tolerances(single: bool = False) -> tuple[float, float]:
    """The relative tolerances of the check: of what is compared with the independent model's
    values, and of what is compared with its differences or its integration (their own error
    about 1e-10: the derivatives, the regressor, an RK4 step, the quadratures); ``single``: for a
    model in single precision."""
    return (FLOAT_TOL, FLOAT_TOL * 10) if single else (TOL, TOL * DERIVATIVE_FACTOR)


class EmittedModelError(RuntimeError):
    """The emitted model differs from the independent model: a defect of the generator."""


@dataclass
class _State:
    x: np.ndarray
    u: np.ndarray | None
    t: float

    def text(self, n: int, timed: bool) -> str:
        fmt = lambda v: "(" + ", ".join(f"{float(a):.6g}" for a in v) + ")"  # noqa: E731
        out = f"phi = {fmt(self.x[:n])}, phidot = {fmt(self.x[n:])}"
        if self.u is not None:
            out += f", u = {fmt(self.u)}"
        return out + (f", t = {self.t:.6g}" if timed else "")


class PythonMirror:
    """The generated Python module called as build.CModel is (the state first, t last)."""

    def __init__(self, module, time_dependent: bool):
        self.mod, self.time_dependent = module, time_dependent
        self.n, self.nu = module.N, len(module.CONTROLS)
        self.has_momentum = hasattr(module, "momentum")
        self.real = "double"

    def _t(self, t) -> tuple:
        return (float(t),) if self.time_dependent else ()

    def mass_matrix(self, q, params=None):
        return np.asarray(self.mod.mass_matrix(q, params))

    def forces(self, x, u=None, params=None, t=0.0):
        return np.asarray(self.mod.forces(*self._t(t), x, u, params))

    def qdd(self, x, u=None, params=None, t=0.0):
        return np.asarray(self.mod.qdd(*self._t(t), x, u, params))

    def rhs(self, t, x, u=None, params=None):
        return np.asarray(self.mod.rhs(t, x, u, params))

    def qdd_derivatives(self, x, u=None, params=None, t=0.0):
        return tuple(np.asarray(a) for a in self.mod.qdd_derivatives(*self._t(t), x, u, params))

    def linearize(self, x, u=None, params=None, t=0.0):
        return tuple(np.asarray(a) for a in self.mod.linearize(t, x, u, params))

    def energy(self, x, params=None, t=0.0):
        return float(self.mod.energy(*self._t(t), x, params))

    def momentum(self, x, params=None, t=0.0):
        return float(self.mod.momentum(*self._t(t), x, params))

    @property
    def has_quadratures(self) -> bool:
        return hasattr(self.mod, "quad_state")

    def quad_state(self, t, x0, params=None):
        return np.asarray(self.mod.quad_state(t, x0, params))


def parameters(spec, rng: np.random.Generator | None = None) -> dict | None:
    """The values the check uses: the spec's [values], and for a parameter without one a number
    drawn from [0.5, 1.5]; None for a spec without symbolic parameters."""
    if not spec.params:
        return None
    rng = rng or np.random.default_rng(SEED)
    given = {str(k): float(v) for k, v in spec.values.items()}
    return {str(p): given[str(p)] if str(p) in given else float(rng.uniform(0.5, 1.5)) for p in spec.params}


def states(spec, rng: np.random.Generator, count: int = STATES) -> list[_State]:
    n, nu = spec.n, len(spec.controls)
    out = []
    for _ in range(count):
        x = np.concatenate([rng.uniform(-math.pi, math.pi, n), rng.normal(size=n)])
        u = rng.normal(size=nu) if nu else None
        out.append(_State(x, u, float(rng.uniform(0.0, 3.0))))
    return out


class _Checker:
    def __init__(self, spec, target, ch, params, what: str):
        self.spec, self.target, self.ch, self.params, self.what = spec, target, ch, params, what
        self.n = spec.n
        single = getattr(target, "real", "double") == "float"
        self.tol, self.dtol = tolerances(single)
        # where M's smallest eigenvalue is below this of its largest, the emitted model may call M singular
        # (its pivots at rounding; float's rounding is 1e9 times double's)
        self.singular = 1e-4 if single else 1e-9
        # a value of φ̈ (not its residual) is good to about eps / (M's smallest eigenvalue over its largest):
        # the RK4 step is compared where that is 1e-3 or better
        self.conditioned = 1e3 * float(np.finfo(np.float32 if single else np.float64).eps)
        self.prefix = spec.name
        self.floor = 1e-300  # the state's ‖M‖ (run)
        self.worst: dict = {}  # function → its largest difference over its tolerance, in the order compared

    def fail(self, fn: str, state: _State | None, diff: float, tol: float, detail: str = "") -> None:
        where = f" at {state.text(self.n, self.target.time_dependent)}" if state is not None else ""
        raise EmittedModelError(
            f"the emitted {self.what} {self.prefix}_{fn} differs from the independent model by {diff:.3g} "
            f"(relative; tolerance {tol:.1g}){detail}{where}: a defect of the generator")

    def close(self, fn: str, state, got, want, scale: float, tol: float | None = None, detail: str = "") -> None:
        tol = self.tol if tol is None else tol
        got, want = np.asarray(got, dtype=float), np.asarray(want, dtype=float)
        if got.shape != want.shape:
            self.fail(fn, state, math.inf, tol, f" (shape {got.shape}, expected {want.shape})")
        diff = float(np.max(np.abs(got - want))) / scale if got.size else 0.0
        if not diff <= tol:  # NaN fails too
            self.fail(fn, state, diff, tol, detail)
        self.worst[fn] = max(self.worst.get(fn, 0.0), diff / tol)

    # ---- the independent model's pieces
    def M(self, x):
        return reference.mass_matrix(self.ch, x[: self.n])

    def f(self, x, u, t):
        return reference.forces(self.ch, x, u, t)

    def run(self, rng: np.random.Generator, count: int) -> None:
        drawn = states(self.spec, rng, count)
        for s in drawn:
            M_ref, f_ref = self.M(s.x), self.f(s.x, s.u, s.t)
            # ‖M‖ is also the floor of every torque's scale (the torque of 1 rad/s²): a torque that
            # is zero by the chain's shape (a body on its own axis) is zero to rounding, not to 1e-9 of itself
            self.floor = scale_M = max(float(np.max(np.abs(M_ref))), 1e-300)
            smallest = float(np.linalg.eigvalsh((M_ref + M_ref.T) / 2)[0]) / scale_M
            try:
                self._state(s, M_ref, f_ref, smallest, rng)
            except ArithmeticError as exc:  # SINGULAR or NONFINITE from the emitted model
                if smallest <= self.singular:
                    continue  # next to a singular configuration (a ball joint's lock): M's pivots at its rounding
                where = s.text(self.n, self.target.time_dependent)
                raise EmittedModelError(
                    f"the emitted {self.what} model refused a state the independent model computes ({exc}; M's smallest "
                    f"eigenvalue is {smallest:.3g} of its largest) at {where}: a defect of the generator") from None
        self._quadratures(drawn[0])

    def _state(self, s, M_ref, f_ref, smallest, rng) -> None:
        """Every comparison at the state ``s``."""
        T, n, p, scale_M = self.target, self.n, self.params, self.floor
        self.close("mass_matrix", s, T.mass_matrix(s.x[:n], p), M_ref, scale_M)
        self.close("forces", s, T.forces(s.x, s.u, p, t=s.t), f_ref, max(float(np.max(np.abs(f_ref))), scale_M))
        E_ref, U_ref = reference.energy(self.ch, s.x, s.t), reference.potential(self.ch, s.x, s.t)
        # relative to |T| + |U|: T − U may cancel to far less than either
        self.close("energy", s, T.energy(s.x, p, t=s.t), E_ref, max(abs(E_ref + U_ref) + abs(U_ref), 1e-300))
        if T.has_momentum:
            K_ref = reference.momentum(self.ch, s.x, s.t)
            self.close("momentum", s, T.momentum(s.x, p, t=s.t), K_ref,
                       max(abs(K_ref), scale_M * float(np.max(np.abs(s.x[n:])))))
        if smallest <= 1e-12:
            return  # drawn parameter values that make M indefinite here: M and f only
        qdd = T.qdd(s.x, s.u, p, t=s.t)
        self._residual("qdd", s, M_ref, qdd, f_ref)
        self.close("rhs", s, T.rhs(s.t, s.x, s.u, p), np.concatenate([s.x[n:], qdd]),
                   max(float(np.max(np.abs(qdd))), float(np.max(np.abs(s.x[n:]))), 1e-300))
        self._derivatives(s, M_ref, f_ref, qdd, rng)
        self._regressor(s, qdd)
        if smallest > self.conditioned:  # the step compares values, not residuals: where the precision holds them
            self._rk4_step(s)

    def _residual(self, fn, s, M, qdd, f, tol=None, detail=""):
        """M φ̈ − f relative to ‖M‖‖φ̈‖ + ‖f‖ (the backward error of φ̈)."""
        qdd = np.asarray(qdd, dtype=float)
        scale = float(np.max(np.abs(M)) * np.max(np.abs(qdd)) + np.max(np.abs(f)))
        self.close(fn, s, M @ qdd - f, np.zeros_like(f), max(scale, self.floor), tol, detail)

    def _derivatives(self, s, M, f, qdd, rng) -> None:
        """∂φ̈ along a random direction (dφ, dφ̇, du), by the differentiated M φ̈ = f."""
        T, n, p = self.target, self.n, self.params
        q, dq, dv, du = T.qdd_derivatives(s.x, s.u, p, t=s.t)
        self._residual("qdd_derivatives", s, M, q, f, detail=" (its qdd output)")
        d = rng.normal(size=2 * n)
        e = rng.normal(size=len(s.u)) if s.u is not None else None
        got = dq @ d[:n] + dv @ d[n:] + (du @ e if e is not None else 0.0)

        def at(h):
            x, u = s.x + h * d, (s.u + h * e if e is not None else None)
            return np.concatenate([self.M(x).ravel(), self.f(x, u, s.t)])

        D = _richardson(at)
        dM, df = D[: n * n].reshape(n, n), D[n * n:]
        tol = self.dtol
        scale = float(np.max(np.abs(M)) * np.max(np.abs(got)) + np.max(np.abs(df)) + np.max(np.abs(dM)) * np.max(np.abs(qdd)))
        self.close("qdd_derivatives", s, M @ got - (df - dM @ qdd), np.zeros(n), max(scale, self.floor), tol,
                   " (along a random direction)")
        A, B = T.linearize(s.x, s.u, p, t=s.t)
        want_A = np.zeros((2 * n, 2 * n))
        want_A[:n, n:], want_A[n:, :n], want_A[n:, n:] = np.eye(n), dq, dv
        self.close("linearize", s, A, want_A, max(float(np.max(np.abs(want_A))), 1e-300), detail=" (A)")
        if du.size:
            want_B = np.zeros((2 * n, du.shape[1]))
            want_B[n:] = du
            self.close("linearize", s, B, want_B, max(float(np.max(np.abs(want_B))), 1e-300), detail=" (B)")

    def _regressor(self, s, qdd) -> None:
        T, n, p = self.target, self.n, self.params
        if not hasattr(T, "lib") or not hasattr(T.lib, f"{T.name}_regressor"):
            return
        Y, tau0 = T.regressor(s.x[:n], s.x[n:], qdd, p, t=s.t)
        pi = T.standard_parameters(p)
        want = reference.joint_torques(self.ch, s.u) if s.u is not None else np.zeros(n)
        got = Y @ pi + tau0
        # at φ̈ the joint torques that the model's own φ̈ needs are the controls (u) and nothing else
        self.close("regressor", s, got, want, max(float(np.max(np.abs(Y @ pi))), float(np.max(np.abs(want))), self.floor),
                   self.dtol, " (Y pi + tau0 at the model's own qdd, against the control torques)")

    def _rk4_step(self, s) -> None:
        T = self.target
        if not hasattr(T, "integrate"):
            return
        x, u, p = s.x, s.u, self.params
        f = lambda t, y: reference.rhs(self.ch, t, y, u)  # noqa: E731
        real = getattr(T, "dtype", np.float64)
        t0 = float(real(s.t))  # the times the C's grid holds, and the step between them exactly
        k1 = f(t0, x)
        h = min(STEP, STEP_MOVE * max(1.0, float(np.max(np.abs(x)))) / max(float(np.max(np.abs(k1))), 1e-300))
        if h < 1e3 * float(np.finfo(real).eps) * abs(t0):  # a step lost in t's digits (a stiff chain, in float): from t = 0
            t0 = 0.0
            k1 = f(t0, x)
        t1 = float(real(t0 + h))
        h = t1 - t0
        k2 = f(t0 + h / 2, x + h / 2 * k1)
        k3 = f(t0 + h / 2, x + h / 2 * k2)
        k4 = f(t1, x + h * k3)
        want = x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        got = T.integrate([t0, t1], x, "rk4", h=h, u=u, params=p)[-1]
        scale = h * max(float(np.max(np.abs(k1))), 1e-300)
        self.close("integrate", s, got, want, scale, self.dtol, " (one RK4 step)")

    def _quadratures(self, s) -> None:
        """The state the quadratures (30) give at t = QUAD_T from the first state (its rates
        halved), against the independent model integrated there."""
        T = self.target
        has = T.has_quadratures if isinstance(T, PythonMirror) else hasattr(T.lib, f"{T.name}_quad_state")
        if not has:
            return
        x0 = np.concatenate([s.x[: self.n], 0.5 * s.x[self.n:]])
        M = self.M(x0)
        if np.linalg.eigvalsh((M + M.T) / 2)[0] <= self.conditioned * np.max(np.abs(M)):
            return  # values, not residuals: where the precision holds them
        try:
            got = T.quad_state(QUAD_T, x0, self.params)
        except ArithmeticError:  # a motion on the separatrix, which the quadratures refuse
            return
        want = reference.simulate(self.ch, x0, [0.0, QUAD_T])[-1]
        self.close("quad_state", s, got, want, max(float(np.max(np.abs(want))), 1e-300), self.dtol,
                   f" (the state at t = {QUAD_T} from phi, phidot / 2)")


def _richardson(f, h: float = 1e-3) -> np.ndarray:
    """d/ds f(s) at s = 0: central differences with one Richardson step (error O(h⁴))."""
    d1 = (f(h) - f(-h)) / (2 * h)
    d2 = (f(h / 2) - f(-h / 2)) / h
    return (4 * d2 - d1) / 3


def check(spec, target, what: str = "C", count: int = STATES, seed: int = SEED) -> dict[str, float]:
    """Hold ``target`` (a build.CModel, or a ``PythonMirror``) to the independent model of
    ``spec`` at ``count`` random states; an ``EmittedModelError`` at the first difference.
    Returns the functions compared (without the model's name), in order, each with its largest
    difference over its tolerance (under 1: the margin the check had)."""
    rng = np.random.default_rng(seed)
    params = parameters(spec, rng)
    ch = reference.numeric(spec, params)
    checker = _Checker(spec, target, ch, params, what)
    checker.run(rng, count)
    return dict(checker.worst)
