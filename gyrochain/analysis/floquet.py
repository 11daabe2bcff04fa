"""Driven pendulums: the period of a model's time dependence, the equilibria that persist for all
t, and their stability by Floquet theory on the emitted variational equations (``gyrochain steady``
of a model that depends on t, ``gyrochain sweep --measure floquet``; ``orbits`` uses the verdicts).

* The period.  A model reads t (NAME_TIME_DEPENDENT) through the spec's expressions: the platform's
  motion, λ(t), loads and torques of t.  It is periodic when every t of the emitted dynamics sits
  in a sine or cosine whose argument is linear in t, ωᵢ t + cᵢ (a sine of such a sine is fine), and
  the ωᵢ are commensurate: T = 2π / gcd(ωᵢ), at the run's parameter values (``time_period``).  A
  period the user gives (``--period``) is checked on the emitted φ̈ instead: φ̈(t + T) = φ̈(t) at
  random states and times (``check_period``).
* Equilibria for all t: φ̇ = 0 and φ̈(φ, 0, t) = 0 at every t (Kapitza's upright and hanging
  pendulum).  Gauss–Newton on the residuals at SAMPLES times of a period, stacked, from the starts
  of ``start_grid``; kept when φ̈ vanishes at CHECKS further random times too.
* Floquet multipliers μ: the eigenvalues of the monodromy matrix Φ(T), the fundamental matrix of
  the linearisation over one period (NAME_integrate_variational from the identity at t = 0, at
  rtol = atol = 1e-12); exponents log μ / T.  Where φ¹ is cyclic (Φ's first column stays e₁) its
  trivial multiplier 1 is dropped.
* Verdicts (``verdict``): "unstable" (a multiplier outside the unit circle, |μ| > 1 + MU_TOL:
  Lyapunov's first method); "asymptotically stable" (every |μ| < 1 − MU_TOL); "linearly stable"
  (every multiplier on or inside the unit circle: stable to first order, which for a conservative
  model is all a linearisation can say).  The verdict changes along a parameter are located by
  bisection: near a transition curve a pair of multipliers leaves the circle as the square root of
  the distance, so the verdict flips within (MU_TOL)² of the parameter's true boundary.
"""
from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field
from fractions import Fraction

import numpy as np
import sympy as sp

from ..derive.algebra import Poly
from ..chainspec.errors import SpecError
from ..chainspec.spec import T as TIME
from ..models.paramtable import ParamTable

SAMPLES = 16  # times of a period at which Newton asks φ̈ = 0
MAX_OWN_CYCLES = 1e5  # the pendulum's own oscillations in one drive period past which steady refuses the work
CHECKS = 64  # further random times at which an equilibrium must hold
EQUILIBRIUM_TOL = 1e-9  # |φ̈| at most this times max(1, |∂φ̈/∂φ|) at every sample: an equilibrium for all t
MU_TOL = 1e-6  # |μ| − 1 beyond this is off the unit circle (Φ is good to ~1e-10 at the tolerances used)
RTOL = ATOL = 1e-12  # of the variational integration over a period
MAX_DENOMINATOR = 1000  # frequency ratios are rational with denominators up to this, or incommensurate

STARTS = ("every combination of 0, pi/2, pi, -pi/2 per free coordinate (n_free <= 4); beyond that 0 and pi per "
          "coordinate (at most 256) and 32 random points (seed 0)")


def start_grid(n_free: int) -> list[list[float]]:
    """The Newton starts of the searches for equilibria (``STARTS``) over n_free coordinates."""
    if n_free <= 4:
        return [list(c) for c in itertools.product((0.0, np.pi / 2, np.pi, -np.pi / 2), repeat=n_free)]
    grid = [list(c) for c in itertools.islice(itertools.product((0.0, np.pi), repeat=n_free), 256)]
    return grid + [list(r) for r in np.random.default_rng(0).uniform(-np.pi, np.pi, (32, n_free))]


def wrap(phi):
    """Angles in (−π, π]."""
    r = (np.asarray(phi, float) + np.pi) % (2 * np.pi) - np.pi
    return np.where(r <= -np.pi + 1e-12, r + 2 * np.pi, r)


def distinct(starts, solve) -> list[np.ndarray]:
    """The distinct solutions (angles wrapped, equal to 1e-7 merged, sorted) that ``solve(start)``
    finds from the starts (None where it finds none): the equilibria of steady, floquet, orbits."""
    found: list = []
    for s in starts:
        phi = solve(s)
        if phi is None:
            continue
        phi = wrap(phi)
        if not any(np.max(np.abs(wrap(phi - f))) < 1e-7 for f in found):
            found.append(phi)
    return sorted(found, key=lambda p: tuple(np.round(p, 9)))


# --------------------------------------------------------------------------- the period
@dataclass(frozen=True)
class TimeDependence:
    """How the emitted dynamics read t: the frequencies ωᵢ of the sines and cosines of t (sympy
    expressions of the parameters), or why they are not periodic (``why`` not empty)."""

    frequencies: tuple
    why: str = ""


def time_dependence(model) -> TimeDependence:
    """The sines and cosines of t in the emitted φ̈ and its derivatives (assemble.Model lines)."""
    freqs, why = [], ""
    for key in ("qdd", "qdd_derivatives", "forces"):
        line = model.lines.get(key)
        if line is None:
            continue
        for _, rhs in line.temporaries:
            if isinstance(rhs, Poly):
                if any(a.sym == TIME for a in rhs.atoms()):
                    why = why or "t enters the equations as a polynomial (a load or torque growing with t)"
                continue
            if not rhs.has(TIME):
                continue
            rest = rhs
            for f in rhs.atoms(sp.sin, sp.cos):
                arg = sp.expand(f.args[0])
                if arg.has(TIME) and arg.is_polynomial(TIME) and sp.degree(arg, TIME) == 1:
                    w = arg.coeff(TIME, 1)
                    if not w.has(TIME):
                        if not any(sp.simplify(w - v) == 0 or sp.simplify(w + v) == 0 for v in freqs):
                            freqs.append(w)
                        rest = rest.xreplace({f: sp.Dummy()})
            if rest.has(TIME):
                why = why or f"t enters as {sp.sstr(rhs)}, not only through sines and cosines of (a t + b)"
    return TimeDependence(tuple(freqs), why)


def time_period(model, params: dict | None, what: str = "steady") -> tuple[float, str]:
    """The period T of the model's time dependence at the parameter values ``params`` and how it
    was found (a line for the report); SpecError(what, why) where there is none."""
    dep = time_dependence(model)
    if dep.why:
        raise SpecError(what, f"the model is not periodic in t: {dep.why}")
    if not dep.frequencies:
        raise SpecError(what, "the equations of motion do not depend on t (only the energy does: a platform "
                                    "moving uniformly): they have no period")
    values = {sp.Symbol(k, real=True): v for k, v in (params or {}).items()}
    omegas = []
    for w in dep.frequencies:
        try:
            omegas.append(abs(float(sp.sympify(w).subs(values))))
        except TypeError:
            raise SpecError("--param", f"the frequency {w} needs a value for {', '.join(map(str, w.free_symbols))}") from None
    omega = common_frequency(omegas, what)
    names = ", ".join(sp.sstr(w) for w in dep.frequencies)
    return 2 * math.pi / omega, f"2 pi/{omega:.10g} from the frequencies of t in the spec's expressions ({names} rad/s)"


def common_frequency(omegas, what: str) -> float:
    """The frequency whose period is the period of all the |ωᵢ| given (their rationals' gcd):
    SpecError where one is not finite, all are 0, or two are incommensurate."""
    if any(not math.isfinite(w) for w in omegas):
        raise SpecError("--param", "a frequency of t is not finite")
    omegas = [w for w in omegas if w > 0.0]
    if not omegas:
        raise SpecError(what, "every frequency of t is 0 at these parameter values: the model is not driven")
    base = omegas[0]
    ratios = []
    for w in omegas:
        r = Fraction(w / base).limit_denominator(MAX_DENOMINATOR)
        if abs(float(r) - w / base) > 1e-12 * (w / base):
            raise SpecError(what, f"the model is quasi-periodic, not periodic: the frequencies {base:.10g} and "
                                        f"{w:.10g} rad/s of t are incommensurate")
        ratios.append(r)
    # gcd of the rationals: gcd of the numerators over the lcm of the denominators
    den = math.lcm(*(r.denominator for r in ratios))
    num = math.gcd(*(int(r * den) for r in ratios))
    return base * num / den


def time_periods(model, params: list) -> np.ndarray:
    """time_period at many points at once (``params``: a dict per point, or None for all): the
    frequencies evaluated over all the points as arrays, the gcd once per distinct set of them;
    NaN where a point has no period (a frequency 0 or not finite there, or incommensurate ones)."""
    dep = time_dependence(model)
    if dep.why or not dep.frequencies:
        return np.full(len(params), np.nan)
    syms = sorted(set().union(*(sp.sympify(w).free_symbols for w in dep.frequencies)), key=str)
    columns = [params.column(k) if isinstance(params, ParamTable) else np.array([p[k] for p in params], float)
               for k in map(str, syms)]  # (the sweep checked they have values)
    W = np.abs(np.stack([np.broadcast_to(np.asarray(sp.lambdify(syms, w, "numpy")(*columns), float), (len(params),))
                         for w in dep.frequencies], axis=1))
    if W.shape[1] == 1:  # one frequency (a drive): NumPy's 1-D unique, many times quicker than by rows
        values, which = np.unique(W[:, 0], return_inverse=True)
        distinct = values[:, None]
    else:
        distinct, which = np.unique(W, axis=0, return_inverse=True)
    T = np.full(len(distinct), np.nan)
    for k, omegas in enumerate(distinct):
        try:
            T[k] = 2 * math.pi / common_frequency([float(w) for w in omegas], "floquet")
        except SpecError:
            pass
    return T[np.ravel(which)]


def check_period(cm, T: float, params, u, what: str = "--period") -> None:
    """SpecError unless φ̈(t + T, x) = φ̈(t, x) at random states x and times t spread over many
    periods and at least 10 s (a "period" far below the drive's own, 1e-9 s say, moves t too
    little to show within one period of itself).  The tolerance is 1e-9 of φ̈ plus what a
    relative error of 1e-8 in T explains (a period printed to ten digits is a period)."""
    if not (math.isfinite(T) and T > 0):
        raise SpecError(what, f"expected a positive period, got {T:g}")
    rng = np.random.default_rng(1)
    n = cm.n
    span = max(20.0 * T, 10.0)
    for _ in range(12):
        x = np.concatenate([rng.uniform(-np.pi, np.pi, n), rng.normal(size=n)])
        t = rng.uniform(0.0, span)
        try:
            a, b, c = (cm.qdd(x, u, params, t=s) for s in (t, t + T, t + T * (1 + 1e-8)))
        except ArithmeticError:
            continue
        gap = np.max(np.abs(a - b))
        if gap > 1e-9 * max(1.0, np.max(np.abs(a))) + 2.0 * np.max(np.abs(c - b)):
            raise SpecError(what, f"{T:.10g} s is not a period of the model: phi'' at t = {t:.6g} and t + {T:.6g} "
                                  f"differ by {gap:.3g}")


def snap_period(T: float, T0: float | None) -> tuple[float, str]:
    """A period the user gave, as a whole multiple of the spec's own period T0 when it is one to
    1e-8 (T0 exact, as the printed ten digits are not): (the period, how it was found)."""
    if T0:
        k = round(T / T0)
        if k >= 1 and abs(T / T0 - k) < 1e-8:
            return k * T0, f"given with --period: {k} x the spec's period" if k > 1 else "given with --period: the spec's period"
    return T, "given with --period"


# --------------------------------------------------------------------------- equilibria and multipliers
def _residual(cm, phi, times, params, u):
    """φ̈(φ, 0, t) at each of ``times``, stacked, and ∂φ̈/∂φ there, stacked."""
    x = np.concatenate([phi, np.zeros(cm.n)])
    rows, jac = [], []
    for t in times:
        q, dq, _, _ = cm.qdd_derivatives(x, u, params, t=t)
        rows.append(q)
        jac.append(dq)
    return np.concatenate(rows), np.vstack(jac)


def equilibrium(cm, start, times=(0.0,), params=None, u=None, cyclic: bool = False, tol: float = 1e-12,
                iters: int = 60):
    """Gauss–Newton (least squares, with backtracking) for φ̈(φ, 0, t) = 0 at every t of ``times``
    (one time for an autonomous model), from ``start``; φ¹ held at 0 when it is cyclic.  Returns
    (φ, the scale of ∂φ̈/∂φ) or None when it does not converge."""
    free = list(range(1, cm.n)) if cyclic else list(range(cm.n))
    phi = np.array(start, float)
    if cyclic:
        phi[0] = 0.0
    try:
        r, J = _residual(cm, phi, times, params, u)
    except ArithmeticError:
        return None
    scale = max(1.0, np.max(np.abs(J)))
    for _ in range(iters):
        if np.max(np.abs(r)) <= tol * scale or not free:
            break
        step = np.linalg.lstsq(J[:, free], -r, rcond=None)[0]
        lam = 1.0
        while lam > 1e-4:
            trial = phi.copy()
            trial[free] += lam * step
            try:
                r2, J2 = _residual(cm, trial, times, params, u)
            except ArithmeticError:
                lam /= 2
                continue
            if np.max(np.abs(r2)) < np.max(np.abs(r)):
                break
            lam /= 2
        else:
            return None
        phi, r, J = trial, r2, J2
    if np.max(np.abs(r)) > 1e3 * tol * scale:
        return None
    return phi, scale


@dataclass
class Driven:
    """An equilibrium that persists for all t and its Floquet analysis at one parameter set."""

    phi: np.ndarray
    period: float
    multipliers: np.ndarray  # (the exponents are log μ / period: fmt_multipliers)
    verdict: str
    reason: str
    monodromy: np.ndarray = field(repr=False, default=None)


def monodromy(cm, x, T: float, params=None, u=None, t0: float = 0.0, tol: float = RTOL) -> np.ndarray:
    """Φ(t0 + T) from the identity at t0 along the motion from x (NAME_integrate_variational, at
    rtol = atol = ``tol``)."""
    return cm.integrate_variational(t0, t0 + T, x, u=u, params=params, rtol=tol, atol=tol)[1]


def multipliers(Phi: np.ndarray, cyclic: bool) -> np.ndarray:
    """The eigenvalues of Φ; with ``cyclic`` those of Φ without φ¹'s row and column (its
    multiplier 1: nothing depends on φ¹), sorted by decreasing modulus."""
    P = Phi[1:, 1:] if cyclic else Phi
    mu = np.linalg.eigvals(P)
    return mu[np.lexsort((-mu.imag, -np.abs(mu)))]


def verdict(mu: np.ndarray) -> tuple[str, str]:
    """(verdict, reason) from the multipliers (see the module's docstring)."""
    if not len(mu):
        return "linearly stable", "no coordinate left to perturb"
    big = mu[np.argmax(np.abs(mu))]
    top = abs(big)
    if top > 1.0 + MU_TOL:
        return "unstable", f"Floquet multiplier {_fmt_complex(big)} is outside the unit circle (modulus {top:.6g})"
    if top < 1.0 - MU_TOL:
        return "asymptotically stable", f"every Floquet multiplier is inside the unit circle (largest modulus {top:.6g})"
    inside = int(np.sum(np.abs(mu) < 1.0 - MU_TOL))
    where = "on the unit circle" if not inside else f"on or inside the unit circle ({inside} inside)"
    return "linearly stable", f"every Floquet multiplier is {where}: stable to first order"


def _fmt_complex(z: complex, digits: int = 6) -> str:
    tiny = 1e-12 * max(abs(z), 1.0)
    re_, im = (z.real if abs(z.real) > tiny else 0.0), (z.imag if abs(z.imag) > tiny else 0.0)
    return f"{re_:.{digits}g}{im:+.{digits}g}i" if im else f"{re_:.{digits}g}"


def fmt_multipliers(mu: np.ndarray, T: float, digits: int = 4) -> str:
    """The multipliers and the exponents log μ / T (the imaginary parts in (−π/T, π/T]), as printed:
    parts below 1e-9 of the scale print as 0, so the line is the same on every machine."""
    def clean(z, scale):
        tiny = 1e-9 * scale
        return complex(z.real if abs(z.real) > tiny else 0.0, z.imag if abs(z.imag) > tiny else 0.0)

    ms = ", ".join(_fmt_complex(clean(z, 1.0), digits) for z in mu)
    ex = [clean(complex(np.log(abs(z)), np.angle(z)) / T, 1.0 / T) if z != 0 else complex(-np.inf) for z in mu]
    return f"multipliers: {ms}; exponents (1/s): " + ", ".join(_fmt_complex(z, digits) for z in ex)


class DrivenAnalysis:
    """A built time-periodic model (gyrochain.build.CModel) at one parameter set: its persistent
    equilibria and their Floquet verdicts.  ``period``: the user's (checked), or None for the
    spec's (``time_period``)."""

    def __init__(self, cm, model, params=None, u=None, period: float | None = None, what: str = "steady"):
        if not cm.has_variational:
            raise SpecError(what, f"the Floquet analysis needs NAME_integrate_variational, emitted up to n = 16 (n = {cm.n})")
        self.c, self.model, self.n = cm, model, cm.n
        self.u = None if u is None else np.asarray(u, float)
        self.fixed_period, self.what = period, what  # what: the command, named in its errors
        self.set_params(params)

    def _check_work(self) -> None:
        """A drive so slow that one period holds more than MAX_OWN_CYCLES of the pendulum's own
        oscillations (|λ|max of the linearisation at φ = 0, t = 0) would take hours per multiplier:
        refused with the numbers (the slow-drive limit is the static problem)."""
        try:
            A, _ = self.c.linearize(np.zeros(2 * self.n), self.u, self.params, t=0.0)
            lam = float(np.max(np.abs(np.linalg.eigvals(A))))
        except (ArithmeticError, np.linalg.LinAlgError):
            return
        cycles = self.period * lam / (2 * math.pi)
        if math.isfinite(cycles) and cycles > MAX_OWN_CYCLES:
            raise SpecError("--vary" if self.fixed_period is None and self.what == "steady" and self.params else self.what,
                            f"the drive's period {self.period:.4g} s holds {cycles:.3g} of the pendulum's own oscillations "
                            f"(at most {MAX_OWN_CYCLES:.0e}): its Floquet multipliers would take hours; a drive that slow "
                            "is the static problem (steady of the spec with the drive held)")

    def set_params(self, params) -> None:
        self.params = params
        if self.fixed_period is None:
            self.period, self.period_how = time_period(self.model, params, self.what)
        else:
            check_period(self.c, self.fixed_period, params, self.u, "--period")
            try:
                own = time_period(self.model, params, self.what)[0]
            except SpecError:  # no period from the expressions: the user's, checked on phi''
                own = None
            self.period, self.period_how = snap_period(self.fixed_period, own)
        check_period(self.c, self.period, params, self.u, "--period" if self.fixed_period else self.what)
        self._check_work()
        self.times = self.period * np.arange(SAMPLES) / SAMPLES
        self.cyclic = self._cyclic()

    def _cyclic(self) -> bool:
        """Whether φ̈ does not depend on φ¹ (checked on the emitted ∂φ̈/∂φ at random states and times)."""
        rng = np.random.default_rng(0)
        for _ in range(3):
            x = np.concatenate([rng.uniform(-3, 3, self.n), rng.normal(size=self.n)])
            try:
                _, dq, _, _ = self.c.qdd_derivatives(x, self.u, self.params, t=rng.uniform(0, self.period))
            except ArithmeticError:
                continue
            if np.max(np.abs(dq[:, 0])) > 1e-13 * max(1.0, np.max(np.abs(dq))):
                return False
        return True

    def solve(self, start, tol: float = 1e-12, iters: int = 60):
        """φ with φ̈(φ, 0, t) = 0 at the sample times (``equilibrium``), or None when Newton does
        not converge or the equilibrium does not persist at other times."""
        got = equilibrium(self.c, start, self.times, self.params, self.u, self.cyclic, tol, iters)
        if got is None:
            return None
        phi, scale = got
        return phi if self.persists(phi, scale) else None

    def persists(self, phi, scale: float = 1.0) -> bool:
        """φ̈(φ, 0, t) = 0 at CHECKS random times of a period too (to 1e-9 of ``scale``)."""
        times = np.random.default_rng(2).uniform(0.0, self.period, CHECKS)
        try:
            r, _ = _residual(self.c, phi, times, self.params, self.u)
        except ArithmeticError:
            return False
        return bool(np.max(np.abs(r)) <= 1e-9 * scale)

    tol = RTOL  # of the integration of a period (continuation asks for more: its boundaries to 1e-10)

    def classify(self, phi) -> Driven:
        x = np.concatenate([phi, np.zeros(self.n)])
        Phi = monodromy(self.c, x, self.period, self.params, self.u, tol=self.tol)
        mu = multipliers(Phi, self.cyclic)
        v, why = verdict(mu)
        return Driven(np.array(phi, float), self.period, mu, v, why, Phi)

    def equilibria(self, extra_starts=()) -> list[Driven]:
        nf = self.n - 1 if self.cyclic else self.n
        pre = [0.0] if self.cyclic else []
        starts = [np.array(pre + g) for g in start_grid(nf)] + [np.asarray(e, float) for e in extra_starts]
        return [self.classify(p) for p in distinct(starts, self.solve)]

    def along(self, name: str, values: np.ndarray, eq: Driven) -> "Continued":
        """The equilibrium ``eq`` continued over the parameter ``name`` = values (increasing): the
        period recomputed at each, Newton from the last point, the verdict, and the values where
        it changes (bisection).  Restores the parameters it started from."""
        base = dict(self.params or {})
        out = Continued(name)
        phi = eq.phi
        try:
            for v in values:
                try:
                    self.set_params({**base, name: float(v)})
                except SpecError as exc:
                    raise SpecError(f"--vary {name}", f"at {name} = {v:g}: {exc.message}") from None
                p = self.solve(phi)
                if p is None:
                    out.lost = float(v)
                    break
                phi = wrap(p)
                out.points.append((float(v), self.classify(phi)))
            for (a, da), (b, db) in zip(out.points, out.points[1:]):
                if da.verdict != db.verdict:
                    out.changes.append((self._bisect(base, name, a, b, da), da.verdict, db.verdict))
        finally:
            self.set_params(base or None)
        return out

    def _bisect(self, base, name, lo, hi, d_lo) -> float:
        phi = d_lo.phi
        for _ in range(60):
            mid = (lo + hi) / 2
            self.set_params({**base, name: mid})
            p = self.solve(phi)
            if p is not None and self.classify(wrap(p)).verdict == d_lo.verdict:
                lo, phi = mid, wrap(p)
            else:
                hi = mid
            if hi - lo <= 1e-13 * max(1.0, abs(hi)):
                break
        return (lo + hi) / 2


@dataclass
class Continued:
    """An equilibrium along a parameter: (value, Driven) in increasing order, the values where the
    verdict changes with the verdicts on either side, and where Newton lost it (None: never)."""

    name: str
    points: list = field(default_factory=list)
    changes: list = field(default_factory=list)
    lost: float | None = None


def fmt_phi(phi) -> str:
    """Coordinates as the reports print them (9 significant digits)."""
    return "[" + ", ".join(f"{v:.9g}" for v in phi) + "]"


def verdict_segments(points, name: str) -> list[str]:
    """The lines of a continuation: ``name in [a, b) on the grid: verdict: reason`` for each run of
    equal verdicts; ``points`` are (value, verdict, reason) in increasing order."""
    if not points:
        return []
    runs, cur = [], points[0]
    for p in points[1:]:
        if p[1] != cur[1]:
            runs.append((cur, p[0]))
            cur = p
    runs.append((cur, None))
    last = points[-1][0]
    return [f"{name} in [{p[0]:.6g}, {f'{end:.6g})' if end is not None else f'{last:.6g}]'} on the grid: {p[1]}: {p[2]}"
            for p, end in runs]


def found_line(eqs, most, at, starts: str, how: str = "") -> str:
    """How many equilibria were found, from what, and how many are printed."""
    if at is not None:
        return f"{len(eqs)} found by Newton{how} from phi = {fmt_phi(at)} (--at)"
    shown = f"; the first {most} printed (--max-equilibria)" if most is not None and most < len(eqs) else ""
    return f"{len(eqs)} found by Newton{how} from {starts}{shown}"


def report(an: DrivenAnalysis, eqs: list[Driven], continued: list[Continued] | None = None, values=None,
           digits: int = 4, most: int | None = None, at=None) -> str:
    out = [f"periodic in t: period {an.period:.10g} s ({an.period_how})"]
    cyc = " (phi1 is cyclic: any phi1; phi1 = 0 shown, its multiplier 1 dropped)" if an.cyclic else ""
    how = f" on phi'' = 0 at {SAMPLES} times of a period (checked at {CHECKS} more)"
    out.append(f"equilibria for all t{cyc}: {found_line(eqs, most, at, STARTS, how)}")
    for e in eqs[:most]:
        out.append(f"  phi = {fmt_phi(e.phi)}: {e.verdict}: {e.reason}")
        out.append(f"    {fmt_multipliers(e.multipliers, e.period, digits)}")
    for c in continued or []:
        out.append(f"along {c.name} in [{values[0]:.6g}, {values[-1]:.6g}] ({len(values)} values), "
                   f"phi = {fmt_phi(c.points[0][1].phi) if c.points else '?'}:")
        out += ["  " + ln for ln in verdict_segments([(v, d.verdict, d.reason) for v, d in c.points], c.name)]
        for w, v1, v2 in c.changes:
            out.append(f"  verdict changes at {c.name} = {w:.10g}: {v1} -> {v2}")
        if c.lost is not None:
            out.append(f"  Newton lost the equilibrium at {c.name} = {c.lost:.6g} (it no longer persists there)")
    return "\n".join(out)


# --------------------------------------------------------------------------- a sweep's measure
def largest_multiplier(cm, model, x, params, u=None, cyclic: bool = False, what: str = "--measure floquet") -> float:
    """max |μ| of the equilibrium state x (φ̇ = 0) at the parameters ``params`` over the period the
    spec's expressions give there; NaN where x is not an equilibrium for all t at these values (φ̈
    not 0, to 1e-9 of the scale of ∂φ̈/∂φ, at SAMPLES times of the period)."""
    T, _ = time_period(model, params, what)
    if not held_for_all_t(cm, x, T, params, u):
        return float("nan")
    mu = multipliers(monodromy(cm, np.asarray(x, float), T, params, u), cyclic and cm.n > 1)
    return float(np.max(np.abs(mu))) if len(mu) else 1.0


def held_for_all_t(cm, x, T: float, params, u) -> bool:
    """Whether φ̈(x) = 0 at SAMPLES times of the period T, to EQUILIBRIUM_TOL of the scale of ∂φ̈/∂φ
    (the GPU's floquet kernel asks the same at the same times)."""
    for t in T * np.arange(SAMPLES) / SAMPLES:
        q, dq, _, _ = cm.qdd_derivatives(x, u, params, t=t)
        if np.max(np.abs(q)) > EQUILIBRIUM_TOL * max(1.0, np.max(np.abs(dq))):
            return False
    return True


def sweep_setup(compiled, model, x, first_params, u, varied_states, what: str = "--measure floquet") -> bool:
    """A sweep's floquet measure: a time-periodic model of up to 16 bodies, only parameters varied,
    the state x an equilibrium for all t at the grid's first point; whether φ¹ is cyclic.
    ``compiled()`` builds the model (only once the cheap checks passed)."""
    from ..derive.assemble import time_dependent

    n = len(x) // 2
    if not time_dependent(model):
        raise SpecError(what, "the model does not depend on t: an equilibrium's stability is `gyrochain steady`'s")
    if n > 16:
        raise SpecError(what, f"needs NAME_integrate_variational, emitted up to n = 16 (n = {n})")
    if varied_states:
        raise SpecError(what, f"vary parameters only (not {varied_states[0]}): the state is the equilibrium "
                              "(--phi, phidot 0)")
    if np.any(np.asarray(x[n:]) != 0.0):
        raise SpecError("--phidot", "floquet: an equilibrium has phidot = 0")
    try:
        time_period(model, first_params, what)  # periodic at all (one line if not)
    except SpecError as exc:
        at = ", ".join(f"{k} = {v:g}" for k, v in (first_params or {}).items())
        raise SpecError(exc.field, f"{exc.message} (at the grid's first point: {at})") from None
    cm = compiled()
    if not np.isfinite(largest_multiplier(cm, model, x, first_params, u, what=what)):
        raise SpecError("--phi", f"floquet: phi = {[float(v) for v in x[:n]]} is not an equilibrium for all t at "
                                 + ", ".join(f"{k} = {v:g}" for k, v in (first_params or {}).items()))
    return DrivenAnalysis(cm, model, first_params, u, what=what).cyclic


def sweep_moduli_batch(gm, model, X0, params, u, cyclic) -> tuple[np.ndarray, np.ndarray]:
    """sweep_moduli with all the points of a chunk in one launch of the GPU's floquet kernel
    (``gm.floquet_batch``): the periods evaluated over the points at once (time_periods), the
    equilibrium test and the monodromy matrix in each thread, the eigenvalues of all at once."""
    nb = len(X0)
    mu = np.full(nb, np.nan)
    T = time_periods(model, params) if params[0] is not None else np.full(nb, time_periods(model, [{}])[0])
    prm = params if params[0] is not None else None
    Phi, held, codes = gm.floquet_batch(T, X0, SAMPLES, EQUILIBRIUM_TOL, u=u, params=prm, rtol=RTOL, atol=ATOL)
    ok = (held == 1) & (codes == 0)
    P = Phi[ok][:, 1:, 1:] if cyclic and gm.n > 1 else Phi[ok]
    mu[ok] = np.max(np.abs(np.linalg.eigvals(P)), axis=1) if P.shape[1] else 1.0
    return mu, codes


def sweep_moduli(cm, model, X0, params, u, cyclic) -> tuple[np.ndarray, np.ndarray]:
    """max |μ| at each start state X0[k] (an equilibrium) with params[k]: NaN where it is not an
    equilibrium for all t there or the drive stops (a frequency 0); the integrators' codes."""
    mu = np.full(len(X0), np.nan)
    codes = np.zeros(len(X0), dtype=np.int32)
    for k, x in enumerate(X0):
        try:
            mu[k] = largest_multiplier(cm, model, x, params[k], u, cyclic)
        except ArithmeticError as exc:  # the period's integration failed
            codes[k] = getattr(exc, "code", 1)
        except SpecError:  # no period at this point (a frequency of t is 0 there)
            pass
    return mu, codes
