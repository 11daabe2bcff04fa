"""Each joint's equation of motion as the document writes it out: in full where it fits a few lines
(the groups substituted, collected by φ̈ʳ and the monomials of φ̇), else with the printed
quantities by name; each with the paper's number of the same equation."""
from __future__ import annotations

import sympy as sp

from .texterms import breaks, fold_numbers, visible


TAG_WIDTH = 7  # ems the equation's number and the paper's take at the right
EOM_MAX_LINES = 6  # the equations of motion are written out when each fits this many lines


def assembled(spec, vals: dict, doc, kin) -> dict:
    """Each joint's equation of motion written out, Σᵣ M_kr φ̈ʳ + Q_k + Γ_k (+ Π_k + Λ̊_k) = G_k + Lᵏ
    (+ W_k + τ_k), the left side collected by φ̈ʳ and the monomials of φ̇: the lines of each (the
    right side's first line starts with "= "), or the reason they are not written out."""
    n = spec.n
    acc = doc.accelerations(n)
    gens = acc + kin.phidot[1:]
    joint = dict(vals["joint"])
    rows = []
    for k in range(n):
        left = sum((vals["M"][_m_index(n, k, r)] * acc[r] for r in range(n)), sp.Integer(0))
        extra = [vals[key][k] for key in ("Pi", "Lamdot") if vals[key]]
        left += vals["Q"][k] + vals["Gamma"][k] + sum(extra, sp.Integer(0))
        right = vals["G"][k] + (vals["Phi"][k] if vals["Phi"] else 0) + joint.get(k, 0)
        pieces = doc.grouped_pieces(left, gens, free_last=True)
        rhs = doc.w.pieces(fold_numbers(doc.canonical(sp.sympify(right)).expr)) if right != 0 else []
        if k + 1 in spec.controls:
            rhs = [p for p in rhs if p != "0"] + [rf"L^{{{k + 1}}}"]
        rhs = rhs or ["0"]
        width = doc.width - TAG_WIDTH
        lines = breaks(pieces, width)
        lines[1:] = [r"\quad " + ln for ln in lines[1:]]
        right_lines = breaks(rhs, width - 2)
        if visible(lines[-1]) + visible(right_lines[0]) + 2 < width and len(right_lines) == 1:
            lines[-1] += " = " + right_lines[0]
        else:
            lines += ["\\quad = " + right_lines[0]] + ["\\quad " + ln for ln in right_lines[1:]]
        if len(lines) > EOM_MAX_LINES:
            return dict(rows=None, reason=f"written out, the equation of joint {k + 1} alone would take {len(lines)} lines")
        rows.append(dict(k=k + 1, lines=lines))
    return dict(rows=rows, count="one equation per joint" if n > 1 else "one equation", named=False)


LEFT = (("Q", "Q"), ("Gamma", r"\Gamma"), ("Pi", r"\Pi"), ("Lamdot", r"\mathring\Lambda"))
RIGHT = (("G", "G"), ("Phi", "W"), ("joint", r"\tau"))


def _named(spec, eqs: dict, doc, pair_form: bool, reason: str) -> dict:
    """Each joint's equation of motion with the printed quantities by name, Σᵣ M_kr φ̈ʳ + Q_k + Γ_k
    (+ Π_k + Λ̊_k) = G_k + Lᵏ (+ W_k + τ_k): the ones that are zero for this chain left out, M_kr
    named as printed (its upper triangle).  A long chain whose M is printed as z^k·ξ^r keeps the sum."""
    n = spec.n
    printed = {e.lhs for key in ("M", *(k for k, _ in LEFT + RIGHT)) if eqs.get(key) for e in eqs[key]["rows"]}
    rows = []
    for k in range(1, n + 1):
        if pair_form:
            left = [rf"\sum_{{r=1}}^{{{n}}} " + m_name(k, "r", n) + r" \, \ddot\varphi^{r}"]
        else:
            left = [m_name(min(k, r), max(k, r), n) + rf" \, \ddot\varphi^{{{r}}}" for r in range(1, n + 1)
                    if m_name(min(k, r), max(k, r), n) in printed]
        left += [f"{name}_{{{k}}}" for _, name in LEFT if f"{name}_{{{k}}}" in printed]
        right = [f"{name}_{{{k}}}" for _, name in RIGHT[:1] if f"{name}_{{{k}}}" in printed]
        right += [rf"L^{{{k}}}"] if k in spec.controls else []
        right += [f"{name}_{{{k}}}" for _, name in RIGHT[1:] if f"{name}_{{{k}}}" in printed]
        lines = breaks(left, 0.9 * (doc.width - TAG_WIDTH))  # a name with its φ̈ is wider than its text's estimate
        lines[1:] = [r"\quad " + ln for ln in lines[1:]]
        lines[-1] += " = " + (" + ".join(right) or "0")
        rows.append(dict(k=k, lines=lines))
    return dict(rows=rows, count=("one equation per joint" if n > 1 else "one equation"), named=True, reason=reason)


def m_name(k, r, n: int) -> str:
    """M_kr as printed: M_{12}, or M_{1,12} in a chain of ten or more joints."""
    return f"M_{{{k}{',' if n > 9 else ''}{r}}}"


def _m_index(n: int, k: int, r: int) -> int:
    """Where M_kr is in the printed upper triangle (k, r from 0)."""
    k, r = min(k, r), max(k, r)
    return k * n - k * (k - 1) // 2 + (r - k)


def eom(spec, vals: dict, doc, kin, eqs: dict, closed: bool, pair_form: bool) -> dict:
    """The equations of motion written out in full where each fits a few lines, else with the
    quantities by name; each with the paper's number of the same equation (its (17), (18), (19)
    are joints n, 2…n − 1 and 1 of a fixed base, (8), (9), (10) those of the general case)."""
    out = assembled(spec, vals, doc, kin) if closed else dict(rows=None)
    if not out["rows"]:
        reason = out.get("reason") or f"for $n = {spec.n}$ the closed forms are long"
        out = _named(spec, eqs, doc, pair_form, reason)
    last, middle, first = ("8", "9", "10") if spec.general else ("17", "18", "19")
    for row in out["rows"]:
        row["paper"] = last if row["k"] == spec.n else first if row["k"] == 1 else middle
    return out
