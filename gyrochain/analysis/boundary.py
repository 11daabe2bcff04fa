r"""A special point of a branch continued in two parameters: the stability boundary as a curve.

From a point located by ``continuation`` (a fold, a collision of eigenvalues on the imaginary
axis, a Hopf point, a Floquet multiplier through ±1, …) the unknowns become y = (φ free, α, β)
and the equations F(y) = 0 (the equilibrium, as in ``continuation``) and ψ(y) = 0, ψ the test
function that located the point (for a fold or a branch point, det ∂F/∂φ).  The curve is traced
by the same pseudo-arclength steps, both ways from the point, until it leaves the box of the two
ranges.  F's derivatives are the emitted C's; ψ's gradient is a central difference (step DIFF in
the scaled y), which only sets how fast Newton converges: the curve is where ψ itself vanishes,
to NEWTON_TOL.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .continuation import MAX_TURN, MIN_STEP, Equilibria, Pseudoarclength

DIFF = 1e-6  # the central difference step of ψ's gradient, in the scaled y


@dataclass
class Curve:
    """The boundary: its points (the two parameters' values and φ), in order along the curve, and
    why each end stops."""

    kind: str
    points: list = field(default_factory=list)  # (values, φ, y)
    ends: list = field(default_factory=list)


class Boundary(Pseudoarclength):
    """The codimension-one condition ``kind`` (a key of continuation.KINDS) on the equilibria of
    ``eq`` (an Equilibria in two parameters)."""

    def __init__(self, eq: Equilibria, kind: str, max_steps: int = 400, step: float = 0.02, progress=None):
        self.eq, self.kind, self.max_steps, self.h0, self.progress = eq, kind, max_steps, step, progress
        self.h_max = max(step, 0.1)
        self.scale = 1.0

    def psi(self, y) -> float:
        if self.kind in ("LP", "BP"):
            _, J, scale = self.eq.residual(y)
            return self.eq.det(J, scale)
        return self.eq.spectrum(y)[2][self.kind] / self.scale

    def system(self, y):
        """(G, JG): [F/scale; ψ] and its Jacobian (F's exact, ψ's row by central differences)."""
        F, J, scale = self.eq.residual(y)
        grad = np.empty(len(y))
        for i in range(len(y)):
            e = np.zeros(len(y))
            e[i] = DIFF
            grad[i] = (self.psi(y + e) - self.psi(y - e)) / (2 * DIFF)
        return np.append(F / scale, self.psi(y)), np.vstack([J / scale, grad]), scale

    def residual(self, y):
        """The system as the corrector takes it: (G, JG, 1), G already scaled."""
        G, JG, _ = self.system(y)
        return G, JG, 1.0

    def trace(self, y0) -> Curve:
        """The curve through y0 (a located special point of the first parameter's branch), both ways."""
        self.scale = 1.0
        if self.kind not in ("LP", "BP"):  # ψ in units of its gradient: a step of 1 in y moves it by about 1
            grad = float(np.linalg.norm(self.system(y0)[1][-1]))
            self.scale = grad if grad > 0 else 1.0
        got = self.correct(y0, self._fixed_first(y0), y0)
        if got is None:
            raise ArithmeticError("the special point could not be corrected in two parameters")
        y0, JG, _ = got
        t0 = self.tangent(JG)
        halves = []
        for sign in (1.0, -1.0):
            halves.append(self._half(y0, sign * t0))
        back, fwd = halves[1], halves[0]
        curve = Curve(self.kind)
        curve.points = [*reversed(back[0][1:]), *fwd[0]]
        curve.ends = [back[1], fwd[1]]
        return curve

    def _fixed_first(self, y0):
        """A direction that holds the first parameter: the point is corrected at its own α."""
        e = np.zeros(len(y0))
        e[-2] = 1.0
        return e

    def _half(self, y0, t):
        eq, h = self.eq, self.h0
        pts = [self._record(y0)]
        y, steps = y0, 0
        while True:
            if steps >= self.max_steps:
                return pts, f"ran out of steps ({self.max_steps})"
            got = self.correct(y + h * t, t, y)
            if got is not None:
                yn, JG, its = got
                tn = self.tangent(JG, t)
                if tn @ t < math.cos(MAX_TURN):
                    got = None
            if got is None:
                h /= 2
                if h < MIN_STEP:
                    return pts, f"Newton could not go on (step below {MIN_STEP:g})"
                continue
            steps += 1
            if not eq.inside(yn):  # the last point on the box's edge, where the curve leaves it
                edge = self._on_edge(y, yn)
                if edge is not None:
                    pts.append(edge)
                return pts, "reached the edge of the ranges"
            pts.append(self._record(yn))
            if self.progress:
                self.progress(len(pts), pts[-1])
            y, t = yn, tn
            h = min(self.h_max, h * 1.5) if its <= 3 else h

    def _on_edge(self, y, yn):
        """The point of the curve between y (inside) and yn (outside) on the ranges' edge."""
        eq = self.eq
        inside, outside = eq.values(y), eq.values(yn)
        best = None
        for i, ((lo, hi), a, b) in enumerate(zip(eq.ranges, inside, outside)):
            if lo <= b <= hi:
                continue
            bound = hi if b > hi else lo
            w = (bound - a) / (b - a)
            if best is None or w < best[0]:
                best = (w, i, bound)
        w, i, edge = best
        hold = np.zeros(len(y))
        hold[len(y) - eq.np + i] = 1.0
        got = self.correct(y + w * (yn - y), hold, y + w * (yn - y))
        if got is None:
            return None
        values, phi, ye = self._record(got[0])
        values = tuple(edge if k == i else v for k, v in enumerate(values))  # the edge itself, not its last digit
        return values, phi, ye

    def _record(self, y):
        return tuple(self.eq.values(y)), self.eq.phi_of(y), y
