"""A program's outputs → ordered straight-line assignments for one emitted function.

The program already names every recursion quantity, so what is left to share is products: a
monomial of degree ≥ 2 that several definitions use (ω₂ω₃, m·cos φ …) becomes one temporary
``w<i>``, placed just before its first use.  Dead definitions are dropped.
"""
from __future__ import annotations

from dataclasses import dataclass

from .algebra import Atom, Poly
from .program import Program, Var


@dataclass(frozen=True)
class StraightLine:
    """``temporaries`` are computed in order (right sides: Poly, or sympy for non-polynomial
    quantities); ``outputs`` then use them."""

    temporaries: tuple
    outputs: tuple

    def op_count(self) -> int:
        ops = 0
        for _, rhs in self.temporaries:
            ops += rhs.op_count() if isinstance(rhs, Poly) else _sympy_ops(rhs)
        return ops + sum(o.op_count() for o in self.outputs)


def _sympy_ops(expr) -> int:
    import sympy as sp

    return max(1, int(sp.count_ops(expr)))


def straight_line(program: Program, outputs, prefix: str = "w", have=frozenset()) -> StraightLine:
    """``have``: quantities an earlier section of the same function computed (not repeated)."""
    outputs = [Poly.lift(e) for e in outputs]
    defs = program.needed(outputs, have)
    polys = [rhs for _, rhs in defs if isinstance(rhs, Poly)] + outputs
    seen: dict = {}
    for p in polys:
        for m in p.terms:
            if len(m) >= 2:
                seen[m] = seen.get(m, 0) + 1
    shared = {m: None for m, count in seen.items() if count >= 2}
    temps: dict = {}
    lines: list = []

    def rewrite(p: Poly) -> Poly:
        out = {}
        for m, c in p.terms.items():
            if m in shared:
                t = temps.get(m)
                if t is None:
                    t = temps[m] = Atom(Var(f"{prefix}{len(temps)}"))
                    lines.append((t, Poly({m: 1})))
                m = (t,)
            out[m] = c
        return Poly(out)

    for a, rhs in defs:
        lines.append((a, rewrite(rhs) if isinstance(rhs, Poly) else rhs))
    outs = tuple(rewrite(p) for p in outputs)
    return StraightLine(tuple(lines), outs)
