"""Exact numbers: the coefficients of algebra.Poly, folded to doubles only when printed.

The spec's decimals are exact rationals (spec.py reads 0.003 as 3/1000), so sums and products of
them are kept as ``int`` or ``fractions.Fraction``: a coefficient is exactly what the spec's
numbers give, and one that is zero in exact arithmetic vanishes instead of printing as 1e-19.

Numbers that are not rational — cos θ and sin θ of a structural angle that sympy does not reduce
to a rational (θ = 0.3), √2 of θ = π/4, π — are ``Const`` atoms, and a coefficient that has them
is a ``Surd``: a polynomial in them with rational coefficients, reduced by the relations known
exactly, (sin θ)² = 1 − (cos θ)² and (√a)² = a (each Const that has such a relation carries
its square).  Relations nobody told us about (cos 0.6 = 2 cos²0.3 − 1) are caught when a
coefficient is folded: its value is computed to ``PREC`` bits and a sum that cancels to below
``2^-ZERO_BITS`` of its parts is the zero it is.

Folding (``to_float``) rounds the exact value once to the nearest double, so the C, the Python
and the LaTeX print the correctly rounded number of what the spec says (0.003, not
0.002999999999999999).
"""
from __future__ import annotations

import itertools
from fractions import Fraction
from operator import attrgetter

import mpmath
import sympy as sp

PREC = 320  # bits of a folded Surd's value (then rounded once to 53)
ZERO_BITS = 200  # a Surd whose value is below 2^-ZERO_BITS of the sum of its parts' sizes is zero

_order = itertools.count()
_by_order = attrgetter("order")


class Const:
    """An irrational number the derivation meets: ``expr`` its exact sympy value, ``square`` the
    exact number its square reduces to (None when no relation is known)."""

    __slots__ = ("expr", "square", "order", "sym", "_value")

    def __init__(self, expr: sp.Expr, square=None):
        self.expr = expr
        self.square = square
        self.order = next(_order)
        self.sym = ConstSymbol(f"kappa{self.order}")
        self._value = None
        _BY_SYMBOL[self.sym] = self

    def value(self) -> mpmath.mpf:
        if self._value is None:
            with mpmath.workprec(PREC + 20):
                self._value = mpmath.mpf(sp.N(self.expr, int(PREC * 0.302) + 10)._mpf_)
        return self._value

    def __repr__(self) -> str:
        return f"Const({self.expr})"


class ConstSymbol(sp.Symbol):
    """A Const inside a sympy expression (the LaTeX's canonical forms reduce and fold them)."""


_BY_SYMBOL: dict = {}
_REGISTRY: dict = {}  # exact sympy value → Const


def const_of(sym: sp.Symbol) -> Const | None:
    return _BY_SYMBOL.get(sym)


def _const(expr: sp.Expr, square=None) -> "Surd":
    c = _REGISTRY.get(expr)
    if c is None:
        c = _REGISTRY[expr] = Const(expr, square)
    return Surd({(c,): Fraction(1)})


def _trig_pair(arg: sp.Expr) -> tuple:
    """cos and sin of a numeric angle sympy leaves unevaluated: two Consts, (sin)² = 1 − (cos)²."""
    key_c, key_s = sp.cos(arg, evaluate=False), sp.sin(arg, evaluate=False)
    c = _const(key_c)
    return c, _const(key_s, 1 - c * c)


# --------------------------------------------------------------------------- Surd
def add_terms(a: dict, b: dict) -> dict:
    """The sum of two {monomial: coefficient} maps, terms that cancel exactly dropped (Surd and
    algebra.Poly alike)."""
    out = dict(a)
    for m, c in b.items():
        v = out.get(m, 0) + c
        if v:
            out[m] = v
        else:
            out.pop(m, None)
    return out


def _mono_product(a: tuple, b: tuple):
    """The product of two monomials of Consts, reduced: an int 1 and a monomial, or a number."""
    key = (a, b)
    hit = _PRODUCTS.get(key)
    if hit is not None:
        return hit
    m = sorted(a + b, key=_by_order)
    factor, rest, i = 1, [], 0
    while i < len(m):
        if i + 1 < len(m) and m[i] is m[i + 1] and m[i].square is not None:
            factor = factor * m[i].square
            i += 2
        else:
            rest.append(m[i])
            i += 1
    out = factor * _normal({tuple(rest): Fraction(1)})
    _PRODUCTS[key] = out
    return out


_PRODUCTS: dict = {}


def _normal(terms: dict):
    """A Surd, or the rational it is when it has no Const."""
    if not terms:
        return 0
    if len(terms) == 1 and () in terms:
        v = terms[()]
        return int(v) if v.denominator == 1 else v
    return Surd(terms)


class Surd:
    """Σ q·Π Const, q rational, reduced by the Consts' squares; never a bare rational."""

    __slots__ = ("terms",)

    def __init__(self, terms: dict):
        self.terms = terms

    @staticmethod
    def _lift(x) -> dict:
        if isinstance(x, Surd):
            return x.terms
        if isinstance(x, (int, Fraction)):
            return {(): Fraction(x)} if x else {}
        return None

    def __add__(self, other):
        o = Surd._lift(other)
        if o is None:
            return NotImplemented
        return _normal(add_terms(self.terms, o))

    __radd__ = __add__

    def __neg__(self):
        return Surd({m: -q for m, q in self.terms.items()})

    def __sub__(self, other):
        return self + (-other)

    def __rsub__(self, other):
        return (-self) + other

    def __mul__(self, other):
        o = Surd._lift(other)
        if o is None:
            return NotImplemented
        if not o:
            return 0
        if len(o) == 1 and () in o:
            q = o[()]
            return _normal({m: v * q for m, v in self.terms.items()})
        out = 0
        for ma, qa in self.terms.items():
            for mb, qb in o.items():
                out = out + _mono_product(ma, mb) * (qa * qb)
        return out

    __rmul__ = __mul__

    def __eq__(self, other):
        return isinstance(other, Surd) and self.terms == other.terms

    def __hash__(self):
        return hash(frozenset(self.terms.items()))

    def __repr__(self) -> str:
        return " + ".join(f"{q}*" + "*".join(repr(c) for c in m) for m, q in self.terms.items())


# --------------------------------------------------------------------------- conversions
def exact(x):
    """An exact number from an int, a float (its binary value), a Fraction, a Surd or a sympy number."""
    if isinstance(x, (int, Fraction, Surd)):
        return x
    if isinstance(x, float):
        if x.is_integer():
            return int(x)
        return Fraction(x)
    x = sp.sympify(x)
    if not x.is_number:
        raise ValueError(f"{x} is not a number")
    if x.is_Integer:
        return int(x)
    if x.is_Rational:
        return Fraction(int(x.p), int(x.q))
    if x.is_Float:
        return _ratio(x._mpf_)
    if x.is_Add:
        out = 0
        for a in x.args:
            out = out + exact(a)
        return out
    if x.is_Mul:
        out = 1
        for a in x.args:
            out = out * exact(a)
        return out
    if x.is_Pow:
        base, e = x.base, x.exp
        if e.is_Integer and e > 0:
            b, out = exact(base), 1
            for _ in range(int(e)):
                out = out * b
            return out
        if e.is_Integer and base.is_Rational:
            return exact(x)  # unreachable: sympy evaluates a rational power
        if e == sp.S.Half and (base.is_Rational and base > 0 or not base.is_Rational):
            return _const(x, exact(base))
    if isinstance(x, (sp.cos, sp.sin)):
        c, s = _trig_pair(x.args[0])
        return c if isinstance(x, sp.cos) else s
    return _const(x)


def value(c) -> mpmath.mpf:
    """The value to PREC bits; a Surd whose sum cancels below 2^-ZERO_BITS of its parts is 0."""
    with mpmath.workprec(PREC):
        if not isinstance(c, Surd):
            return mpmath.mpf(c.numerator) / c.denominator if isinstance(c, Fraction) else mpmath.mpf(c)
        total, size = mpmath.mpf(0), mpmath.mpf(0)
        for m, q in c.terms.items():
            t = mpmath.mpf(q.numerator) / q.denominator
            for k in m:
                t *= k.value()
            total += t
            size += abs(t)
        return mpmath.mpf(0) if abs(total) <= size * mpmath.mpf(2) ** -ZERO_BITS else total


_FLOATS: dict = {}


def _ratio(mpf_tuple) -> Fraction:
    """The exact binary value of an mpmath number."""
    sign, man, exp, _ = mpf_tuple
    v = Fraction(man * 2**exp) if exp >= 0 else Fraction(man, 2**-exp)
    return -v if sign else v


def to_float(c) -> float:
    """The nearest double to the exact value (one rounding)."""
    if isinstance(c, int):
        return float(c)
    if isinstance(c, Fraction):
        return c.numerator / c.denominator  # int / int is correctly rounded in Python
    if isinstance(c, float):
        return c
    hit = _FLOATS.get(c)
    if hit is None:
        v = value(c)
        hit = _FLOATS[c] = float(_ratio(v._mpf_))
    return hit


def is_unit(c) -> bool:
    """±1 exactly (a coefficient that prints as a sign only)."""
    return not isinstance(c, Surd) and (c == 1 or c == -1)


def to_sympy(c, symbolic: bool = False) -> sp.Expr:
    """A coefficient as sympy: a rational exactly; a Surd as its correctly rounded double, or
    (``symbolic``) as Σ q·Π κ with the Consts as ConstSymbols (for the LaTeX's canonical forms)."""
    if isinstance(c, int):
        return sp.Integer(c)
    if isinstance(c, Fraction):
        return sp.Rational(c.numerator, c.denominator)
    if isinstance(c, float):
        return sp.Float(c)
    if symbolic:
        return sp.Add(*(sp.Mul(sp.Rational(q.numerator, q.denominator), *(k.sym for k in m)) for m, q in c.terms.items()))
    return sp.Float(to_float(c))


def to_sympy_exact(c) -> sp.Expr:
    """A coefficient as its exact sympy value (Consts by their own expressions)."""
    if not isinstance(c, Surd):
        return to_sympy(c)
    return sp.Add(*(sp.Mul(sp.Rational(q.numerator, q.denominator), *(k.expr for k in m)) for m, q in c.terms.items()))


def inverse(c):
    """1/c exactly: a rational's reciprocal, else a Const of the exact reciprocal."""
    if isinstance(c, Surd):
        return exact(1 / to_sympy_exact(c))
    return Fraction(1) / exact(c)


def is_negative(c) -> bool:
    return to_float(c) < 0 if isinstance(c, Surd) else c < 0
