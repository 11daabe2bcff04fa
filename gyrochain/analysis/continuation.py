r"""Branches of equilibria traced by continuation in one parameter: ``gyrochain continue SPEC``.

The unknowns are y = (φ of the free coordinates, α), α a symbolic parameter of the spec; the
equations are $\ddot\varphi(\varphi, 0, t; \alpha) = 0$ — at t = 0 for an autonomous model, at the
SAMPLES times of a period, stacked, for a model driven periodically in t (its equilibria for all t,
as ``steady`` finds them).  Every derivative is the emitted C's: $\partial\ddot\varphi/\partial\varphi$
from NAME_qdd_derivatives and $\partial\ddot\varphi/\partial\alpha$ from NAME_param_derivatives;
nothing is differenced.

* Pseudo-arclength continuation (Keller): from a point and its unit tangent t (the null vector of
  the Jacobian J = [∂F/∂φ | ∂F/∂α]), the predictor y + h t is corrected by Newton on F = 0 and
  t·(y − y_pred) = 0, so a branch is followed through its folds.  α is measured in units of the
  range (hi − lo) per radian, so that a step is balanced between the two.  The step h grows by 1.5
  after an easy correction, halves after a failed one or where the tangent turns by more than
  MAX_TURN, down to MIN_STEP.
* Along the branch, the spectrum: the eigenvalues of the linearisation (``steady``'s reduced one
  where φ¹ is cyclic), or for a driven model the Floquet multipliers over a period
  (NAME_integrate_variational).  The test functions, each a smooth real function that changes
  sign at its special point:
  - fold: the tangent's α component;
  - branch point (two branches cross): det [J; tᵀ] (J averaged over the sample times of a driven
    model);
  - for a conservative, gyroscopic or otherwise reversible model (its eigenvalues symmetric,
    λ and −λ): the discriminant $\prod_{i<j}(s_i - s_j)^2$ of the polynomial whose roots are
    $s = \lambda^2$ — negative exactly while a pair of s is complex, so it changes sign where two
    eigenvalues on the imaginary axis collide and leave it (a Krein collision: a gyroscopically
    stabilised motion loses stability, a follower load starts flutter); the Krein signatures of
    the colliding pair, the sign of $\bar v^{\mathsf T}(\omega^2 M + K)v$ for the eigenvector of
    $i\omega$, are reported;
  - otherwise (damping): Hopf, $\prod_{i<j}(\lambda_i + \lambda_j)$, zero where a pair ±iω crosses;
  - driven: a multiplier through +1, det(Φ − I); through −1 (period doubling), det(Φ + I); and a
    collision on the unit circle, the discriminant of the polynomial in $c = \mu + 1/\mu$ when
    the multipliers come in pairs μ, 1/μ (a conservative drive), else a Neimark–Sacker pair,
    $\prod_{i<j}(\mu_i\mu_j - 1)$.
* Each sign change is located by the Illinois variant of regula falsi on the arclength, each trial
  a point corrected onto the branch, until the arclength is known to SPECIAL_TOL; the point's α, φ
  and spectrum are reported, with the stability on either side.  At a branch point the second
  branch leaves along the other null vector of J, both ways, and is traced too (BRANCHES at most).
"""
from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field, replace

import numpy as np

from . import floquet
from .floquet import wrap

MAX_TURN = 0.3  # rad: a step whose tangent turns more than this is taken again, shorter
MAX_CORRECTION = 0.3  # a step whose corrector moves further than this times the step is taken again, shorter
MIN_STEP = 1e-9  # the shortest step before the branch is given up
NEWTON_ITERS = 12
NEWTON_TOL = 1e-12  # |F| relative to max(1, |J|), and the step's size, at a corrected point
SPECIAL_TOL = 1e-13  # the bracket of a special point's arclength (scaled units; relative beyond 1)
RATE = "phidot1"  # the varied quantity that is the rate of a steady rotation about a cyclic joint 1, not a parameter
BRANCHES = 8  # branches traced in one run, those leaving branch points included
KINDS = {"LP": "fold", "BP": "branch point", "KC": "eigenvalues collide on the imaginary axis",
         "RC": "eigenvalues collide on the real axis", "H": "Hopf point",
         "+1": "multiplier +1", "PD": "period doubling (multiplier -1)", "NS": "Neimark-Sacker pair",
         "KCm": "Krein collision on the unit circle"}


class ContinuationError(ValueError):
    """Bad input to the continuation (one line, naming what)."""


@dataclass
class Point:
    """A point of a branch: the parameter, the coordinates, the spectrum, the verdict, the tests."""

    alpha: float
    phi: np.ndarray
    spectrum: np.ndarray
    verdict: str
    y: np.ndarray = field(repr=False)
    tangent: np.ndarray = field(repr=False)
    tests: dict = field(repr=False, default_factory=dict)


@dataclass
class Special:
    """A located special point: its kind (a key of KINDS), the point, the verdicts on either side
    and what else there is to say (the frequency at a collision, the Krein signatures)."""

    kind: str
    point: Point
    before: str
    after: str
    detail: str = ""


@dataclass
class Branch:
    points: list = field(default_factory=list)
    specials: list = field(default_factory=list)
    end: str = ""  # why the branch stops: it left the range, ran out of steps, closed, could not go on
    origin: str = ""  # where it starts: the start, or the branch point it leaves
    ends: tuple = ()  # why each end stops, for a branch traced both ways from its start


class Pseudoarclength:
    """The tangent and the corrector of a problem whose ``residual(y)`` is (F, J, scale)."""

    def tangent(self, J, previous=None) -> np.ndarray:
        """The unit null vector of J, turned to go on the way ``previous`` went."""
        t = np.linalg.svd(J)[2][-1]
        if previous is not None and t @ previous < 0:
            t = -t
        return t / np.linalg.norm(t)

    def correct(self, pred, t0, anchor=None):
        """Newton on F(y) = 0, t0·(y − anchor) = t0·(pred − anchor) from ``pred``: (y, J, iterations)
        or None."""
        anchor = pred if anchor is None else anchor
        target = t0 @ (pred - anchor)
        y = pred.copy()
        for it in range(1, NEWTON_ITERS + 1):
            try:
                F, J, scale = self.residual(y)
            except ArithmeticError:
                return None
            G = np.append(F / scale, t0 @ (y - anchor) - target)
            A = np.vstack([J / scale, t0])
            dy = np.linalg.lstsq(A, -G, rcond=None)[0]
            y = y + dy
            # converged: the step is below the tolerance, or (near a branch point, where the step's
            # size is round-off over a small singular value) the equations already held before it
            if np.max(np.abs(dy)) <= NEWTON_TOL * max(1.0, np.max(np.abs(y))) or \
                    (it >= 3 and np.max(np.abs(G)) <= NEWTON_TOL):
                F, J, scale = self.residual(y)
                if np.max(np.abs(F)) <= 1e3 * NEWTON_TOL * scale:
                    return y, J, it
                return None
        return None


class Equilibria(Pseudoarclength):
    """The equations of the equilibria of a built model (gyrochain.build.CModel) as functions of
    y = (φ free, α[, β]), each parameter in units of its range per radian; ``steady``: a
    steady.Analysis of an autonomous model, ``driven``: a floquet.DrivenAnalysis of a model of t."""

    def __init__(self, cm, model, params: dict, u, names, ranges, steady=None, driven=None):
        self.c, self.n, self.u = cm, cm.n, u
        self.names, self.ranges = list(names), [tuple(map(float, r)) for r in ranges]
        self.name, (self.lo, self.hi) = self.names[0], self.ranges[0]
        self.params = dict(params)
        order = [str(p) for p in model.spec.params]
        self.steady, self.driven = steady, driven
        self.cyclic = (driven.cyclic if driven else steady.cyclic)
        if RATE in self.names and not (steady is not None and steady.cyclic and not steady.drains):
            raise ContinuationError(f"--vary {RATE}: the rate of a steady rotation about joint 1's axis, which needs "
                                    "phi1 cyclic (l1 vertical, nothing acting in joint 1) in a model that does not "
                                    "depend on t")
        self.ks = [order.index(nm) if nm != RATE else -1 for nm in self.names]
        self.free = list(range(1, self.n)) if self.cyclic else list(range(self.n))
        self.units = [hi - lo for lo, hi in self.ranges]  # each parameter per radian of y
        self.np = len(self.names)
        self.omega = 0.0  # φ̇¹ where it is not a varied parameter: equilibria

    def values(self, y) -> list[float]:
        return [lo + u * float(v) for (lo, _), u, v in zip(self.ranges, self.units, y[-self.np:])]

    def alpha(self, y) -> float:
        return self.values(y)[0]

    def y_of(self, phi, values) -> np.ndarray:
        values = np.atleast_1d(np.asarray(values, float))
        scaled = [(v - lo) / u for v, (lo, _), u in zip(values, self.ranges, self.units)]
        return np.concatenate([np.asarray(phi, float)[self.free], scaled])

    def phi_of(self, y) -> np.ndarray:
        phi = np.zeros(self.n)
        phi[self.free] = y[:-self.np]
        return phi

    def at(self, y) -> dict:
        return {**self.params, **{k: v for k, v in zip(self.names, self.values(y)) if k != RATE}}

    def rate(self, y) -> float:
        """φ̇¹ at y: the varied rate of a steady rotation, or 0 (an equilibrium)."""
        return self.values(y)[self.names.index(RATE)] if RATE in self.names else self.omega

    def inside(self, y) -> bool:
        return all(lo <= v <= hi for v, (lo, hi) in zip(self.values(y), self.ranges))

    def times(self, params: dict) -> np.ndarray:
        if self.driven is None:
            return np.zeros(1)
        self.driven.set_params(params)
        return self.driven.times

    def residual(self, y) -> tuple[np.ndarray, np.ndarray, float]:
        """(F, J, scale): F stacked over the times, J = [∂F/∂φ free | ∂F/∂α·unit …], and the scale
        of ∂φ̈/∂φ (what |F| is measured against)."""
        params, phi = self.at(y), self.phi_of(y)
        x = np.concatenate([phi, [self.rate(y)], np.zeros(self.n - 1)])
        rows, jac = [], []
        free = self.free
        for t in self.times(params):
            q, dq, dv, _ = self.c.qdd_derivatives(x, self.u, params, t=float(t))
            dp = self.c.param_derivatives(x, self.u, params, t=float(t))[1] if any(k >= 0 for k in self.ks) else None
            cols = [dv[free, 0] if k < 0 else dp[free, k] for k in self.ks]  # ∂φ̈/∂φ̇¹ for the rate: exact too
            rows.append(q[free])
            jac.append(np.column_stack([dq[np.ix_(free, free)], np.column_stack(cols) * np.array(self.units)]))
        J = np.vstack(jac)
        return np.concatenate(rows), J, max(1.0, float(np.max(np.abs(J[:, :-self.np]), initial=0.0)))

    def det(self, J, scale: float) -> float:
        """det ∂F/∂φ (averaged over the sample times of a driven model), scaled: zero at a fold or a
        branch point of equilibria."""
        m = len(self.free)
        Jphi = J[:, :m].reshape(-1, m, m).mean(axis=0)
        return float(np.linalg.det(Jphi / scale)) if m else 1.0

    # ---- the spectrum and the tests
    def spectrum(self, y) -> tuple[np.ndarray, str, dict]:
        """(eigenvalues or multipliers, the verdict, the spectrum's tests) at y."""
        params, phi = self.at(y), self.phi_of(y)
        if self.driven is not None:
            self.driven.set_params(params)
            d = self.driven.classify(phi)
            Phi = d.monodromy[1:, 1:] if self.cyclic else d.monodromy
            return d.multipliers, d.verdict, self._driven_tests(d.multipliers, Phi)
        self.steady.params = params
        s = self.steady.classify(phi, self.rate(y))
        return s.eigenvalues, s.verdict, self._autonomous_tests(s.eigenvalues)

    def point(self, y, J, previous_t=None) -> Point:
        t = self.tangent(J, previous_t)
        spectrum, verdict, tests = self.spectrum(y)
        m = J.shape[1] - 1
        Jbp = J.reshape(-1, m, m + 1).mean(axis=0) if self.driven is not None else J
        tests["LP"] = float(t[-1])
        tests["BP"] = float(np.linalg.det(np.vstack([Jbp, t])))
        return Point(self.alpha(y), self.phi_of(y), spectrum, verdict, y, t, tests)

    def symmetric(self, ev) -> bool:
        """Whether the eigenvalues come in pairs λ, −λ (no damping: conservative, gyroscopic, a
        follower load): the characteristic polynomial is even."""
        if not len(ev):
            return True
        scale = max(1.0, float(np.max(np.abs(ev))))
        return all(np.min(np.abs(ev + z)) <= 1e-7 * scale for z in ev)

    def _autonomous_tests(self, ev) -> dict:
        if not len(ev):
            return {}
        scale = max(1.0, float(np.max(np.abs(ev))))
        if self.reversible:
            s = _even_roots(ev) / scale ** 2
            return {"KC": float(np.real(np.prod([(a - b) ** 2 for a, b in itertools.combinations(s, 2)])))}
        return {"H": float(np.real(np.prod([(a + b) / scale for a, b in itertools.combinations(ev, 2)])))}

    def _driven_tests(self, mu, Phi) -> dict:
        m = Phi.shape[0]
        tests = {"+1": float(np.linalg.det(Phi - np.eye(m))), "PD": float(np.linalg.det(Phi + np.eye(m)))}
        return {**tests, **circle_tests(mu, self.reversible)}

    reversible = True  # set per branch from its first point's spectrum (``symmetric``)


def _even_roots(ev) -> np.ndarray:
    """The n roots s = λ² of the even characteristic polynomial whose 2n roots are ``ev``."""
    coeffs = np.real(np.poly(ev))[::2]  # p(λ) = Σ c_k λ^(2n−2k) … only even powers survive
    return np.roots(coeffs) if len(coeffs) > 1 else np.zeros(0)


def circle_tests(mu, reversible: bool) -> dict:
    """The tests of multipliers meeting on the unit circle (two pairs or more): of a conservative
    drive (pairs μ, 1/μ) the discriminant in c = μ + 1/μ, a Krein collision; else the product of
    μᵢμⱼ − 1, a Neimark–Sacker pair."""
    if len(mu) < 4:
        return {}
    if reversible:
        c = pair_sums(mu)
        return {"KCm": float(np.real(np.prod([(a - b) ** 2 for a, b in itertools.combinations(c, 2)])))}
    return {"NS": float(np.real(np.prod([a * b - 1.0 for a, b in itertools.combinations(mu, 2)])))}


def pair_sums(mu) -> np.ndarray:
    """μ + 1/μ for one multiplier of each pair μ, 1/μ (the roots of the polynomial in c)."""
    coeffs = np.real(np.poly(mu))
    m = len(mu) // 2
    # p(μ) = μ^m q(μ + 1/μ) for a palindromic p: q from p by the substitution (its first m+1 coefficients)
    q = np.zeros(m + 1)
    rest = coeffs.copy()
    for k in range(m + 1):
        q[k] = rest[k]
        # subtract q_k μ^(m−k) (μ + 1/μ)^(m−k) expanded, from the palindromic p / μ^m
        binom = np.array([math.comb(m - k, j) for j in range(m - k + 1)])
        rest[k:k + 2 * (m - k) + 1:2] -= q[k] * binom
    return np.roots(q) if m else np.zeros(0)


# --------------------------------------------------------------------------- tracing
class Tracer:
    """Traces branches of ``Equilibria`` within [lo, hi]: steps, special points, branch points."""

    def __init__(self, eq: Equilibria, max_steps: int = 400, step: float = 0.02, progress=None):
        self.eq, self.max_steps, self.h0, self.progress = eq, max_steps, step, progress
        self.h_max = max(step, 0.1)
        self.steps = 0

    def start(self, phi, alpha: float) -> Point:
        """The branch's first point: Newton at fixed α from φ (ContinuationError if it finds none)."""
        eq = self.eq
        y = eq.y_of(phi, alpha)
        e_alpha = np.zeros_like(y)
        e_alpha[-1] = 1.0
        got = eq.correct(y, e_alpha)  # α held: t0 = e_α
        if got is None:
            raise ContinuationError(f"--from: Newton found no equilibrium at {eq.name} = {alpha:g} from phi = "
                                    f"{floquet.fmt_phi(phi)}")
        y, J, _ = got
        if np.linalg.matrix_rank(J / max(1.0, np.max(np.abs(J))), tol=1e-9) < J.shape[1] - 1:
            raise ContinuationError(f"--from: the Jacobian of the equilibrium at {eq.name} = {alpha:g}, phi = "
                                    f"{floquet.fmt_phi(eq.phi_of(y))} is singular (a fold or a branch point): start "
                                    "a little away from it")
        first = eq.point(y, J, e_alpha)
        reversible = eq.symmetric(first.spectrum) if eq.driven is None else palindromic(first.spectrum)
        if reversible != eq.reversible:  # the tests of a spectrum with (or without) its symmetry
            eq.reversible = reversible
            first = eq.point(y, J, e_alpha)
        return first

    def trace_both(self, first: Point, origin: str = "") -> Branch:
        """The branch through ``first`` both ways: its points in the order of the branch, from the
        end the way back reached to the end the way on reached."""
        ahead = self.trace(first, origin)
        odd = {k: -first.tests[k] for k in ("LP", "BP") if k in first.tests}  # both odd in t
        back_first = replace(first, tangent=-first.tangent, tests={**first.tests, **odd})
        back = self.trace(back_first, origin)
        gone = [p for p in back.points[1:] if np.linalg.norm(p.y - first.y) > 1e-12 * max(1.0, np.linalg.norm(first.y))]
        out = Branch([*reversed(gone), *ahead.points], origin=origin)  # (a start at the range's end: once)
        for s in reversed(back.specials):  # met going back: the sides swap
            out.specials.append(Special(s.kind, s.point, s.after, s.before, s.detail))
        out.specials += ahead.specials
        out.end = f"both ways {ahead.end}" if back.end == ahead.end else f"{back.end}; {ahead.end}"
        out.ends = (back.end, ahead.end)
        return out

    def trace(self, first: Point, origin: str = "", at=None) -> Branch:
        """The branch from ``first`` on (after ``at``, a branch point it leaves, when given)."""
        br = Branch([first], origin=origin)
        if at is not None:  # the branch point, with the new branch's tangent, opens it
            br.points.insert(0, replace(at, tangent=(first.y - at.y) / np.linalg.norm(first.y - at.y)))
        eq, h = self.eq, self.h0
        while True:
            if self.steps >= self.max_steps:
                edge = self._leaving(br.points[0]) if len(br.points) == 1 else None
                br.end = (f"reached the range's end, {eq.name} = {edge:.10g}" if edge is not None
                          else f"ran out of steps ({self.max_steps}; --max-steps raises it)")
                return br
            last = br.points[-1]
            pred = last.y + h * last.tangent
            got = eq.correct(pred, last.tangent, anchor=last.y)
            if got is not None:  # kept when the corrector stayed near the predictor and the branch turned little:
                y, J, its = got  # else the step may have jumped to another branch nearby
                if np.linalg.norm(y - pred) > MAX_CORRECTION * h:
                    got = None
                else:
                    p = eq.point(y, J, last.tangent)
                    if p.tangent @ last.tangent < math.cos(MAX_TURN):
                        got = None
            if got is None:
                h /= 2
                if h < MIN_STEP:
                    br.end = f"Newton could not go on past {eq.name} = {last.alpha:.10g} (step below {MIN_STEP:g})"
                    return br
                continue
            self.steps += 1
            self._specials(br, last, p)
            br.points.append(p)
            if self.progress:
                self.progress(len(br.points), p)
            if not eq.lo <= p.alpha <= eq.hi:  # the last point at the range's end, not past it
                edge = eq.hi if p.alpha > eq.hi else eq.lo
                br.points.pop()
                br.specials = [s for s in br.specials if eq.lo <= s.point.alpha <= eq.hi]
                end = self.at_alpha(last, p, edge)
                if end is not None:
                    br.points.append(end)
                br.end = f"reached the range's end, {eq.name} = {edge:.10g}"
                return br
            if len(br.points) > 3 and np.linalg.norm(wrap(p.y - br.points[0].y)) < 0.5 * h:
                br.end = "closed on itself"
                return br
            h = min(self.h_max, h * 1.5) if its <= 3 else h

    def _leaving(self, p: Point) -> float | None:
        """The range's end at which p lies, its tangent pointing out (a branch that starts there and
        has nowhere to go that way), or None."""
        eq = self.eq
        if p.alpha == eq.lo and p.tangent[-1] < 0:
            return eq.lo
        if p.alpha == eq.hi and p.tangent[-1] > 0:
            return eq.hi
        return None

    def _specials(self, br: Branch, a: Point, b: Point) -> None:
        """The special points between a and b, located, in the order of the branch. Where the
        tangent's α component and det [J; t] change sign together the point is a branch point
        (a pitchfork's branch turns there): it is said once, as one."""
        found = {kind: self.locate(a, b, kind) for kind in a.tests
                 if kind in b.tests and a.tests[kind] * b.tests[kind] < 0}
        if "LP" in found and "BP" in found:  # in one step: a pitchfork's branch turning at its branch point
            del found["LP"]
        if "+1" in found and "BP" in found:  # branches of periodic orbits cross: where the exact det(Φ − I) says
            found["BP"] = found.pop("+1")
            found.pop("LP", None)
        elif "+1" in found and "LP" in found:
            del found["+1"]  # a fold of periodic orbits (or of equilibria for all t): the multiplier +1 is the fold's own
        new = []
        chord = (b.y - a.y) / np.linalg.norm(b.y - a.y)  # the branch's way through a branch point (J's null space
        for kind, p in found.items():                    # is two-dimensional there: its tangent would be any)
            if kind == "+1":
                kind = getattr(self.eq, "plus_one", "+1")  # a driven orbit's multiplier +1 off a fold: a branch point
            if kind == "BP":
                p = replace(p, tangent=chord)
            if kind == "KC" and eq_real_collision(p.spectrum):
                kind = "RC"  # real eigenvalues meet and leave the axis as a quadruple: no change of stability
            new.append(Special(kind, p, a.verdict, b.verdict, self._detail(kind, p, a, b)))
        step = np.linalg.norm(b.y - a.y)  # a pitchfork's branch turns at its branch point: one point, said as the BP
        for old in [o for o in br.specials[-2:] if o.kind in ("LP", "BP")]:
            for s in [s for s in new if {s.kind, old.kind} == {"LP", "BP"}]:
                if np.linalg.norm(s.point.y - old.point.y) <= step:
                    (new.remove(s) if s.kind == "LP" else br.specials.remove(old))
        br.specials += sorted(new, key=lambda s: (s.point.y - a.y) @ a.tangent)

    def at_alpha(self, a: Point, b: Point, alpha: float) -> Point | None:
        """The point of the branch between a and b where the parameter is ``alpha``."""
        eq = self.eq
        w = (alpha - a.alpha) / (b.alpha - a.alpha)
        e_alpha = np.zeros_like(a.y)
        e_alpha[-1] = 1.0
        got = eq.correct(a.y + w * (b.y - a.y), e_alpha)
        if got is None:
            return None
        p = eq.point(got[0], got[1], a.tangent)
        p.alpha = alpha  # the range's end itself (its scaled y rounds it in the last digit)
        return p

    def locate(self, a: Point, b: Point, kind: str) -> Point:
        """The zero of the test ``kind`` between a and b: Illinois on the arclength s from a (the
        points with t_a·(y − a) = s), each trial predicted from the nearer end of the bracket
        along its tangent, so that the prediction improves as the bracket shrinks (which a
        Newton near a branch point, where the system turns singular, needs)."""
        eq = self.eq
        s_lo, s_hi = 0.0, float(a.tangent @ (b.y - a.y))
        f_lo, f_hi = a.tests[kind], b.tests[kind]
        p_lo, p_hi = a, b
        best, side = b, 0

        def trial(s):
            base, s_base = (p_lo, s_lo) if abs(s - s_lo) <= abs(s_hi - s) else (p_hi, s_hi)
            pred = base.y + (s - s_base) / (a.tangent @ base.tangent) * base.tangent  # on t_a·(y − a) = s
            got = eq.correct(pred, a.tangent, anchor=a.y)
            if got is not None and np.linalg.norm(got[0] - pred) > MAX_CORRECTION * max(abs(s - s_base), 1e-9):
                return None  # it went to another branch through a branch point nearby
            return got

        seen = [(0.0, f_lo, a.y, None), (s_hi, f_hi, b.y, None)]  # (s, test, y, J) of the points corrected
        for _ in range(80):
            s = (s_lo * f_hi - s_hi * f_lo) / (f_hi - f_lo)
            got = trial(s)
            if got is None:
                s = (s_lo + s_hi) / 2
                got = trial(s)
                if got is None:  # Newton fails this near a branch point: the zero from the points around it
                    return self._interpolated(seen, s_lo, s_hi, a) or best
            p = eq.point(got[0], got[1], a.tangent)
            best, f = p, p.tests.get(kind, 0.0)
            seen.append((s, f, got[0], got[1]))
            if f == 0.0 or abs(s_hi - s_lo) <= SPECIAL_TOL * max(1.0, abs(s)):
                break
            if f * f_lo > 0:
                s_lo, f_lo, p_lo = s, f, p
                if side == -1:
                    f_hi /= 2
                side = -1
            else:
                s_hi, f_hi, p_hi = s, f, p
                if side == 1:
                    f_lo /= 2
                side = 1
        return best

    def _interpolated(self, seen, s_lo: float, s_hi: float, a: Point) -> Point | None:
        """The zero of a test between s_lo and s_hi from the (up to) two corrected points nearest it
        on each side: the test and y as cubics in s, the point the cubic y gives at the zero (the
        test is smooth along the branch: what a Newton there cannot reach, the fit does)."""
        left = sorted((e for e in seen if e[0] <= s_lo), key=lambda e: -e[0])[:2]
        right = sorted((e for e in seen if e[0] >= s_hi), key=lambda e: e[0])[:2]
        near = left + right
        if len(left) < 1 or len(right) < 1 or any(e[3] is None for e in near[:1] + near[-1:]) and len(near) < 3:
            return None
        ss = np.array([e[0] for e in near])
        deg = len(near) - 1
        f = np.polyfit(ss - s_lo, [e[1] for e in near], deg)
        roots = [r.real + s_lo for r in np.roots(f) if abs(r.imag) < 1e-12 and -1e-12 <= r.real <= s_hi - s_lo + 1e-12]
        if not roots:
            return None
        star = min(roots, key=lambda r: abs(r - (s_lo + s_hi) / 2))  # (one zero in the bracket; of several, the middle's)
        Y = np.polyfit(ss - s_lo, np.array([e[2] for e in near]), deg)
        y = np.array([np.polyval(Y[:, k], star - s_lo) for k in range(Y.shape[1])])
        J = next(e[3] for e in sorted(near, key=lambda e: abs(e[0] - star)) if e[3] is not None)
        try:
            return self.eq.point(y, J, a.tangent)
        except ArithmeticError:
            return None

    def _detail(self, kind: str, p: Point, a: Point, b: Point) -> str:
        ev = p.spectrum
        if kind in ("KC", "H") and len(ev):
            near = ev[np.argmin(np.abs(ev.real))]
            omega = abs(near.imag)
            if kind == "KC":  # the mean of the two λ² that meet: a double root's own digits are half lost
                sq = _even_roots(ev)
                i, j = min(itertools.combinations(range(len(sq)), 2), key=lambda ij: abs(sq[ij[0]] - sq[ij[1]]))
                omega = math.sqrt(max(0.0, -float(np.real(sq[i] + sq[j])) / 2))
            text = f"at ω = {omega:.10g} rad/s"
            if kind == "KC" and self.eq.driven is None:
                apart = a if a.tests["KC"] > 0 else b  # the side where the pair is apart on the axis
                text += krein(self.eq, apart, omega)
            return text
        if kind == "+1" and getattr(self.eq, "plus_one", "") == "+1" and getattr(self.eq, "driven", None) is False:
            return "(a pair of the nontrivial multipliers: another family of orbits branches off here)"
        if kind in ("NS", "KCm") and len(ev):
            on = ev[np.argmax(np.abs(ev.imag))]
            return f"multipliers e^(±{abs(np.angle(on)):.10g}i)"
        return ""

    def switch(self, bp: Special) -> list[Point]:
        """The first points of the other branch through the branch point ``bp``, both ways."""
        eq, p = self.eq, bp.point
        F, J, scale = eq.residual(p.y)
        V = np.linalg.svd(J / scale)[2]
        null = V[-2:]  # the two smallest directions: the branches' tangents span them
        other = null[0] - (null[0] @ p.tangent) * p.tangent
        if np.linalg.norm(other) < 0.5:
            other = null[1] - (null[1] @ p.tangent) * p.tangent
        other /= np.linalg.norm(other)
        out = []
        for sign in (1.0, -1.0):
            d = sign * other
            got = eq.correct(p.y + self.h0 * d, d, anchor=p.y)
            if got is not None:
                q = eq.point(got[0], got[1], d)
                if np.linalg.norm(q.y - p.y) > 0.1 * self.h0:
                    out.append(q)
        return out


def eq_real_collision(ev) -> bool:
    """Whether the two s = λ² that meet at a collision are positive (real eigenvalues ±√s meet):
    the closest pair of s is on the positive axis."""
    s = _even_roots(ev)
    if len(s) < 2:
        return False
    i, j = min(itertools.combinations(range(len(s)), 2), key=lambda ij: abs(s[ij[0]] - s[ij[1]]))
    return float(np.real(s[i] + s[j])) > 0


def palindromic(mu) -> bool:
    """Whether the multipliers come in pairs μ, 1/μ (a conservative drive)."""
    if len(mu) % 2 or not len(mu):
        return False
    return all(np.min(np.abs(mu - 1.0 / z)) <= 1e-6 * max(1.0, abs(z)) for z in mu)


def krein(eq: Equilibria, p: Point, omega: float) -> str:
    """The Krein signatures of the eigenvalues near iω just before they meet: the sign of
    v̄ᵀ(ω²M + K)v for the eigenvectors v of δφ (the energy the mode carries)."""
    st = eq.steady
    if not st.conservative:
        return f"; not a Krein collision: the model is not conservative ({', '.join(st.others)})"
    st.params = eq.at(p.y)
    s = st.classify(p.phi, eq.rate(p.y))
    m = s.K.shape[0]
    if m == 0:
        return ""
    # the quadratic pencil λ²M + λG + K in the reduced coordinates, its eigenvectors from the linearisation A
    x = np.concatenate([p.phi, np.zeros(eq.n)])
    M = st.c.mass_matrix(x[:eq.n], st.params)
    Mr = M[1:, 1:] - np.outer(M[1:, 0], M[0, 1:]) / M[0, 0] if eq.cyclic else M
    A = np.block([[np.zeros((m, m)), np.eye(m)], [-np.linalg.solve(Mr, s.K), -np.linalg.solve(Mr, s.G)]])
    lam, vec = np.linalg.eig(A)
    near = [i for i in np.argsort(np.abs(lam - 1j * omega))[:2]]
    signs = []
    for i in near:
        v = vec[:m, i]
        w = abs(lam[i].imag)
        signs.append("+" if np.real(np.conj(v) @ (w * w * Mr + s.K) @ v) > 0 else "-")
    return f"; Krein signatures {signs[0]}, {signs[1]}" + (" (opposite: the pair leaves the axis)" if signs[0] != signs[1] else "")
