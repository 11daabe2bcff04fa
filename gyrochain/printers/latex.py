"""The LaTeX target: the document a reviewer reads, in the paper's notation.

Closed forms (small n) are reduced exactly to their shortest canonical trigonometric form
(trigform.py) and printed term by term; long chains show the recursion's quantities in order.
Numbers print to 10 significant digits (the C and Python carry full precision).
"""
from __future__ import annotations

import hashlib
import re

import sympy as sp
from .. import __version__
from ..derive import trigform
from ..derive.algebra import ZERO, Poly
from ..derive.assemble import Model
from ..derive.exact import Fraction, is_negative, is_unit, to_float
from ..derive.kinematics import Kinematics, platform_symbols
from ..chainspec.spec import T as TIME
from . import texbodies, texcheck, texeom, texintegrals, texlisting, texrecursion, texscene, texsources, textype
from .texlayout import DISPLAY_WIDTH, TEXT_WIDTH, Numbers, TexEquation, block, per_row, term_counts
from .common import one_line, tex_escape
from .texterms import TexWriter, breaks, fold_numbers, join, number_text, param_tex, visible


def writer_for(spec, kin: Kinematics) -> TexWriter:
    """How each symbol prints and in which order: the platform's ω⁰, ε⁰, v̇₀, γ⁰, the program's
    quantities, φᵏ, φ̇ᵏ, the torques Lᵏ and the parameters."""
    names, rank, angles = {TIME: "t"}, {TIME: (TexWriter.TIME, 0)}, {}
    tex = {"omega": r"\omega^{0}", "epsilon": r"\varepsilon^{0}", "vdot": r"\dot v_{0", "gamma": r"\gamma^{0}"}
    for g, (key, syms) in enumerate(platform_symbols().items()):
        for i, sym in enumerate(syms, start=1):
            names[sym] = f"{tex[key]},{i}}}" if key == "vdot" else f"{tex[key]}_{{{i}}}"
            rank[sym] = (TexWriter.PLATFORM, 3 * g + i)
    for j, (a, _) in enumerate(kin.prog.defs):
        names[a.sym] = kin.prog.tex.get(a.sym) or r"\mathrm{" + tex_escape(a.name) + "}"
        rank[a.sym] = (TexWriter.QUANTITY, j)
    for k in range(1, kin.n + 1):
        names[kin.phi[k]], rank[kin.phi[k]], angles[kin.phi[k]] = rf"\varphi^{{{k}}}", (TexWriter.ANGLE, k), k
        names[kin.phidot[k]], rank[kin.phidot[k]] = rf"\dot\varphi^{{{k}}}", (TexWriter.VELOCITY, k)
        names[kin.torque[k]], rank[kin.torque[k]] = rf"L^{{{k}}}", (TexWriter.TORQUE, k)
    for p in spec.params:
        names[p] = param_tex(p.name)
    return TexWriter(names, rank, angles)


MAX_LATEX_TERMS = 400

CLOSED_FORM_MAX_N = 3  # above this the LaTeX shows the recursion instead of expanded closed forms


class Shown(tuple):
    """Printed lines of one quantity, with the number of terms."""

    terms: int | None = None

    @staticmethod
    def of(lines, terms=None) -> "Shown":
        out = Shown(lines)
        out.terms = terms
        return out

    @staticmethod
    def is_zero(lines) -> bool:
        return tuple(lines) == ("0",)


def _angles(expr: sp.Expr) -> list:
    """The joint angles φᵏ whose cos or sin the expression has, in order."""
    found = {a.args[0] for a in expr.atoms(sp.cos, sp.sin) if a.args[0].is_Symbol and a.args[0].name.startswith("phi_")}
    return sorted(found, key=lambda s: int(s.name[4:]))


class Doc:
    """One document's printing: its writer, and each quantity in its own normal form
    (trigform.py): the form with the fewest terms, so that the same function prints the same way
    in every document."""

    def __init__(self, writer: TexWriter, links: dict | None = None):
        self.w, self.links = writer, links or {}
        self.width = DISPLAY_WIDTH  # ems of a display's line (texterms.visible)
        self._seen: dict = {}  # expr → its Canonical
        self.used: dict = {}  # form → how many printed quantities have it

    def canonical(self, expr: sp.Expr) -> trigform.Canonical:
        """``expr`` in its normal form (reduced once)."""
        can = self._seen.get(expr)
        if can is None:
            can = self._seen[expr] = trigform.canonical(expr, _angles(expr), links=self.links)
            if can.form is not None:
                self.used[can.form] = self.used.get(can.form, 0) + 1
        return can

    def lines(self, expr: sp.Expr, width: float = 0, expand: bool = True, count: int | None = None) -> Shown:
        """A sum printed term by term and broken into lines: expanded into the document's
        trigonometric form, or as it is (``expand=False``: already in it, ``count`` its terms)."""
        if expand:
            can = self.canonical(expr)
            expr, count = can.expr, can.terms
        expr = fold_numbers(expr)
        if len(sp.Add.make_args(expr)) > MAX_LATEX_TERMS:
            return Shown.of([rf"\text{{({len(sp.Add.make_args(expr))} terms when expanded; not shown)}}"], count)
        return Shown.of(self.w.lines(expr, width or self.width), count)

    def grouped(self, expr: sp.Expr, gens: list) -> Shown:
        """Collected by monomials of φ̇ (the paper's coefficient · φ̇ʰφ̇ʳ layout)."""
        can = self.canonical(expr)
        pieces = self.grouped_pieces(can.expr, gens, reduced=True)
        return Shown.of(breaks(pieces, self.width) if pieces else ["0"], can.terms)

    def grouped_pieces(self, expr: sp.Expr, gens: list, reduced: bool = False, free_last: bool = False) -> list[str]:
        """The signed terms of ``expr`` collected by the monomials of ``gens`` (in the document's
        form unless ``reduced`` says it is already); the terms free of them first, or last."""
        if not reduced:
            expr = self.canonical(expr).expr
        groups: dict = {}
        for term in sp.Add.make_args(expr):
            coeff, mono = term.as_independent(*gens, as_Add=False)
            groups[mono] = groups.get(mono, 0) + coeff
        pieces = []
        for mono in sorted(groups, key=lambda m: ((free_last and m == 1), sp.Poly(m, *gens).monoms()[0][::-1] if m != 1 else ())):
            inner = self.w.pieces(fold_numbers(groups[mono]))
            if inner == ["0"]:
                continue
            factor = "" if mono == 1 else self.w.term(mono)[1]
            if not factor:
                pieces.extend(inner)
            elif len(inner) == 1:  # one term: its sign is the line's ("- 0.5 sin φ² φ̇²", not "+ (-0.5 sin φ²) φ̇²")
                neg = inner[0].startswith("- ")
                body = inner[0][2:] if neg else inner[0]
                pieces.append(("- " if neg else "") + (factor if body == "1" else body + r" \, " + factor))
            else:
                pieces.extend(_bracketed(inner, factor, self.width))
        return pieces

    def accelerations(self, n: int) -> list:
        """φ̈¹ … φ̈ⁿ as symbols the writer prints (the equations of motion and ∂R/∂x have them)."""
        acc = [sp.Symbol(f"qddot_{k}") for k in range(1, n + 1)]
        for k, a in enumerate(acc, start=1):
            self.w.names[a], self.w.rank[a] = rf"\ddot\varphi^{{{k}}}", (TexWriter.ACCELERATION, k)
        return acc

    def poly_lines(self, p: Poly, width: float = 0) -> Shown:
        """A polynomial of the program as it stands (no expansion), printed without sympy: the
        recursion listing of a long chain has thousands of these."""
        if not p.terms:
            return Shown.of(["0"])
        pieces = []
        for m, c in p.terms.items():
            factors, i = [], 0
            while i < len(m):
                j = i
                while j < len(m) and m[j] is m[i]:
                    j += 1
                factors.append(self.w.factor(m[i].sym, j - i))
                i = j
            body = " ".join(factors)
            if not m or not is_unit(c):
                body = number_text(abs(to_float(c)) if not isinstance(c, (int, Fraction)) else abs(c)) + (" " + body if body else "")
            pieces.append(("- " if is_negative(c) else "") + body)
        return Shown.of(breaks(pieces, width or self.width))


def _bracketed(inner: list[str], factor: str, width: float) -> list[str]:
    r"""A multi-term coefficient of a velocity monomial in brackets: one piece, or for a long one a
    piece per term (the line breaker may then split it, \Bigl( and \Bigr) pairing across lines: an opening
    and a closing delimiter, so that a minus after the bracket is a sign)."""
    if visible(join(inner)) < 0.8 * width:
        return [r"\left(" + join(inner) + r"\right) \, " + factor]
    return [r"\Bigl(" + inner[0], *inner[1:-1], inner[-1] + r"\Bigr) \, " + factor]


T10_MAX_TERMS = 20  # T₁ + T₀ is written out up to this many terms of the program's algebra (ship_gimbal: 15)
CLOSED_FORM_MAX_N_GENERAL = 2  # the same for a spec with platform motion or loads (more symbols)


CLOSED_FORM_MAX_TERMS = 1000  # M's upper triangle in the program's algebra, before the trigonometric reduction


def _closed(spec, kin, dyn) -> bool:
    """Whether the document prints closed forms: up to n = 3 always (n = 2 with a moving
    platform, whose symbols multiply the terms), and for a longer chain without the loop form and
    without platform motion when its mass matrix is small enough to reduce (a UR5's upper triangle
    has 286 terms before the reduction, a Panda's 3,258: its document shows the recursion)."""
    n = spec.n
    if dyn.loops is not None:
        return False
    if spec.general and kin.platform is not None:
        return n <= CLOSED_FORM_MAX_N_GENERAL
    if n <= CLOSED_FORM_MAX_N:
        return True
    raw = kin.prog.inline_poly([dyn.M[k][r] for k in range(n) for r in range(k, n)])
    return sum(len(p.terms) for p in raw) <= CLOSED_FORM_MAX_TERMS


def _split_platform(prog, p: Poly, platform: set) -> tuple[sp.Expr, sp.Expr]:
    """A closed form split into the terms without and with ω⁰, ε⁰, v̇₀ (the grouping of (8)–(10))."""
    (full,) = prog.inline_poly([p])
    rest = Poly({m: c for m, c in full.terms.items() if not any(a.sym in platform for a in m)})
    plat = Poly({m: c for m, c in full.terms.items() if any(a.sym in platform for a in m)})
    return rest.to_sympy(prog.sympy_of, symbolic=True), plat.to_sympy(prog.sympy_of, symbolic=True)


def _mass_targets(dyn, n: int) -> list:
    """What the mass matrix section prints: M's upper triangle, or for the loop form of a long
    chain (loopform.py) the 6-vectors Sᵏ then z1ᵏ of each joint, from which M_kr = z1ᵏ·Sʳ (k ≥ r):
    O(n) quantities instead of n(n + 1)/2."""
    if dyn.loops is not None:
        return [x for k in range(n) for x in (*dyn.loops.S[k], *dyn.loops.z1[k])]
    return [dyn.M[k][r] for k in range(n) for r in range(k, n)]


def _values(spec, kin, dyn, ints, closed: bool) -> dict:
    """The document's quantities: closed forms (sympy, small n) or the program's polynomials.
    In the general case with a moving platform and closed forms, the platform terms of Q and Γ
    are split off as Π (lines 4–7 of (8)–(10))."""
    n = spec.n
    get = (lambda ps: kin.prog.inline(list(ps), symbolic=True)) if closed else list
    out = dict(M=get(_mass_targets(dyn, n)), Q=get(dyn.Q), Gamma=get(dyn.Gamma),
               G=get(dyn.G), U=get([ints.U])[0], K=get([ints.momentum])[0] if ints.momentum is not None else None,
               Pi=None, Lamdot=get(dyn.Lamdot), Phi=get(dyn.Phi),
               joint=[(k, v) for k, v in enumerate(get(dyn.joint)) if not dyn.joint[k].is_zero()])
    if spec.base is not None and spec.base.moves and closed:  # T = T2 + T1 + T0: the part beyond (21)
        qd = kin.qd[1:]  # in the program's algebra, where T − T₂ cancels exactly and cheaply
        T2 = sum((dyn.M[k][r] * qd[k] * qd[r] * (0.5 if k == r else 1.0) for k in range(n) for r in range(k, n)), ZERO)
        T10 = ints.T - T2
        if len(T10.terms) <= T10_MAX_TERMS:  # a platform turning about skew axes gives thousands of terms: not shown
            (out["T10"],) = kin.prog.inline([T10], symbolic=True)
    if spec.general and kin.platform is not None and closed:
        sy = platform_symbols()
        platform = set(sy["omega"] + sy["epsilon"] + sy["vdot"])
        Q, Gam, Pi = [], [], []
        for k in range(n):
            rq, pq = _split_platform(kin.prog, dyn.Q[k], platform)
            rg, pg = _split_platform(kin.prog, dyn.Gamma[k], platform)
            Q.append(rq), Gam.append(rg), Pi.append(pq + pg)
        out.update(Q=Q, Gamma=Gam, Pi=Pi)
    return out


def _platform_rows(kin, doc: Doc) -> dict | None:
    """ω⁰, ε⁰, v̇₀ and γ⁰ in the platform's frame, from the spec's motion (zero ones named once)."""
    pm = kin.platform
    if pm is None:
        return None
    sy = platform_symbols()
    rows = []
    for key, vals in (("omega", pm.omega), ("epsilon", pm.eps), ("vdot", pm.acc), ("gamma", pm.down)):
        for sym, v in zip(sy[key], vals):
            rows.append(TexEquation(doc.w.name(sym), doc.lines(sp.sympify(v), expand=False)))
    return block(rows)


DERIVATIVE_TEX_MAX_N = 2  # closed forms of the derivatives are computed up to this n
DERIVATIVE_TEX_MAX_TERMS = 60  # and printed when they have at most this many terms in all


def _derivative_tex(model: Model, stages, doc: Doc, printed_terms: int | None) -> dict:
    """∂R/∂φʲ and ∂R/∂φ̇ʲ of R = M φ̈ − f (closed forms, φ̈ as symbols): with them
    ∂φ̈/∂x = −M⁻¹ ∂R/∂x, the implicit derivative of (17)–(19) that the emitted code computes.
    Printed for small models; otherwise the reason, and where the values are."""
    kin, dyn, n = stages.kin, stages.dyn, model.spec.n
    if n > DERIVATIVE_TEX_MAX_N or (model.spec.general and n > CLOSED_FORM_MAX_N_GENERAL):
        return dict(rows=None, reason=f"this document expands them only up to $n = {DERIVATIVE_TEX_MAX_N}$"
                    + (f" (for $n = {n}$ the equations they differentiate already have {printed_terms} terms above)"
                       if printed_terms else ""))
    acc = doc.accelerations(n)
    vals = kin.prog.inline([dyn.M[i][j] for i in range(n) for j in range(n)] + list(dyn.f), symbolic=True)
    M = [vals[i * n:(i + 1) * n] for i in range(n)]
    R = [sum((M[i][j] * acc[j] for j in range(n)), sp.Integer(0)) - vals[n * n + i] for i in range(n)]
    entries, terms = [], 0
    for syms, tex in ((kin.phi, r"\varphi"), (kin.phidot, r"\dot\varphi")):
        for j in range(1, n + 1):
            for i in range(n):
                lhs = rf"\frac{{\partial R_{{{i + 1}}}}}{{\partial {tex}^{{{j}}}}}"
                can = doc.canonical(trigform.diff(R[i], syms[j]))
                entries.append((lhs, can))
                terms += can.terms
                if terms > DERIVATIVE_TEX_MAX_TERMS:  # too long to print: the rest need not be reduced
                    return dict(rows=None, reason=f"the first {len(entries)} of their {2 * n * n} closed-form entries "
                                f"already have {terms} terms, more than the {DERIVATIVE_TEX_MAX_TERMS} this document prints")
    return dict(block([TexEquation(lhs, doc.lines(can.expr, expand=False, count=can.terms)) for lhs, can in entries]),
                reason=None)


def _bodies(spec, kin, doc: Doc) -> list[dict]:
    """The spec's table: θᵏ, mᵏ, cᵏ, sᵏ, λᵏ, Aᵏ, the control flag and the direction cosines αᵏ."""
    show = lambda x: doc.w.sum_text(fold_numbers(sp.sympify(x)))  # noqa: E731

    def mat(m):
        m = m.tolist() if isinstance(m, sp.MatrixBase) else m
        rows = [" & ".join(show(x) for x in row) for row in m]
        return r"\begin{pmatrix}" + r" \\ ".join(rows) + r"\end{pmatrix}"

    # c, s, λ as rows (one line a body) when a body's row of the table fits the page, else as columns
    wide = max((sum(visible(show(x)) + 1 for key in ("c", "s", "lam") for x in getattr(b, key)) for b in spec.bodies),
               default=0) + 14 > TEXT_WIDTH

    def vec(v):
        return r"\begin{pmatrix}" + (r" \\ " if wide else " & ").join(show(x) for x in v) + r"\end{pmatrix}"

    wide_inertia = max((sum(visible(show(x)) + 1.5 for row in b.A for x in row) * 2 / 3 for b in spec.bodies),
                       default=0) + 4 > TEXT_WIDTH

    def components(A):  # A₁₁, A₂₂, A₃₃, A₁₂, A₁₃, A₂₃: one line a body, or the matrix where that is too wide
        cells = [show(A[i][j]) for i, j in ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))]
        return cells if not wide_inertia else [mat(A)]

    return [dict(k=k, theta=texscene.angle_text(b.theta, doc.w, fold_numbers), m=show(b.m), c=vec(b.c),
                 s=vec(b.s) if k < spec.n else r"\text{(none: last body)}",
                 lam=vec(b.lam), A=components(b.A), control="disturbance" if b.disturbance else "yes" if b.control else "no", alpha=mat(kin.alpha[k]))
            for k, b in enumerate(spec.bodies, start=1)]


GROUP_MAX_LINES = 3  # a velocity group longer than this is printed by its coefficients


def _by_coefficients(doc: Doc, name: str, k: int, expr: sp.Expr, gens: list) -> tuple[TexEquation, list]:
    """A velocity group as the sum of its coefficients times the monomials of φ̇ (Q_k =
    Σ_{h≤r} Q_{k,hr} φ̇ʰφ̇ʳ, Γ_k = Σ_r Γ_{k,r} φ̇ʳ; every index a subscript, so none reads as a power): the
    group's line, and each coefficient in its own normal form as a named quantity."""
    n = len(gens)
    sep = "," if n > 9 else ""
    groups: dict = {}
    for term in sp.Add.make_args(doc.canonical(expr).expr):
        coeff, mono = term.as_independent(*gens, as_Add=False)
        groups[mono] = groups.get(mono, 0) + coeff
    pieces, rows, terms = [], [], 0
    for mono in sorted(groups, key=lambda m: sp.Poly(m, *gens).monoms()[0][::-1] if m != 1 else ()):
        can = doc.canonical(sp.expand(groups[mono]))
        if can.terms == 0:
            continue
        index = sep.join(str(i + 1) for i, e in enumerate(sp.Poly(mono, *gens).monoms()[0]) for _ in range(e))
        cname = f"{name}_{{{k},{index}}}"
        rows.append(TexEquation(cname, doc.lines(can.expr, expand=False, count=can.terms)))
        pieces.append(cname + r" \, " + doc.w.term(mono)[1])
        terms += can.terms
    return TexEquation(f"{name}_{{{k}}}", Shown.of(breaks(pieces, 0.8 * doc.width) if pieces else ["0"], terms)), rows


def _momentum_lines(spec, vals: dict, doc: Doc, gens: list, grouped, by_name: bool) -> Shown:
    """ℓ collected by φ̇; where that is longer than a few lines, as Σ_r M_1r φ̇ʳ (the printed M by
    name) plus the rest (the rotors' share), so that the mass matrix is not written twice."""
    shown = grouped(vals["K"])
    if not by_name or len(shown) <= GROUP_MAX_LINES:
        return shown
    n = spec.n
    rest = sp.expand(vals["K"] - sum((vals["M"][r] * gens[r] for r in range(n)), sp.Integer(0)))
    pieces = [texeom.m_name(1, r + 1, n) + r" \, " + doc.w.name(gens[r]) for r in range(n) if vals["M"][r] != 0]
    extra = doc.grouped_pieces(rest, gens) if rest != 0 else []
    return Shown.of(breaks(pieces + extra, 0.8 * doc.width))


def _equations(spec, vals: dict, doc: Doc, closed: bool, gens: list, pair_form: bool = False,
               choice: texbodies.Choice | None = None) -> dict:
    """M, Q, Γ, G, Π, Λ̊, W, τ, U and k as printed: closed forms (small n) or the recursion's
    quantities (their definitions listed in the recursion section); with ``choice``, a closed form
    longer than a few lines as the sum of the bodies' shares."""
    n = spec.n
    choice = choice or texbodies.Choice(doc, None)
    if closed:
        lines, grouped = doc.lines, (lambda e: doc.grouped(e, gens))
    else:  # the recursion's polynomials, or the sums of the bodies' shares as they are
        lines = grouped = (lambda e: doc.poly_lines(e) if isinstance(e, Poly) else doc.lines(e, expand=False))
    if pair_form:  # per joint S^k then z^k (six components each), as _mass_targets lists them
        names = [f"{v}^{{{k + 1}}}_{{{i + 1}}}" for k in range(n) for v in (r"\xi", "z") for i in range(6)]
    else:
        names = [texeom.m_name(k + 1, r + 1, n) for k in range(n) for r in range(k, n)]
    coefficients = {"Q": [], "Gamma": []}

    def velocity_group(key, name, k, v):
        before = choice.start()
        shown = grouped(v)
        if not closed or len(shown) <= GROUP_MAX_LINES:
            return TexEquation(f"{name}_{{{k}}}", choice.shown(key, k - 1, shown, before))
        eq, rows = _by_coefficients(doc, name, k, v, gens)
        instead = choice.instead(key, k - 1, max((len(r.lines) for r in rows), default=0), before)
        if instead is not None:  # a coefficient is longer than a few lines: the group as the bodies' shares
            return TexEquation(eq.lhs, instead)
        coefficients[key] += rows
        return eq

    def short(key, lhs, i, v):
        before = choice.start()
        return TexEquation(lhs, choice.shown(key, i, lines(v), before))

    out = dict(
        M=[short("M", lhs, i, v) for i, (lhs, v) in enumerate(zip(names, vals["M"]))],
        Q=[velocity_group("Q", "Q", k + 1, v) for k, v in enumerate(vals["Q"])],
        Gamma=[velocity_group("Gamma", r"\Gamma", k + 1, v) for k, v in enumerate(vals["Gamma"])],
        G=[short("G", f"G_{{{k + 1}}}", k, v) for k, v in enumerate(vals["G"])],
        Pi=[TexEquation(rf"\Pi_{{{k + 1}}}", grouped(v)) for k, v in enumerate(vals["Pi"] or [])],
        Lamdot=[TexEquation(rf"\mathring\Lambda_{{{k + 1}}}", lines(v)) for k, v in enumerate(vals["Lamdot"])],
        Phi=[TexEquation(f"W_{{{k + 1}}}", lines(v)) for k, v in enumerate(vals["Phi"])],
        joint=[TexEquation(rf"\tau_{{{k + 1}}}", lines(v)) for k, v in vals["joint"]],
    )
    # the terms of the closed forms printed (a group written wholly as the bodies' shares has none to count)
    counts = term_counts([(sym, sum(eq.lines.terms or 0 for eq in out[key])) for sym, key in
                          (("M", "M"), ("Q", "Q"), (r"\Gamma", "Gamma"), ("G", "G"))
                          if not choice.chosen or any(eq.lines.terms for eq in out[key])])
    blocks = {key: block(eqs) if eqs else None for key, eqs in out.items()}
    blocks.update({key + "_coefficients": block(rows) if rows else None for key, rows in coefficients.items()})
    U = TexEquation("U", short("U", "U", 0, vals["U"]).lines, "22")
    T10 = TexEquation("T_{1} + T_{0}", lines(vals["T10"])) if vals.get("T10") is not None else None
    K = TexEquation(r"\ell", _momentum_lines(spec, vals, doc, gens, grouped, closed and not pair_form), "27") if vals["K"] is not None else None
    printed = sum(eq.lines.terms or 0 for key in ("M", "Q", "Gamma", "G") for eq in out[key]) if closed else None
    return dict(blocks, U=U, T10=T10, K=K, term_counts=counts, printed_terms=printed)


def _quadratures(model: Model, doc: Doc) -> dict | None:
    """J, C, A, U and β of the quadratures (30), when the model has them."""
    if model.quad is None:
        return None
    kin = model.kin
    J, C, A, U2, beta = kin.prog.inline(model.quad.terms, symbolic=True)
    # written in φ, the name the quadratures give the angle of joint 2 (J(φ), not J in φ²)
    w = doc.w
    inner = Doc(TexWriter({**w.names, kin.phi[2]: r"\varphi", kin.phidot[2]: r"\dot\varphi"}, w.rank, w.angles), doc.links)
    inner._seen, inner.used = doc._seen, doc.used  # the same forms, counted once for the document
    doc = inner
    return dict(J=tuple(doc.lines(J)), C=tuple(doc.lines(C)), A=tuple(doc.lines(A)), U=tuple(doc.lines(U2)),
                beta=tuple(doc.lines(beta)), nikolai=model.quad.nikolai, U_const=not (U2.free_symbols & {kin.phi[2]}))


def _jacobi(model: Model, doc: Doc, closed: bool):
    """Jacobi's integral H written out (closed forms), None where it is not an integral."""
    h = model.integrals.jacobi
    if h is None:
        return None
    if not closed:
        return dict(K=None)
    (value,) = model.kin.prog.inline([h], symbolic=True)
    return dict(K=TexEquation("H", doc.grouped(value, model.kin.phidot[1:])))


def _tex(model: Model) -> dict:
    spec, n = model.spec, model.spec.n
    # the general case reads the stages derived with the platform's motion as symbols, as (8)–(10) state it
    stages = model.symbolic if spec.general else model
    kin, dyn = stages.kin, stages.dyn
    ints = model.symbolic.ints if spec.general else model.integrals
    closed = _closed(spec, kin, dyn)
    doc = Doc(writer_for(spec, kin), texscene.parallel_links(spec, kin))
    vals = _values(spec, kin, dyn, ints, closed)
    pair_form = dyn.loops is not None
    recursion, aux, shares, choice = [], False, None, None
    if texbodies.applies(spec, kin, dyn):  # body by body, in quantities of each body's frame: all, or the long ones
        shares = texbodies.shares(spec, kin, doc)
        by_body = texbodies.values(spec, kin, dyn, ints, vals, shares, doc)
        if closed:
            choice = texbodies.Choice(doc, by_body)
        else:
            vals = by_body
    elif not closed:  # the printed quantities in the recursion's named quantities (Appendix A)
        targets = _mass_targets(dyn, n) + list(dyn.Q) + list(dyn.Gamma) + list(dyn.G)
        targets += [ints.U] + ([ints.momentum] if ints.momentum is not None else [])
        targets += list(dyn.Lamdot) + list(dyn.Phi) + [j for j in dyn.joint if not j.is_zero()]
        printed = {f"{g}_{{{k}}}" for g in ("Q", r"\Gamma", "G", r"\Pi", r"\mathring\Lambda", "W", r"\tau") for k in range(1, n + 1)}
        recursion, full = texrecursion.recursion(kin, doc, targets, printed)
        vals = texrecursion.substituted(vals, full)
        aux = any(r.lhs.startswith(r"\zeta") for r in recursion)
    eqs = _equations(spec, vals, doc, closed, kin.phidot[1:], pair_form, choice)
    if shares is not None and (not closed or choice.chosen):
        bodies, count = texbodies.layout(shares, doc, spec, kin, choice.chosen if closed else None)
        shares = dict(bodies=bodies, count=count, gyro=shares.gyro, partial=closed, lines=texbodies.SHARE_LINES,
                      stated=any(b["stated"] for b in bodies))
    else:
        shares = None
    bodies = _bodies(spec, kin, doc)
    out = dict(
        general=spec.general,
        moving=spec.base is not None and spec.base.moves,
        gravity=spec.g != 0,
        jacobi=_jacobi(model, doc, closed),
        **texintegrals.statements(model),
        **eqs,
        platform=_platform_rows(kin, doc) if spec.general else None,
        shares=shares,
        recursion=texrecursion.paragraphs(recursion),
        recursion_gamma=any(r.lhs.startswith(r"\Gamma^{") for r in recursion),
        recursion_aux=aux,
        eom=texeom.eom(spec, vals, doc, kin, eqs, closed, pair_form),
        quad=_quadratures(model, doc),
        check=texcheck.check(spec, kin, dyn, texcheck.groups(spec, kin, dyn, vals["Pi"] is not None)),
        bodies=bodies,
        body_rows=texscene.runs(bodies),
        alpha_per_row=per_row([b["alpha"] for b in bodies], TEXT_WIDTH),
        offsets=[(k, texscene.angle_text(b.offset, doc.w, fold_numbers)) for k, b in enumerate(spec.bodies, start=1)
                 if b.offset != 0],
        armature=[(k, doc.w.sum_text(fold_numbers(b.armature))) for k, b in enumerate(spec.bodies, start=1)
                  if b.armature != 0],
        scene=texscene.scene(spec, doc.w, fold_numbers),
        # the one form of the angles' functions, stated where the equations are written in closed form
        g=doc.w.sum_text(fold_numbers(spec.g)),
        closed=closed,
        pair_form=pair_form,
        controls=", ".join(f"$L^{{{k}}}$" for k in spec.controls if k not in spec.disturbances),
        disturbances=", ".join(f"$L^{{{k}}}$" for k in spec.disturbances),
        deriv=_derivative_tex(model, stages, doc, eqs["printed_terms"]),
        deriv_generic="d_jvp" in model.lines,
        deriv_world=model.der_form == "world",
        deriv_world_inverse=model.world_columns == "inverse",
        base=texsources.base_parameters(model),
        references=texsources.reference_texts(model, __version__),
    )
    out["form_text"] = texscene.forms_text(doc.used)
    out["notation"] = texscene.notation(model, out, [doc.w.name(p) for p in spec.params])
    return out


def initial_text(spec) -> str:
    """The spec's initial state as the document states it (E and k of the quadratures are its
    values); a vector whose entries are all the same is said once."""
    if spec.initial is None:
        return "The spec gives no initial state."

    def vec(sym, v):
        values = [f"{float(x):.10g}" for x in v]
        common = max(values, key=values.count)
        if len(values) > 8 and values.count(common) > len(values) - 4:  # a long chain's state: the exceptions, then the rest
            odd = [rf"${sym}^{{{k}}} = {x}$, " for k, x in enumerate(values, start=1) if x != common]
            return "".join(odd) + rf"${sym}^k = {common}$ for {'every other' if odd else 'every'} $k \le {len(values)}$"
        return rf"${sym} = (" + r",\allowbreak ".join(values) + ")$"  # a long chain's state wraps
    return "Initial state: " + vec(r"\varphi", spec.initial["phi"]) + ", " + vec(r"\dot\varphi", spec.initial["phidot"]) + "."


PAPERS = {"a4": "25mm", "letter": "1in"}  # generate --paper: the page and its margins


class LatexTarget:
    """The document a reviewer reads: the spec, the equations (17)–(19) or (8)–(10), the
    integrals, the quadratures and the derivatives, in the paper's notation."""

    suffixes = (".tex",)

    def files(self, model: Model, context: dict, env) -> dict[str, str]:
        spec = model.spec
        tex = _tex(model)
        tex.update(
            name_tex=tex_escape(spec.name),
            description_tex=textype.typeset(spec.description, {p.name: param_tex(p.name) for p in spec.params}),
            sha_tex=r"\allowbreak ".join(re.findall(".{1,16}", hashlib.sha256(spec.source.encode("utf-8")).hexdigest())),
            spec_label_tex=tex_escape(one_line(context["label"])),
            counts_tex=[(tex_escape(k), v) for k, v in sorted(context["counts"].items())],
            has_momentum=tex["K"] is not None,
            source_tex=texsources.source_text(model, context),
            initial_tex=initial_text(spec),
            articulated=model.qdd_form == "articulated",
            n=spec.n,
            k_range="$k = " + (", ".join(str(k) for k in range(1, spec.n + 1)) if spec.n <= 3 else rf"1,\dots,{spec.n}") + "$",
            eq=Numbers(),
            # the first lines, a TeX comment: the same words as the C's and Python's
            version=context["version"], spec_label=context["spec_label"], spec_sha=context["spec_sha"],
            regenerate=context["regenerate"],
            paper=context["paper"], margin=PAPERS[context["paper"]],
            listing=texlisting.listing(spec.source.rstrip("\n")),
        )
        template = env.get_template("model.tex.jinja")
        first = template.render(tex)
        tex["notation"] = texscene.used_rows(tex["notation"], first)  # only the symbols the document writes
        tex["eq"] = Numbers()  # the equations numbered afresh
        return {f"{spec.name}.tex": template.render(tex)}
