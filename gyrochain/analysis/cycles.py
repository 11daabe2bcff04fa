r"""Branches of periodic orbits traced by continuation: ``gyrochain continue SPEC --orbits``.

The same pseudo-arclength Tracer as the equilibria (continuation.py), on the shooting equations
of ``orbits`` with the emitted variational equations (NAME_integrate_variational):

* A model driven with period T(α) (the spec's sines and cosines of t, or --period): the orbits of
  the drive's period.  The unknowns are y = (x₀, α), the equations $x(T; x_0, \alpha) - x_0 = 0$,
  their Jacobian $[\Phi(T) - I \mid \partial x(T)/\partial\alpha]$: Φ the monodromy matrix (exact,
  the variational equations), the parameter's column by central differences of the flow over
  α ± DIFF (T(α) with it).  A fold is a zero of the tangent's α component, exactly where
  $\Phi - I$ is singular whatever the column's error; branch points as for the equilibria.
* An autonomous model whose energy (23) is an integral: its nonlinear normal modes, a family
  over the energy.  The unknowns are y = (x₀, T, α), α = E − E₀ the energy above the stable
  equilibrium's, and the equations
      $x(T; x_0) - x_0 = 0$,   $x_{0,j} = 0$ (a turning point of the mode: the phase condition),
      $E(x_0) - E_0 - \alpha = 0$,
  2n + 2 equations in 2n + 2 unknowns of which one is redundant (the energy is conserved, so
  $\nabla E^{\mathsf T}(\Phi - I) = 0$ and $\nabla E \cdot f = 0$): the Jacobian has rank 2n + 1, its
  null vector is the family's tangent, and Newton solves the consistent system by least squares.
  The energy's gradient is by central differences of the emitted energy.
* The multipliers: the eigenvalues of Φ(T).  An autonomous orbit has two at 1; they are divided
  out of the characteristic polynomial, $p(\mu) = (\mu - 1)^2 q(\mu)$, and the tests are smooth
  functions of q's coefficients: $q(1) = p''(1)/2$ (a nontrivial pair through +1: a family
  bifurcates and the orbit changes stability), $q(-1)$ (period doubling; $p(-1)/4$ where the
  trivial pair is exactly 1), and on q's
  roots, the nontrivial multipliers, the collision on the unit circle (a conservative model) or
  the Neimark–Sacker pair.  A driven orbit's tests are det(Φ − I) (a multiplier +1: a fold where
  the tangent's α component vanishes with it, else a branch point, located on the exact Φ rather
  than on det [J; t], whose α column is differenced), det(Φ + I) and the unit circle's.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from . import floquet
from . import orbits as shooting
from .continuation import ContinuationError, Point, Pseudoarclength, circle_tests, palindromic

ENERGY = "energy"  # the varied quantity of a family of nonlinear normal modes: the energy above the equilibrium's, J
DIFF = 1e-5  # the step of the parameter's central difference, in units of its range
PERIOD_RATIO = 20.0  # a family's periods within this factor of its first: beyond, a step has gone astray (T → 0
#                      solves x(T) = x₀ trivially) or the family nears an orbit of infinite period (a separatrix)
SWING_SAMPLES = 256  # the times of a period at which a diagram's amplitude is sampled
TOL = 1e-14  # rtol = atol of a period's integration (the variational one and the differenced ones)


@dataclass
class OrbitPoint(Point):
    """A point of a branch of periodic orbits: its start's rates and its period besides."""

    phidot: np.ndarray = None
    period: float = float("nan")
    amplitude: np.ndarray = None  # half of each angle's swing over the period (``Orbits.swing``), for the diagram


class Orbits(Pseudoarclength):
    """The shooting equations of the periodic orbits of a built model as functions of y, the
    parameter (or the energy) in units of its range: ``period`` is T(params) of a driven model
    (None: autonomous, the family over the energy, ``E0`` the equilibrium's and ``phase`` the
    index of the state component that is 0 at the start)."""

    steady = None
    plus_one = "+1"  # what a multiplier +1 away from a fold is: a branch point of a driven model's orbits (set below)

    def __init__(self, cm, params: dict, u, name: str, lo: float, hi: float, period=None, phase: int = 0,
                 E0: float = 0.0, T_ref: float | None = None):
        self.c, self.n, self.u = cm, cm.n, u
        self.name, self.lo, self.hi = name, float(lo), float(hi)
        self.unit = self.hi - self.lo
        self.params, self.period_of = dict(params), period
        self.driven = period is not None  # (what the Tracer asks: a driven model's tests)
        self.phase, self.E0 = phase, E0
        self.T_ref = T_ref  # the family's first period: y holds log(T/T_ref), and |log(T/T_ref)| ≤ log PERIOD_RATIO
        self.m = 2 * self.n + (0 if self.driven else 1)  # the unknowns before α: x₀[, T]
        self.reversible = True
        if self.driven:
            self.plus_one = "BP"  # det(Φ − I) = 0 on the branch but no fold: branches cross (exact, unlike det [J; t])

    def alpha(self, y) -> float:
        return self.lo + self.unit * float(y[-1])

    def y_of(self, x0, alpha: float, T: float | None = None) -> np.ndarray:
        head = [np.asarray(x0, float)] + ([] if self.driven else [[math.log(float(T) / self.T_ref)]])
        return np.concatenate(head + [[(alpha - self.lo) / self.unit]])

    def at(self, y) -> dict:
        return {**self.params, self.name: self.alpha(y)} if self.driven else self.params

    def period(self, y) -> float:
        return float(self.period_of(self.at(y))) if self.driven else self.T_ref * math.exp(float(y[2 * self.n]))

    def _flow(self, y, s: float) -> np.ndarray:
        """x(T) of the driven model from y's x₀ with the parameter at s (scaled)."""
        z = y.copy()
        z[-1] = s
        params, T = self.at(z), self.period(z)
        return self.c.integrate([0.0, T], y[:2 * self.n], rtol=TOL, atol=TOL, u=self.u, params=params)[-1]

    def energy(self, x) -> float:
        return float(self.c.energy(np.asarray(x, float), self.params))

    def _energy_gradient(self, x) -> np.ndarray:
        g = np.empty(len(x))
        for i in range(len(x)):
            h = 1e-6 * max(1.0, abs(x[i]))
            e = np.zeros(len(x))
            e[i] = h
            g[i] = (self.energy(x + e) - self.energy(x - e)) / (2 * h)
        return g

    def shoot(self, y):
        """(x(T), Φ(T), T) from y."""
        T = self.period(y)
        if not T > 0 or (not self.driven and abs(float(y[2 * self.n])) > math.log(PERIOD_RATIO)):
            raise ArithmeticError("a period not positive, or out of the family's (a Newton step astray)")
        x1, Phi = self.c.integrate_variational(0.0, T, y[:2 * self.n], u=self.u, params=self.at(y), rtol=TOL, atol=TOL)
        if not np.max(np.abs(Phi)) <= shooting.UNSHOOTABLE:  # round-off grown past the orbit: beyond single shooting
            raise ArithmeticError("the monodromy grows beyond what single shooting resolves")
        return x1, Phi, T

    def residual(self, y):
        """(F, J, scale), J over (x₀[, T], α in units of its range)."""
        n2 = 2 * self.n
        x0 = y[:n2]
        x1, Phi, T = self.shoot(y)
        scale = max(1.0, float(np.max(np.abs(Phi))))
        if self.driven:
            column = (self._flow(y, y[-1] + DIFF) - self._flow(y, y[-1] - DIFF)) / (2 * DIFF)
            return x1 - x0, np.column_stack([Phi - np.eye(n2), column]), scale
        f1 = self.c.rhs(T, x1, self.u, self.params)
        F = np.concatenate([x1 - x0, [x0[self.phase]], [self.energy(x0) - self.E0 - self.alpha(y)]])
        J = np.zeros((n2 + 2, n2 + 2))
        J[:n2, :n2], J[:n2, n2] = Phi - np.eye(n2), T * f1  # ∂x(T)/∂ log T
        J[n2, self.phase] = 1.0
        J[n2 + 1, :n2], J[n2 + 1, -1] = self._energy_gradient(x0), -self.unit
        return F, J, scale

    # ---- the multipliers and the tests
    def multipliers(self, Phi) -> tuple[np.ndarray, dict]:
        """(the nontrivial multipliers by decreasing modulus, the tests of the spectrum)."""
        mu = np.linalg.eigvals(Phi)
        p = np.real(np.poly(mu))
        if self.driven:  # +1: a fold (where the tangent's α component vanishes too) or a branch point
            tests = {"+1": float(np.polyval(p, 1.0)), "PD": float(np.polyval(p, -1.0))}
        else:
            q = np.polydiv(p, [1.0, -2.0, 1.0])[0]  # p / (μ − 1)²: the trivial pair divided out
            mu = np.roots(q) if len(q) > 1 else np.zeros(0, complex)
            tests = {"+1": float(np.polyval(q, 1.0)), "PD": float(np.polyval(q, -1.0))} if len(q) > 1 else {}
        tests.update(circle_tests(mu, self.reversible))
        return mu[np.lexsort((-mu.imag, -np.abs(mu)))], tests

    def point(self, y, J, previous_t=None) -> OrbitPoint:
        t = self.tangent(J, previous_t)
        _x1, Phi, T = self.shoot(y)
        mu, tests = self.multipliers(Phi)
        verdict = floquet.verdict(mu)[0]
        tests["LP"] = float(t[-1])
        if self.driven:  # (its sign tells a branch point from a fold; where, det(Φ − I) says: the α column is differenced)
            tests["BP"] = float(np.linalg.det(np.vstack([J, t])))
        n = self.n
        return OrbitPoint(self.alpha(y), y[:n].copy(), mu, verdict, y, t, tests, phidot=y[n:2 * n].copy(), period=T)

    def swing(self, p: OrbitPoint, samples: int = SWING_SAMPLES) -> np.ndarray:
        """Half of each angle's swing (max − min) over the orbit, sampled at ``samples`` times of
        the period: the amplitude a diagram draws (sampled: to about (π/samples)²/2 of itself)."""
        ts = np.linspace(0.0, p.period, samples + 1)
        X = self.c.integrate(ts, p.y[:2 * self.n], rtol=1e-10, atol=1e-12, u=self.u, params=self.at(p.y))
        phi = X[:, :self.n]
        return (phi.max(axis=0) - phi.min(axis=0)) / 2

    def start(self, x0, alpha: float, T: float | None = None) -> OrbitPoint:
        """The branch's first point: Newton at fixed α from x₀ (and T), ContinuationError if none."""
        y = self.y_of(x0, alpha, T)
        e_alpha = np.zeros_like(y)
        e_alpha[-1] = 1.0
        got = self.correct(y, e_alpha)
        if got is None:
            where = (f"from phi = {floquet.fmt_phi(np.asarray(x0)[:self.n])}, phidot = "
                     f"{floquet.fmt_phi(np.asarray(x0)[self.n:])}")
            raise ContinuationError(f"--from: Newton found no periodic orbit at {self.name} = {alpha:g} {where}"
                                    if self.driven else f"--vary {ENERGY}: Newton lost the orbit at {ENERGY} = {alpha:g} "
                                    f"{where}; start at a smaller energy")
        y, J, _ = got
        y[:self.n] = floquet.wrap(y[:self.n])  # the same orbit, its angles in (−π, π]
        if self.driven and np.linalg.matrix_rank(J / max(1.0, np.max(np.abs(J))), tol=1e-9) < J.shape[1] - 1:
            raise ContinuationError(f"--from: the orbit at {self.name} = {alpha:g} is at a fold or a branch point "
                                    "(its monodromy has the multiplier 1): start a little away from it")
        first = self.point(y, J, e_alpha)
        reversible = palindromic(first.spectrum) if len(first.spectrum) else True
        if reversible != self.reversible:
            self.reversible = reversible
            first = self.point(y, J, e_alpha)
        return first


def driven_firsts(eq: Orbits, starts, alpha0: float) -> list[OrbitPoint]:
    """The first points of a driven model's branches: Newton from each start (φ, or φ and φ̇; at
    rest at φ = 0 when none is given)."""
    n = eq.n
    out = []
    for s in starts or [np.zeros(n)]:
        s = np.asarray(s, float)
        x0 = np.concatenate([s, np.zeros(n)]) if len(s) == n else s
        out.append(eq.start(x0, alpha0))
    return out


def mode_starts(cm, params, u, phi, energy: float, modes):
    """The first orbits of the nonlinear normal modes at the stable equilibrium φ, at ``energy``
    above it: for each linear mode (``modes``: their numbers, 1 = the slowest; all when empty)
    (k, (x₀, T, the phase condition's index, E₀, a description)), by ``orbits``' start and Newton."""
    from ..chainspec.errors import SpecError

    try:
        lin = shooting.linear_modes(cm, phi, params or None, u)
    except SpecError as exc:  # (orbits' --at is continue's --from)
        raise ContinuationError(f"--from: {exc.message}") from None
    picked = list(modes or range(1, len(lin) + 1))
    for k in picked:
        if not 1 <= k <= len(lin):
            raise ContinuationError(f"--mode: the equilibrium has {len(lin)} linear modes; got {k}")
    out = []
    for k in picked:
        omega, v = lin[k - 1]
        sh = shooting.Shooting(cm, params or None, u)
        x0, sh.phase, E0 = shooting.mode_start(sh, phi, omega, v, energy)
        T_lin = 2 * math.pi / omega
        got = sh.solve(x0, T_lin, E0 + energy, 0.0, 0.0)
        if got is None or not T_lin / 3 <= got[1] <= 3 * T_lin:  # (T → 0 solves x(T) = x₀ too)
            raise ContinuationError(f"--vary {ENERGY}: Newton found no orbit of mode {k} at {ENERGY} = {energy:g} above "
                                    f"the equilibrium phi = {floquet.fmt_phi(phi)}; start at a smaller energy")
        out.append((k, (got[0], got[1], sh.phase, E0, f"mode {k} (linear: omega = {omega:.10g} rad/s)")))
    return out
