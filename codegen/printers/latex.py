"""The LaTeX target: the document a reviewer reads, in the paper's notation.

Closed forms (small n) are reduced exactly to their shortest canonical trigonometric form
(trigform.py) and printed term by term; long chains show the recursion's quantities in order.
Numbers print to 10 significant digits (the C and Python carry full precision).
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp
from sympy.printing.latex import LatexPrinter

from .. import trigform
from ..algebra import Poly
from ..assemble import Model
from ..exact import is_negative, is_unit, to_float
from ..kinematics import Kinematics, platform_symbols
from .common import one_line, tex_escape


def fold_numbers(expr: sp.Expr) -> sp.Expr:
    """Evaluate every subexpression made of numbers only (sqrt(3)/2, cos(3/10), …) to a Float."""
    if expr.is_Atom:
        return expr
    if expr.is_number:
        return sp.Float(expr.evalf(30), 30)
    args = [fold_numbers(a) for a in expr.args]
    return expr.func(*args) if any(a is not b for a, b in zip(args, expr.args)) else expr


def _latex_names(kin: Kinematics, upto: int | None = None) -> dict:
    """How each symbol prints: the platform's ω⁰, ε⁰, v̇₀, γ⁰, the program's quantities (the
    first ``upto`` definitions), c_k, s_k, φᵏ, φ̇ᵏ and the torques Lᵏ."""
    names = {}
    tex = {"omega": r"\omega^{0}", "epsilon": r"\varepsilon^{0}", "vdot": r"\dot v_{0", "gamma": r"\gamma^{0}"}
    for key, syms in platform_symbols().items():
        for i, sym in enumerate(syms, start=1):
            names[sym] = f"{tex[key]},{i}}}" if key == "vdot" else f"{tex[key]}_{{{i}}}"
    for a, _ in kin.prog.defs[:upto]:
        names[a.sym] = kin.prog.tex.get(a.sym) or r"\mathrm{" + tex_escape(a.name) + "}"
    for k in range(1, kin.n + 1):
        names[_abbrev(sp.cos, kin.phi[k])] = rf"\mathrm{{c}}_{{{k}}}"
        names[_abbrev(sp.sin, kin.phi[k])] = rf"\mathrm{{s}}_{{{k}}}"
        names[kin.phi[k]] = rf"\varphi^{{{k}}}"
        names[kin.phidot[k]] = rf"\dot\varphi^{{{k}}}"
        names[kin.torque[k]] = rf"L^{{{k}}}"
    return names


class TexPrinter(LatexPrinter):
    def __init__(self, names):
        super().__init__({"symbol_names": names, "full_prec": False, "mul_symbol": None})


def _display(expr: sp.Expr) -> sp.Expr:
    """Numbers to 10 significant digits for reading (the C and Python carry full precision)."""
    expr = fold_numbers(expr)
    reps = {a: sp.Float(a, 10) for a in expr.atoms(sp.Rational, sp.Float) if not a.is_Integer}
    return expr.xreplace(reps)


MAX_LATEX_TERMS = 400
CLOSED_FORM_MAX_N = 3  # above this the LaTeX shows the recursion instead of expanded closed forms


class Shown(tuple):
    """Printed lines of one quantity, with the canonical trigonometric form they are in
    (trigform.py: "c", "s", "f", or None) and the number of terms."""

    form: str | None = None
    terms: int | None = None

    @staticmethod
    def of(lines, form=None, terms=None) -> "Shown":
        out = Shown(lines)
        out.form, out.terms = form, terms
        return out


def _angles(expr: sp.Expr) -> list:
    """The joint angles φᵏ whose cos or sin the expression has, in order."""
    found = {a.args[0] for a in expr.atoms(sp.cos, sp.sin) if a.args[0].is_Symbol and a.args[0].name.startswith("phi_")}
    return sorted(found, key=lambda s: int(s.name[4:]))


def _canonical(expr: sp.Expr) -> trigform.Canonical:
    return trigform.canonical(expr, _angles(expr))


def _abbrev(f, phi: sp.Symbol) -> sp.Symbol:
    """The LaTeX abbreviation c_k = cos φᵏ, s_k = sin φᵏ."""
    return sp.Symbol(f"{f.__name__}_{phi.name}", real=True)


def _abbreviate(expr: sp.Expr) -> sp.Expr:
    reps = {a: _abbrev(type(a), a.args[0]) for a in expr.atoms(sp.sin, sp.cos) if a.args[0].is_Symbol}
    return expr.xreplace(reps)


def _tex_number(c) -> str:
    text = f"{abs(to_float(c)):.10g}"
    if "e" in text:
        mant, exp = text.split("e")
        text = rf"{mant} \cdot 10^{{{int(exp)}}}"
    return text


def _break(pieces: list[str], width: int) -> list[str]:
    """Signed terms joined into lines of about ``width`` characters."""
    lines, cur = [], ""
    for t in pieces:
        piece = t if not cur else (f" {t}" if t.startswith("-") else f" + {t}")
        if cur and len(cur) + len(piece) > width:
            lines.append(cur)
            cur = t if t.startswith("-") else f"+ {t}"
        else:
            cur += piece
    lines.append(cur)
    return lines


def _poly_tex_lines(p: Poly, pr: TexPrinter, width: int = 260) -> list[str]:
    """A polynomial of the program as it stands (no expansion), printed without sympy: the
    recursion listing of a long chain has thousands of these."""
    if not p.terms:
        return ["0"]
    names = pr._settings["symbol_names"]
    pieces = []
    for m, c in p.terms.items():
        factors, i = [], 0
        while i < len(m):
            j = i
            while j < len(m) and m[j] is m[i]:
                j += 1
            name = names.get(m[i].sym) or pr.doprint(m[i].sym)
            factors.append(name if j - i == 1 else f"{{{name}}}^{{{j - i}}}")
            i = j
        body = " ".join(factors)
        if not m or not is_unit(c):
            body = _tex_number(c) + (r" \, " + body if body else "")
        pieces.append(("-" if is_negative(c) else "") + body)
    return _break(pieces, width)


def _tex_lines(expr: sp.Expr, pr: TexPrinter, width: int = 260, expand: bool = True) -> Shown:
    """A sum printed term by term and broken into lines: expanded into its canonical
    trigonometric form with the fewest terms (trigform.py), or as it is (``expand=False``)."""
    form = count = None
    if expand:
        can = _canonical(expr)
        expr, form, count = can.expr, can.form, can.terms
    return Shown.of(_sum_lines(_display(_abbreviate(expr)), pr, width), form, count)


def _sum_lines(expr: sp.Expr, pr: TexPrinter, width: int) -> list[str]:
    if expr == 0:
        return ["0"]
    terms = sp.Add.make_args(expr)
    if len(terms) > MAX_LATEX_TERMS:
        return [rf"\text{{({len(terms)} terms when expanded; not shown)}}"]
    lines, cur = [], ""
    for term in sorted(terms, key=sp.default_sort_key):
        t = pr.doprint(term)
        piece = t if not cur else (f" {t}" if t.startswith("-") else f" + {t}")
        if cur and len(cur) + len(piece) > width:
            lines.append(cur)
            piece = t if t.startswith("-") else f"+ {t}"
            cur = piece
        else:
            cur += piece
    lines.append(cur)
    return lines


def _grouped(expr: sp.Expr, gens: list, pr: TexPrinter) -> Shown:
    """Collect an expression by monomials of φ̇ (the paper's coefficient · φ̇ʰφ̇ʳ layout), in its
    canonical trigonometric form with the fewest terms."""
    can = _canonical(expr)
    groups: dict = {}
    for term in sp.Add.make_args(can.expr):
        coeff, mono = term.as_independent(*gens, as_Add=False)
        groups[mono] = groups.get(mono, 0) + coeff
    out = []
    for mono in sorted(groups, key=lambda m: (sp.Poly(m, *gens).monoms()[0][::-1] if m != 1 else ())):
        body = _sum_lines(_display(_abbreviate(groups[mono])), pr, 220)
        if body == ["0"]:
            continue
        factor = "" if mono == 1 else pr.doprint(mono)
        plus = "+ " if out else ""
        single = len(sp.Add.make_args(groups[mono])) == 1
        if single and factor:  # one term: its sign is the line's, no brackets ("- s_2 φ̇¹φ̇²", not "+ (-s_2) φ̇¹φ̇²")
            sign, text = ("-", body[0][1:].lstrip()) if body[0].startswith("-") else ("+", body[0])
            lead = ("- " if sign == "-" else "+ ") if out else ("-" if sign == "-" else "")
            out.append(lead + (factor if text == "1" else rf"{text} \, {factor}"))
        elif len(body) == 1:
            out.append(plus + (rf"\left({body[0]}\right){factor}" if factor else body[0]))
        else:
            out.append(plus + r"\Big(" + body[0])
            out.extend(body[1:-1])
            out.append(body[-1] + rf"\Big){factor}")
    return Shown.of(out or ["0"], can.form, can.terms)


@dataclass(frozen=True)
class TexEquation:
    lhs: str
    lines: tuple[str, ...]  # a Shown when the quantity was expanded

    @property
    def form(self) -> str | None:
        return getattr(self.lines, "form", None)


CLOSED_FORM_MAX_N_GENERAL = 2  # the same for a spec with platform motion or loads (more symbols)


def _split_platform(prog, p: Poly, platform: set) -> tuple[sp.Expr, sp.Expr]:
    """A closed form split into the terms without and with ω⁰, ε⁰, v̇₀ (the grouping of (8)–(10))."""
    (full,) = prog.inline_poly([p])
    rest = Poly({m: c for m, c in full.terms.items() if not any(a.sym in platform for a in m)})
    plat = Poly({m: c for m, c in full.terms.items() if any(a.sym in platform for a in m)})
    return rest.to_sympy(prog.sympy_of, symbolic=True), plat.to_sympy(prog.sympy_of, symbolic=True)


def _general_tex(model: Model, pr, closed: bool, lines, grouped) -> dict:
    """The LaTeX of the general case: the platform's motion, the platform terms Π_k apart, λ̊, the
    loads' generalized forces and the joint torques, from the model's stages derived with ω⁰,
    ε⁰, v̇₀, γ⁰ as symbols (``model.symbolic``)."""
    kin, dyn = model.symbolic.kin, model.symbolic.dyn
    rest = None
    pm = kin.platform
    sy = platform_symbols()
    platform = set(sy["omega"] + sy["epsilon"] + sy["vdot"])
    out = dict(platform=None, Pi=None, Lamdot=None, Phi=None, joint=None)
    if pm is not None:
        rows = []
        for key, vals in (("omega", pm.omega), ("epsilon", pm.eps), ("vdot", pm.acc), ("gamma", pm.down)):
            for sym, v in zip(sy[key], vals):
                rows.append(TexEquation(pr.doprint(sym), _tex_lines(sp.sympify(v), pr, 200, expand=False)))
        out["platform"] = rows
        if closed:
            Pi, rest = [], ([], [])
            for k in range(model.spec.n):
                rq, pq = _split_platform(kin.prog, dyn.Q[k], platform)
                rg, pg = _split_platform(kin.prog, dyn.Gamma[k], platform)
                rest[0].append(rq)
                rest[1].append(rg)
                Pi.append(TexEquation(rf"\Pi_{{{k + 1}}}", grouped(pq + pg)))
            out["Pi"] = Pi
    if dyn.Lamdot:
        out["Lamdot"] = [TexEquation(rf"\mathring\Lambda_{{{k + 1}}}", lines(e)) for k, e in enumerate(_vals(kin, dyn.Lamdot, closed))]
    if dyn.Phi:
        out["Phi"] = [TexEquation(rf"\Phi_{{{k + 1}}}", lines(e)) for k, e in enumerate(_vals(kin, dyn.Phi, closed))]
    if dyn.joint:
        out["joint"] = [TexEquation(rf"\tau_{{{k + 1}}}", lines(e)) for k, e in enumerate(_vals(kin, dyn.joint, closed))
                        if not dyn.joint[k].is_zero()]
    out["rest"] = rest  # Q_k, Γ_k without the platform terms
    return out


DERIVATIVE_TEX_MAX_N = 2  # closed forms of the derivatives in the LaTeX up to this n


def _derivative_tex(model: Model, pr) -> list:
    """∂R/∂φʲ and ∂R/∂φ̇ʲ of R = M φ̈ − f (closed forms, φ̈ as symbols): with them
    ∂φ̈/∂x = −M⁻¹ ∂R/∂x, the implicit derivative of (17)–(19) that the emitted code computes."""
    kin, dyn, n = model.kin, model.dyn, model.spec.n
    names = pr._settings["symbol_names"]
    acc = [sp.Symbol(f"qddot_{k}") for k in range(1, n + 1)]
    for k, a in enumerate(acc, start=1):
        names[a] = rf"\ddot\varphi^{{{k}}}"
    vals = kin.prog.inline([dyn.M[i][j] for i in range(n) for j in range(n)] + list(dyn.f), symbolic=True)
    M = [vals[i * n:(i + 1) * n] for i in range(n)]
    R = [sum((M[i][j] * acc[j] for j in range(n)), sp.Integer(0)) - vals[n * n + i] for i in range(n)]
    out = []
    for kind, syms, tex in (("q", kin.phi, r"\varphi"), ("v", kin.phidot, r"\dot\varphi")):
        for j in range(1, n + 1):
            for i in range(n):
                d = sp.diff(R[i], syms[j])
                out.append(TexEquation(rf"\frac{{\partial R_{{{i + 1}}}}}{{\partial {tex}^{{{j}}}}}", _tex_lines(d, pr)))
    return out


def _vals(kin, polys, closed: bool) -> list:
    return kin.prog.inline(polys, symbolic=True) if closed else list(polys)


def _bodies(spec, kin, pr) -> list[dict]:
    """The spec's table: θᵏ, mᵏ, cᵏ, sᵏ, λᵏ, Aᵏ, the control flag and the direction cosines αᵏ."""

    def mat(m):
        m = m.tolist() if isinstance(m, sp.MatrixBase) else m
        rows = [" & ".join(pr.doprint(_display(sp.sympify(x))) for x in row) for row in m]
        return r"\begin{pmatrix}" + r" \\ ".join(rows) + r"\end{pmatrix}"

    def vec(v):
        return r"\begin{pmatrix}" + r" \\ ".join(pr.doprint(_display(x)) for x in v) + r"\end{pmatrix}"

    return [dict(k=k, theta=pr.doprint(b.theta), m=pr.doprint(_display(b.m)), c=vec(b.c),
                 s=vec(b.s) if k < spec.n else r"\text{---}",
                 lam=vec(b.lam), A=mat(b.A), control="yes" if b.control else "no", alpha=mat(kin.alpha[k]))
            for k, b in enumerate(spec.bodies, start=1)]


def _equations(spec, kin, dyn, ints, pr, closed: bool, general: dict | None) -> dict:
    """M, Q, Γ, G, U and k: closed forms (small n) or the recursion's quantities listed in order."""
    n = spec.n
    targets = [dyn.M[k][r] for k in range(n) for r in range(k, n)]
    targets += list(dyn.Q) + list(dyn.Gamma) + list(dyn.G) + [ints.U]
    if ints.momentum is not None:
        targets.append(ints.momentum)
    recursion = []
    extra = list(dyn.Lamdot) + list(dyn.Phi) + [j for j in dyn.joint if not j.is_zero()] if general else []
    if closed:
        values = iter(kin.prog.inline(targets, symbolic=True))
        lines, grouped = (lambda e: _tex_lines(e, pr)), (lambda e: _grouped(e, kin.phidot[1:], pr))
    else:
        values = iter(targets)
        lines = grouped = (lambda e: Shown.of(_poly_tex_lines(e, pr)))
        for a, rhs in kin.prog.needed(targets + extra):
            body = _poly_tex_lines(rhs, pr) if isinstance(rhs, Poly) else _tex_lines(rhs, pr, expand=False)
            recursion.append(TexEquation(pr.doprint(a.sym), tuple(body)))
    M = [TexEquation(f"M_{{{k + 1}{r + 1}}}", lines(next(values))) for k in range(n) for r in range(k, n)]
    Qv, Gv = [next(values) for _ in range(n)], [next(values) for _ in range(n)]
    if general and general["rest"] is not None:  # the platform terms are shown apart, as Π_k
        Qv, Gv = general["rest"]
    Q = [TexEquation(f"Q_{{{k + 1}}}", grouped(v)) for k, v in enumerate(Qv)]
    Gam = [TexEquation(rf"\Gamma_{{{k + 1}}}", grouped(v)) for k, v in enumerate(Gv)]
    G = [TexEquation(f"G_{{{k + 1}}}", lines(next(values))) for k in range(n)]
    U = TexEquation("U", lines(next(values)))
    K = TexEquation("k", grouped(next(values))) if ints.momentum is not None else None
    term_counts = ", ".join(f"${sym}$ {sum(eq.lines.terms or 0 for eq in eqs)}" for sym, eqs in
                            (("M", M), ("Q", Q), (r"\Gamma", Gam), ("G", G)))
    return dict(M=M, Q=Q, Gamma=Gam, G=G, U=U, K=K, term_counts=term_counts, recursion=recursion)


def _quadratures(model: Model, pr) -> dict | None:
    """J, C, A, U and β of the quadratures (30), when the model has them."""
    if model.quad is None:
        return None
    kin = model.kin
    J, C, A, U2, beta = kin.prog.inline(model.quad.terms, symbolic=True)
    return dict(J=tuple(_tex_lines(J, pr)), C=tuple(_tex_lines(C, pr)), A=tuple(_tex_lines(A, pr)),
                U=tuple(_tex_lines(U2, pr)), beta=tuple(_tex_lines(beta, pr)), nikolai=model.quad.nikolai,
                U_const=not (U2.free_symbols & {kin.phi[2]}))


def _joined(reasons) -> str:
    return tex_escape("; ".join(reasons))


def integral_statements(model: Model) -> dict:
    """What the document says of the energy (23) and the momentum (27): from the same facts
    (integrals.Integrals) that set the header's HAS_ENERGY_INTEGRAL, HAS_MOMENTUM_INTEGRAL and
    generate's report; each verdict is one sentence "... is an integral of this model" or "... is
    not an integral of this model: <why>"."""
    spec, facts = model.spec, model.integrals
    extra = ""
    if facts.U_extra:
        extra = (r"$U$ includes the force function of " + ", ".join(tex_escape(w) for w, _ in facts.U_extra)
                 + r" (springs: $-\tfrac12 k(\varphi-\varphi_0)^2$; constant fixed forces: $\mathbf F\cdot\mathbf r_P$).  ")
    if facts.has_energy_integral:
        why = ("no load but gravity, springs and constant fixed forces does work" if spec.general
               else r"the base is fixed, every $\boldsymbol\lambda^k$ is constant and no control torque acts")
        energy = extra + f"The energy (23) is an integral of this model: {why}."
    else:
        energy = extra + f"The energy (23) is not an integral of this model: work is done by {_joined(facts.energy_reasons)}."
    K = r"$\hat{\mathbf e}^1_1\cdot\mathbf K_{O^1}$"
    if facts.momentum is None:
        intro = None
        momentum = r"The momentum (27) is not an integral of this model: $\theta^1 \ne 0$, the axis $l^1$ is not vertical."
    elif facts.momentum_condition:
        intro = (rf"Momentum (27), $\partial\mathcal L/\partial\dot\varphi^1 = $ {K}; it is conserved, $= k$, only when "
                 rf"the axis $l^1$ is vertical, (25): {tex_escape(facts.momentum_condition)}. The function is")
        momentum = "The momentum (27) is not an integral of this model for every value of its parameters."
    elif facts.has_momentum_integral:
        intro = (r"Momentum (27): the axis $l^1$ is vertical ($\sin\theta^1 = 0$, (25)) and nothing turns the chain "
                 r"about it (no torque, spring or damper in joint 1, no load with a moment about $l^1$"
                 + (", the platform turning about $l^1$ only" if spec.base is not None and spec.base.moves else "")
                 + rf"), so {K} $= k$ with")
        momentum = "The momentum (27) is an integral of this model."
    else:
        intro = rf"Momentum (27), {K} (the axis $l^1$ is vertical in the platform, $\sin\theta^1 = 0$):"
        momentum = f"The momentum (27) is not an integral of this model: {_joined(facts.momentum_reasons)}."
    return dict(energy_statement=energy, momentum_intro=intro, momentum_statement=momentum)


def _tex(model: Model) -> dict:
    spec, n = model.spec, model.spec.n
    general = None
    if spec.general:  # the equations as (8)–(10) state them: from the stages with a symbolic platform
        kin, dyn, ints = model.symbolic.kin, model.symbolic.dyn, model.symbolic.ints
        closed = n <= CLOSED_FORM_MAX_N_GENERAL
        pr = TexPrinter(_latex_names(kin, model.symbolic.kin_defs))
        grouped_ = (lambda e: _grouped(e, kin.phidot[1:], pr)) if closed else (lambda e: Shown.of(_poly_tex_lines(e, pr)))
        lines_ = (lambda e: _tex_lines(e, pr)) if closed else (lambda e: Shown.of(_poly_tex_lines(e, pr)))
        general = _general_tex(model, pr, closed, lines_, grouped_)
    else:
        kin, dyn, ints = model.kin, model.dyn, model.integrals
        closed = n <= CLOSED_FORM_MAX_N
        pr = TexPrinter(_latex_names(kin))
    gen = {k: general[k] if general else None for k in ("platform", "Pi", "Lamdot", "Phi", "joint")}
    facts = model.integrals
    return dict(
        general=spec.general,
        moving=kin.platform is not None,
        jacobi=facts.jacobi is not None,
        **integral_statements(model),
        **gen,
        **_equations(spec, kin, dyn, ints, pr, closed, general),
        quad=_quadratures(model, pr),
        bodies=_bodies(spec, kin, pr),
        g=pr.doprint(_display(spec.g)),
        params=", ".join(f"${pr.doprint(p)}$" for p in spec.params),
        closed=closed,
        controls=", ".join(f"$L^{{{k}}}$" for k in spec.controls),
        deriv=_derivative_tex(model, pr) if n <= DERIVATIVE_TEX_MAX_N else None,
        deriv_generic="d_jvp" in model.lines,
        deriv_world=model.der_form == "world",
    )


def source_text(model: Model, context: dict) -> str:
    """Where the document comes from: the paper and the works it builds on, the spec and its
    sha256, the generator's and sympy's versions (the same facts as MANIFEST.json)."""
    import hashlib

    spec = model.spec
    nikolai = model.quad is not None and model.quad.nikolai
    return (rf"Derived from the spec \texttt{{{tex_escape(one_line(context['label']))}}} "
            rf"(sha256 \texttt{{{hashlib.sha256(spec.source.encode('utf-8')).hexdigest()[:16]}}}\dots) by gyrochain "
            rf"{tex_escape(context['codegen_version'])} with sympy {tex_escape(context['sympy_version'])}, following the paper "
            r"\emph{The compound spatial pendulum} (a Donetsk collection on rigid-body dynamics), whose equations of motion "
            r"build on P.~V.~Kharlamov, \emph{On the equations of motion of a system of rigid bodies}"
            + (r"; the quadratures of the balanced gyroscope follow E.~L.~Nikolai, \emph{On the motion of a balanced "
               r"gyroscope in a Cardan suspension}, PMM 3(4), 1939" if nikolai else "") + ".")


def initial_text(spec) -> str:
    """The spec's [initial] state as the document states it (E and k of the quadratures are its values)."""
    if spec.initial is None:
        return r"The spec gives no initial state (\texttt{[initial]})."
    fmt = lambda v: ", ".join(f"{float(x):.10g}" for x in v)  # noqa: E731
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
            description_tex=tex_escape(one_line(spec.description)),
            spec_label_tex=tex_escape(one_line(context["label"])),
            counts_tex=[(tex_escape(k), v) for k, v in sorted(context["counts"].items())],
            has_momentum=tex["K"] is not None,
            source_tex=source_text(model, context),
            initial_tex=initial_text(spec),
            articulated=model.qdd_form == "articulated",
            n=spec.n,
        )
        return {f"{spec.name}.tex": env.get_template("model.tex.jinja").render(tex)}
