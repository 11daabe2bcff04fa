"""What the C and Python printers share: numbers as round-trip double literals, polynomials
printed without sympy, the emitted functions (``Function``: temporaries and outputs, printed),
the symbols' spellings, and spec text made safe for comments and docstrings."""
from __future__ import annotations

import functools
from dataclasses import dataclass
from pathlib import Path

import jinja2
import sympy as sp

from .. import TEMPLATES
from ..derive import world
from ..derive.algebra import Poly
from ..derive.assemble import Model
from ..derive.exact import Fraction, Surd, is_unit, to_float
from ..derive.kinematics import Kinematics
from ..chainspec.spec import T as TIME
from ..derive.straightline import StraightLine



def literal(value) -> str:
    """A double literal that round-trips: the shortest repr of the nearest double (of an exact
    coefficient: its correctly rounded double, exact.to_float)."""
    text = repr(to_float(value) if isinstance(value, (int, Fraction, Surd)) else float(value))
    return text if any(ch in text for ch in ".en") else text + ".0"


class NumbersAsDoubles:
    """Mixed into the C and Python printers: every number one double literal that round-trips."""

    def parenthesize(self, item, level, strict=False):
        # a rational prints as one double literal: it needs no parentheses of a quotient
        if getattr(item, "is_Number", False) and item >= 0:
            return self._print(item)
        return super().parenthesize(item, level, strict)

    def _print(self, expr, **kwargs):
        # a constant that is not a rational (π/4 of an offset, √2 of an expression: the C and Python
        # printers' own spellings M_PI_4, M_SQRT2 and math.pi are not C99's, nor the spec's folded
        # numbers) is its correctly rounded double
        if isinstance(expr, sp.Expr) and not expr.is_Number and expr.is_number and expr.is_extended_real:
            return literal(sp.N(expr, 40))
        return super()._print(expr, **kwargs)

    def _print_Float(self, expr):
        return literal(expr)

    def _print_Rational(self, expr):
        return literal(expr)

    def _print_Integer(self, expr):
        return literal(expr)

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
            body = literal(abs(v))
        elif is_unit(c):
            body = "*".join(factors)
        else:
            body = "*".join([literal(abs(v))] + factors)
        if not out:
            out.append(("-" if v < 0 else "") + body)
        else:
            out.append((" - " if v < 0 else " + ") + body)
    return "".join(out) or "0.0"


def signed_sum(row, term) -> str:
    """Σ cⱼ xⱼ over ``row`` = ((j, cⱼ), ...) with the signs written as operators: ``term(j, c)``
    spells c xⱼ for c > 0 (C, Python, the LaTeX and the command's table alike)."""
    out = []
    for j, c in row:
        neg = float(c) < 0
        text = term(j, -c if neg else c)
        out.append(("-" if neg else "") + text if not out else (" - " if neg else " + ") + text)
    return "".join(out)


@dataclass(frozen=True)
class Function:
    """One emitted function: temporaries and output assignments, already printed."""

    name: str
    temporaries: tuple[tuple[str, str], ...]
    outputs: tuple[tuple[str, str], ...]
    # the names of the temporaries each temporary and each output reads (printers/chunks.py)
    reads: tuple = ()
    out_reads: tuple = ()
    pre: tuple = ()  # C statements before the temporaries (the calls of a long function's parts)


def function_of(name: str, line: StraightLine, targets: list[str], printer) -> Function:
    names = printer.names

    def spell(a):
        return names.get(a.sym, a.name)

    def code(rhs):
        return poly_code(rhs, spell) if isinstance(rhs, Poly) else printer.doprint(rhs)

    temps = tuple((lhs.name, code(rhs)) for lhs, rhs in line.temporaries)
    outs = tuple((t, code(e)) for t, e in zip(targets, line.outputs))
    own = {lhs.name for lhs, _ in line.temporaries}

    def reads(rhs):
        found = [a.name for a in rhs.atoms()] if isinstance(rhs, Poly) else [s.name for s in rhs.free_symbols]
        return tuple(sorted(set(found) & own))

    return Function(name, temps, outs, tuple(reads(rhs) for _, rhs in line.temporaries),
                    tuple(reads(e) for e in line.outputs))


# NAME_qdd_derivatives: φ̈ by the articulated recursion (line "qdd_derivatives"), then one column of
# ∂φ̈ per direction (lines "d_q1" …), each its own static C function reading the recursion's values
# it needs from an array: a Jacobian of a long chain is too big for one function (gcc's time grows
# faster than its length); a block whose output is NULL is not computed.
BLOCK_OF_KIND = {"q": "dqdd_dphi", "v": "dqdd_dphidot", "u": "dqdd_du"}


def spellings(model: Model, style: str) -> dict:
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


def with_q(names: dict, kin: Kinematics) -> dict:
    out = dict(names)
    for k in range(1, kin.n + 1):
        out[kin.phi[k]] = f"q[{k - 1}]"
    return out



def functions(model: Model, printer_cls, style: str, array_printer_cls=None) -> dict[str, Function]:
    spec = model.spec
    n = spec.n
    names = spellings(model, style)
    pr = printer_cls(names)
    prq = printer_cls(with_q(names, model.kin))
    lower = [f"M[{i * n + j}]" for i in range(n) for j in range(i + 1)]
    if style == "py":
        lower = [f"M[{i}, {j}]" for i in range(n) for j in range(i + 1)]
    if model.qdd_form == "composite":
        qdd_targets = lower + [f"f[{k}]" for k in range(n)]
    else:
        qdd_targets = [f"acc[{k}]" for k in range(n)] + [f"piv[{k}]" for k in range(n)]
    if model.dyn.loops is not None:  # the loop form: per joint S and z1 into arrays, the pairs in loops
        if style == "c":
            axes = [f"{v}_[{6 * k + i}]" for v in ("S", "z1") for k in range(n) for i in range(6)]
        else:
            axes = [f"{v}_[{k}, {i}]" for v in ("S", "z1") for k in range(n) for i in range(6)]
    fs = {
        "mass_matrix": function_of("mass_matrix", model.lines["mass_matrix"], axes if model.dyn.loops else lower, prq),
        "forces": function_of("forces", model.lines["forces"], [f"f[{k}]" for k in range(n)], pr),
        "qdd": function_of("qdd", model.lines["qdd"], qdd_targets, pr),
        "energy": function_of("energy", model.lines["energy"], ["result"], pr),
    }
    if "momentum" in model.lines:
        fs["momentum"] = function_of("momentum", model.lines["momentum"], ["result"], pr)
    if "jacobi" in model.lines:
        fs["jacobi"] = function_of("jacobi", model.lines["jacobi"], ["result"], pr)
    if model.der_form == "world":
        rhs = [f"acc[{k}]" for k in range(n)]  # τ − ID(φ, φ̇, 0), solved for φ̈ in place
        if style == "c":
            vecs = [f"{name}_[{6 * k + i}]" for name in world.VECTORS for k in range(n) for i in range(6)]
            vecs += [f"IC_[{world.IC_PARTS * k + i}]" for k in range(n) for i in range(world.IC_PARTS)]
        else:
            vecs = [f"{name}_[{k}, {i}]" for name in world.VECTORS for k in range(n) for i in range(6)]
            vecs += [f"IC_[{k}, {i}]" for k in range(n) for i in range(world.IC_PARTS)]
        ext = [f"ext[{i}]" for i in range(len(model.der.ext))]
        fs["qdd_derivatives"] = function_of("qdd_derivatives", model.lines["qdd_derivatives"], rhs + vecs + ext, pr)
    elif model.der is not None:
        acc = [f"acc[{k}]" for k in range(n)] + [f"piv[{k}]" for k in range(n)]
        fs["qdd_derivatives"] = function_of("qdd_derivatives", model.lines["qdd_derivatives"], acc, pr)
        # C: a column function reads the recursion's values from b[]; Python: they are locals
        prb = printer_cls({**names, **{a.sym: f"b[{i}]" for i, a in enumerate(model.der_store)}}) if style == "c" else pr
        if "d_jvp" in model.lines:
            prb.names.update({d: f"d[{i}]" for i, d in enumerate(model.der.dirs)})
            fs["d_jvp"] = function_of("d_jvp", model.lines["d_jvp"], [f"col[{i}]" for i in range(n)], prb)
        for j, label in enumerate(model.der.labels if "d_jvp" not in model.lines else ()):
            key = BLOCK_OF_KIND[label[0]]
            col = int(label[1:]) - 1
            targets = [f"col[{i}]" for i in range(n)] if style == "c" else [f"{key}[{i}, {col}]" for i in range(n)]
            fs[f"d_{label}"] = function_of(f"d_{label}", model.lines[f"d_{label}"], targets, prb)
    if "momenta" in model.lines:
        fs["momenta"] = function_of("momenta", model.lines["momenta"], [f"pm[{k}]" for k in range(n)], pr)
        fs["velocity_terms"] = function_of("velocity_terms", model.lines["velocity_terms"],
                                         ([] if model.dyn.loops else lower) + [f"k[{i}]" for i in range(n)], prq)
        fs["pdot"] = function_of("pdot", model.lines["pdot"], [f"pdot[{k}]" for k in range(n)], pr)
    if model.reg is not None:
        fs.update(_regressor_functions(model, printer_cls, names, style))
    if model.pder is not None:  # φ̈, then ∂φ̈/∂p row-major n × np into dp
        rec = [f"acc[{k}]" for k in range(n)] + [f"piv[{k}]" for k in range(n)]
        fs["param_derivatives"] = function_of("param_derivatives", model.lines["param_derivatives"],
                                              rec + [f"dp[{i}]" for i in range(n * len(model.pder.params))], pr)
    if model.tder:  # φ̈, then ∂φ̈/∂t into dp
        rec = [f"acc[{k}]" for k in range(n)] + [f"piv[{k}]" for k in range(n)]
        fs["time_derivative"] = function_of("time_derivative", model.lines["time_derivative"],
                                            rec + [f"dp[{i}]" for i in range(n)], pr)
    if model.hess is not None and style == "c":  # (the weights μ are lam's second half: lam . f)
        prh = printer_cls({**names, **{m: f"lam[{n + k}]" for k, m in enumerate(model.hess.mu)}})
        targets = [f"acc[{k}]" for k in range(n)] + [f"piv[{k}]" for k in range(n)]
        fs["rhs_hessian"] = function_of("rhs_hessian", model.lines["rhs_hessian"],
                                        targets + [f"hv[{k}]" for k in range(len(model.hess.upper))], prh)
    if "quad_terms" in model.lines:
        # a function of φ = φ² alone (ψ = φ¹ is cyclic); in Python on numpy arrays of φ
        qnames = {**names, model.kin.phi[2]: "phi"}
        qpr = (array_printer_cls or printer_cls)(qnames)
        fs["quad_terms"] = function_of("quad_terms", model.lines["quad_terms"], [f"out[{i}]" for i in range(5)], qpr)
    return fs



def _regressor_functions(model: Model, printer_cls, names: dict, style: str) -> dict[str, Function]:
    """NAME_regressor, NAME_base_regressor, NAME_energy_regressor and NAME_standard_parameters:
    φ, φ̇, φ̈ in their own arrays; Y row-major n × len(π) (C) or an n × len(π) array (Python)."""
    reg, kin, n = model.reg, model.kin, model.spec.n
    own = dict(names)
    for k in range(1, n + 1):
        own[kin.phi[k]], own[kin.phidot[k]], own[reg.phidd[k]] = f"phi[{k - 1}]", f"phidot[{k - 1}]", f"phidd[{k - 1}]"
    pr = printer_cls(own)

    def matrix(name: str, cols: int) -> list[str]:
        return [f"{name}[{i * cols + j}]" if style == "c" else f"{name}[{i}, {j}]" for i in range(n) for j in range(cols)]

    npi, nb = len(reg.params), model.base.count
    tau0 = [f"t0_[{k}]" for k in range(n)]
    return {
        "regressor": function_of("regressor", model.lines["regressor"], matrix("Y", npi) + tau0, pr),
        "base_regressor": function_of("base_regressor", model.lines["base_regressor"], matrix("Yb", nb) + tau0, pr),
        "energy_regressor": function_of("energy_regressor", model.lines["energy_regressor"],
                                        [f"h[{j}]" for j in range(npi)] + ["e0_"], pr),
        "standard_parameters": function_of("standard_parameters", model.lines["standard_parameters"],
                                           [f"pi[{j}]" for j in range(npi)], pr),
    }


def environment(compiled: Path | None = None) -> jinja2.Environment:
    """The templates' environment, one per process and folder: jinja2 compiles a template once per
    environment (model.c.jinja took about half a second), and reloads one whose file changed.
    ``compiled``: a private folder where compiled templates are kept for the next process (the
    pipeline passes one in the user's build cache); a kept one is used only while its template's
    text is the same."""
    return _environment(str(TEMPLATES), None if compiled is None else str(compiled))


@functools.lru_cache(maxsize=4)
def _environment(folder: str, compiled: str | None) -> jinja2.Environment:
    return jinja2.Environment(
        loader=jinja2.FileSystemLoader(folder),
        bytecode_cache=None if compiled is None else jinja2.FileSystemBytecodeCache(compiled),
        undefined=jinja2.StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
        keep_trailing_newline=True,
        autoescape=False,
    )



# ASCII that the default (OT1) text font has no glyph for: pdflatex would print "¿" for ">"
_TEX_TEXT = {"<": r"\textless{}", ">": r"\textgreater{}", "|": r"\textbar{}"}


def tex_escape(text: str) -> str:
    """Spec text as LaTeX text: the special characters escaped, the ASCII that OT1 lacks spelled
    by name, anything else as "?" (pdflatex without inputenc extras: the document compiles)."""
    out = []
    for ch in text:
        if ch in _TEX_TEXT:
            out.append(_TEX_TEXT[ch])
        elif ch in "\\":
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


def one_line(text: str) -> str:
    return " ".join(text.split())


def c_comment(text: str) -> str:
    """Spec text inside a C block comment: one line, no comment delimiters, printable ASCII."""
    text = one_line(text).replace("*/", "* /").replace("/*", "/ *").replace("??", "? ?")  # no trigraphs
    return "".join(ch if 32 <= ord(ch) < 127 else "?" for ch in text)


def build_text(text: str) -> str:
    """Spec text in a CMake comment or a pkg-config field: one line of printable ASCII without the
    characters CMake's configure_file or pkg-config would expand (@, $) or a shell quotes."""
    return "".join(ch if 32 <= ord(ch) < 127 and ch not in "@$`\\\"" else "?" for ch in one_line(text))


def py_docstring(text: str) -> str:
    """Spec text inside a Python triple-quoted docstring."""
    return one_line(text).replace("\\", "\\\\").replace('"', '\\"')


