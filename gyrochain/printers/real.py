"""Single precision (``generate --real float``): the model's C in float, printed from its double C.

The derivation and the C printer are the same for both; this module retypes the printed C, header
and cdef token by token outside comments and string literals: ``double`` → ``float``, every
floating literal gets the ``f`` suffix, the math functions their float versions (``sinf``,
``sqrtf``, …), ``HUGE_VAL`` → ``HUGE_VALF``, and the header says ``#define NAME_REAL float``.
So no arithmetic is promoted to double (the tests compile with ``-Wdouble-promotion
-Wfloat-conversion -Werror``).  The constants that depend on the precision — the unit round-off in
the LDLᵀ pivot test and the integrators' step floors, its square root in the difference steps, a
floor against division by zero, GAUSS2's round-off floor, the slack of a fixed-step count, the
quadratures' tolerance and separatrix distance — are found where the kernels and templates put
them (``PRECISION``: each pattern must be found once or more wherever its kernel is emitted, or
the printing fails) and given float's values.
"""
from __future__ import annotations

import re

# precision-dependent constants of the double C: (regex, its float replacement, what it is, where)
PRECISION = [
    (r"2\.220446049250313e-16", "1.1920929e-07f", "the unit round-off (pivot test, step floors)", None),
    (r"1\.4901161193847656e-08", "3.4526698e-04f", "its square root (difference steps)", "canonical_newton_"),
    (r"1e-300\b", "1e-30f", "a floor against division by zero", "dop853_"),
    (r"(#define \w+_GAUSS_FLOOR )1e-12\b", r"\g<1>1e-05f", "GAUSS2's round-off floor of a correction (~80 eps)", "gauss2_step_"),
    (r"(d > 0\.9 \* dprev && d > )1e-12\b", r"\g<1>1e-05f", "the same floor in the Newton iterations", "gauss2_newton_"),
    (r"(\(1\.0 - )1e-10\b", r"\g<1>1e-05f", "the slack of a fixed-step count (h = T/m gives m steps)", "nsteps_"),
    (r"(#define \w+_QUAD_TOL )1e-13\b", r"\g<1>1e-05f", "the quadratures' Kronrod tolerance", "quad_"),
    (r"(#define \w+_SEPARATRIX_TOL )1e-14\b", r"\g<1>1e-06f", "the quadratures' separatrix distance", "quad_"),
]
_MATH = ("sin cos tan sqrt fabs pow exp log asin acos atan atan2 sinh cosh tanh asinh acosh atanh floor ceil "
         "fmin fmax fmod hypot cbrt").split()
_SKIP = re.compile(r'(/\*.*?\*/|//[^\n]*|"(?:\\.|[^"\\])*")', re.S)  # comments and strings stay as they are
_LITERAL = re.compile(r"(?<![\w.])((?:\d+\.\d*|\.\d+)(?:[eE][+-]?\d+)?|\d+[eE][+-]?\d+)(?![\w.])")
_FUNCTION = re.compile(r"\b(" + "|".join(_MATH) + r")(?=\s*\()")


def _code(text: str) -> str:
    text = re.sub(r"\bdouble\b", "float", text)
    text = _LITERAL.sub(lambda m: m.group(1) + "f", text)
    text = _FUNCTION.sub(lambda m: m.group(1) + "f", text)
    return re.sub(r"\bHUGE_VAL\b", "HUGE_VALF", text)


def retype(text: str) -> str:
    """C text in float: the code outside comments and strings retyped (see the module)."""
    parts = _SKIP.split(text)
    return "".join(p if i % 2 else _code(p) for i, p in enumerate(parts))


def _precision(texts: dict[str, str], name: str) -> dict[str, str]:
    """The precision-dependent constants of a model's double C and header given float's values;
    each one its kernels emit must be found."""
    out = dict(texts)
    both = "".join(texts.values())
    for pattern, repl, what, where in PRECISION:
        if where is not None and f"{name}_{where}" not in both:
            continue  # its kernel is not in this model
        found = 0
        for fname, text in out.items():
            out[fname], k = re.subn(pattern, repl, text)
            found += k
        if not found:
            raise ValueError(f"the float printer did not find {what} ({pattern}) in {name}'s C")
    return out


FLT_MAX, FLT_MIN = 3.4028234663852886e38, 1.1754943508222875e-38


def check_range(text: str) -> None:
    """Every constant of the code (outside comments and strings) within float's normal range, or a
    one-line SpecError: a mass of 1e-50 or 1e39 would become 0 or inf in the float C (and gcc would
    warn of an overflow in every line that has it)."""
    from ..chainspec.errors import SpecError

    parts = _SKIP.split(text)
    for i, part in enumerate(parts):
        if i % 2:
            continue
        for m in _LITERAL.finditer(part):
            v = abs(float(m.group(1)))
            if v > FLT_MAX or 0 < v < FLT_MIN:
                raise SpecError("--real", f"float holds numbers from {FLT_MIN:.3g} to {FLT_MAX:.3g}; the model has the "
                                          f"constant {m.group(1)} (from the spec's numbers): generate it in double, or "
                                          "give the spec in other units")


def single_precision(files: dict[str, str], name: str) -> dict[str, str]:
    """The C target's files of a model retyped to float (the others as they are); a constant
    beyond float's range is refused (``check_range``)."""
    out = dict(files)
    out.update(_precision({f"{name}.c": files[f"{name}.c"], f"{name}.h": files[f"{name}.h"]}, name))
    check_range(out[f"{name}.c"].replace("1e-30f", "1e-30"))  # (the precision constants are float's now)
    for fname in (f"{name}.c", f"{name}.h", f"{name}.cdef"):
        out[fname] = retype(out[fname])
    double_line = f"#define {name.upper()}_REAL double\n"
    if double_line not in files[f"{name}.h"]:
        raise ValueError(f"{name}.h: no {double_line.strip()} line to change")
    return out  # (the header's #define NAME_REAL double was retyped with the rest)
