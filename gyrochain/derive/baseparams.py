"""Base parameters: the combinations of the standard parameters π that the motion determines.

Columns of Y are linearly dependent: a body's mass, its first moment along its own joint axis
and part of its inertia act as if they were fixed to the body before it, and near the base some
columns vanish (body 1 turns about one fixed axis).  Gautier's grouping rules give these
relations symbolically for the common geometries, but every special case (parallel axes, axes
through the centre of mass, a vertical first axis, a moving platform, rotors) needs a rule of its
own; so the relations are found numerically, from the regressor itself, whatever the geometry:

1.  Y is stacked at random states (φ, φ̇, φ̈ and t), its columns scaled to unit length, and
    factored by QR in the order of π (no pivoting), so a column is kept when it is not a
    combination of the columns before it: the kept ones are the base columns B, and each base
    parameter is named after the earliest standard parameter of its group (body 1 before body 2,
    m before h before A before λ), as in the grouping rules' β = A¹₁₁ + A²₃₃ + m² s².
2.  The other columns D are Y_D = Y_B K (least squares; the residual is round-off), so
    Y π = Y_B β with β = π_B + K π_D.
3.  Each coefficient of K is recovered as an exact number when it is one: a rational with a
    denominator up to 10⁴ or a decimal of up to twelve places, within 1e-12 of the computed
    value (a coefficient is a product of the spec's lengths and the cosines of its angles, so
    with decimal geometry and right angles it is such a number), kept only where the regressor
    at fresh states agrees with the exact column as well as with the computed one.  What is not
    recovered is kept as the computed double and said to be numerical.

The relations depend on the geometry only (θ, δ, s, g and the platform's motion), not on the
inertial values; a spec whose geometry has symbolic parameters is taken at their [values].
"""
from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

import numpy as np
import sympy as sp

from . import reference
from ..chainspec.errors import SpecError
from ..chainspec.spec import ChainSpec

RANK_TOL = 1e-8  # a scaled column is dependent when its part outside the earlier ones is below this
EXACT_TOL = 1e-12  # a candidate exact coefficient is this near the computed one (relative, or absolute below 1)


@dataclass(frozen=True)
class BaseParameters:
    columns: tuple  # indices into π of the base columns B, in order
    K: tuple  # per base parameter: ((index into π, coefficient), ...), its own column first with 1
    numerical: tuple  # per base parameter: whether a coefficient could not be recovered exactly
    residual: float  # max |Y_B K − Y_D| / max |Y| over the fresh states of the check
    at: tuple = ()  # (name, value) of the geometry's symbolic parameters: K holds at these values

    @property
    def count(self) -> int:
        return len(self.columns)

    def matrix(self, n_params: int) -> np.ndarray:
        """K as a (count × len(π)) array: β = K π."""
        out = np.zeros((self.count, n_params))
        for i, row in enumerate(self.K):
            for j, c in row:
                out[i, j] = float(c)
        return out

    def expression(self, i: int, symbols) -> sp.Expr:
        """βᵢ in the standard parameters' ``symbols`` (sympy)."""
        return sp.Add(*[c * symbols[j] for j, c in self.K[i]])


def geometric(spec: ChainSpec) -> list:
    """The symbolic parameters the regressor reads (angles, offsets, lengths, gravity, the
    platform's motion), in the spec's order: the base parameters depend on their values."""
    found = set(sp.sympify(spec.g).free_symbols)
    for b in spec.bodies:
        for x in (b.theta, b.offset, *b.s):
            found |= sp.sympify(x).free_symbols
    if spec.base is not None:
        found |= set(spec.params)  # the platform's motion: take every parameter as geometric
    return [p for p in spec.params if p in found]


def geometry_values(spec: ChainSpec, values: dict | None = None) -> dict:
    """Values for every symbolic parameter: the given (or [values]) ones; a parameter without a
    value that the geometry does not read gets 1 (the regressor does not depend on it); one
    the geometry reads is refused."""
    values = dict(spec.values if values is None else values)
    reads = geometric(spec)
    for p in spec.params:
        if str(p) not in values:
            if p in reads:
                raise SpecError(f"[values].{p}", "the base parameters depend on it (it sets the geometry): give it a "
                                                   "value in [values]")
            values[str(p)] = 1.0
    return values


def _stack(ch, cols, n, rng, states: int) -> np.ndarray:
    rows = []
    for _ in range(states):
        q = rng.uniform(-np.pi, np.pi, n)
        v, a = rng.normal(size=(2, n))
        rows.append(reference.regressor(ch, cols, q, v, a, float(rng.uniform(0.0, 10.0))))
    return np.vstack(rows)


def _exact(x: float):
    """The simplest exact number near x: 0, a rational with a denominator up to 10⁴, or a decimal of
    up to twelve places, within EXACT_TOL of it (a candidate: ``find`` keeps it only if the
    regressor agrees), else None."""
    tol = EXACT_TOL * max(1.0, abs(x))
    if abs(x) <= tol:
        return sp.Integer(0)
    r = Fraction(x).limit_denominator(10_000)
    if abs(float(r) - x) <= tol:
        return sp.Rational(r.numerator, r.denominator)
    for places in range(13):
        d = round(x, places)
        if abs(d - x) <= tol:
            return sp.Rational(Fraction(repr(d)))
    return None


def find(spec: ChainSpec, params, values: dict | None = None, seed: int = 0) -> BaseParameters:
    """The base parameters of ``params`` (regressor.parameters(spec)) for this spec's geometry."""
    vals = geometry_values(spec, values)
    ch = reference.numeric(spec, vals)
    cols = [(p.kind, p.body, p.index) for p in params]
    n, npar = spec.n, len(params)
    rng = np.random.default_rng(seed)
    states = max(8, 3 * npar // n + 4)
    Y = _stack(ch, cols, n, rng, states)
    norms = np.linalg.norm(Y, axis=0)
    live = norms > RANK_TOL * max(norms.max(), 1e-300)
    Ys = np.where(live, Y / np.where(live, norms, 1.0), 0.0)
    base: list[int] = []
    Q = np.zeros((Y.shape[0], 0))
    for j in range(npar):  # QR in the order of π: keep a column that the kept ones do not span
        if not live[j]:
            continue
        r = Ys[:, j] - Q @ (Q.T @ Ys[:, j])
        r = r - Q @ (Q.T @ r)  # twice is enough (Kahan–Parlett)
        if np.linalg.norm(r) > RANK_TOL:
            base.append(j)
            Q = np.column_stack([Q, r / np.linalg.norm(r)])
    dep = [j for j in range(npar) if j not in base]
    X = np.linalg.lstsq(Y[:, base], Y[:, dep], rcond=None)[0] if dep and base else np.zeros((len(base), len(dep)))
    # each dependent column's coefficients as exact numbers where the regressor, at fresh states,
    # agrees with them as well as with the computed ones (a wrong candidate, off by 1e-13 of a
    # coefficient, leaves a residual a thousand times the round-off's)
    Yc = _stack(ch, cols, n, np.random.default_rng(seed + 1), 4)
    coef = {}  # (base row, dependent column) -> the coefficient (sympy: exact, or a Float)
    for jj, d in enumerate(dep):
        floats = X[:, jj]
        exact = [_exact(float(x)) for x in floats]
        r_float = np.linalg.norm(Yc[:, base] @ floats - Yc[:, d])
        if all(c is not None for c in exact):
            r_exact = np.linalg.norm(Yc[:, base] @ np.array([float(c) for c in exact]) - Yc[:, d])
            if r_exact <= 4 * r_float + 1e-14 * np.linalg.norm(Yc[:, d]):
                coef.update({(i, d): c for i, c in enumerate(exact) if c != 0})
                continue
        coef.update({(i, d): sp.Float(float(x), 17) for i, x in enumerate(floats) if abs(x) > RANK_TOL * 1e-3})
    rows = tuple(((b, sp.Integer(1)),) + tuple((d, coef[i, d]) for d in dep if (i, d) in coef) for i, b in enumerate(base))
    numerical = tuple(any(not c.is_Rational for _, c in row) for row in rows)
    Kx = np.zeros((len(base), npar))
    for i, row in enumerate(rows):
        for j, c in row:
            Kx[i, j] = float(c)
    # the check, on fresh states: Y π = Y_B (K π) for every π, i.e. Y = Y_B K
    scale = max(np.abs(Yc).max(), 1e-300)
    residual = float(np.abs(Yc[:, base] @ Kx - Yc).max() / scale) if base else float(np.abs(Yc).max())
    at = tuple((str(p), float(vals[str(p)])) for p in geometric(spec))
    return BaseParameters(tuple(base), rows, numerical, residual, at)
