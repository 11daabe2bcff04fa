"""Numbers folded exactly (issue 14): no round-off residue in the C, the Python or the LaTeX.

The checks read the emitted text only, so they catch a residue however it got there:
- a coefficient below the round-off level of its own expression (1e-12 of the largest number in
  the same statement or equation) is the remains of an exact cancellation done in floating point;
- a C or Python literal of 16–17 digits that lies within a few ulps of a short decimal it is not
  (0.002999999999999999 for 0.003) is an exact value rounded more than once.
They run on every example and on random specs; the unit tests below pin exact.py and trigform.py.
"""
from __future__ import annotations

import math
import re
from fractions import Fraction
from pathlib import Path

import mpmath
import numpy as np
import pytest
import sympy as sp

from gyrochain import exact, trigform
from gyrochain.algebra import Poly
from gyrochain.pipeline import derive_and_render
from gyrochain.printers.common import poly_code
from gyrochain.program import Program
from gyrochain.randspec import random_spec_text
from gyrochain.spec import load_spec, parse_spec

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = sorted(p.stem for p in (ROOT / "specs").glob("*.toml"))
RESIDUE = 1e-12  # a coefficient this much smaller than the largest of its expression is round-off

NUMBER = re.compile(r"(?<![\w.])(\d+\.\d*(?:e[-+]?\d+)?|\d+e[-+]?\d+)(?![\w.])")
C_STATEMENT = re.compile(r"^\s+(?:const double [A-Za-z_]\w*|[A-Za-z_]\w*\[\d+\]) [-+]?= (.*);$")
PY_STATEMENT = re.compile(r"^\s+[A-Za-z_][\w\[\], ]* = (.*)$")


def _small_ones(numbers: list[float]) -> list[float]:
    big = max((abs(v) for v in numbers), default=0.0)
    return [v for v in numbers if v != 0.0 and abs(v) < RESIDUE * big]


def _near_short(text: str) -> str | None:
    """The short decimal a long literal is a few ulps away from, if any."""
    v = float(text)
    digits = len(re.sub(r"[^0-9]", "", text.split("e")[0]).lstrip("0"))
    if digits < 16 or v == 0.0:
        return None
    for d in range(1, 11):
        short = f"{v:.{d}g}"
        w = float(short)
        if w != v and abs(w - v) <= 4 * math.ulp(v):
            return short
    return None


def residue_report(files: dict[str, str]) -> list[str]:
    """Every suspicious number of the emitted files, as 'file: line' messages (empty: clean)."""
    out = []
    for fname, text in files.items():
        if fname.endswith(".c") or fname.endswith(".py"):
            pattern = C_STATEMENT if fname.endswith(".c") else PY_STATEMENT
            for line in text.splitlines():
                m = pattern.match(line)
                if not m:
                    continue
                lits = NUMBER.findall(m.group(1))
                for v in _small_ones([float(x) for x in lits]):
                    out.append(f"{fname}: {v!r} below round-off of its statement: {line.strip()[:160]}")
                for x in lits:
                    short = _near_short(x)
                    if short:
                        out.append(f"{fname}: {x} printed for what is likely {short}: {line.strip()[:160]}")
        elif fname.endswith(".tex"):
            for eq in _tex_equations(text):
                for v in _small_ones(_tex_numbers(eq)):
                    out.append(f"{fname}: {v:g} below round-off of its equation: {eq.strip()[:160]}")
    return out


def _tex_equations(text: str) -> list[str]:
    """The right sides of the LaTeX's equations, continuation lines joined."""
    eqs: list[str] = []
    for chunk in re.split(r"\\\\|\\end\{align\*\}", re.sub(r"\\tag\*?\{(?:[^{}]|\{(?:[^{}]|\{[^{}]*\})*\})*\}", "", text)):
        if "&=" in chunk:
            eqs.append(chunk.rsplit("&=", 1)[1])
        elif chunk.strip().startswith(r"&\quad") and eqs:
            eqs[-1] += chunk
    return eqs


def _tex_numbers(rhs: str) -> list[float]:
    """The coefficients of a LaTeX right side (10-digit decimals, maybe · 10^{e}); exponents,
    indices and superscripts are not numbers of the formula."""
    rhs = re.sub(r"\^\{[^}]*\}|_\{[^}]*\}|\^\d|_\d", " ", rhs.replace(r" \cdot 10^{", " E{"))
    out = []
    for mant, exp in re.findall(r"(?<![\w.])(\d+(?:\.\d+)?)(?: E\{(-?\d+)\})?", rhs):
        out.append(float(mant) * 10.0 ** int(exp or 0))
    return out


# --------------------------------------------------------------------------- the emitted files
def _with_angles(text: str, angles: list[str]) -> str:
    """A random spec with its structural angles replaced (by expressions such as "pi/4")."""
    it = iter(angles)
    return re.sub(r"^theta = .*$", lambda m: f'theta = "{next(it)}"', text, flags=re.M)


def _random_cases() -> dict[str, str]:
    cases = {}
    for i, (n, planar, controls) in enumerate([(2, False, ()), (3, False, (1,)), (2, True, ()), (5, False, (2,))]):
        rng = np.random.default_rng(1400 + i)
        cases[f"random_{'planar' if planar else 'spatial'}{n}"] = random_spec_text(rng, n, planar=planar, controls=controls)
    rng = np.random.default_rng(1410)
    # exact special angles (sqrt(2)/2, sqrt(3)/2) and angles whose cosines are related in a way
    # exact.py is not told (cos 0.6 = 2 cos^2 0.3 - 1)
    cases["special_angles3"] = _with_angles(random_spec_text(rng, 3), ["pi/4", "pi/3", "pi/6"])
    cases["related_angles3"] = _with_angles(random_spec_text(rng, 3), ["0.3", "0.6", "0.3"])
    return cases


RANDOM = _random_cases()


@pytest.mark.parametrize("name", EXAMPLES)
def test_examples_have_no_residue(name):
    files, _ = derive_and_render(load_spec(ROOT / "specs" / f"{name}.toml"), name)
    assert residue_report(files) == []


@pytest.mark.parametrize("name", sorted(RANDOM))
def test_random_specs_have_no_residue(name):
    files, _ = derive_and_render(parse_spec(RANDOM[name]), name)
    assert residue_report(files) == []


def test_the_check_catches_what_was_printed_before():
    """Lines as the generator printed them before numbers were folded exactly (gimbal.c,
    spatial3.tex): the report must flag each."""
    files = {
        "gimbal.c": "        const double pN2_1 = 0.002999999999999999*om2_2*om2_3 + 0.5*om2_2;\n",
        "gimbal.py": "        Ja2rdr_33 = 0.0075 + 0.0014999999999999996*c2phi2\n",
        "spatial3.tex": r"Q_{1} &= 0.0001234638751 \mathrm{c}_{3} \mathrm{s}_{3}^{2} - 2.458949501 \cdot 10^{-20} \mathrm{c}_{3} \mathrm{s}_{3} \\" + "\n",
        "gyrostat2.c": "    const double a = 0.0466019543*x + 3.469446952e-18*y;\n",
    }
    report = residue_report(files)
    assert len(report) == 4, report
    assert residue_report({"ok.c": "    const double a = 0.003*x + 0.0015*y;\n"}) == []


def test_exact_values_are_printed():
    """Products and sums of the spec's decimals print as their exact values (0.1*0.03 = 0.003)."""
    text = (ROOT / "specs" / "gimbal.toml").read_text()
    files, model = derive_and_render(parse_spec(text), "gimbal")
    c = files["gimbal.c"]
    assert "0.003*" in c and "0.0015*" in c
    assert "0.002999999999999999" not in c and "0.0014999999999999996" not in c


# --------------------------------------------------------------------------- exact.py
def _reference_double(expr: sp.Expr) -> float:
    """The correctly rounded double of an exact sympy number, by 80 digits and one rounding."""
    with mpmath.workprec(53):
        return float(mpmath.mpf(str(sp.N(expr, 80))))


def test_fold_is_correctly_rounded():
    rng = np.random.default_rng(3)
    for _ in range(200):
        p, q = (int(x) for x in rng.integers(1, 10**12, 2))
        f = Fraction(p, q) * Fraction(7, 10**int(rng.integers(0, 8)))
        assert exact.to_float(f) == _reference_double(sp.Rational(f.numerator, f.denominator))
    for arg in ("3/10", "1/7", "2"):
        a = sp.Rational(arg)
        c, s = exact.exact(sp.cos(a)), exact.exact(sp.sin(a))
        for value, expr in ((c, sp.cos(a)), (s * c * Fraction(7, 3), sp.sin(a) * sp.cos(a) * sp.Rational(7, 3)),
                            (c * c * c - Fraction(1, 10) * s, sp.cos(a) ** 3 - sp.sin(a) / 10)):
            assert exact.to_float(value) == _reference_double(expr)


def test_known_relations_reduce_exactly():
    c, s = exact.exact(sp.cos(sp.Rational(3, 10))), exact.exact(sp.sin(sp.Rational(3, 10)))
    assert c * c + s * s == 1
    assert s * s * s == s - c * c * s
    r = exact.exact(sp.sqrt(2) / 2)
    assert r * r == Fraction(1, 2)
    assert exact.exact(sp.cos(sp.pi / 3)) == Fraction(1, 2)
    # sin(pi/5) = sqrt(5/8 - sqrt(5)/8): its square reduces through the nested root
    c5, s5 = exact.exact(sp.cos(sp.pi / 5)), exact.exact(sp.sin(sp.pi / 5))
    assert c5 * c5 + s5 * s5 == 1


def test_unknown_relation_folds_to_zero_and_is_not_printed():
    c3, c6 = exact.exact(sp.cos(sp.Rational(3, 10))), exact.exact(sp.cos(sp.Rational(3, 5)))
    zero = c6 - (2 * c3 * c3 - 1)
    assert isinstance(zero, exact.Surd)  # not zero structurally
    assert exact.to_float(zero) == 0.0
    P = Program()
    x = P.input(sp.Symbol("x"))
    p = x * Poly.const(zero) + Poly.const(Fraction(3, 1000)) * x
    assert poly_code(p, lambda a: a.name) == "0.003*x"


def test_spec_decimals_fold_exactly():
    P = Program()
    m, l = P.from_sympy(sp.Rational(1, 10)), P.from_sympy(sp.Rational(3, 100))
    assert (m * l).constant() == Fraction(3, 1000)
    assert poly_code(m * l, str) == "0.003"
    assert (Poly.const(0.1) * 3).constant() != Fraction(3, 10)  # a float literal is its binary value


# --------------------------------------------------------------------------- trigform.py
PHI = [sp.Symbol(f"phi_{k}", real=True) for k in (1, 2, 3)]


def _random_trig_poly(rng, phis, terms: int = 8) -> sp.Expr:
    out = sp.Integer(0)
    for _ in range(terms):
        t = sp.Rational(int(rng.integers(-9, 10)), int(rng.integers(1, 9)))
        for phi in phis:
            t *= sp.cos(phi) ** int(rng.integers(0, 4)) * sp.sin(phi) ** int(rng.integers(0, 4))
        out += t * sp.Symbol("w") ** int(rng.integers(0, 2))
    return out


def _numeric(expr, phis, at) -> float:
    return complex(expr.subs({**dict(zip(phis, at)), sp.Symbol("w"): 0.7}).evalf(30)).real


def test_every_form_is_the_same_function_and_the_shortest_is_chosen():
    rng = np.random.default_rng(7)
    for trial in range(6):
        phis = PHI[: 1 + trial % 3]
        e = _random_trig_poly(rng, phis)
        can = trigform.canonical(e, phis)
        assert can.terms == min(can.terms_by_form.values())
        for form in ("c", "s", "f"):  # C and S only where axes are parallel (the next test)
            table = {"c": trigform._eliminate(trigform._split(e, phis), 1), "s": trigform._eliminate(trigform._split(e, phis), 0),
                     "f": trigform._fourier(trigform._split(e, phis), len(phis))}[form]
            assert len(table) == can.terms_by_form[form]
        for _ in range(3):
            at = rng.uniform(-3, 3, len(phis))
            assert _numeric(can.expr, phis, at) == pytest.approx(_numeric(e, phis, at), rel=1e-12, abs=1e-12)


def _nested(rng, atoms, depth: int) -> sp.Expr:
    """A random unexpanded expression: sums, products and powers (negative ones of atoms) of
    rationals and ``atoms``."""
    if depth == 0 or rng.random() < 0.2:
        return atoms[int(rng.integers(len(atoms)))] if rng.random() < 0.8 else sp.Rational(int(rng.integers(-5, 6)), 3)
    kind = rng.integers(4)
    parts = [_nested(rng, atoms, depth - 1) for _ in range(int(rng.integers(2, 4)))]
    if kind == 0:
        return sp.Add(*parts)
    if kind == 1:
        return sp.Mul(*parts)
    if kind == 2:
        return sp.Add(*parts) ** 2
    return sp.Mul(atoms[int(rng.integers(len(atoms)))] ** -int(rng.integers(1, 3)), sp.Add(*parts))


def test_the_plain_expansion_is_sympys():
    """trigform's own multiplication gives the terms of sympy's expand, term for term, on nested
    expressions in the atoms it takes (symbols, a structural constant, cos and sin of angles and of
    nested linear arguments, negative powers), and hands what it does not take to sympy."""
    t, w, m = sp.symbols("t w m")
    kappa = exact.to_sympy(exact.exact(sp.sqrt(2)), symbolic=True)
    atoms = [w, m, kappa, sp.cos(PHI[0]), sp.sin(PHI[0]), sp.cos(PHI[1]), sp.sin(PHI[1]),
             sp.sin(PHI[1] - sp.Rational(7, 5)), sp.cos(sp.Rational(3, 7) * t + sp.Rational(1, 3) * sp.sin(2 * t))]

    def sympys(e):  # each term as (coefficient, factors' product), the factors' order aside
        return sorted(((sp.sympify(c), sp.Mul(*(f for *_, f in fs))) for c, fs in trigform._expanded(e)), key=str)

    def reference(e):
        terms = (term.as_coeff_mul() for term in sp.Add.make_args(sp.expand(e)) if term != 0)
        return sorted(((c, sp.Mul(*fs)) for c, fs in terms), key=str)

    rng = np.random.default_rng(11)
    for _ in range(40):
        e = _nested(rng, atoms, 3)
        assert trigform._poly(e) is not None  # taken, not handed on
        assert sympys(e) == reference(e), e
    for e in (sp.sqrt(w) * (w + 1) ** 2, sp.Float(0.1) * w * (w + m), sp.exp(w) ** 2 * (m + 1), (w + m) ** -1 * w):
        with pytest.raises(trigform._NotPlain):
            trigform._poly(e)
        assert sympys(e) == reference(e), e


def test_the_plain_derivative_is_sympys():
    """trigform.diff (the LaTeX's ∂R/∂x) is sympy's diff, expanded: the same terms, on nested
    expressions of joint angles, rates, a structural constant and functions of time whose arguments
    hold the angle (shifted, scaled) or hold time inside a sine (sympy's chain rule then)."""
    t, w = sp.symbols("t w")
    kappa = exact.to_sympy(exact.exact(sp.sqrt(2)), symbolic=True)
    atoms = [w, kappa, PHI[0], sp.cos(PHI[0]), sp.sin(PHI[0]), sp.cos(PHI[1]), sp.sin(PHI[1]),
             sp.sin(PHI[1] - sp.Rational(7, 5)), sp.cos(sp.Rational(-3, 2) * PHI[0] + PHI[1]),
             sp.cos(sp.Rational(3, 7) * t + sp.Rational(1, 3) * sp.sin(2 * t))]
    rng = np.random.default_rng(12)
    for _ in range(10):
        e = _nested(rng, atoms, 3)
        for x in (PHI[0], PHI[1], w, t):
            got = trigform.diff(e, x)
            assert sp.expand(got - sp.diff(e, x)) == 0, (e, x)
            assert set(sp.Add.make_args(got)) == set(sp.Add.make_args(sp.expand(sp.diff(e, x)))), (e, x)


def test_forms_are_canonical():
    """Two writings of the same function give the same printed form."""
    c, s = sp.cos(PHI[1]), sp.sin(PHI[1])
    a, b = sp.Rational(3, 7), sp.Rational(-2, 5)
    one = a * c**2 + b * s**2 + c**3 * s
    two = b + (a - b) * c**2 + c * s - c * s**3
    assert trigform.canonical(one, PHI[1:2]).expr == trigform.canonical(two, PHI[1:2]).expr
    # the double pendulum's gravity moment: 3 terms in c/s, 2 in multiple angles
    g = -2 * s * sp.cos(PHI[0]) - 2 * c * sp.sin(PHI[0]) - 3 * sp.sin(PHI[0])
    can = trigform.canonical(g, PHI[:2])
    assert can.form == "f" and can.terms == 2
    assert can.expr == -2 * sp.sin(PHI[0] + PHI[1]) - 3 * sp.sin(PHI[0])


def test_sums_of_angles_where_axes_are_parallel():
    """Forms C and S: a planar arm's functions in the sums of its angles, the same function, and
    fewer terms than in any form of the angles alone (a UR5's M15 has 3)."""
    rng = np.random.default_rng(8)
    links = {PHI[1]: (PHI[0], 1), PHI[2]: (PHI[1], 1)}
    a1, a2, a3 = PHI[0], PHI[0] + PHI[1], PHI[0] + PHI[1] + PHI[2]
    e = sp.expand_trig(sp.Rational(3, 2) * sp.cos(a3) - sp.Rational(1, 3) * sp.sin(a2) * sp.cos(a3) + sp.cos(a1) ** 2)
    can = trigform.canonical(e, PHI[:3], links=links)
    assert can.form in ("C", "S") and can.terms == 3 < min(can.terms_by_form[f] for f in ("c", "s", "f")), can.terms_by_form
    assert can.expr.has(sp.cos(a3)) and can.expr.has(sp.sin(a2))
    for _ in range(5):
        at = rng.uniform(-3, 3, 3)
        assert _numeric(can.expr, PHI[:3], at) == pytest.approx(_numeric(e, PHI[:3], at), rel=1e-12, abs=1e-12)
    # an axis that points the other way (θ = π) turns the run by the difference
    d = sp.expand_trig(sp.cos(PHI[0] - PHI[1]))
    assert trigform.canonical(d, PHI[:2], links={PHI[1]: (PHI[0], -1)}).terms == 1


def test_the_same_function_prints_the_same_in_every_document():
    """Each quantity in its own shortest normal form: the gimbal's carrier and the same carrier on
    a ship print M11 alike (the ship's document once chose sin² for the whole document)."""
    gimbal = (ROOT / "generated" / "gimbal" / "gimbal.tex").read_text()
    ship = (ROOT / "generated" / "ship_gimbal" / "ship_gimbal.tex").read_text()
    for tex in (gimbal, ship):
        m11 = re.search(r"^M_\{11\} &= (.*?) \\tag", tex, flags=re.M).group(1)
        assert re.fullmatch(r"[\d.]+ \+ [\d.]+ \\left\(\\cos\\varphi\^\{2\}\\right\)\^\{2\}", m11), m11
        assert "normal forms that has the fewest terms" in tex
    import texread

    ur5 = (ROOT / "generated" / "ur5" / "ur5.tex").read_text()
    m15 = sp.expand(texread.parse(texread.equations(ur5)["M_{15}"], texread.document_names(ur5, 6)))
    assert len(sp.Add.make_args(m15)) == 3, m15
