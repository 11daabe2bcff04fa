"""The derivation's algebra: polynomials with exact coefficients over named atoms.

Every recursion quantity is named (see program.py), so each definition is a short polynomial in
earlier names, the state and the spec's symbolic parameters.  Sums and products of such
polynomials are all the derivation needs; doing them with dicts instead of sympy trees is what
lets the generator reach n = 32 (sympy is kept for the spec's own expressions, LaTeX and proofs).

A ``Poly`` maps monomials to coefficients.  A monomial is a tuple of ``Atom``s sorted by their
creation order, an atom repeated for a power; the empty tuple is the constant term.  Numbers of a
numeric spec fold into the coefficients as they meet, exactly (exact.py: rationals, and the
irrational constants of the structural angles with their relations), and exact zeros vanish, so a
planar chain, a chain without rotors or with zero offsets gets a smaller model by construction,
and no coefficient is the round-off of a cancellation.
"""
from __future__ import annotations

import itertools
from operator import attrgetter

import sympy as sp

from .exact import add_terms, exact, is_unit, to_sympy as number_to_sympy

_order = itertools.count()
_by_order = attrgetter("order")


class Atom:
    """A name a polynomial is built from: a state symbol, a parameter, or a program quantity.
    ``sym`` is its sympy symbol (printing, LaTeX, proofs); ``order`` fixes monomial layout."""

    __slots__ = ("sym", "order", "name")

    def __init__(self, sym: sp.Symbol):
        self.sym = sym
        self.name = sym.name
        self.order = next(_order)

    def __repr__(self) -> str:
        return self.name


def _mono_mul(a: tuple, b: tuple) -> tuple:
    if not a:
        return b
    if not b:
        return a
    return tuple(sorted(a + b, key=_by_order))


class Poly:
    __slots__ = ("terms",)

    def __init__(self, terms: dict):
        self.terms = terms  # monomial → nonzero exact number (int, Fraction or exact.Surd)

    # ---- construction
    @staticmethod
    def const(c) -> "Poly":
        c = exact(c)
        return Poly({(): c} if c else {})

    @staticmethod
    def atom(a: Atom) -> "Poly":
        return Poly({(a,): 1})

    # ---- queries
    def is_zero(self) -> bool:
        return not self.terms

    def constant(self):
        """The value if the polynomial is a number, else None."""
        if not self.terms:
            return 0
        if len(self.terms) == 1 and () in self.terms:
            return self.terms[()]
        return None

    def is_simple(self) -> bool:
        """A number or one atom times a number: cheaper inlined than named."""
        if len(self.terms) > 1:
            return False
        return all(len(m) <= 1 for m in self.terms)

    def atoms(self) -> dict:
        """The atoms, in order of first appearance (a dict used as an ordered set)."""
        out: dict = {}
        for m in self.terms:
            for a in m:
                out[a] = None
        return out

    # ---- arithmetic
    @staticmethod
    def lift(x) -> "Poly":
        if isinstance(x, Poly):
            return x
        if isinstance(x, Atom):
            return Poly.atom(x)
        return Poly.const(x)

    def __add__(self, other) -> "Poly":
        other = Poly.lift(other)
        if not other.terms:
            return self
        if not self.terms:
            return other
        return Poly(add_terms(self.terms, other.terms))

    __radd__ = __add__

    def __neg__(self) -> "Poly":
        return Poly({m: -c for m, c in self.terms.items()})

    def __sub__(self, other) -> "Poly":
        return self + (-Poly.lift(other))

    def __rsub__(self, other) -> "Poly":
        return Poly.lift(other) + (-self)

    def __mul__(self, other) -> "Poly":
        other = Poly.lift(other)
        if not self.terms or not other.terms:
            return Poly({})
        out: dict = {}
        for ma, ca in self.terms.items():
            for mb, cb in other.terms.items():
                m = _mono_mul(ma, mb)
                v = out.get(m, 0) + ca * cb
                if v:
                    out[m] = v
                else:
                    out.pop(m, None)
        return Poly(out)

    __rmul__ = __mul__

    def subs(self, full: dict) -> "Poly":
        """Replace atoms by polynomials (``full``: Atom → Poly); others stay."""
        out = Poly({})
        for m, c in self.terms.items():
            t = Poly({(): c})
            rest = []
            for a in m:
                if a in full:
                    t = t * full[a]
                else:
                    rest.append(a)
            if rest:
                t = t * Poly({tuple(rest): 1})
            out = out + t
        return out

    # ---- cost
    def op_count(self) -> int:
        """Multiplications and additions of the printed form (coefficients ±1 cost nothing)."""
        if not self.terms:
            return 0
        ops = len(self.terms) - 1
        for m, c in self.terms.items():
            if m:
                ops += len(m) - 1 + (0 if is_unit(c) else 1)
        return ops

    # ---- conversion
    def to_sympy(self, atom_sym=None, symbolic: bool = False) -> sp.Expr:
        """The sympy expression; ``atom_sym`` may map an atom to its replacement.  Rational
        coefficients stay exact; irrational ones are their correctly rounded doubles, or with
        ``symbolic`` sums of products of exact.ConstSymbols (for the LaTeX's canonical forms)."""
        get = atom_sym or (lambda a: a.sym)
        out = []
        for m, c in self.terms.items():
            out.append(sp.Mul(number_to_sympy(c, symbolic), *(get(a) for a in m)))
        return sp.Add(*out)


ZERO = Poly({})
ONE = Poly({(): 1})
