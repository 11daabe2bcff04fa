"""The LaTeX target: the document a reviewer reads, in the paper's notation.

Closed forms (small n) are reduced exactly to their shortest canonical trigonometric form
(trigform.py) and printed term by term; long chains show the recursion's quantities in order.
Numbers print to 10 significant digits (the C and Python carry full precision).
"""
from __future__ import annotations

import hashlib
import re
from dataclasses import dataclass

import sympy as sp
from .. import trigform
from ..algebra import ZERO, Poly
from ..assemble import Model
from ..exact import Fraction, is_negative, is_unit, to_float
from ..kinematics import Kinematics, platform_symbols
from ..spec import T as TIME
from . import texscene
from .common import one_line, signed_sum, tex_escape
from .texterms import TexWriter, breaks, join, number_text


def fold_numbers(expr: sp.Expr) -> sp.Expr:
    """Evaluate every subexpression made of numbers only (sqrt(3)/2, cos(3/10), …) to a Float;
    rationals stay exact (they print as the spec wrote them)."""
    if expr.is_Atom:
        return expr
    if expr.is_number:
        return expr if expr.is_Rational else sp.Float(expr.evalf(30), 30)
    args = [fold_numbers(a) for a in expr.args]
    return expr.func(*args) if any(a is not b for a, b in zip(args, expr.args)) else expr




def param_tex(name: str) -> str:
    r"""A spec parameter's name in the document, in sans serif (the document's own symbols are in
    serif type, so no parameter reads as one of them): a letter head and a subscript tail (m2 →
    m_{2}, J1z → J_{\mathrm{1z}}, A11 → A_{11}, k_spring → k_{\mathrm{spring}}); a longer head, Greek
    names included, as the word."""
    m = re.fullmatch(r"([A-Za-z]+?)_?([0-9].*|(?<=_).+)?", name)
    head, tail = (m.group(1), m.group(2)) if m else (name, None)
    head = rf"\mathsf{{{tex_escape(head)}}}"
    if not tail:
        return head
    tail = tail if tail.isdigit() else rf"\mathrm{{{tex_escape(tail)}}}"
    return f"{head}_{{{tail}}}"


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
    """One document's printing: its writer and the one trigonometric form it keeps (trigform.py),
    chosen as the form with the fewest terms over the equations of motion."""

    def __init__(self, writer: TexWriter):
        self.w, self.form, self.counts = writer, None, {}
        self._seen: dict = {}  # expr → its Canonical in its own shortest form (from choose)

    def choose(self, exprs) -> None:
        totals = dict.fromkeys(trigform.FORMS, 0)
        for e in exprs:
            can = self._seen[e] = trigform.canonical(e, _angles(e))
            for f in totals:
                totals[f] += can.terms_by_form.get(f, can.terms)
        self.form = min(trigform.FORMS, key=lambda f: (totals[f], trigform.FORMS.index(f)))
        self.counts = totals

    def canonical(self, expr: sp.Expr) -> trigform.Canonical:
        """``expr`` in the document's form (reduced once: choose's result is reused when its own
        shortest form is the document's)."""
        can = self._seen.get(expr)
        if can is not None and can.form in (None, self.form):
            return can
        return trigform.canonical(expr, _angles(expr), self.form)

    def lines(self, expr: sp.Expr, width: int = 230, expand: bool = True, count: int | None = None) -> Shown:
        """A sum printed term by term and broken into lines: expanded into the document's
        trigonometric form, or as it is (``expand=False``: already in it, ``count`` its terms)."""
        if expand:
            can = self.canonical(expr)
            expr, count = can.expr, can.terms
        expr = fold_numbers(expr)
        if len(sp.Add.make_args(expr)) > MAX_LATEX_TERMS:
            return Shown.of([rf"\text{{({len(sp.Add.make_args(expr))} terms when expanded; not shown)}}"], count)
        return Shown.of(self.w.lines(expr, width), count)

    def grouped(self, expr: sp.Expr, gens: list) -> Shown:
        """Collected by monomials of φ̇ (the paper's coefficient · φ̇ʰφ̇ʳ layout)."""
        can = self.canonical(expr)
        groups: dict = {}
        for term in sp.Add.make_args(can.expr):
            coeff, mono = term.as_independent(*gens, as_Add=False)
            groups[mono] = groups.get(mono, 0) + coeff
        pieces = []
        for mono in sorted(groups, key=lambda m: (sp.Poly(m, *gens).monoms()[0][::-1] if m != 1 else ())):
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
                pieces.extend(_bracketed(inner, factor))
        return Shown.of(breaks(pieces, 230) if pieces else ["0"], can.terms)

    def poly_lines(self, p: Poly, width: int = 230) -> Shown:
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
        return Shown.of(breaks(pieces, width))


def _bracketed(inner: list[str], factor: str) -> list[str]:
    r"""A multi-term coefficient of a velocity monomial in brackets: one piece, or for a long one a
    piece per term (the line breaker may then split it, \Big( and \Big) pairing across lines)."""
    if len(join(inner)) < 200:
        return [r"\left(" + join(inner) + r"\right) \, " + factor]
    return [r"\Big(" + inner[0], *inner[1:-1], inner[-1] + r"\Big) \, " + factor]


@dataclass(frozen=True)
class TexEquation:
    lhs: str
    lines: tuple[str, ...]  # a Shown when the quantity was expanded


def block(eqs: list[TexEquation]) -> dict:
    """Equations to print and the names of those that are zero (one line states them)."""
    rows = [e for e in eqs if not Shown.is_zero(e.lines)]
    zero = [e.lhs for e in eqs if Shown.is_zero(e.lines)]
    return dict(rows=rows, zero=", ".join(f"${z}$" for z in zero))


T10_MAX_TERMS = 20  # T₁ + T₀ is written out up to this many terms of the program's algebra (ship_gimbal: 15)
CLOSED_FORM_MAX_N_GENERAL = 2  # the same for a spec with platform motion or loads (more symbols)


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
            rows.append(TexEquation(doc.w.name(sym), doc.lines(sp.sympify(v), 200, expand=False)))
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
    acc = [sp.Symbol(f"qddot_{k}") for k in range(1, n + 1)]
    for k, a in enumerate(acc, start=1):
        doc.w.names[a], doc.w.rank[a] = rf"\ddot\varphi^{{{k}}}", (TexWriter.ACCELERATION, k)
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

    def vec(v):
        return r"\begin{pmatrix}" + r" \\ ".join(show(x) for x in v) + r"\end{pmatrix}"

    return [dict(k=k, theta=texscene.angle_text(b.theta, doc.w, fold_numbers), m=show(b.m), c=vec(b.c),
                 s=vec(b.s) if k < spec.n else r"\text{(none: last body)}",
                 lam=vec(b.lam), A=mat(b.A), control="yes" if b.control else "no", alpha=mat(kin.alpha[k]))
            for k, b in enumerate(spec.bodies, start=1)]


def _equations(spec, vals: dict, doc: Doc, closed: bool, gens: list, pair_form: bool = False) -> dict:
    """M, Q, Γ, G, Π, Λ̊, W, τ, U and k as printed: closed forms (small n) or the recursion's
    quantities (their definitions listed in the recursion section)."""
    n = spec.n
    if closed:
        lines, grouped = doc.lines, (lambda e: doc.grouped(e, gens))
    else:
        lines = grouped = doc.poly_lines
    if pair_form:  # per joint S^k then z^k (six components each), as _mass_targets lists them
        names = [f"{v}^{{{k + 1}}}_{{{i + 1}}}" for k in range(n) for v in (r"\xi", "z") for i in range(6)]
    else:
        names = [f"M_{{{k + 1}{r + 1}}}" for k in range(n) for r in range(k, n)]
    out = dict(
        M=[TexEquation(lhs, lines(v)) for lhs, v in zip(names, vals["M"])],
        Q=[TexEquation(f"Q_{{{k + 1}}}", grouped(v)) for k, v in enumerate(vals["Q"])],
        Gamma=[TexEquation(rf"\Gamma_{{{k + 1}}}", grouped(v)) for k, v in enumerate(vals["Gamma"])],
        G=[TexEquation(f"G_{{{k + 1}}}", lines(v)) for k, v in enumerate(vals["G"])],
        Pi=[TexEquation(rf"\Pi_{{{k + 1}}}", grouped(v)) for k, v in enumerate(vals["Pi"] or [])],
        Lamdot=[TexEquation(rf"\mathring\Lambda_{{{k + 1}}}", lines(v)) for k, v in enumerate(vals["Lamdot"])],
        Phi=[TexEquation(f"W_{{{k + 1}}}", lines(v)) for k, v in enumerate(vals["Phi"])],
        joint=[TexEquation(rf"\tau_{{{k + 1}}}", lines(v)) for k, v in vals["joint"]],
    )
    counts = ", ".join(f"${sym}$ {sum(eq.lines.terms or 0 for eq in out[key])}" for sym, key in
                       (("M", "M"), ("Q", "Q"), (r"\Gamma", "Gamma"), ("G", "G")))
    blocks = {key: block(eqs) if eqs else None for key, eqs in out.items()}
    U = TexEquation("U", lines(vals["U"]))
    T10 = TexEquation("T_{1} + T_{0}", lines(vals["T10"])) if vals.get("T10") is not None else None
    K = TexEquation(r"\ell", grouped(vals["K"])) if vals["K"] is not None else None
    printed = sum(eq.lines.terms or 0 for key in ("M", "Q", "Gamma", "G") for eq in out[key]) if closed else None
    return dict(blocks, U=U, T10=T10, K=K, term_counts=counts, printed_terms=printed)


def _recursion(kin, doc: Doc, targets: list) -> list:
    """The program's definitions the printed quantities need, in order (long chains)."""
    out = []
    for a, rhs in kin.prog.needed(targets):
        body = doc.poly_lines(rhs) if isinstance(rhs, Poly) else doc.lines(rhs, expand=False)
        out.append(TexEquation(doc.w.name(a.sym), tuple(body)))
    return out


def _quadratures(model: Model, doc: Doc) -> dict | None:
    """J, C, A, U and β of the quadratures (30), when the model has them."""
    if model.quad is None:
        return None
    kin = model.kin
    J, C, A, U2, beta = kin.prog.inline(model.quad.terms, symbolic=True)
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


def _joined(reasons) -> str:
    """The facts' reasons (plain text, as the CLI prints them) in the document: O1, l1 as $O^1$, $l^1$."""
    return re.sub(r"\b([Ol])(\d+)\b", r"$\1^{\2}$", tex_escape("; ".join(reasons)))


def integral_statements(model: Model) -> dict:
    """What the document says of the energy (23) and the momentum (27): from the same facts
    (integrals.Integrals) that set the header's HAS_ENERGY_INTEGRAL, HAS_MOMENTUM_INTEGRAL and
    generate's report; each verdict is one sentence "... is an integral of this model" or "... is
    not an integral of this model: <why>"."""
    spec, facts = model.spec, model.integrals
    extra = ""
    if facts.U_extra:
        springs = [w for w, _ in facts.U_extra if "spring" in w]
        kinds = ([r"for a spring $-\tfrac12\kappa^k(\varphi^k-\varphi^k_{\mathrm{rest}})^2$"] if springs else []) + (
            ["for a constant force fixed in space the force dotted with the position of its point from $O^1$"]
            if len(springs) < len(facts.U_extra) else [])
        extra = (r"$U$ includes the force function of " + ", ".join(tex_escape(w) for w, _ in facts.U_extra)
                 + " (" + "; ".join(kinds) + ").  ")
    if facts.has_energy_integral:
        why = (r"the base is fixed, every $\boldsymbol\lambda^k$ is constant, no control torque acts"
               + (", no joint has a damper or a torque expression, and no load but gravity, springs and constant "
                  "forces fixed in space does work" if spec.general else ", and gravity is the only load"))
        energy = extra + f"The energy (23) is an integral of this model: {why}."
    elif all(r.startswith("control torques") for r in facts.energy_reasons):
        joints = ", ".join(str(k) for k in spec.controls)
        energy = extra + (r"The energy (23) is not an integral of this model for every input: it is conserved when the "
                          rf"control torques vanish ($L^k = 0$), and in general $dE/dt = \sum_k L^k\dot\varphi^k$, over the controlled "
                          rf"joint{'s' if len(spec.controls) > 1 else ''} {joints}.")
    else:
        energy = extra + f"The energy (23) is not an integral of this model: work is done by {_joined(facts.energy_reasons)}."
    K = r"$\hat{\mathbf e}^1_1\cdot\mathbf K_{O^1}$"
    if facts.momentum is None:
        intro = None
        momentum = r"The momentum (27) is not an integral of this model: $\theta^1 \ne 0$, the axis $l^1$ is not vertical."
    elif facts.momentum_condition:
        intro = (rf"Momentum (27), {K}; it is conserved, $= \ell$, only when "
                 rf"the axis $l^1$ is vertical, (25): {tex_escape(facts.momentum_condition)}. The function is")
        momentum = "The momentum (27) is not an integral of this model for every value of its parameters."
    elif facts.has_momentum_integral:
        intro = (r"Momentum (27): the axis $l^1$ is vertical ($\sin\theta^1 = 0$, (25)) and nothing turns the chain "
                 r"about it (no torque, spring or damper in joint 1, no load with a moment about $l^1$"
                 + (", the platform turning about $l^1$ only" if spec.base is not None and spec.base.moves else "")
                 + rf"), so {K} $= \ell$ with")
        momentum = "The momentum (27) is an integral of this model."
    else:
        where = " in the platform" if spec.base is not None else ""
        intro = rf"Momentum (27), {K} (the axis $l^1$ is vertical{where}, $\sin\theta^1 = 0$):"
        momentum = f"The momentum (27) is not an integral of this model: {_joined(facts.momentum_reasons)}."
    return dict(energy_statement=energy, momentum_intro=intro, momentum_statement=momentum)


def _tex(model: Model) -> dict:
    spec, n = model.spec, model.spec.n
    # the general case reads the stages derived with the platform's motion as symbols, as (8)–(10) state it
    stages = model.symbolic if spec.general else model
    kin, dyn = stages.kin, stages.dyn
    ints = model.symbolic.ints if spec.general else model.integrals
    closed = n <= (CLOSED_FORM_MAX_N_GENERAL if spec.general else CLOSED_FORM_MAX_N)
    doc = Doc(writer_for(spec, kin))
    vals = _values(spec, kin, dyn, ints, closed)
    if closed:  # one trigonometric form for the whole document: the shortest over the equations of motion
        doc.choose(vals["M"] + vals["Q"] + vals["Gamma"] + vals["G"] + (vals["Pi"] or []))
    pair_form = dyn.loops is not None
    eqs = _equations(spec, vals, doc, closed, kin.phidot[1:], pair_form)
    recursion = []
    if not closed:
        targets = _mass_targets(dyn, n) + list(dyn.Q) + list(dyn.Gamma) + list(dyn.G)
        targets += [ints.U] + ([ints.momentum] if ints.momentum is not None else [])
        targets += list(dyn.Lamdot) + list(dyn.Phi) + [j for j in dyn.joint if not j.is_zero()]
        recursion = _recursion(kin, doc, targets)
    out = dict(
        general=spec.general,
        moving=spec.base is not None and spec.base.moves,
        gravity=spec.g != 0,
        jacobi=_jacobi(model, doc, closed),
        **integral_statements(model),
        **eqs,
        platform=_platform_rows(kin, doc) if spec.general else None,
        recursion=recursion,
        quad=_quadratures(model, doc),
        bodies=_bodies(spec, kin, doc),
        offsets=[(k, texscene.angle_text(b.offset, doc.w, fold_numbers)) for k, b in enumerate(spec.bodies, start=1)
                 if b.offset != 0],
        scene=texscene.scene(spec, doc.w, fold_numbers),
        form_text=texscene.FORM_TEXT.get(doc.form),
        form_counts=texscene.form_counts(doc.form, doc.counts),
        g=doc.w.sum_text(fold_numbers(spec.g)),
        closed=closed,
        pair_form=pair_form,
        controls=", ".join(f"$L^{{{k}}}$" for k in spec.controls),
        deriv=_derivative_tex(model, stages, doc, eqs["printed_terms"]),
        deriv_generic="d_jvp" in model.lines,
        deriv_world=model.der_form == "world",
        deriv_world_inverse=model.world_columns == "inverse",
        base=base_parameters(model),
        references=[REFERENCES[k] for k in references(model)],
    )
    out["notation"] = texscene.notation(model, out, [doc.w.name(p) for p in spec.params])
    return out


def _coefficient(c) -> str:
    """An exact coefficient as a reviewer reads it: a decimal when it is one (lengths and their
    products), else a fraction; a numerical one as its double."""
    if isinstance(c, sp.Rational):
        q = int(c.q)
        while q % 2 == 0:
            q //= 2
        while q % 5 == 0:
            q //= 5
        if q == 1:
            text = format(sp.Float(abs(c), 30), "f").rstrip("0").rstrip(".")
        else:
            text = rf"\tfrac{{{abs(c.p)}}}{{{c.q}}}"
    else:
        text = f"{abs(float(c)):.15g}"
    return text


def base_parameters(model: Model) -> dict | None:
    """The base parameters' section (generate --regressor): π, and each βᵢ as a formula of it."""
    if model.reg is None:
        return None
    params, base = model.reg.params, model.base
    rows = []
    for i, row in enumerate(base.K):
        text = signed_sum(row, lambda j, c: params[j].tex if c == 1 else rf"{_coefficient(c)}\,{params[j].tex}")
        rows.append((rf"\beta_{{{i + 1}}}", text))
    return dict(
        pi=r",\allowbreak ".join(p.tex for p in params),
        count=len(params),
        nbase=base.count,
        rows=rows,
        numerical=[i + 1 for i, flag in enumerate(base.numerical) if flag],
        damping=any(p.kind == "b" for p in params),
        at=", ".join(f"${param_tex(name)} = {value:g}$" for name, value in base.at),
        rotors=any(p.kind == "lam" for p in params),
    )


# the works a document cites: the paper and the one it builds on always, the others where the
# document uses them (Nikolai's quadratures) or the spec's description names them
REFERENCES = {
    "paper": r"\emph{Sostavnoi prostranstvennyi mayatnik} [The compound spatial pendulum], in a Donetsk collection on rigid-body dynamics.",
    "kharlamov": r"P.~V.~Kharlamov, \emph{On the equations of motion of a system of rigid bodies}, in the same collection as [1].",
    "nikolai": r"E.~L.~Nikolai, \emph{On the motion of a balanced gyroscope in a Cardan suspension}, Prikladnaya Matematika i Mekhanika (PMM) 3(4), 1939.",
    "kapitza": r"P.~L.~Kapitza, \emph{Dynamic stability of a pendulum when its point of suspension vibrates}, Zh. Eksp. Teor. Fiz. 21 (1951) 588--597.",
    "floquet": r"G.~Floquet, \emph{Sur les \'equations diff\'erentielles lin\'eaires \`a coefficients p\'eriodiques}, Ann. Sci. \'Ec. Norm. Sup. 12 (1883) 47--88.",
    "mathieu": r"\'E.~Mathieu, \emph{M\'emoire sur le mouvement vibratoire d'une membrane de forme elliptique}, J. Math. Pures Appl. 13 (1868) 137--203.",
    "ziegler": r"H.~Ziegler, \emph{Die Stabilit\"atskriterien der Elastomechanik}, Ingenieur-Archiv 20 (1952) 49--56.",
}


def references(model: Model) -> list[str]:
    """The keys of REFERENCES this document cites, in the order of their numbers."""
    keys = ["paper", "kharlamov"]
    if model.quad is not None and model.quad.nikolai or "nikolai" in model.spec.description.lower():
        keys.append("nikolai")
    keys += [k for k in ("kapitza", "floquet", "mathieu", "ziegler") if k in model.spec.description.lower()]
    return keys


def source_text(model: Model, context: dict) -> str:
    """Where the document comes from: the paper and the works it builds on, the spec and its
    sha256, the generator's and sympy's versions (the same facts as MANIFEST.json)."""
    spec, cited = model.spec, references(model)
    named = [k for k in cited[2:] if k != "nikolai" or model.quad is None or not model.quad.nikolai]
    nikolai = "nikolai" in cited and model.quad is not None and model.quad.nikolai
    return (rf"Derived from the spec \texttt{{{tex_escape(one_line(context['label']))}}} "
            rf"(sha256 \texttt{{{hashlib.sha256(spec.source.encode('utf-8')).hexdigest()[:16]}}}\dots) by gyrochain "
            rf"{tex_escape(context['gyrochain_version'])} with sympy {tex_escape(context['sympy_version'])}, following the paper "
            r"\emph{The compound spatial pendulum} [1], whose equations of motion build on Kharlamov's [2]"
            + (rf"; the quadratures of the balanced gyroscope follow Nikolai [{cited.index('nikolai') + 1}]" if nikolai else "")
            + (r". The description names " + ", ".join(f"[{cited.index(k) + 1}]" for k in named) if named else "") + ".")


def initial_text(spec) -> str:
    """The spec's [initial] state as the document states it (E and k of the quadratures are its values)."""
    if spec.initial is None:
        return r"The spec gives no initial state (\texttt{[initial]})."
    fmt = lambda v: r",\allowbreak ".join(f"{float(x):.10g}" for x in v)  # noqa: E731  (a long chain's state wraps)
    return (rf"Initial state (\texttt{{[initial]}}): $\varphi = ({fmt(spec.initial['phi'])})$, "
            rf"$\dot\varphi = ({fmt(spec.initial['phidot'])})$.")


class LatexTarget:
    """The document a reviewer reads: the spec, the equations (17)–(19) or (8)–(10), the
    integrals, the quadratures and the derivatives, in the paper's notation."""

    suffixes = (".tex",)

    def files(self, model: Model, context: dict, env) -> dict[str, str]:
        spec = model.spec
        tex = _tex(model)
        tex.update(
            name_tex=tex_escape(spec.name),
            description_tex=texscene.description_tex(one_line(spec.description)),
            sha_tex=hashlib.sha256(spec.source.encode("utf-8")).hexdigest(),
            spec_label_tex=tex_escape(one_line(context["label"])),
            counts_tex=[(tex_escape(k), v) for k, v in sorted(context["counts"].items())],
            has_momentum=tex["K"] is not None,
            source_tex=source_text(model, context),
            initial_tex=initial_text(spec),
            articulated=model.qdd_form == "articulated",
            n=spec.n,
            k_range=r"$k = 1$" if spec.n == 1 else rf"$k = 1,\dots,{spec.n}$",
            # the first lines, a TeX comment: the same words as the C's and Python's
            version=context["version"], spec_label=context["spec_label"], spec_sha=context["spec_sha"],
            regenerate=context["regenerate"],
        )
        return {f"{spec.name}.tex": env.get_template("model.tex.jinja").render(tex)}
