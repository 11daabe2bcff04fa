"""A program's outputs → ordered straight-line assignments (number folding + one CSE per function)."""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .program import Program, Var


def fold_numbers(expr: sp.Expr) -> sp.Expr:
    """Evaluate every subexpression made of numbers only (sqrt(3)/2, cos(3/10), …) to a Float."""
    if expr.is_Atom:
        return expr
    if expr.is_number:
        return sp.Float(expr.evalf(30), 30)
    args = [fold_numbers(a) for a in expr.args]
    return expr.func(*args) if any(a is not b for a, b in zip(args, expr.args)) else expr


@dataclass(frozen=True)
class StraightLine:
    """``temporaries`` are computed in order; ``outputs`` then use them."""

    temporaries: tuple[tuple[sp.Symbol, sp.Expr], ...]
    outputs: tuple[sp.Expr, ...]

    def op_count(self) -> int:
        exprs = [rhs for _, rhs in self.temporaries] + list(self.outputs)
        return int(sum(sp.count_ops(e) for e in exprs))


def straight_line(program: Program, outputs, prefix: str = "w") -> StraightLine:
    """The definitions ``outputs`` need, with one CSE over all of them.

    CSE sees the definitions' right-hand sides as one list; each common subexpression is then
    placed just before the first definition that uses it, which is always after every quantity
    it reads (a subexpression of a right side only reads quantities defined before that side).
    """
    outputs = [fold_numbers(sp.sympify(e)) for e in outputs]
    defs = [(sym, fold_numbers(rhs)) for sym, rhs in program.needed(outputs)]
    exprs = [rhs for _, rhs in defs] + outputs
    temps, reduced = sp.cse(exprs, symbols=sp.numbered_symbols(prefix, cls=Var), order="canonical")
    temp_rhs = dict(temps)
    order = {sym: i for i, (sym, _) in enumerate(temps)}
    placed: set = set()
    lines: list = []

    def place(expr):
        for t in sorted((a for a in expr.free_symbols if a in temp_rhs and a not in placed), key=order.get):
            if t in placed:
                continue
            place(temp_rhs[t])
            placed.add(t)
            lines.append((t, temp_rhs[t]))

    for (sym, _), rhs in zip(defs, reduced[: len(defs)]):
        place(rhs)
        lines.append((sym, rhs))
    outs = reduced[len(defs) :]
    for e in outs:
        place(e)
    return StraightLine(tuple(lines), tuple(outs))
