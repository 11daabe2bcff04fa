"""Canonical trigonometric forms of the closed forms the LaTeX shows.

An expanded quantity is a sum of terms q·κ…·cₖᵃ sₖᵇ·r: q rational, κ the irrational constants
of exact.py (cos θ of a structural angle, √2, …), cₖ = cos φᵏ, sₖ = sin φᵏ, and r the rest (φ̇,
the torques, the spec's symbols).  The same function has many such sums (sₖ² + cₖ² = 1), so the
LaTeX shows each quantity in one of three canonical forms, each unique for the function it shows:

  ``c``  a polynomial in cₖ and sₖ without sₖ² (sₖ² = 1 − cₖ² used): powers cₖᵃ and cₖᵃ sₖ;
  ``s``  the same without cₖ² (cₖ² = 1 − sₖ²);
  ``f``  multiple angles: cos and sin of integer combinations m·φ = m₁φ¹ + m₂φ² + … (the Fourier
         form, cₖ = (zₖ + 1/zₖ)/2, sₖ = (zₖ − 1/zₖ)/2i),

  ``C``, ``S``  the forms c and s in the cumulative angles of runs of parallel axes: where joint k's
         axis is parallel to joint k−1's (sin θᵏ = 0), the bodies of the run turn by sums such as
         ψ = φ² + φ³ + φ⁴ (φᵏ − ψ for an axis that points the other way), and cos ψ, sin ψ take the
         place of cos φᵏ, sin φᵏ (a planar arm's mass matrix has cos(φ² + φ³), not its four products);

whichever has the fewest terms (ties go to c, then s, then C, S, f).  The reduction is exact: the
coefficients are exact numbers until the end, where each is folded to its correctly rounded
double, and a coefficient that is zero in exact arithmetic is not shown.
"""
from __future__ import annotations

import functools
import itertools
from dataclasses import dataclass
from fractions import Fraction
from math import comb

import sympy as sp

from .exact import Surd, const_of, exact, to_float, to_sympy

FORMS = ("c", "s", "C", "S", "f")


@dataclass(frozen=True)
class Canonical:
    expr: sp.Expr  # the quantity in the chosen form, numbers exact rationals or rounded doubles
    form: str | None  # "c", "s", "f"; None when no cₖ, sₖ appears
    terms: int  # terms of expr
    terms_by_form: dict  # the term count of every form (the LaTeX's choice is the least)


def _split(expr: sp.Expr, phis: list) -> dict:
    """{(exponents (a₁, b₁, a₂, b₂, …), rest): exact number} of the expanded expression."""
    index = {}
    for k, phi in enumerate(phis):
        index[sp.cos(phi)] = 2 * k
        index[sp.sin(phi)] = 2 * k + 1
    table: dict = {}
    for coeff, factors in _expanded(expr):
        number, exps, rest = exact(coeff), [0] * (2 * len(phis)), []
        for base, e, f in factors:
            slot = index.get(base)
            const = const_of(base) if isinstance(base, sp.Symbol) else None
            if slot is not None and e.is_Integer and e > 0:
                exps[slot] += int(e)
            elif const is not None and e.is_Integer and e > 0:
                number = number * exact_power(const, int(e))
            else:
                rest.append(f)
        key = (tuple(exps), sp.Mul(*rest))
        table[key] = table.get(key, 0) + number
    return {k: v for k, v in table.items() if v}


class _NotPlain(Exception):
    """A node the plain expansion below does not take: sympy's expand does it."""


def _expanded(expr: sp.Expr) -> list:
    """The terms of expand(expr), each as (rational coefficient, [(base, exponent, factor), …]) the
    way as_coeff_mul and as_base_exp give them, many times faster than sympy's expand: the
    polynomial is multiplied out in dicts of exact fractions over its atoms (symbols, and cos and
    sin of linear arguments).  Anything else (floats, roots, quotients, other functions) goes to sympy."""
    try:
        poly = _poly(expr)
    except _NotPlain:
        out = []
        for term in sp.Add.make_args(sp.expand(expr)):
            if term != 0:
                coeff, factors = term.as_coeff_mul()
                out.append((coeff, [(*f.as_base_exp(), f) for f in factors]))
        return out
    return [(q.numerator if q.denominator == 1 else q,
             [(atom, sp.Integer(k), atom if k == 1 else sp.Pow(atom, k)) for atom, k in mono])
            for mono, q in poly.items()]


def _poly(e: sp.Expr) -> dict:
    """{((atom, integer exponent), … in a fixed order): nonzero Fraction} of e multiplied out."""
    if e.is_Rational:
        return {(): Fraction(int(e.p), int(e.q))} if e != 0 else {}
    if _is_atom(e):
        return {((e, 1),): Fraction(1)}
    if e.is_Add:
        out: dict = {}
        for a in e.args:
            for mono, q in _poly(a).items():
                _add(out, mono, q)
        return out
    if e.is_Mul:
        out = {(): Fraction(1)}
        for a in e.args:
            out = _times(out, _poly(a))
        return out
    if e.is_Pow and e.exp.is_Integer:
        if e.exp < 0 and _is_atom(e.base):  # exponents of one atom add, as in sympy's Mul
            return {((e.base, int(e.exp)),): Fraction(1)}
        if e.exp > 0:
            out, base = {(): Fraction(1)}, _poly(e.base)
            for _ in range(int(e.exp)):
                out = _times(out, base)
            return out
    raise _NotPlain


def _is_atom(e: sp.Expr) -> bool:
    """A symbol, or cos or sin of a sum of a rational and rational multiples of atoms (which
    sympy's expand leaves as it is)."""
    return e.is_Symbol or (isinstance(e, (sp.cos, sp.sin)) and all(map(_is_linear_term, sp.Add.make_args(e.args[0]))))


def _is_linear_term(a: sp.Expr) -> bool:
    return a.is_Rational or _is_atom(a) or (a.is_Mul and len(a.args) == 2 and a.args[0].is_Rational and _is_atom(a.args[1]))


def _times(a: dict, b: dict) -> dict:
    out: dict = {}
    for ma, qa in a.items():
        for mb, qb in b.items():
            if not ma or not mb:
                mono = ma or mb
            else:
                exps = dict(ma)
                for atom, k in mb:
                    exps[atom] = exps.get(atom, 0) + k
                mono = tuple(sorted(((x, k) for x, k in exps.items() if k), key=_order))
            _add(out, mono, qa * qb)
    return out


def diff(expr: sp.Expr, sym: sp.Symbol) -> sp.Expr:
    """∂expr/∂sym, expanded (the same function as sympy's diff, and the same canonical forms), from
    the polynomial of _poly: each atom differentiated where it stands.  sympy's diff where that
    does not take expr or an atom's argument depends on sym through another function."""
    try:
        poly = _poly_of(expr)
        out: dict = {}
        for mono, q in poly.items():
            for i, (atom, k) in enumerate(mono):
                da = _atom_diff(atom, sym)
                if not da:
                    continue
                rest = mono[:i] + (((atom, k - 1),) if k != 1 else ()) + mono[i + 1:]
                for m, r in _times({rest: q * k}, da).items():
                    _add(out, m, r)
    except _NotPlain:
        return sp.expand(sp.diff(expr, sym))
    return sp.Add(*(sp.Mul(sp.Rational(q.numerator, q.denominator), *(a ** k for a, k in mono)) for mono, q in out.items()))


@functools.lru_cache(maxsize=8)
def _poly_of(expr: sp.Expr) -> dict:
    """_poly(expr), kept for the next derivative of the same expression (read, never changed)."""
    return _poly(expr)


@functools.lru_cache(maxsize=256)
def _atom_diff(atom: sp.Expr, sym: sp.Symbol) -> dict:
    """∂atom/∂sym as a polynomial ({} where it is 0); kept, as every monomial holding the atom asks
    for it again (read, never changed)."""
    if atom.is_Symbol:
        return {(): Fraction(1)} if atom == sym else {}
    slope = Fraction(0)  # ∂(argument)/∂sym: the argument is linear in atoms (_is_atom)
    for a in sp.Add.make_args(atom.args[0]):
        r, b = (a.args[0], a.args[1]) if a.is_Mul else (sp.Integer(1), a)
        if b == sym:
            slope += Fraction(int(r.p), int(r.q))
        elif not b.is_Rational and not b.is_Symbol and sym in b.free_symbols:
            raise _NotPlain  # a function of sym inside the argument: sympy's chain rule
    if not slope:
        return {}
    other = _poly(sp.sin(atom.args[0]) if isinstance(atom, sp.cos) else sp.cos(atom.args[0]))
    sign = -1 if isinstance(atom, sp.cos) else 1
    return {m: sign * slope * r for m, r in other.items()}


@functools.lru_cache(maxsize=None)
def _atom_key(atom: sp.Expr):
    return sp.default_sort_key(atom)


def _order(pair) -> tuple:
    return _atom_key(pair[0])


@functools.lru_cache(maxsize=None)
def exact_power(const, e: int):
    """const**e, exact (kept: a Surd is never changed)."""
    out = 1
    one = Surd({(const,): Fraction(1)})
    for _ in range(e):
        out = out * one
    return out


def _add(table: dict, key, value) -> None:
    v = table.get(key, 0) + value
    if v:
        table[key] = v
    else:
        table.pop(key, None)


def _eliminate(table: dict, drop: int) -> dict:
    """Form c (``drop`` = 1: sₖ² → 1 − cₖ²) or s (``drop`` = 0: cₖ² → 1 − sₖ²)."""
    out: dict = {}
    for (exps, rest), number in table.items():
        per_k = []
        for k in range(len(exps) // 2):
            a, b = exps[2 * k], exps[2 * k + 1]
            x, keep = (b, 0) if drop == 1 else (a, 1)  # x: exponent of the eliminated one
            half, odd = divmod(x, 2)
            choices = []
            for j in range(half + 1):  # (1 − y²)^half = Σ C(half, j)(−1)^j y^(2j), y the kept one
                kept = (a if keep == 0 else b) + 2 * j
                pair = (kept, odd) if keep == 0 else (odd, kept)
                choices.append((pair, (-1) ** j * comb(half, j)))
            per_k.append(choices)
        for combo in itertools.product(*per_k):
            q, new = 1, []
            for pair, c in combo:
                q *= c
                new.extend(pair)
            _add(out, (tuple(new), rest), number * q)
    return out


@functools.lru_cache(maxsize=None)
def _laurent(a: int, b: int) -> tuple:
    """cᵃ sᵇ as ((m, (re, im)), …) with c = (z + 1/z)/2, s = (z − 1/z)/2i (kept: read, never changed)."""
    out: dict = {}
    unit = [(1, 0), (0, -1), (-1, 0), (0, 1)][b % 4]  # (1/i)^b
    scale = Fraction(1, 2 ** (a + b))
    for i in range(a + 1):
        for j in range(b + 1):
            m = (a - 2 * i) + (b - 2 * j)
            q = scale * comb(a, i) * comb(b, j) * (-1) ** j
            re, im = out.get(m, (0, 0))
            out[m] = (re + q * unit[0], im + q * unit[1])
    return tuple(out.items())


def _fourier(table: dict, n: int) -> dict:
    """Form f: {((kind, m), rest): number}, kind "cos" or "sin", m with its first nonzero entry > 0."""
    acc: dict = {}
    expansions: dict = {}  # exponents → their multiple-angle series (many terms share them)
    for (exps, rest), number in table.items():
        series = expansions.get(exps)
        if series is None:
            series = {(): (Fraction(1), Fraction(0))}
            for k in range(n):
                nxt = {}
                for mm, (r1, i1) in series.items():
                    for m, (r2, i2) in _laurent(exps[2 * k], exps[2 * k + 1]):
                        nxt[mm + (m,)] = (r1 * r2 - i1 * i2, r1 * i2 + i1 * r2)
                series = nxt
            expansions[exps] = series
        for m, (re, im) in series.items():
            first = next((x for x in m if x), 0)
            plus = tuple(-x for x in m) if first < 0 else m
            sign = -1 if first < 0 else 1  # sin(−θ) = −sin θ
            if re:
                _add(acc, (("cos", plus), rest), number * re)
            if im and first != 0:
                _add(acc, (("sin", plus), rest), number * (-im * sign))
    return acc


def _folded(table: dict) -> dict:
    """Coefficients as doubles; those zero by a relation exact.py does not know are dropped."""
    return {k: v for k, v in table.items() if not isinstance(v, Surd) or to_float(v) != 0.0}


def _cumulative(expr: sp.Expr, phis: list, links: dict) -> tuple[sp.Expr, list, dict]:
    """``expr`` in the cumulative angles ψ of the runs of parallel axes (``links``: φᵏ → (φᵏ⁻¹, σ),
    σ = cos θᵏ = ±1): ψᵏ = φᵏ + σψᵏ⁻¹ along a run, ψ = φ at its start, so that φᵏ = ψᵏ − σψᵏ⁻¹ and
    cos φᵏ, sin φᵏ are the difference formulas.  Returns the expression in the ψ, the ψ, and each
    ψ's sum of angles."""
    psis, sums = [], {}
    for phi in phis:
        psi = sp.Symbol("psi_" + phi.name[4:], real=True)
        prev = links.get(phi)
        sums[psi] = phi + (prev[1] * sums[_psi_of(prev[0])] if prev and _psi_of(prev[0]) in sums else 0)
        psis.append(psi)
    rep = {}
    for phi, psi in zip(phis, psis):
        prev = links.get(phi)
        if prev is None or _psi_of(prev[0]) not in sums:
            rep[sp.cos(phi)], rep[sp.sin(phi)] = sp.cos(psi), sp.sin(psi)
            continue
        q, sigma = _psi_of(prev[0]), prev[1]
        rep[sp.cos(phi)] = sp.cos(psi) * sp.cos(q) + sigma * sp.sin(psi) * sp.sin(q)
        rep[sp.sin(phi)] = sp.sin(psi) * sp.cos(q) - sigma * sp.cos(psi) * sp.sin(q)
    return expr.xreplace(rep), psis, sums


def _psi_of(phi: sp.Symbol) -> sp.Symbol:
    return sp.Symbol("psi_" + phi.name[4:], real=True)


def _terms(form: str, table: dict, phis: list) -> sp.Expr:
    terms = []
    for key, v in table.items():
        trig, rest = key
        if form == "f":
            kind, m = trig
            angle = sp.Add(*(mk * phi for mk, phi in zip(m, phis)))
            factor = (sp.cos if kind == "cos" else sp.sin)(angle) if any(m) else sp.Integer(1)
        else:
            factor = sp.Mul(*(f(phi) ** e for k, phi in enumerate(phis) for f, e in ((sp.cos, trig[2 * k]), (sp.sin, trig[2 * k + 1]))))
        terms.append(to_sympy(v) * factor * rest)
    return sp.Add(*terms)


def canonical(expr: sp.Expr, phis: list, form: str | None = None, links: dict | None = None) -> Canonical:
    """``expr`` (cos φᵏ, sin φᵏ as sympy functions; irrational constants as exact.ConstSymbols)
    in the canonical form with the fewest terms, or in ``form``.  ``links`` (φᵏ → (φᵏ⁻¹, cos θᵏ)
    for each axis parallel to the one before) allows the cumulative forms C and S."""
    table = _split(expr, phis)
    has_trig = any(any(exps) for exps, _ in table)
    if not has_trig:
        folded = _folded(table)
        out = sp.Add(*(to_sympy(v) * rest for (_, rest), v in folded.items()))
        return Canonical(out, None, len(folded), {})
    n = len(phis)
    forms = {"c": _folded(_eliminate(table, 1)), "s": _folded(_eliminate(table, 0)), "f": _folded(_fourier(table, n))}
    linked = [phi for phi in phis if phi in links and links[phi][0] in phis] if links else []
    if linked:
        moved, psis, sums = _cumulative(expr, phis, links)
        cum = _split(moved, psis)
        forms.update(C=_folded(_eliminate(cum, 1)), S=_folded(_eliminate(cum, 0)))
    counts = {k: len(v) for k, v in forms.items()}
    if form is None or form not in forms:
        form = min(forms, key=lambda k: (counts[k], FORMS.index(k)))
    if form in ("C", "S"):
        out = _terms(form, forms[form], psis).xreplace({sp.cos(p): sp.cos(sums[p]) for p in psis}
                                                      | {sp.sin(p): sp.sin(sums[p]) for p in psis})
    else:
        out = _terms(form, forms[form], phis)
    return Canonical(out, form, counts[form], counts)
