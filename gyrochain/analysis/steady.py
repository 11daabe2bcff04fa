r"""Steady motions of a generated model and their stability: ``python -m gyrochain steady SPEC``.

Everything here runs on the emitted C through its exact derivatives (NAME_qdd_derivatives,
NAME_mass_matrix); nothing is differenced.

* Equilibria: $\dot\varphi = 0$, $\ddot\varphi(\varphi) = 0$, by Newton's method with
  $\partial\ddot\varphi/\partial\varphi$ from a documented set of starts (``STARTS``).  When
  $\varphi^1$ is cyclic ($l^1$ vertical, no torque in joint 1:
  $\partial\ddot\varphi/\partial\varphi^1 \equiv 0$) an equilibrium is the $\omega = 0$ member of
  the steady rotations below and $\varphi^1$ is arbitrary (reported as 0).
* Steady rotations / precessions $\dot\varphi^1 = \omega$, $\varphi^2, \dots$ at rest, where
  $\varphi^1$ is cyclic: $\ddot\varphi^r(\varphi; \omega) = 0$ for $r \ge 2$ (then
  $\ddot\varphi^1 = 0$ too, from the conservation of $p_1 = \partial\mathcal{L}/\partial\dot\varphi^1$),
  continued over a grid of $\omega$ and joined into branches; new branches are looked for from
  every start at every $\omega$.
* Stability.  The linearisation A = NAME_linearize; for a steady rotation the reduced system at
  fixed momentum: $\delta\varphi^1$ drops out (cyclic), and
  $\delta\dot\varphi^1 = -(\partial p_1/\partial\varphi^r\,\delta\varphi^r + M_{1r}\,\delta\dot\varphi^r)/M_{11}$
  on $\delta p_1 = 0$, where $\partial p_1/\partial\dot\varphi = M_{1\cdot}$ (the first row of M)
  and $\partial p_1/\partial\varphi^r = -M_{1\cdot}\,\partial\ddot\varphi/\partial\dot\varphi^r$
  ($p_1$ is conserved, so its gradient is a left null vector of A).  The reduced equations are
  $M_{\mathrm{red}}\,\delta\ddot q + G\,\delta\dot q + K\,\delta q = 0$ with
  $M_{\mathrm{red}} = M_{rr} - M_{r1} M_{1r}/M_{11}$ (Routh), so
  $K = -M_{\mathrm{red}}\,\partial\delta\ddot q/\partial\delta q$ is the Hessian of the energy at an
  equilibrium, of the amended potential at a steady rotation (Routh), and G the gyroscopic
  matrix.  Verdicts (``classify``):
  - "unstable": an eigenvalue of A with positive real part (Lyapunov's first method);
  - "stable (energy–momentum)": K positive definite and the energy (or Jacobi) integral exists
    at constant u — a Lyapunov function (Lagrange–Dirichlet; Routh for steady rotations);
  - "asymptotically stable": every eigenvalue in the open left half plane (damping);
  - "linearly stable": every eigenvalue on the imaginary axis and distinct; when K is not
    positive definite this is gyroscopic stabilisation (Kelvin–Tait–Chetaev), stable to first
    order but not proved by the linearisation — the reason says so;
  - "degenerate": a zero eigenvalue of K (a family of steady motions, or higher-order terms
    decide).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from . import floquet
from .floquet import STARTS, distinct, fmt_phi, found_line, start_grid, verdict_segments
from .floquet import wrap as _wrap


class SteadyError(ValueError):
    """Bad input to the analysis (one line, naming what)."""


@dataclass
class Steady:
    phi: np.ndarray  # the coordinates (φ¹ = 0 when it is cyclic)
    omega: float  # φ̇¹ (0 for an equilibrium)
    eigenvalues: np.ndarray  # of the (reduced) linearisation
    K: np.ndarray  # Hessian of the energy / amended potential (reduced coordinates)
    G: np.ndarray  # gyroscopic (and damping) matrix
    verdict: str
    reason: str


@dataclass
class Branch:
    """Steady rotations continued over ω: ``points`` in increasing ω; ``changes`` the values of ω
    where the verdict changes (refined by bisection), with the verdicts on either side."""

    points: list = field(default_factory=list)
    changes: list = field(default_factory=list)


def _apart(phi, branches) -> np.ndarray:
    """How far ``phi`` is from each branch's last point (the largest wrapped coordinate difference),
    for all of them at once: an arm's continuation carries thousands of branches."""
    if not branches:
        return np.zeros(0)
    last = np.array([b.points[-1].phi for b in branches])
    return np.max(np.abs(_wrap(last - phi)), axis=1)


TIME_DEPENDENT = "steady: the model depends on t (a moving platform or a load of t): it has no steady motions in this sense"


def check_inputs(spec, params, u) -> None:
    """The inputs the analysis needs, checked before anything is built."""
    missing = [str(p) for p in spec.params if params is None or str(p) not in params]
    if missing:
        raise SteadyError("--param: give a value for every symbolic parameter; missing: " + ", ".join(missing))
    if u is not None and not np.all(np.isfinite(u)):
        raise SteadyError("--u: not finite")


class Analysis:
    """A built model (gyrochain.build.CModel) with the facts the verdicts need."""

    def __init__(self, cmodel, model, params=None, u=None):
        from ..derive.assemble import time_dependent

        spec = model.spec
        self.c, self.n = cmodel, spec.n
        if time_dependent(model):
            raise SteadyError(TIME_DEPENDENT)
        check_inputs(spec, params, u)
        if u is None and spec.controls:  # the control torques default to zero, as in every command
            u = np.zeros(len(spec.controls))
        self.params, self.u = params, (None if u is None else np.asarray(u, float))
        ints = model.integrals
        others = [r for r in ints.energy_reasons if not r.startswith("control torques")]
        self.conservative = not others or ints.jacobi is not None
        self.others = others
        self.integral = "Jacobi integral" if ints.jacobi is not None and others else "energy"
        u1 = 1 in spec.controls and self.u[spec.controls.index(1)] != 0.0
        self.cyclic = ints.momentum is not None and not u1 and self._cyclic_numerically()
        # φ¹ may be absent while p₁ still is not conserved: damping or a torque of φ̇ in joint 1.
        # Then any φ¹ is an equilibrium, but there are no steady rotations, and δp₁ is not fixed.
        self.drains = [r for r in ints.momentum_reasons if r != "control torque in joint 1"] if self.cyclic else []
        self.rate = self._reference_rate()

    def _reference_rate(self) -> float:
        """The fastest rate of the linearisations at rest over the starts (the scale of 'zero'
        for eigenvalues and for K / M)."""
        rate = 0.0
        for s in self.starts():
            try:
                A, _ = self.c.linearize(np.concatenate([s, np.zeros(self.n)]), self.u, self.params)
            except ArithmeticError:
                continue
            rate = max(rate, np.max(np.abs(np.linalg.eigvals(A))))
        return rate if rate > 0 else 1.0

    def _cyclic_numerically(self) -> bool:
        rng = np.random.default_rng(0)
        for _ in range(2):
            x = np.concatenate([rng.uniform(-3, 3, self.n), rng.normal(size=self.n)])
            try:
                _, dq, _, _ = self.c.qdd_derivatives(x, self.u, self.params)
            except ArithmeticError:
                continue
            if np.max(np.abs(dq[:, 0])) > 1e-13 * max(1.0, np.max(np.abs(dq))):
                return False
        return True

    # ---- Newton on φ̈ = 0
    def solve(self, start, omega: float = 0.0, tol: float = 1e-12, iters: int = 60):
        """Newton (least squares, with backtracking) for φ̈ = 0 in the free coordinates; None if
        it does not converge."""
        n = self.n
        free = list(range(1, n)) if self.cyclic else list(range(n))
        phi = np.array(start, float)
        if self.cyclic:
            phi[0] = 0.0

        def resid(ph):
            x = np.concatenate([ph, [omega if self.cyclic else 0.0] + [0.0] * (n - 1)])
            q, dq, _, _ = self.c.qdd_derivatives(x, self.u, self.params)
            return q[free], dq[np.ix_(free, free)]

        if not free:
            return phi
        try:
            r, J = resid(phi)
        except ArithmeticError:
            return None
        scale = max(1.0, np.max(np.abs(J)))
        for _ in range(iters):
            if np.max(np.abs(r)) <= tol * scale:
                return phi
            step = np.linalg.lstsq(J, -r, rcond=None)[0]
            lam = 1.0
            while lam > 1e-4:
                trial = phi.copy()
                trial[free] += lam * step
                try:
                    r2, J2 = resid(trial)
                except ArithmeticError:
                    lam /= 2
                    continue
                if np.max(np.abs(r2)) < np.max(np.abs(r)) or np.max(np.abs(r2)) <= tol * scale:
                    break
                lam /= 2
            else:
                return None
            phi, r, J = trial, r2, J2
        return phi if np.max(np.abs(r)) <= 1e3 * tol * scale else None

    def starts(self, extra=()):
        pre = [0.0] if self.cyclic else []
        grid = start_grid(self.n - 1 if self.cyclic else self.n)
        return [np.array(pre + g) for g in grid] + [np.asarray(e, float) for e in extra]

    # ---- the linearisation and the verdict
    def classify(self, phi, omega: float = 0.0) -> Steady:
        n = self.n
        x = np.concatenate([phi, [omega if self.cyclic else 0.0] + [0.0] * (n - 1)])
        _, dq, dv, _ = self.c.qdd_derivatives(x, self.u, self.params)
        M = self.c.mass_matrix(x[:n], self.params)
        if self.cyclic and self.drains:  # δφ¹ drops out, δφ̇¹ stays a state (p₁ is not conserved)
            Kq, Kv, Mr = dq[1:, 1:], dv, M[1:, 1:]
            terms = np.max(np.abs(Kq), initial=0.0)
            m = n - 1
            A = np.block([[np.zeros((m, m)), np.zeros((m, 1)), np.eye(m)], [dq[:, 1:], dv]])
            K, G = -Mr @ Kq, -Mr @ dv[1:, 1:]
            return self._steady(phi, omega, A, (K + K.T) / 2, G, Mr, terms)
        if self.cyclic:
            l_v = M[0]
            l_q = -l_v @ dv[:, 1:]  # ∂p₁/∂φʳ, r ≥ 2
            col = dv[1:, 0]  # how φ̈ʳ reads δφ̇¹
            corr = np.outer(col, l_q / l_v[0])
            Kq = dq[1:, 1:] - corr
            terms = max(np.max(np.abs(dq[1:, 1:]), initial=0.0), np.max(np.abs(corr), initial=0.0))
            Kv = dv[1:, 1:] - np.outer(col, l_v[1:] / l_v[0])
            Mr = M[1:, 1:] - np.outer(M[1:, 0], M[0, 1:]) / M[0, 0]
        else:
            Kq, Kv, Mr = dq, dv, M
            terms = np.max(np.abs(dq))
        m = Kq.shape[0]
        A = np.block([[np.zeros((m, m)), np.eye(m)], [Kq, Kv]]) if m else np.zeros((0, 0))
        K, G = -Mr @ Kq, -Mr @ Kv
        return self._steady(phi, omega, A, (K + K.T) / 2, G, Mr, terms)

    def _steady(self, phi, omega, A, K, G, Mr, terms) -> Steady:
        m = K.shape[0]
        ev = np.linalg.eigvals(A) if A.size else np.zeros(0)
        # what zero means for K: round-off of the terms it was computed from, and a floor at
        # 1e-14 of the fastest rate's scale (K exactly zero in exact arithmetic)
        big = np.max(np.abs(Mr)) if m else 1.0
        kzero = max(1e-11 * big * terms, 1e-14 * big * max(self.rate, abs(omega)) ** 2)
        verdict, reason = self._verdict(ev, K, G, kzero, omega)
        return Steady(np.array(phi, float), float(omega), ev, K, G, verdict, reason)

    def _verdict(self, ev, K, G, kzero: float, omega: float):
        """``kzero``: below this an eigenvalue of K counts as zero."""
        if not len(ev):
            return "stable (energy–momentum)", "no coordinate left to perturb: a uniform rotation of the whole chain"
        size = max(self.rate, abs(omega), np.max(np.abs(ev)))
        tol = 1e-7 * size
        kev = np.linalg.eigvalsh(K)
        neg = int(np.sum(kev < -kzero))
        zero = int(np.sum(np.abs(kev) <= kzero))
        what = "amended potential" if self.cyclic and not self.drains else ("energy" if self.integral == "energy" else "effective potential (Jacobi integral)")
        worst = ev[np.argmax(ev.real)]
        if worst.real > tol:
            why = f"eigenvalue {worst.real:.6g}{worst.imag:+.6g}i has a positive real part"
            if neg:
                why += f"; the Hessian of the {what} has {neg} negative eigenvalue{'s' if neg > 1 else ''}"
            return "unstable", why
        if self.conservative and neg == 0 and zero == 0:
            return "stable (energy–momentum)", f"the Hessian of the {what} is positive definite (smallest eigenvalue {kev[0]:.6g})"
        if np.all(ev.real < -tol):
            return "asymptotically stable", f"every eigenvalue has a negative real part (largest {worst.real:.6g})"
        if zero:
            return "degenerate", f"the Hessian of the {what} is singular ({zero} zero eigenvalue{'s' if zero > 1 else ''}): a family of steady motions or higher-order terms decide"
        if neg:
            plural = "s" if neg > 1 else ""
            gyroscopic = np.max(np.abs(G - G.T), initial=0.0) > 1e-9 * max(1.0, np.max(np.abs(K), initial=0.0))
            if not gyroscopic and not self.conservative:  # Ziegler's column: the follower load, not Γ, does it
                return "linearly stable", (f"every eigenvalue is on the imaginary axis although the Hessian of the {what} has "
                                           f"{neg} negative eigenvalue{plural}: not by gyroscopic terms (there are none) but "
                                           f"by the non-conservative loads ({', '.join(self.others)}); stable to first order, "
                                           "not proved")
            return "linearly stable", (f"gyroscopic stabilisation: the Hessian of the {what} has {neg} negative eigenvalue{plural}, the "
                                       "gyroscopic terms make every eigenvalue imaginary (stable to first order, not proved)")
        return "linearly stable", "every eigenvalue is on the imaginary axis"

    # ---- the searches
    def equilibria(self, extra_starts=()) -> list[Steady]:
        return [self.classify(p, 0.0) for p in distinct(self.starts(extra_starts), lambda s: self.solve(s, 0.0))]

    def rotations(self, omegas, extra_starts=()) -> list[Branch]:
        """Steady rotations φ̇¹ = ω over the grid ``omegas`` (increasing), as branches."""
        if not self.cyclic:
            raise SteadyError("--omega: phi1 is not cyclic (l1 not vertical, or a torque in joint 1): no steady rotations")
        if self.drains:
            raise SteadyError(f"--omega: {', '.join(self.drains)} acts in joint 1: a rotation about l1 would lose its "
                              "momentum, so there are no steady rotations (the equilibria are analysed)")
        omegas = np.asarray(omegas, float)
        branches: list[Branch] = []
        active: list[Branch] = []
        for w in omegas:
            still, ended = [], []
            for br in active:
                last = br.points[-1]
                phi = self.solve(last.phi, w)
                if phi is None or np.max(np.abs(_wrap(phi - last.phi))) >= 0.5:
                    ended.append(br)  # a fold, or Newton jumped away (steep near a pitchfork)
                    continue
                phi = _wrap(phi)
                if (_apart(phi, still) < 1e-6).any():
                    ended.append(br)  # Newton fell onto a branch already continued (a pitchfork)
                    continue
                br.points.append(self.classify(phi, w))
                still.append(br)
            active = still
            for s in self.starts(extra_starts):
                phi = self.solve(s, w)
                if phi is None:
                    continue
                phi = _wrap(phi)
                if (_apart(phi, active) < 1e-6).any():
                    continue
                gaps = _apart(phi, ended)
                if (gaps < 1.0).any():  # the branch Newton lost from its last point, found again from a start
                    br = ended.pop(int(np.argmin(gaps)))  # (by position: a Branch holds arrays, == is ambiguous)
                    br.points.append(self.classify(phi, w))
                else:
                    br = Branch([self.classify(phi, w)])
                    branches.append(br)
                active.append(br)
        for br in branches:
            self._changes(br)
        return branches

    def _changes(self, br: Branch) -> None:
        for a, b in zip(br.points, br.points[1:]):
            if a.verdict == b.verdict:
                continue
            lo, hi, phi = a.omega, b.omega, a.phi
            for _ in range(50):
                mid = (lo + hi) / 2
                p = self.solve(phi, mid)
                if p is None:
                    break
                if self.classify(_wrap(p), mid).verdict == a.verdict:
                    lo, phi = mid, _wrap(p)
                else:
                    hi = mid
                if hi - lo <= 1e-12 * max(1.0, abs(hi)):
                    break
            br.changes.append(((lo + hi) / 2, a.verdict, b.verdict))


# --------------------------------------------------------------------------- report
def _fmt_ev(ev, digits: int = 10) -> str:
    """The eigenvalues as printed: a part below 1e-12 of the largest modulus is the eigensolver's
    round-off and prints as 0 (as does one below 1e-12 /s; the verdicts are decided on the unrounded values, with their own
    tolerance), so the same spec prints the same line on every machine."""
    tiny = 1e-12 * max(max((abs(z) for z in ev), default=0.0), 1.0)  # 1/s: a rate of 1e-12/s is zero
    ev = [complex(z.real if abs(z.real) > tiny else 0.0, z.imag if abs(z.imag) > tiny else 0.0) for z in ev]
    ev = sorted(ev, key=lambda z: (-z.real, -z.imag))
    return ", ".join(f"{z.real:.{digits}g}{z.imag:+.{digits}g}i" if abs(z.imag) > 0 else f"{z.real:.{digits}g}" for z in ev)


def report(an, eqs, branches=None, omegas=None, digits: int | None = None, most: int | None = None, at=None) -> str:
    """The printed analysis: of an autonomous model (Analysis: equilibria, steady rotations), or of
    a time-periodic one (floquet.DrivenAnalysis: ``branches`` are then its continuations along
    ``--vary`` and ``omegas`` their values).  ``digits``: of the eigenvalues (default 10) or the
    multipliers (default 4); ``most``: the equilibria printed (all by default); ``at``: the one
    Newton start the equilibrium was found from (--at)."""
    if isinstance(an, floquet.DrivenAnalysis):
        return floquet.report(an, eqs, branches, omegas, digits=digits or 4, most=most, at=at)
    out = []
    n = an.n
    cyc = " (phi1 is cyclic: any phi1; phi1 = 0 shown)" if an.cyclic else ""
    out.append(f"equilibria{cyc}: {found_line(eqs, most, at, STARTS)}")
    for e in eqs[:most]:
        out.append(f"  phi = {fmt_phi(e.phi)}: {e.verdict}: {e.reason}")
        out.append(f"    eigenvalues: {_fmt_ev(e.eigenvalues, digits or 10)}")
    if branches is not None:
        out.append(f"steady rotations phidot1 = omega, phi2..{n} at rest, omega in [{omegas[0]:.6g}, {omegas[-1]:.6g}] ({len(omegas)} values): {len(branches)} branch{'es' if len(branches) != 1 else ''}")
        for i, br in enumerate(branches, 1):
            a, b = br.points[0], br.points[-1]
            out.append(f"  branch {i}: omega {a.omega:.6g} .. {b.omega:.6g}, phi from {fmt_phi(a.phi)} to {fmt_phi(b.phi)}")
            out += ["    " + ln for ln in verdict_segments([(p.omega, p.verdict, p.reason) for p in br.points], "omega")]
            for w, v1, v2 in br.changes:
                out.append(f"    verdict changes at omega = {w:.10g}: {v1} -> {v2}")
    return "\n".join(out)


def default_omegas(an: Analysis, eqs) -> np.ndarray:
    """A symmetric grid of ω over four times the fastest small-oscillation rate of the
    equilibria (10 rad/s if they have none), 161 values."""
    rate = max((np.max(np.abs(e.eigenvalues)) for e in eqs if len(e.eigenvalues)), default=0.0)
    top = 4.0 * rate if rate > 0 else 10.0
    return np.linspace(-top, top, 161)


MAX_GRID = 1000  # points of an lo:hi:N grid of steady or orbits: each is a Newton solve (or a Floquet continuation step)


def parse_range(text: str, what: str = "--omega", example: str = "-20:20:81") -> np.ndarray:
    """``lo:hi:N`` (N values from lo to hi, 2 ≤ N ≤ MAX_GRID, lo < hi)."""
    try:
        a, b, count = text.split(":")
        a, b, count = float(a), float(b), int(count)
    except ValueError:
        raise SteadyError(f"{what}: expected lo:hi:N, for example {example}") from None
    if not (np.isfinite(a) and np.isfinite(b) and a < b and count >= 2):
        raise SteadyError(f"{what}: expected finite lo < hi and N >= 2")
    if count > MAX_GRID:
        raise SteadyError(f"{what}: {count} points; at most {MAX_GRID} (each is a Newton solve), for example {a:g}:{b:g}:{MAX_GRID}")
    return np.linspace(a, b, count)


def check_vary_values(spec, given: dict, vary: tuple, what: str = "--vary") -> None:
    """Every point of a --vary grid is a run's parameter values: checked as --param values are
    (physical.run_values: a mass positive, an inertia possible), the ends first, before any work."""
    from ..chainspec.physical import check_values, run_values

    name, grid = vary
    values = run_values(spec, {k: v for k, v in given.items() if k != name}, needed=[])  # the --param values alone
    said = "".join(f", --param {k}={v:g}" for k, v in given.items() if k != name)
    if len(values) + (name not in values) < len(spec.params):
        return  # a parameter has no value yet: run_values says so, naming it, when the command starts
    for i in [0, len(grid) - 1, *range(1, len(grid) - 1)]:
        v = float(grid[i])
        check_values(spec, {**values, name: v}, f" with {what} {name}={v:g}{said}"
                     + (" and the spec's [values]" if len(values) > len(given) - (name in given) else ""))


def parse_vary(text: str, spec) -> tuple[str, np.ndarray]:
    """``--vary name=lo:hi:N``: a symbolic parameter of the spec and its grid."""
    name, eq, rng = text.partition("=")
    name = name.strip()
    if not eq or not name:
        raise SteadyError("--vary: expected name=lo:hi:N, for example a=0:0.03:61")
    names = [str(p) for p in spec.params]
    if name not in names:
        from ..chainspec.errors import did_you_mean

        raise SteadyError(f"--vary {name}: not a symbolic parameter of the spec ({did_you_mean(name, names)}"
                          + (f"its parameters: {', '.join(names)})" if names else "it has none)"))
    return name, parse_range(rng, f"--vary {name}", "0:0.03:61")


def compile_spec(spec, driven_ok: bool = False):
    """The spec's compiled model and its derivation (pipeline.compiled): (CModel, assemble.Model).
    A model that depends on t is refused unless ``driven_ok``."""
    from ..models import pipeline
    from ..derive.assemble import time_dependent

    cm, model = pipeline.compiled(spec)
    if time_dependent(model) and not driven_ok:
        raise SteadyError(TIME_DEPENDENT)
    return cm, model


def analyze(spec, params=None, u=None, omegas=None, starts=(), rotations: bool = True, period: float | None = None,
            vary: tuple | None = None, at=None):
    """Find and classify the spec's steady motions: (Analysis, equilibria, branches or None,
    ω grid or None).  A model that depends on t periodically gets its equilibria for all t and
    their Floquet verdicts instead (floquet.DrivenAnalysis, equilibria, the continuations along
    ``vary`` = (name, values) or None, the values); ``period`` replaces the spec's period.  ``at``:
    only the equilibrium Newton finds from there (no search, no rotations)."""
    from ..derive.assemble import time_dependent

    for s in starts:
        if len(s) != spec.n or not np.all(np.isfinite(s)):
            raise SteadyError(f"--start: expected {spec.n} finite numbers")
    check_inputs(spec, params, u)
    cm, model = compile_spec(spec, driven_ok=True)
    if time_dependent(model):
        if omegas is not None:
            raise SteadyError("--omega: the model depends on t: it has no steady rotations (its equilibria for all t are analysed)")
        return _analyze_driven(cm, model, params, u, starts, period, vary, at)
    if period is not None:
        raise SteadyError("--period: the model does not depend on t")
    if vary is not None:
        raise SteadyError("--vary: only for a model that depends on t (steady rotations take --omega)")
    an = Analysis(cm, model, params, u)
    if at is not None:
        start = np.array([0.0, *at[1:]]) if an.cyclic else np.asarray(at, float)
        phi = an.solve(start, 0.0)
        if phi is None:
            raise SteadyError(f"--at: Newton found no equilibrium from phi = {fmt_phi(start)}")
        return an, [an.classify(_wrap(phi), 0.0)], None, None
    eqs = an.equilibria(starts)
    branches = None
    if an.cyclic and not an.drains and rotations:
        omegas = default_omegas(an, eqs) if omegas is None else omegas
        branches = an.rotations(omegas, starts)
    return an, eqs, branches, omegas


def _analyze_driven(cm, model, params, u, starts, period, vary, at=None):
    from ..chainspec.errors import SpecError

    if u is None and model.spec.controls:
        u = np.zeros(len(model.spec.controls))
    try:
        an = floquet.DrivenAnalysis(cm, model, params, u, period)
        if at is not None:
            phi = an.solve(np.array([0.0, *at[1:]]) if an.cyclic else np.asarray(at, float))
            if phi is None:
                raise SteadyError(f"--at: Newton found no equilibrium that persists for all t from phi = {fmt_phi(at)}")
            return an, [an.classify(_wrap(phi))], None, None
        eqs = an.equilibria()
        for s in starts:  # a start the user gives must lead to an equilibrium that persists
            phi = an.solve(s)
            if phi is None:
                raise SteadyError(f"--start {','.join(f'{v:g}' for v in s)}: no equilibrium that persists for all t was "
                                  "found from it (phi'' = 0 at every t of a period)")
            if not any(np.max(np.abs(_wrap(_wrap(phi) - e.phi))) < 1e-7 for e in eqs):
                eqs.append(an.classify(_wrap(phi)))
        continued = [an.along(vary[0], vary[1], e) for e in eqs] if vary else None
    except SpecError as exc:
        raise SteadyError(f"{exc.field}: {exc.message}") from None
    except ArithmeticError as exc:  # the integration of a period failed (gyrochain.build.IntegrationError)
        raise SteadyError(f"steady: the variational equations over a period did not integrate: {exc}") from None
    return an, eqs, continued, (vary[1] if vary else None)
