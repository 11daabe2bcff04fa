"""A straight-line program of named quantities: the recursions' values as temporaries.

Expanding the paper's sums into one closed form per equation explodes with n; naming every
recursion quantity (ωᵏ, εᵏ, the composite first moment hᵏ, …) keeps the model O(n²).  ``let``
names a polynomial unless it is a number or one term of degree ≤ 1 (those are cheaper inlined),
so zero terms vanish and numbers fold at generation time.  ``inline`` gives back the closed form
when it is wanted (LaTeX, symbolic proofs).

A definition's right side is a ``Poly`` of earlier names, or, for the few quantities that are not
polynomial (cos φᵏ, sin φᵏ, functions of symbolic parameters such as cos θ), a sympy expression of
state and parameters that the sympy printers print.
"""
from __future__ import annotations

import sympy as sp

from .algebra import Atom, Poly
from .exact import exact, inverse


class Var(sp.Symbol):
    """A generated quantity.  A class of its own, so it never equals a user's parameter of the
    same name (sympy compares the class), and prints by its name in every printer."""


class Program:
    def __init__(self):
        self.defs: list[tuple[Atom, object]] = []  # (atom, Poly | sympy expression)
        self.rhs: dict[Atom, object] = {}
        self.tex: dict[sp.Symbol, str] = {}
        self._by_name: dict[str, Atom] = {}
        self._inputs: dict[sp.Symbol, Atom] = {}  # state symbols and parameters
        self._opaque: dict[sp.Expr, Poly] = {}
        self._deps: dict[Atom, tuple] = {}  # program quantities a sympy right side reads

    # ---- inputs
    def input(self, sym: sp.Symbol) -> Poly:
        """The polynomial of a state symbol or parameter (one atom per symbol)."""
        a = self._inputs.get(sym)
        if a is None:
            a = self._inputs[sym] = Atom(sym)
        return Poly.atom(a)

    def from_sympy(self, expr) -> Poly:
        """A spec value (sympy, numbers exact) as a polynomial.  Sums, products and integer powers
        of parameters stay polynomial; anything else (sqrt, cos of a parameter, 1/m) becomes a
        named quantity computed once from its sympy form."""
        expr = sp.sympify(expr)
        if expr.is_number:
            return Poly.const(exact(expr))
        if expr.is_Symbol:
            return self.input(expr)
        if expr.is_Add:
            out = Poly({})
            for a in expr.args:
                out = out + self.from_sympy(a)
            return out
        if expr.is_Mul:
            out = Poly.const(1)
            for a in expr.args:
                out = out * self.from_sympy(a)
            return out
        if expr.is_Pow and expr.exp.is_Integer and expr.exp > 0:
            base, out = self.from_sympy(expr.base), Poly.const(1)
            for _ in range(int(expr.exp)):
                out = out * base
            return out
        if expr not in self._opaque:
            for s in sorted(expr.free_symbols, key=str):
                self.input(s)
            self._opaque[expr] = self.let_sympy(f"pe{len(self._opaque) + 1}", expr)
        return self._opaque[expr]

    def known(self, expr: sp.Expr) -> Poly | None:
        """The quantity ``from_sympy`` or ``alias`` gave for this non-polynomial expression, if any."""
        return self._opaque.get(expr)

    def alias(self, expr: sp.Expr, value: Poly) -> None:
        """Let ``from_sympy`` answer ``expr`` (cos φᵏ in a user's torque) with a quantity that
        already exists, instead of computing it again."""
        self._opaque[expr] = value

    # ---- definitions
    def _new(self, name: str, rhs, tex: str | None) -> Poly:
        if name in self._by_name:
            raise ValueError(f"quantity {name} defined twice")
        a = Atom(Var(name))
        self._by_name[name] = a
        self.defs.append((a, rhs))
        self.rhs[a] = rhs
        if tex:
            self.tex[a.sym] = tex
        return Poly.atom(a)

    def let(self, name: str, value, tex: str | None = None) -> Poly:
        value = Poly.lift(value)
        if value.is_simple():
            return value
        return self._new(name, value, tex)

    def let_sympy(self, name: str, expr: sp.Expr, tex: str | None = None) -> Poly:
        """A non-polynomial quantity (cos φᵏ, a function of parameters, 1/D), printed by sympy.
        It may read earlier program quantities (``Var`` symbols)."""
        deps = []
        for s in sorted(expr.free_symbols, key=str):
            if isinstance(s, Var):
                deps.append(self._by_name[s.name])
            else:
                self.input(s)
        out = self._new(name, expr, tex)
        self._deps[next(iter(out.terms))[0]] = tuple(deps)
        return out

    def reciprocal(self, name: str, value) -> Poly:
        """1/value: a number folds now, anything else is named (``{name}``) and divided once."""
        value = Poly.lift(value)
        c = value.constant()
        if c is not None:
            return Poly.const(inverse(c))
        value = self.let(f"{name}d", value)
        return self.let_sympy(name, 1 / value.to_sympy())

    def vec(self, name: str, v, tex: str | None = None) -> list:
        """A 3-vector, component i named ``{name}_{i}`` (1-based, as in the paper)."""
        return [self.let(f"{name}_{i + 1}", v[i], tex and f"{tex}_{{{i + 1}}}") for i in range(3)]

    def sym_mat(self, name: str, m, tex: str | None = None) -> list:
        """A symmetric 3×3 matrix; the lower triangle is computed, the upper mirrors it."""
        out = [[None] * 3 for _ in range(3)]
        for i in range(3):
            for j in range(i + 1):
                out[i][j] = out[j][i] = self.let(f"{name}_{i + 1}{j + 1}", m[i][j], tex and f"{tex}_{{{i + 1}{j + 1}}}")
        return out

    # ---- reading the program
    def atom(self, name: str) -> Atom:
        """The quantity of this name (a ``Var`` of a right side back to its atom)."""
        return self._by_name[name]

    def defines(self, name: str) -> bool:
        return name in self._by_name

    def quantity(self, sym: sp.Symbol) -> Atom | None:
        """The program quantity a symbol of a sympy right side names, or None (an input)."""
        return self._by_name.get(sym.name) if isinstance(sym, Var) else None

    def source(self, sym: sp.Symbol) -> Atom | None:
        """The atom a symbol of a sympy right side stands for: a quantity or an input."""
        return self._by_name[sym.name] if isinstance(sym, Var) else self._inputs.get(sym)

    def needed(self, exprs, have=frozenset()) -> list[tuple[Atom, object]]:
        """The definitions the polynomials depend on, in program order (dead code dropped);
        those in ``have`` (computed already, by an earlier section of the same function) and what
        only they need are left out."""
        need: set = set()
        for e in exprs:
            need.update(Poly.lift(e).atoms())
        out = []
        for a, rhs in reversed(self.defs):
            if a in need and a not in have:
                out.append((a, rhs))
                need.update(rhs.atoms() if isinstance(rhs, Poly) else self._deps.get(a, ()))
        return out[::-1]

    def inline_poly(self, exprs) -> list[Poly]:
        """Closed forms as polynomials: every polynomial quantity replaced by its definition;
        non-polynomial ones (cos φᵏ, …) stay atoms."""
        exprs = [Poly.lift(e) for e in exprs]
        full: dict = {}
        for a, rhs in self.needed(exprs):
            if isinstance(rhs, Poly):
                full[a] = rhs.subs(full)
        return [e.subs(full) for e in exprs]

    def sympy_of(self, a: Atom) -> sp.Expr:
        """An atom in sympy: inputs as themselves, non-polynomial quantities by their definition."""
        rhs = self.rhs.get(a)
        return rhs if rhs is not None and not isinstance(rhs, Poly) else a.sym

    def inline(self, exprs, symbolic: bool = False) -> list[sp.Expr]:
        """Closed forms in sympy (small n only); ``symbolic``: irrational constants as
        exact.ConstSymbols (the LaTeX reduces and folds them, trigform.py)."""
        return [p.to_sympy(self.sympy_of, symbolic) for p in self.inline_poly(exprs)]
