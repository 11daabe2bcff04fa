"""The printers on small straight-line programs: shared products become temporaries, numbers
print as round-trip doubles, each target spells the same program its own way."""
from __future__ import annotations

import math

import sympy as sp

from gyrochain.printers.c import CPrinter
from gyrochain.printers.common import function_of, literal, poly_code
from gyrochain.printers.python import NumpyPrinter, PyPrinter
from gyrochain.program import Program
from gyrochain.straightline import straight_line


def small_program():
    """a = x y + 1/10, b = 2 x y − a z, r = sqrt(p) (a parameter's function): two outputs."""
    x, y, z, p = sp.symbols("x y z p", real=True)
    P = Program()
    X, Y, Z = P.input(x), P.input(y), P.input(z)
    a = P.let("a", X * Y + sp.Rational(1, 10))
    b = P.let("b", 2 * X * Y - a * Z)
    r = P.from_sympy(sp.sqrt(p))
    return P, (x, y, z, p), [a * b, b - r]


def test_shared_products_become_temporaries_before_their_first_use():
    P, _, outs = small_program()
    line = straight_line(P, outs)
    names = [a.name for a, _ in line.temporaries]
    assert names[0] == "w0" and names.index("w0") < names.index("a") < names.index("b")  # x*y once, first
    assert names.count("w0") == 1 and "w1" not in names  # only x*y is shared


def test_c_and_python_spell_the_same_program():
    P, (x, y, z, p), outs = small_program()
    line = straight_line(P, outs)
    names = {x: "x[0]", y: "x[1]", z: "x[2]", p: "p->p"}
    c = function_of("f", line, ["out[0]", "out[1]"], CPrinter(names))
    py = function_of("f", line, ["out[0]", "out[1]"], PyPrinter({**names, p: "p_p"}))
    temps = dict(c.temporaries)
    assert temps["w0"] == "x[0]*x[1]"
    assert temps["a"] == "w0 + 0.1"
    assert temps["b"] == "2.0*w0 - x[2]*a"  # factors in the order their atoms were made
    assert temps["pe1"] == "sqrt(p->p)" and dict(py.temporaries)["pe1"] == "math.sqrt(p_p)"
    assert dict(c.outputs) == {"out[0]": "a*b", "out[1]": "b - pe1"}
    # evaluated, both are the program's values
    env = {"x": [0.3, -1.7, 2.5], "p_p": 2.0, "math": math}
    for lhs, rhs in py.temporaries:
        env[lhs] = eval(rhs, env)  # noqa: S307  (our own printed code)
    a = 0.3 * -1.7 + 0.1
    b = 2 * 0.3 * -1.7 - a * 2.5
    assert math.isclose(eval(dict(py.outputs)["out[0]"], env), a * b, rel_tol=1e-15)  # noqa: S307
    assert math.isclose(eval(dict(py.outputs)["out[1]"], env), b - math.sqrt(2.0), rel_tol=1e-15)  # noqa: S307


def test_numbers_are_round_trip_doubles():
    from fractions import Fraction

    assert literal(Fraction(1, 10)) == "0.1" and float(literal(Fraction(1, 3))) == 1 / 3
    assert literal(2) == "2.0" and literal(sp.Rational(3, 2)) == "1.5"
    assert poly_code(small_program()[2][0] * 0, str) == "0.0"


def test_numpy_printer_for_the_quadratures():
    phi = sp.Symbol("phi", real=True)
    pr = NumpyPrinter({phi: "phi"})
    assert pr.doprint(sp.sin(phi) + sp.sqrt(phi)) == "np.sqrt(phi) + np.sin(phi)"
