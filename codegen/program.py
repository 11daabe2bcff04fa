"""A straight-line program of named quantities: the recursions' values as temporaries.

Expanding the paper's sums into one closed form per equation explodes with n; naming every
recursion quantity (ωᵏ, εᵏ, the composite first moment hᵏ, …) keeps the model O(n²).  ``let``
names an expression unless it is a number or a (negated) symbol, so zero terms vanish and
numbers fold at generation time.  ``inline`` gives back the closed form when it is wanted
(LaTeX, symbolic proofs).
"""
from __future__ import annotations

import sympy as sp


class Var(sp.Symbol):
    """A generated quantity.  A class of its own, so it never equals a user's parameter of the
    same name (sympy compares the class), and prints by its name in every printer."""


class Program:
    def __init__(self):
        self.defs: list[tuple[Var, sp.Expr]] = []
        self.tex: dict[Var, str] = {}
        self._by_name: dict[str, Var] = {}

    def let(self, name: str, expr, tex: str | None = None) -> sp.Expr:
        expr = sp.sympify(expr)
        if expr.is_Atom or (-expr).is_Atom:
            return expr
        if name in self._by_name:
            raise ValueError(f"quantity {name} defined twice")
        sym = Var(name, real=True)
        self._by_name[name] = sym
        self.defs.append((sym, expr))
        if tex:
            self.tex[sym] = tex
        return sym

    def vec(self, name: str, v, tex: str | None = None) -> sp.Matrix:
        """A 3-vector, component i named ``{name}_{i}`` (1-based, as in the paper)."""
        return sp.Matrix(
            [self.let(f"{name}_{i + 1}", v[i], tex and f"{tex}_{{{i + 1}}}") for i in range(3)]
        )

    def sym_mat(self, name: str, m, tex: str | None = None) -> sp.Matrix:
        """A symmetric 3×3 matrix; the lower triangle is computed, the upper mirrors it."""
        out = sp.zeros(3, 3)
        for i in range(3):
            for j in range(i + 1):
                out[i, j] = out[j, i] = self.let(f"{name}_{i + 1}{j + 1}", m[i, j], tex and f"{tex}_{{{i + 1}{j + 1}}}")
        return out

    def inline(self, exprs):
        """Closed forms of ``exprs``: every quantity replaced by its definition (small n only)."""
        full: dict = {}
        for sym, rhs in self.defs:
            full[sym] = rhs.xreplace(full)
        return [sp.sympify(e).xreplace(full) for e in exprs]

    def needed(self, exprs) -> list[tuple[Var, sp.Expr]]:
        """The definitions the expressions depend on, in program order (dead code dropped)."""
        need = set()
        for e in exprs:
            need |= {a for a in sp.sympify(e).free_symbols if isinstance(a, Var)}
        out = []
        for sym, rhs in reversed(self.defs):
            if sym in need:
                out.append((sym, rhs))
                need |= {a for a in rhs.free_symbols if isinstance(a, Var)}
        return out[::-1]
