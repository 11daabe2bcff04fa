"""A long chain's recursion in the paper's quantities: the program's named quantities (ωᵏ, εᵏ,
aᵏ, Fᵏ, Nᵏ, hᵏ, Iᵏ, n^{r|k}, …) each defined once, in order, with the program's other
intermediate quantities substituted into the lines that use them, so no name of the code appears."""
from __future__ import annotations

import re

from ..derive.algebra import Poly
from .texlayout import INLINE, TexEquation

INLINE_MAX_TERMS = 12  # an unnamed quantity of the recursion is substituted where it has at most this many terms


def recursion(kin, doc, targets: list, printed: set = frozenset()) -> tuple[list, dict]:
    """A long chain's recursion in the paper's quantities: the program's definitions the printed
    quantities need, in order, of those that have a name of the paper's notation (ωᵏ, εᵏ, aᵏ, Fᵏ,
    Nᵏ, hᵏ, Iᵏ, n^{r|k}, …).  The program's other intermediate quantities (a component of a turn by
    α^{k,k−1}, a term of a sum) are substituted into the lines that use them, so no name of the
    code appears; cos φᵏ and sin φᵏ are not restated.  A function the code computes once and the
    notation has no name for (of a symbolic parameter, say) is called ζⱼ.  A quantity named as one
    the text prints (G_k) is substituted too, so that no line reads G_k = G_k.  Returns the lines
    and the substitution for the printed quantities."""
    needed = kin.prog.needed(targets)
    aux = 0
    for a, rhs in needed:
        if not isinstance(rhs, Poly) and a.sym not in kin.prog.tex:
            aux += 1
            doc.w.names[a.sym] = rf"\zeta_{{{aux}}}"
    full, out, seen = {}, [], set()
    for a, rhs in needed:
        tex = kin.prog.tex.get(a.sym)
        if tex in seen or tex in printed:  # one symbol, one quantity: a second of the same name is substituted
            tex = None
        seen.add(tex)
        if isinstance(rhs, Poly):
            value = rhs.subs(full)
            if tex is None and len(value.terms) > INLINE_MAX_TERMS:  # substituted, it would grow without bound
                aux += 1
                tex = doc.w.names[a.sym] = rf"\zeta_{{{aux}}}"
            if tex is None:
                full[a] = value
                continue
            out.append(TexEquation(tex, tuple(doc.poly_lines(value, INLINE))))
        elif not (tex or "").startswith((r"\cos", r"\sin")):  # cos φᵏ = cos φᵏ says nothing
            out.append(TexEquation(doc.w.name(a.sym), tuple(doc.lines(rhs, INLINE, expand=False))))
    return out, full


def paragraphs(rows: list) -> list[list]:
    """The recursion's lines in runs of the same body (the upper index of the defined quantity):
    a paragraph each, as a reader evaluates them body by body."""
    out, last = [], None
    for r in rows:
        m = re.search(r"\^\{(\d+)", r.lhs)
        body = m.group(1) if m else None
        if not out or body != last:
            out.append([])
        out[-1].append(r)
        last = body
    return out


def substituted(vals: dict, full: dict) -> dict:
    """The printed quantities (the program's polynomials) with its unnamed quantities substituted."""
    def sub(v):
        return v.subs(full) if isinstance(v, Poly) else v
    out = dict(vals)
    for key, v in vals.items():
        if isinstance(v, list):
            out[key] = [(x[0], sub(x[1])) if isinstance(x, tuple) else sub(x) for x in v]
        else:
            out[key] = sub(v)
    return out
