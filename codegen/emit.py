"""Printers and templates: a derived model → {file name: text}.  Writes nothing.

Python makes every decision here; the jinja2 templates in ``templates/`` only lay out strings
that are already printed and loop over them.
"""
from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass
from pathlib import Path

import jinja2
import sympy as sp
from sympy.printing.c import C99CodePrinter
from sympy.printing.latex import LatexPrinter
from sympy.printing.pycode import PythonCodePrinter

from . import __version__, aba, derivatives, quadratures, trigform, world
from .dynamics import Dynamics
from .integrals import Integrals
from .kinematics import Kinematics
from .algebra import Poly
from .exact import Fraction, Surd, is_negative, is_unit, to_float
from .simplify import StraightLine, straight_line
from .spec import T as TIME, ChainSpec

TEMPLATES = Path(__file__).resolve().parent.parent / "templates"


# --------------------------------------------------------------------------- printers
def _literal(value) -> str:
    """A double literal that round-trips: the shortest repr of the nearest double (of an exact
    coefficient: its correctly rounded double, exact.to_float)."""
    text = repr(to_float(value) if isinstance(value, (int, Fraction, Surd)) else float(value))
    return text if any(ch in text for ch in ".en") else text + ".0"


class _NumbersAsDoubles:
    def parenthesize(self, item, level, strict=False):
        # a rational prints as one double literal: it needs no parentheses of a quotient
        if getattr(item, "is_Number", False) and item >= 0:
            return self._print(item)
        return super().parenthesize(item, level, strict)

    def _print_Float(self, expr):
        return _literal(expr)

    def _print_Rational(self, expr):
        return _literal(expr)

    def _print_Integer(self, expr):
        return _literal(expr)

    def _print_Symbol(self, expr):
        return self.names[expr] if expr in self.names else super()._print_Symbol(expr)

    def _pow(self, expr, sqrt: str, inverse: str):
        base, e = expr.base, expr.exp
        b = self.parenthesize(base, sp.printing.precedence.PRECEDENCE["Mul"] + 1)
        if e == 2:
            return f"{b}*{b}"
        if e == 3:
            return f"{b}*{b}*{b}"
        if e == -1:
            return f"{inverse}/{b}"
        if e == -2:
            return f"{inverse}/({b}*{b})"
        if e == sp.Rational(1, 2):
            return f"{sqrt}({self._print(base)})"
        return None


class CPrinter(_NumbersAsDoubles, C99CodePrinter):
    """C99 with the model's names: q[i], x[i], p->name; small integer powers multiplied out."""

    def __init__(self, names: dict):
        super().__init__()
        self.names = names

    def _print_Pow(self, expr):
        return self._pow(expr, "sqrt", "1.0") or super()._print_Pow(expr)


class PyPrinter(_NumbersAsDoubles, PythonCodePrinter):
    def __init__(self, names: dict):
        super().__init__({"fully_qualified_modules": True})
        self.names = names

    def _print_Pow(self, expr, rational=False):
        return self._pow(expr, "math.sqrt", "1.0") or super()._print_Pow(expr, rational)


class NumpyPrinter(PyPrinter):
    """Python on numpy arrays: the functions of φ that the quadratures evaluate at many nodes."""

    def _np(self, expr):
        return f"np.{type(expr).__name__}({self._print(expr.args[0])})"

    _print_sin = _print_cos = _print_tan = _np

    def _print_Pow(self, expr, rational=False):
        return self._pow(expr, "np.sqrt", "1.0") or super()._print_Pow(expr, rational)


# --------------------------------------------------------------------------- prepared data
def poly_code(p: Poly, spell) -> str:
    """A polynomial in C and Python alike (same operators; numbers as round-trip doubles)."""
    if not p.terms:
        return "0.0"
    out = []
    for m, c in p.terms.items():
        v = to_float(c)
        if v == 0.0:  # a Surd that is zero by a relation exact.py does not know
            continue
        factors = [spell(a) for a in m]
        if not m:
            body = _literal(abs(v))
        elif is_unit(c):
            body = "*".join(factors)
        else:
            body = "*".join([_literal(abs(v))] + factors)
        if not out:
            out.append(("-" if v < 0 else "") + body)
        else:
            out.append((" - " if v < 0 else " + ") + body)
    return "".join(out) or "0.0"


@dataclass(frozen=True)
class Function:
    """One emitted function: temporaries and output assignments, already printed."""

    name: str
    temporaries: tuple[tuple[str, str], ...]
    outputs: tuple[tuple[str, str], ...]


def _function(name: str, line: StraightLine, targets: list[str], printer) -> Function:
    names = printer.names

    def spell(a):
        return names.get(a.sym, a.name)

    def code(rhs):
        return poly_code(rhs, spell) if isinstance(rhs, Poly) else printer.doprint(rhs)

    temps = tuple((lhs.name, code(rhs)) for lhs, rhs in line.temporaries)
    outs = tuple((t, code(e)) for t, e in zip(targets, line.outputs))
    return Function(name, temps, outs)


def ldlt_op_count(n: int) -> int:
    """Floating-point operations of the emitted LDLᵀ factorization and solve (unrolled: one
    reciprocal per pivot, products and differences as written)."""
    factor = sum(2 * j + 1 + (n - 1 - j) * (2 * j + 1) for j in range(n))
    solve = 2 * sum(2 * j for j in range(n)) + n
    return factor + solve


@dataclass(frozen=True)
class Model:
    """Everything the generator derived for one spec: inputs of all printers."""

    spec: ChainSpec
    kin: Kinematics
    dyn: Dynamics
    integrals: Integrals
    lines: dict  # name → StraightLine (mass_matrix, forces, qdd, energy, momentum)
    qdd_form: str  # "composite" (M and f, then LDLᵀ) or "articulated" (aba.py: φ̈ and pivots)
    quad: quadratures.TwoBody | None = None  # the integrable two-body case (28)–(30), when it applies
    der: derivatives.Derivatives | derivatives.Tangent | world.World | None = None  # ∂φ̈/∂(φ, φ̇, u)
    der_store: tuple = ()  # the recursion's quantities the columns of ∂φ̈ read (C: the array b)
    der_form: str = "specialised"  # "specialised", "generic" (forward mode) or "world" (world.py)


class FormNotApplicable(ValueError):
    """A forced form that this spec cannot have."""


QDD_FORMS = ("auto", "composite", "articulated")
DER_FORMS = ("auto", "forward", "world")  # NAME_qdd_derivatives: forward mode, or world.py's inverse dynamics


def build_model(spec: ChainSpec, kin: Kinematics, dyn: Dynamics, ints: Integrals, progress=None, qdd_form: str = "auto",
                der_form: str = "auto") -> Model:
    """The straight-line code of every function.  φ̈ is emitted in whichever form costs fewer
    operations for this spec (``qdd_form="auto"``): composite bodies + LDLᵀ (short chains) or
    articulated bodies (long ones); ties go to the composite form.  Its derivatives likewise
    (``der_form="auto"``): the forward mode of the articulated recursion, or the inverse dynamics
    in frame 0 (world.py) where that applies and costs less."""
    if qdd_form not in QDD_FORMS:
        raise ValueError(f"qdd_form must be one of {', '.join(QDD_FORMS)}, not {qdd_form!r}")
    if der_form not in DER_FORMS:
        raise ValueError(f"der_form must be one of {', '.join(DER_FORMS)}, not {der_form!r}")
    if der_form == "world" and not world.applies(spec, kin, dyn):
        raise FormNotApplicable("the world form needs a fixed base, constant rotors and no body loads; this spec has "
                                + ("a moving platform" if kin.platform is not None else "rotors that change" if dyn.Lamdot else "body loads"))
    n = spec.n
    say = progress or (lambda msg: None)
    lower = [dyn.M[i][j] for i in range(n) for j in range(i + 1)]
    lines = {}
    say("straight-line code: mass matrix, forces, qdd, integrals")
    P = kin.prog
    lines["mass_matrix"] = straight_line(P, lower)
    lines["forces"] = straight_line(P, dyn.f)
    composite = straight_line(P, lower + list(dyn.f))
    art = aba.derive(spec, kin, dyn)
    articulated = straight_line(P, list(art.qdd) + list(art.pivots))
    cheaper = articulated.op_count() < composite.op_count() + ldlt_op_count(n)
    if qdd_form == "articulated" or (qdd_form == "auto" and cheaper):
        lines["qdd"], form = articulated, "articulated"
    else:
        lines["qdd"], form = composite, "composite"
    say(f"qdd: {form} form ({articulated.op_count()} ops articulated, {composite.op_count() + ldlt_op_count(n)} composite + LDL^T)")
    lines["energy"] = straight_line(P, [ints.energy])
    if ints.momentum is not None:
        lines["momentum"] = straight_line(P, [ints.momentum])
    if ints.jacobi is not None:
        lines["jacobi"] = straight_line(P, [ints.jacobi])
    quad = quadratures.derive(spec, kin, dyn, ints)
    if quad is not None:
        lines["quad_terms"] = straight_line(P, quad.terms)
    # last, so that the names of everything above do not depend on it; the world form after all
    # the rest (where it applies and is not chosen, the other names stay what they were)
    say("straight-line code: derivatives of qdd")
    use_world = der_form != "forward" and world.applies(spec, kin, dyn)
    forward = None if der_form == "world" else _forward(spec, kin, art, articulated, skip_generic=use_world)
    if forward is not None:
        der_lines = forward[2]
        lines.update(der_lines)
    if canonical_applies(spec, kin, dyn, lines):
        say("straight-line code: momenta p = dL/dphidot and their rate (the symplectic GAUSS2)")
        can = derivatives.canonical(spec, kin, dyn)
        lines["momenta"] = straight_line(P, list(can.p))
        lines["velocity_terms"] = straight_line(P, lower + list(can.k))
        lines["pdot"] = straight_line(P, list(can.pdot))
    chosen = forward
    if use_world:
        w = _world(spec, kin, dyn, art)
        ndir = 2 * n + len(spec.controls)
        line_ops = w[2]["qdd_derivatives"].op_count()
        w_count = world_op_count(n, ndir, line_ops)
        f_count = sum(line.op_count() for line in forward[2].values()) if forward is not None else None
        if f_count is None or line_ops + WORLD_LOOP_WEIGHT * (w_count - line_ops) < f_count:
            for key in forward[2] if forward is not None else ():
                del lines[key]
            lines.update(w[2])
            chosen = w
        say(f"derivatives: world form {w_count} ops" + (f", forward mode {f_count}" if f_count is not None else ""))
    der, store, _, form_d = chosen
    say(f"derivatives: {form_d} form")
    return Model(spec, kin, dyn, ints, lines, form, quad, der, store, der_form=form_d)


def _forward(spec, kin, art, articulated: StraightLine, skip_generic: bool) -> tuple:
    """(der, store, lines, form) of the forward mode: one specialised function per column, or past
    SPECIALISED_MAX_OPS one generic tangent called per column (not derived when
    ``skip_generic``: the world form will be used).  None when nothing was derived."""
    n = spec.n
    P = kin.prog
    lines: dict = {"qdd_derivatives": articulated}
    ndir = 2 * n + len(spec.controls)
    base = [a for a, _ in P.needed(list(art.qdd) + list(art.pivots))]
    have = frozenset(base)
    # the specialised columns cost about 0.1–0.6 of the recursion per direction: past 4× the budget
    # by that estimate they are not derived at all (n = 32 would take minutes of Python)
    if articulated.op_count() * ndir <= 4 * SPECIALISED_MAX_OPS:
        used: set = set()
        der = derivatives.derive(spec, kin, art)
        for j, label in enumerate(der.labels):
            line = straight_line(P, [der.dqdd[k][j] for k in range(n)], prefix=f"w{label}_", have=have)
            lines[f"d_{label}"] = line
            used |= _reads(P, line) & have
        if sum(lines[f"d_{lab}"].op_count() for lab in der.labels) <= SPECIALISED_MAX_OPS:
            return der, tuple(a for a in base if a in used), lines, "specialised"
    if skip_generic:
        return None
    der = derivatives.derive_tangent(spec, kin, art)
    lines = {"qdd_derivatives": articulated, "d_jvp": straight_line(P, list(der.jvp), prefix="wt", have=have)}
    used = _reads(P, lines["d_jvp"]) & have
    return der, tuple(a for a in base if a in used), lines, "generic"


def _world(spec, kin, dyn, art) -> tuple:
    """(der, store, lines, form) of the world form: φ̈ and world.py's per-joint vectors in one
    straight line; the pairs and the solve are loops of the template."""
    P = kin.prog
    der = world.derive(spec, kin, dyn, art)
    outs = [c for name in world.VECTORS for v in der.vec[name] for c in v] + [d for _, _, d in der.ext]
    return der, (), {"qdd_derivatives": straight_line(P, list(art.qdd) + list(art.pivots) + outs)}, "world"


# An operation of the world form's loops (6-dots of arrays, the LDLᵀ solve) costs about twice one of
# straight-line code (measured with gcc -O2: arm7 4.3 µs world vs 4.0 µs forward mode at op counts
# 10.6k vs 13.6k; random spatial chain n = 8 5.5 µs vs 9.1 µs); the choice weighs them so.
WORLD_LOOP_WEIGHT = 2


def world_op_count(n: int, ndir: int, line_ops: int) -> int:
    """Operations of the world form: its straight line, then in loops the 6-dots of M's lower
    triangle and of ∂ID (two per pair below the diagonal, one on and above it, for φ and φ̇),
    the LDLᵀ factorization and the solve with every column."""
    below, upper = n * (n - 1) // 2, n * (n + 1) // 2
    pairs = 11 * upper + 2 * (24 * below + 11 * upper)
    factor = sum(2 * j * (n - j) + 2 * j for j in range(n))
    solve = ndir * (2 * n * (n - 1) + n)
    return line_ops + pairs + factor + solve


def canonical_applies(spec: ChainSpec, kin: Kinematics, dyn: Dynamics, lines: dict) -> bool:
    """Whether the model gets Hamilton's variables (NAME_momenta, NAME_velocities, NAME_pdot and
    NAME_GAUSS2_SYMPLECTIC): a fixed base, every λ constant and nothing that reads t, so that
    p = M φ̇ + k(φ) and the flow in (φ, p) is autonomous."""
    return kin.platform is None and not dyn.Lamdot and not any(reads_time(lines[k]) for k in ("forces", "qdd"))


# Above this many operations in all the specialised columns of ∂φ̈ together (about n = 10 for a
# spatial gyrostat chain), NAME_qdd_derivatives uses one generic tangent function called per column
# instead: exact all the same, ~2n times less code to compile, at most a few times the run time.
SPECIALISED_MAX_OPS = 60000


def _reads(P, line: StraightLine) -> set:
    """The program quantities a straight-line section reads."""
    from .program import Var

    out: set = set()
    for _, rhs in line.temporaries:
        if isinstance(rhs, Poly):
            out.update(rhs.atoms())
        else:
            out.update(P._by_name[s.name] for s in rhs.free_symbols if isinstance(s, Var) and s.name in P._by_name)
    for o in line.outputs:
        out.update(o.atoms())
    return out


GAUSS2_NEWTON_MAX_N = 16  # GAUSS2's Newton matrix is 2n × 2n on the stack: 8 KB at n = 16


def _newton_sweeps(n: int, counts: dict) -> int:
    """A simplified Newton solve of GAUSS2's stages in fixed-point sweeps (2 rhs each): the
    Jacobian, the LU of the 2n × 2n matrix (⅔(2n)³ flops) and ~3 iterations of 2 rhs."""
    rhs = max(1, counts["qdd"])
    setup = (counts.get("qdd_derivatives", 0) + 2 * (2 * n) ** 3 // 3) / rhs
    return int(round(setup / 2 + 3))


def _newton_sweeps_canonical(n: int, counts: dict) -> int:
    """The same for GAUSS2_SYMPLECTIC: 2n + 1 canonical evaluations for the Jacobian by differences,
    the LU of the 4n × 4n matrix and ~4 iterations, in sweeps of 2 canonical evaluations."""
    g = max(1, counts.get("velocities", 0) + counts.get("pdot", 0))
    setup = ((2 * n + 1) * g + 2 * (4 * n) ** 3 // 3) / g
    return int(round(setup / 2 + 4))


# NAME_qdd_derivatives: φ̈ by the articulated recursion (line "qdd_derivatives"), then one column of
# ∂φ̈ per direction (lines "d_q1" …), each its own static C function reading the recursion's values
# it needs from an array: a Jacobian of a long chain is too big for one function (gcc's time grows
# faster than its length); a block whose output is NULL is not computed.
BLOCK_OF_KIND = {"q": "dqdd_dphi", "v": "dqdd_dphidot", "u": "dqdd_du"}


def reads_time(line: StraightLine) -> bool:
    """Whether a straight-line program reads t (a prescribed motion, λ(t), a load of t)."""
    for _, rhs in line.temporaries:
        if isinstance(rhs, Poly):
            if any(a.sym == TIME for a in rhs.atoms()):
                return True
        elif rhs.has(TIME):
            return True
    return any(a.sym == TIME for o in line.outputs for a in o.atoms())


def time_dependent(model: Model) -> bool:
    """Whether any emitted function of the state needs t (then all of them but NAME_mass_matrix
    and NAME_jacobi take it, first; the header says so with NAME_TIME_DEPENDENT 1)."""
    return any(reads_time(model.lines[k]) for k in ("forces", "qdd", "energy", "momentum") if k in model.lines)


def _names(model: Model, style: str) -> dict:
    """How each symbol is spelled in C ('c') or Python ('py')."""
    spec, kin = model.spec, model.kin
    n = spec.n
    names = {TIME: "t"}
    for k in range(1, n + 1):
        names[kin.phi[k]] = f"x[{k - 1}]"
        names[kin.phidot[k]] = f"x[{n + k - 1}]"
        names[kin.torque[k]] = f"tau_{k}"
    for prm in spec.params:
        names[prm] = f"p->{prm}" if style == "c" else f"p_{prm}"
    return names


def _with_q(names: dict, kin: Kinematics) -> dict:
    out = dict(names)
    for k in range(1, kin.n + 1):
        out[kin.phi[k]] = f"q[{k - 1}]"
    return out


def op_counts(model: Model) -> dict[str, int]:
    """Op count of each emitted function (multiplications, additions and function calls of the
    straight-line code; the qdd and rhs counts include the unrolled LDLᵀ solve)."""
    n = model.spec.n
    blocks = ["qdd_derivatives", "d_jvp"] + ([f"d_{lab}" for lab in model.der.labels] if model.der else [])
    counts = {name: line.op_count() for name, line in model.lines.items() if name not in blocks}
    if model.qdd_form == "composite":
        counts["qdd"] += ldlt_op_count(n)
    counts["rhs"] = counts["qdd"]
    if "velocity_terms" in counts:  # M and k, then φ̇ = M⁻¹(p − k) by LDLᵀ
        counts["velocities"] = counts.pop("velocity_terms") + ldlt_op_count(n) + n
    if model.der is not None:
        # φ̈ by the articulated recursion, then every block of derivatives
        if model.der_form == "world":  # the straight line, then the loops
            ndir = 2 * n + len(model.spec.controls)
            counts["qdd_derivatives"] = world_op_count(n, ndir, model.lines["qdd_derivatives"].op_count())
        elif "d_jvp" in model.lines:  # run-time count: the tangent once per column
            cols = len(model.der.labels) * model.lines["d_jvp"].op_count()
            counts["qdd_derivatives"] = model.lines["qdd_derivatives"].op_count() + cols
        else:
            counts["qdd_derivatives"] = sum(model.lines[b].op_count() for b in blocks if b in model.lines)
        counts["linearize"] = counts["qdd_derivatives"]
    return counts


def _functions(model: Model, printer_cls, style: str) -> dict[str, Function]:
    spec = model.spec
    n = spec.n
    names = _names(model, style)
    pr = printer_cls(names)
    prq = printer_cls(_with_q(names, model.kin))
    lower = [f"M[{i * n + j}]" for i in range(n) for j in range(i + 1)]
    if style == "py":
        lower = [f"M[{i}, {j}]" for i in range(n) for j in range(i + 1)]
    if model.qdd_form == "composite":
        qdd_targets = lower + [f"f[{k}]" for k in range(n)]
    else:
        qdd_targets = [f"acc[{k}]" for k in range(n)] + [f"piv[{k}]" for k in range(n)]
    fs = {
        "mass_matrix": _function("mass_matrix", model.lines["mass_matrix"], lower, prq),
        "forces": _function("forces", model.lines["forces"], [f"f[{k}]" for k in range(n)], pr),
        "qdd": _function("qdd", model.lines["qdd"], qdd_targets, pr),
        "energy": _function("energy", model.lines["energy"], ["result"], pr),
    }
    if "momentum" in model.lines:
        fs["momentum"] = _function("momentum", model.lines["momentum"], ["result"], pr)
    if "jacobi" in model.lines:
        fs["jacobi"] = _function("jacobi", model.lines["jacobi"], ["result"], pr)
    if model.der_form == "world":
        acc = [f"acc[{k}]" for k in range(n)] + [f"piv[{k}]" for k in range(n)]
        if style == "c":
            vecs = [f"{name}_[{6 * k + i}]" for name in world.VECTORS for k in range(n) for i in range(6)]
        else:
            vecs = [f"{name}_[{k}, {i}]" for name in world.VECTORS for k in range(n) for i in range(6)]
        ext = [f"ext[{i}]" for i in range(len(model.der.ext))]
        fs["qdd_derivatives"] = _function("qdd_derivatives", model.lines["qdd_derivatives"], acc + vecs + ext, pr)
    elif model.der is not None:
        acc = [f"acc[{k}]" for k in range(n)] + [f"piv[{k}]" for k in range(n)]
        fs["qdd_derivatives"] = _function("qdd_derivatives", model.lines["qdd_derivatives"], acc, pr)
        # C: a column function reads the recursion's values from b[]; Python: they are locals
        prb = printer_cls({**names, **{a.sym: f"b[{i}]" for i, a in enumerate(model.der_store)}}) if style == "c" else pr
        if "d_jvp" in model.lines:
            prb.names.update({d: f"d[{i}]" for i, d in enumerate(model.der.dirs)})
            fs["d_jvp"] = _function("d_jvp", model.lines["d_jvp"], [f"col[{i}]" for i in range(n)], prb)
        for j, label in enumerate(model.der.labels if "d_jvp" not in model.lines else ()):
            key = BLOCK_OF_KIND[label[0]]
            col = int(label[1:]) - 1
            targets = [f"col[{i}]" for i in range(n)] if style == "c" else [f"{key}[{i}, {col}]" for i in range(n)]
            fs[f"d_{label}"] = _function(f"d_{label}", model.lines[f"d_{label}"], targets, prb)
    if "momenta" in model.lines:
        fs["momenta"] = _function("momenta", model.lines["momenta"], [f"pm[{k}]" for k in range(n)], pr)
        fs["velocity_terms"] = _function("velocity_terms", model.lines["velocity_terms"],
                                         lower + [f"k[{i}]" for i in range(n)], prq)
        fs["pdot"] = _function("pdot", model.lines["pdot"], [f"pdot[{k}]" for k in range(n)], pr)
    if "quad_terms" in model.lines:
        # a function of φ = φ² alone (ψ = φ¹ is cyclic); in Python on numpy arrays of φ
        qnames = {**names, model.kin.phi[2]: "phi"}
        qpr = (NumpyPrinter if style == "py" else printer_cls)(qnames)
        fs["quad_terms"] = _function("quad_terms", model.lines["quad_terms"], [f"out[{i}]" for i in range(5)], qpr)
    return fs


# --------------------------------------------------------------------------- LaTeX
def fold_numbers(expr: sp.Expr) -> sp.Expr:
    """Evaluate every subexpression made of numbers only (sqrt(3)/2, cos(3/10), …) to a Float."""
    if expr.is_Atom:
        return expr
    if expr.is_number:
        return sp.Float(expr.evalf(30), 30)
    args = [fold_numbers(a) for a in expr.args]
    return expr.func(*args) if any(a is not b for a, b in zip(args, expr.args)) else expr


def _latex_names(model: Model, kin: Kinematics | None = None) -> dict:
    kin = kin or model.kin
    names = {}
    from .kinematics import platform_symbols

    tex = {"omega": r"\omega^{0}", "epsilon": r"\varepsilon^{0}", "vdot": r"\dot v_{0", "gamma": r"\gamma^{0}"}
    for key, syms in platform_symbols().items():
        for i, sym in enumerate(syms, start=1):
            names[sym] = f"{tex[key]},{i}}}" if key == "vdot" else f"{tex[key]}_{{{i}}}"
    for a, _ in kin.prog.defs:
        names[a.sym] = kin.prog.tex.get(a.sym) or r"\mathrm{" + _tex_escape(a.name) + "}"
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
        if len(body) == 1:
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


def _general_tex_on(model: Model, kin, pr, closed: bool, lines, grouped) -> dict:
    """The LaTeX of the general case: the platform's motion, the platform terms Π_k apart, λ̊, the
    loads' generalized forces and the joint torques, from the derivation ``kin`` made again with
    ω⁰, ε⁰, v̇₀, γ⁰ as symbols (kinematics.derive(symbolic_platform=True))."""
    from . import dynamics, kinematics

    spec = model.spec
    dyn = dynamics.derive(spec, kin)
    rest = None
    pm = kin.platform
    sy = kinematics.platform_symbols()
    platform = set(sy["omega"] + sy["epsilon"] + sy["vdot"])
    n = spec.n
    out = dict(platform=None, Pi=None, Lamdot=None, Phi=None, joint=None)
    if pm is not None:
        rows = []
        for key, vals in (("omega", pm.omega), ("epsilon", pm.eps), ("vdot", pm.acc), ("gamma", pm.down)):
            for sym, v in zip(sy[key], vals):
                rows.append(TexEquation(pr.doprint(sym), _tex_lines(sp.sympify(v), pr, 200, expand=False)))
        out["platform"] = rows
        if closed:
            Pi, rest = [], ([], [])
            for k in range(n):
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
    out["kin"], out["dyn"], out["rest"] = kin, dyn, rest  # rest: Q_k, Γ_k without the platform terms
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


def _tex(model: Model) -> dict:
    spec, kin, dyn, ints = model.spec, model.kin, model.dyn, model.integrals
    n = spec.n
    general = None
    if spec.general:
        closed = n <= CLOSED_FORM_MAX_N_GENERAL
        from . import integrals as _i, kinematics as _k
        kin_s = _k.derive(spec, symbolic_platform=True)
        pr = TexPrinter(_latex_names(model, kin_s))
        grouped_ = (lambda e: _grouped(e, kin_s.phidot[1:], pr)) if closed else (lambda e: Shown.of(_poly_tex_lines(e, pr)))
        lines_ = (lambda e: _tex_lines(e, pr)) if closed else (lambda e: Shown.of(_poly_tex_lines(e, pr)))
        general = _general_tex_on(model, kin_s, pr, closed, lines_, grouped_)
        kin, dyn = general["kin"], general["dyn"]
        ints = _i.derive(spec, kin, dyn)
    else:
        pr = TexPrinter(_latex_names(model))
    phidots = kin.phidot[1:]

    def mat(m):
        m = m.tolist() if isinstance(m, sp.MatrixBase) else m
        rows = [" & ".join(pr.doprint(_display(sp.sympify(x))) for x in row) for row in m]
        return r"\begin{pmatrix}" + r" \\ ".join(rows) + r"\end{pmatrix}"

    def vec(v):
        return r"\begin{pmatrix}" + r" \\ ".join(pr.doprint(_display(x)) for x in v) + r"\end{pmatrix}"

    bodies = []
    for k, b in enumerate(spec.bodies, start=1):
        bodies.append(
            dict(
                k=k,
                theta=pr.doprint(b.theta),
                m=pr.doprint(_display(b.m)),
                c=vec(b.c),
                s=vec(b.s) if k < n else "--",
                lam=vec(b.lam),
                A=mat(b.A),
                control="yes" if b.control else "no",
                alpha=mat(kin.alpha[k]),
            )
        )
    targets = [dyn.M[k][r] for k in range(n) for r in range(k, n)]
    targets += list(dyn.Q) + list(dyn.Gamma) + list(dyn.G) + [ints.U]
    if ints.momentum is not None:
        targets.append(ints.momentum)
    closed = n <= (CLOSED_FORM_MAX_N_GENERAL if general else CLOSED_FORM_MAX_N)
    recursion = []
    extra = []
    if general:
        extra = list(dyn.Lamdot) + list(dyn.Phi) + [j for j in dyn.joint if not j.is_zero()]
    if closed:
        values = iter(kin.prog.inline(targets, symbolic=True))
        lines, grouped = (lambda e: _tex_lines(e, pr)), (lambda e: _grouped(e, phidots, pr))
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
    quad = None
    if model.quad is not None:
        J, C, A, U2, beta = kin.prog.inline(model.quad.terms, symbolic=True)
        quad = dict(
            J=tuple(_tex_lines(J, pr)), C=tuple(_tex_lines(C, pr)), A=tuple(_tex_lines(A, pr)),
            U=tuple(_tex_lines(U2, pr)), beta=tuple(_tex_lines(beta, pr)), nikolai=model.quad.nikolai,
            U_const=not (U2.free_symbols & {kin.phi[2]}),
        )
    deriv = _derivative_tex(model, pr) if n <= DERIVATIVE_TEX_MAX_N else None
    gen = dict(platform=None, Pi=None, Lamdot=None, Phi=None, joint=None)
    if general:
        gen = {k: general[k] for k in gen}
    ints_model = model.integrals
    return dict(
        general=spec.general,
        moving=kin.platform is not None,
        energy_reasons=_tex_escape("; ".join(ints_model.energy_reasons)),
        jacobi=ints_model.jacobi is not None,
        U_extra=[_tex_escape(w) for w, _ in ints_model.U_extra],
        **gen,
        quad=quad,
        momentum_condition=_tex_escape(ints.momentum_condition) if ints.momentum_condition else None,
        bodies=bodies,
        g=pr.doprint(_display(spec.g)),
        params=", ".join(f"${pr.doprint(p)}$" for p in spec.params),
        M=M,
        Q=Q,
        Gamma=Gam,
        G=G,
        term_counts=term_counts,
        U=U,
        K=K,
        closed=closed,
        recursion=recursion,
        controls=", ".join(f"$L^{{{k}}}$" for k in spec.controls),
        deriv=deriv,
        deriv_generic="d_jvp" in model.lines,
        deriv_world=model.der_form == "world",
    )


# --------------------------------------------------------------------------- render
def _env() -> jinja2.Environment:
    return jinja2.Environment(
        loader=jinja2.FileSystemLoader(str(TEMPLATES)),
        undefined=jinja2.StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
        keep_trailing_newline=True,
        autoescape=False,
    )


def _tex_escape(text: str) -> str:
    out = []
    for ch in text:
        if ch in "\\":
            out.append(r"\textbackslash{}")
        elif ch in "&%$#_{}":
            out.append("\\" + ch)
        elif ch == "~":
            out.append(r"\textasciitilde{}")
        elif ch == "^":
            out.append(r"\textasciicircum{}")
        elif ord(ch) < 128:
            out.append(ch)
        else:
            out.append("?")  # pdflatex without inputenc extras: keep the document compiling
    return "".join(out)


def _one_line(text: str) -> str:
    return " ".join(text.split())


def _c_comment(text: str) -> str:
    """Spec text inside a C block comment: one line, no comment delimiters, printable ASCII."""
    text = _one_line(text).replace("*/", "* /").replace("/*", "/ *").replace("??", "? ?")  # no trigraphs
    return "".join(ch if 32 <= ord(ch) < 127 else "?" for ch in text)


def _py_docstring(text: str) -> str:
    """Spec text inside a Python triple-quoted docstring."""
    return _one_line(text).replace("\\", "\\\\").replace('"', '\\"')


def render(model: Model, spec_label: str, tex: bool = True) -> dict[str, str]:
    """All emitted files of one model, by file name (tex=False: the C, header, cdef and Python
    only, without the LaTeX and the manifest; the LaTeX's canonical forms are most of the time)."""
    spec = model.spec
    name, n = spec.name, spec.n
    upper = name.upper()
    counts = op_counts(model)
    cfun = _functions(model, CPrinter, "c")
    pyfun = _functions(model, PyPrinter, "py")
    controls = [(i, k) for i, k in enumerate(spec.controls)]
    ctx = dict(
        name=name,
        NAME=upper,
        n=n,
        nn=n * n,
        spec_label=_c_comment(spec_label),
        description=_c_comment(spec.description),
        spec_label_py=_py_docstring(spec_label),
        description_py=_py_docstring(spec.description),
        params=[str(p) for p in spec.params],
        controls=controls,
        has_params=bool(spec.params),
        has_controls=bool(spec.controls),
        has_momentum="momentum" in cfun,
        general=spec.general,
        time_dependent=time_dependent(model),
        has_jacobi="jacobi" in cfun,
        canonical="momenta" in cfun,
        articulated=model.qdd_form == "articulated",
        has_energy_integral=int(model.integrals.has_energy_integral),
        has_momentum_integral=int(model.integrals.has_momentum_integral),
        momentum_condition=model.integrals.momentum_condition and _c_comment(model.integrals.momentum_condition).replace('"', "'"),
        quad=model.quad is not None,
        fn=cfun,
        py=pyfun,
        der_store=[a.name for a in model.der_store],
        der_dirs=[(lab, lab[0], int(lab[1:]) - 1, j) for j, lab in enumerate(model.der.labels)] if model.der else [],
        der_generic="d_jvp" in model.lines,
        der_world=model.der_form == "world",
        world_vectors=world.VECTORS,
        world_ext=[(k, c, i) for i, (k, c, _) in enumerate(model.der.ext)] if model.der_form == "world" else [],
        newton=n <= GAUSS2_NEWTON_MAX_N,
        newton_sweeps=_newton_sweeps(n, counts),
        newton_sweeps_canonical=_newton_sweeps_canonical(n, counts),
        counts=counts,
        codegen_version=__version__,
        sympy_version=sp.__version__,
    )
    env = _env()
    decls = env.get_template("_decls.jinja").render(ctx)
    ctx["decls"] = decls
    files = {
        f"{name}.h": env.get_template("model.h.jinja").render(ctx),
        f"{name}.c": env.get_template("model.c.jinja").render(ctx),
        f"{name}.cdef": env.get_template("model.cdef.jinja").render(ctx),
        f"{name}.py": env.get_template("model.py.jinja").render(ctx),
    }
    if not tex:
        return files
    tex = _tex(model)
    tex.update(
        name_tex=_tex_escape(name),
        description_tex=_tex_escape(_one_line(spec.description)),
        spec_label_tex=_tex_escape(_one_line(spec_label)),
        counts_tex=[(_tex_escape(k), v) for k, v in sorted(counts.items())],
        has_momentum=tex["K"] is not None,
        articulated=model.qdd_form == "articulated",
        n=n,
    )
    files[f"{name}.tex"] = env.get_template("model.tex.jinja").render(tex)
    manifest = dict(
        spec=spec_label,
        spec_sha256=hashlib.sha256(spec.source.encode("utf-8")).hexdigest(),
        codegen=__version__,
        sympy=sp.__version__,
        op_counts=counts,
        files={k: hashlib.sha256(v.encode("utf-8")).hexdigest() for k, v in sorted(files.items())},
    )
    files["MANIFEST.json"] = json.dumps(manifest, indent=2, sort_keys=True) + "\n"
    return files
