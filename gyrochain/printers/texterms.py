"""Formulas as the LaTeX prints them, one term at a time, in one small grammar.

A sum is printed term by term: the sign as subtraction, the number first (a decimal as the spec
wrote it, an exact fraction as a fraction, anything else to 10 significant digits), then the
factors in a natural order: parameters, time functions and the platform's quantities, the
functions of the joint angles in increasing index (cos before sin), the velocities, the
accelerations and the torques.  cos φᵏ prints as \\cos\\varphi^{k} (the paper's c and s are the
centre-of-mass and offset vectors, so no abbreviation is used).

The grammar is small on purpose: tests/models/test_latex_roundtrip.py reads every printed formula
back and evaluates it against the emitted C.  It is

    sum     := ["-"] term (("+" | "-") term)*
    term    := [number] factor*  |  "\\frac{" sum "}{" sum "}"
    number  := digits ["." digits] [" \\cdot 10^{" int "}"]  |  "\\frac{" int "}{" int "}"
    factor  := name ["^{" int "}"]  |  "\\left(" name "\\right)^{" int "}"  |  "\\left(" sum "\\right)" ["^{" int "}"]
             | func ["^{" int "}"] "(" sum ")"  |  func \\varphi^{k}  |  "\\sqrt{" sum "}"

with the names of the document's notation table.
"""
from __future__ import annotations

import functools
import re
from fractions import Fraction

import sympy as sp

from ..derive.exact import Surd, to_float
from .common import tex_escape

FUNCTIONS = {sp.cos: r"\cos", sp.sin: r"\sin", sp.tan: r"\tan", sp.exp: r"\exp", sp.log: r"\log",
             sp.sinh: r"\sinh", sp.cosh: r"\cosh", sp.tanh: r"\tanh", sp.asin: r"\arcsin",
             sp.acos: r"\arccos", sp.atan: r"\arctan"}
SIGNIFICANT = 10  # digits of a number that is not a short decimal or a small fraction
FRACTION_MAX = 10_000  # an exact rational prints as a fraction when numerator and denominator are below this


def _terminating(q: Fraction) -> bool:
    d = q.denominator
    for p in (2, 5):
        while d % p == 0:
            d //= p
    return d == 1


def number_text(value) -> str:
    """A positive number as the document prints it: an integer or a terminating decimal exactly
    (0.4 stays 0.4), a small exact fraction as \\frac{p}{q}, anything else to 10 significant digits."""
    if isinstance(value, sp.Rational):
        value = Fraction(int(value.p), int(value.q))
    elif isinstance(value, sp.Float):
        value = float(value)
    if isinstance(value, int):
        value = Fraction(value)
    if isinstance(value, Fraction):
        if value.denominator == 1:
            return str(value.numerator)
        if _terminating(value):
            text = _decimal(value)
            if len(text.replace("0.", "").lstrip("0")) <= 12:
                return text
        elif value.numerator < FRACTION_MAX and value.denominator < FRACTION_MAX:
            return rf"\frac{{{value.numerator}}}{{{value.denominator}}}"
        value = float(value)
    if isinstance(value, Surd):
        value = to_float(value)
    text = f"{float(value):.{SIGNIFICANT}g}"
    if "e" in text:
        mant, exp = text.split("e")
        return rf"{mant} \cdot 10^{{{int(exp)}}}"
    return text


def _decimal(q: Fraction) -> str:
    """A terminating fraction as its exact decimal."""
    digits = 0
    while (q * 10 ** digits).denominator != 1:
        digits += 1
    whole = q * 10 ** digits
    text = str(int(whole)).rjust(digits + 1, "0")
    return text[:-digits] + "." + text[-digits:]


@functools.lru_cache(maxsize=4096)
def _text(base: sp.Expr) -> str:
    """sympy's text of a factor (its sort key among functions of time and angles), printed once."""
    return str(base)


class TexWriter:
    """Prints sympy expressions of the LaTeX target in the grammar above.

    ``names``: symbol → its TeX name; ``rank``: symbol → (group, index) for the factor order
    (symbols not in it are parameters, ordered by name)."""

    PARAMETER, TIME, PLATFORM, ANGLE, VELOCITY, ACCELERATION, TORQUE, QUANTITY = range(1, 9)

    def __init__(self, names: dict, rank: dict, angles: dict):
        self.names, self.rank, self.angles = names, rank, angles  # angles: φ symbol → k

    # ---- factors
    def name(self, sym: sp.Symbol) -> str:
        return self.names.get(sym) or sym.name

    def _key(self, base) -> tuple:
        """(group, indices, cos 0 / sin 1, text): every key has this shape, so any two compare."""
        if isinstance(base, sp.Symbol):
            group, index = self.rank.get(base, (self.PARAMETER, 0))
            return (group, (index,), 0, base.name)
        if isinstance(base, (sp.cos, sp.sin)) and base.free_symbols & set(self.angles):
            ks = sorted(self.angles[s] for s in base.args[0].free_symbols if s in self.angles)
            return (self.ANGLE, tuple(ks), 0 if isinstance(base, sp.cos) else 1, _text(base))
        return (self.TIME, (0,), 1, _text(base))

    def _angle_of(self, arg) -> str | None:
        """\\varphi^{k} when the argument is a joint angle itself."""
        if isinstance(arg, sp.Symbol) and arg in self.angles:
            return self.name(arg)
        return None

    def _turned(self, base) -> bool:
        """cos or sin of a combination of angles whose first angle (lowest index) has a negative
        multiple: printed of the negated combination, so that cos(φ¹ − φ² − φ³) is not cos(−φ¹ + φ² + φ³)."""
        if not isinstance(base, (sp.cos, sp.sin)) or not isinstance(base.args[0], sp.Add):
            return False
        lead = [(self.angles[s], t) for t in sp.Add.make_args(base.args[0]) for s in t.free_symbols if s in self.angles]
        return bool(lead) and min(lead, key=lambda kt: kt[0])[1].could_extract_minus_sign()

    def factor(self, base, e: int) -> str:
        pw = "" if e == 1 else f"^{{{e}}}"
        if base is sp.pi:
            return rf"\pi{pw}"
        if self._turned(base):
            return rf"{FUNCTIONS[type(base)]}{pw}\left({self.sum_text(-base.args[0])}\right)"
        if isinstance(base, sp.Symbol):
            text = self.name(base)
            if not pw:
                return text
            return rf"\left({text}\right){pw}" if "^" in text else f"{text}{pw}"
        if isinstance(base, sp.Function) and type(base) in FUNCTIONS:
            fn = FUNCTIONS[type(base)]
            angle = self._angle_of(base.args[0])
            if angle is not None:  # (cos φ²)², not cos² φ², whose upper index reads as a power
                return rf"\left({fn}{angle}\right){pw}" if pw else f"{fn}{angle}"
            return rf"{fn}{pw}\left({self.sum_text(base.args[0])}\right)"
        if isinstance(base, sp.Pow) and base.exp == sp.Rational(1, 2):
            return rf"\sqrt{{{self.sum_text(base.base)}}}" + (rf"^{{{e}}}" if e != 1 else "")
        if isinstance(base, sp.Add):
            return rf"\left({self.sum_text(base)}\right){pw}"
        raise ValueError(f"the LaTeX cannot print the factor {base!r}")

    # ---- terms and sums
    def term(self, expr) -> tuple[bool, str]:
        """(negative, text) of one product."""
        coeff, rest = expr.as_coeff_Mul()
        neg = bool(coeff < 0)
        coeff = -coeff if neg else coeff
        num, den = [], []
        for f in sp.Mul.make_args(rest):
            if f == 1:
                continue
            base, e = f.as_base_exp()
            if not e.is_Integer:
                if e == sp.Rational(1, 2):
                    base, e = sp.sqrt(base, evaluate=False), sp.Integer(1)
                elif e == sp.Rational(-1, 2):
                    base, e = sp.sqrt(base, evaluate=False), sp.Integer(-1)
                else:
                    raise ValueError(f"the LaTeX cannot print the power {f!r}")
            (num if e > 0 else den).append((base, abs(int(e))))
            if isinstance(base, sp.sin) and self._turned(base) and int(e) % 2:
                neg = not neg  # sin(−θ) = −sin θ
        num.sort(key=lambda be: self._key(be[0]))
        den.sort(key=lambda be: self._key(be[0]))
        body = " ".join(self.factor(b, e) for b, e in num)
        if den:
            top = body if body else "1"
            if coeff != 1:
                top = f"{number_text(coeff)} {top}" if body else number_text(coeff)
            return neg, rf"\frac{{{top}}}{{{' '.join(self.factor(b, e) for b, e in den)}}}"
        if coeff == 1 and body:
            return neg, body
        return neg, number_text(coeff) + (f" {body}" if body else "")

    def term_key(self, expr) -> tuple:
        """Terms in a natural order: fewer angle functions first, then by their factors."""
        _, rest = expr.as_coeff_Mul()
        keys = sorted((self._key(b), int(e) if e.is_Integer else 0) for b, e in
                      (f.as_base_exp() for f in sp.Mul.make_args(rest)))
        angle = sum(e for k, e in keys if k[0] == self.ANGLE)
        return (angle, keys)

    def pieces(self, expr) -> list[str]:
        """The signed terms of a sum, each "t" or "- t", in the natural order."""
        out = []
        for t in sorted(sp.Add.make_args(expr), key=lambda t: (self.term_key(t), sp.default_sort_key(t))):
            if t == 0:
                continue
            neg, text = self.term(t)
            out.append(f"- {text}" if neg else text)
        return out or ["0"]

    def sum_text(self, expr) -> str:
        return join(self.pieces(expr))

    def lines(self, expr, width: int) -> list[str]:
        return breaks(self.pieces(expr), width)


def join(pieces: list[str]) -> str:
    out = ""
    for p in pieces:
        out += p if not out else (f" {p}" if p.startswith("- ") else f" + {p}")
    return out


_SPACING = re.compile(r"\\(?:left|right|Big|big)(?![A-Za-z])|\\[,;!]")
_FONT = re.compile(r"\\(?:mathsf|mathrm|mathbf|boldsymbol|mathcal|text|operatorname)\{([^{}]*)\}")
_SCRIPT = re.compile(r"[\^_](?:\{([^{}]*)\}|(\\[A-Za-z]+|.))")
_FUNCTION = re.compile(r"\\(?:cos|sin|tan|exp|log|sinh|cosh|tanh|arcsin|arccos|arctan)(?![A-Za-z])")
_ACCENT = re.compile(r"\\(?:dot|ddot|hat|mathring|tfrac|frac|sqrt)(?![A-Za-z])")


@functools.lru_cache(maxsize=65536)
def visible(tex: str) -> float:
    """About how wide a piece of math is set, in ems of the document's type: a letter or digit
    half an em, a script smaller, a binary operator with its spaces more, cos and sin three
    letters, a fraction's numerator and denominator one above the other (their wider counts).
    The line breaker measures by it, so that a line fits the page whatever its TeX source's length."""
    s = _SPACING.sub("", tex)
    s = _FONT.sub(lambda m: m.group(1), s)
    while "\\frac{" in s:  # the innermost fraction: the wider of its two parts
        m = re.search(r"\\frac\{([^{}]*)\}\{([^{}]*)\}", s)
        if m is None:
            break
        a, b = m.group(1), m.group(2)
        s = s[:m.start()] + (a if visible(a) >= visible(b) else b) + s[m.end():]
    width = 0.0  # the weights: least squares over the printed formulas of the examples, set by LuaLaTeX
    for m in _SCRIPT.finditer(s):
        width += 0.63 * visible(m.group(1) if m.group(1) is not None else m.group(2))
    s = _SCRIPT.sub("", s)
    width += 1.75 * len(_FUNCTION.findall(s))
    s = _ACCENT.sub("", _FUNCTION.sub("", s))
    width += 0.63 * len(re.findall(r"\\[A-Za-z]+", s))
    s = re.sub(r"\\[A-Za-z]+", "", s)
    width += 0.9 * len(re.findall(r"[-+=<>]", s))
    width += 0.47 * sum(1 for ch in s if ch.isalnum())
    width += 0.55 * sum(1 for ch in s if ch in "()[].,|/")
    return width


def breaks(pieces: list[str], width: float) -> list[str]:
    """Signed terms joined into lines about ``width`` ems wide (``visible``); a continuation line
    starts with its sign."""
    lines, cur = [], ""
    for p in pieces:
        piece = p if not cur else (f" {p}" if p.startswith("- ") else f" + {p}")
        if cur and visible(cur) + visible(piece) > width:
            lines.append(cur)
            cur = p if p.startswith("- ") else f"+ {p}"
        else:
            cur += piece
    lines.append(cur)
    return lines


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


def fold_numbers(expr: sp.Expr) -> sp.Expr:
    """Evaluate every subexpression made of numbers only (sqrt(3)/2, cos(3/10), …) to a Float;
    rationals stay exact (they print as the spec wrote them)."""
    if expr.is_Atom:
        return expr
    if expr.is_number:
        return expr if expr.is_Rational else sp.Float(expr.evalf(30), 30)
    args = [fold_numbers(a) for a in expr.args]
    return expr.func(*args) if any(a is not b for a, b in zip(args, expr.args)) else expr
