"""The inertia and the rotor as users have them (issue: CAD, URDF and MuJoCo give the inertia about
the centre of mass as six numbers): I_c converted by the parallel-axis theorem, the six-number form,
3×3 tensors symmetric to round-off symmetrised, rotor = {axis, inertia, speed} meaning
λ = inertia · speed · axis/|axis|.  Each must give exactly the spec written the paper's way."""
from __future__ import annotations

import numpy as np
import sympy as sp

from gyrochain.spec import SYMMETRY_TOL, parse_spec

HEAD = 'name = "ok"\ng = 9.81\n'
LAST = "[[body]]\ntheta = 0.5\nm = 0.2\nc = [0.0, 0.0, -0.2]\nA = [[0.01, 0.0, 0.0], [0.0, 0.01, 0.0], [0.0, 0.0, 0.0001]]\n"


def _body1(fields: str, c: str = "[0.01, -0.02, -0.1]") -> str:
    return HEAD + f"[[body]]\ntheta = 0.0\nm = 0.3\nc = {c}\ns = [0.0, 0.0, -0.2]\n" + fields + "\n" + LAST


def test_six_numbers_and_I_c_give_the_paper_A():
    Ic = np.array([[0.0012, 0.0001, -0.0002], [0.0001, 0.0011, 0.00005], [-0.0002, 0.00005, 0.0004]])
    m, c = 0.3, np.array([0.01, -0.02, -0.1])
    six = f"[{float(Ic[0, 0])!r}, {float(Ic[1, 1])!r}, {float(Ic[2, 2])!r}, {float(Ic[0, 1])!r}, {float(Ic[0, 2])!r}, {float(Ic[1, 2])!r}]"
    matrix = "[" + ", ".join("[" + ", ".join(repr(float(v)) for v in row) + "]" for row in Ic) + "]"
    a = parse_spec(_body1(f"I_c = {six}")).bodies[0].A
    b = parse_spec(_body1(f"I_c = {matrix}")).bodies[0].A
    assert a == b
    # exact: the parallel-axis theorem on the decimals as written
    R = lambda v: sp.Rational(repr(float(v)))  # noqa: E731
    cc = sum(R(x) ** 2 for x in c)
    want = [[R(Ic[i, j]) + R(m) * ((cc if i == j else 0) - R(c[i]) * R(c[j])) for j in range(3)] for i in range(3)]
    assert [list(row) for row in a] == want
    six_A = parse_spec(_body1("A = [0.0045, 0.0044, 0.0012, 0.0001, 0.0, -0.0001]", c="[0.0, 0.0, -0.1]")).bodies[0].A
    r = sp.Rational
    assert six_A == ((r("0.0045"), r("0.0001"), 0), (r("0.0001"), r("0.0044"), r("-0.0001")), (0, r("-0.0001"), r("0.0012")))


def test_round_off_asymmetry_is_symmetrised_and_more_is_not():
    rng = np.random.default_rng(3)
    Q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    A = Q @ np.diag([0.0042, 0.0041, 0.0012]) @ Q.T + 0.3 * (0.0105 * np.eye(3) - np.outer([0.01, -0.02, -0.1], [0.01, -0.02, -0.1]))
    A[0, 1] = np.nextafter(A[0, 1], 1.0)  # a rotated principal tensor: a few ulps apart
    A[2, 0] = np.nextafter(np.nextafter(A[2, 0], -1.0), -1.0)
    assert A[0, 1] != A[1, 0] and A[2, 0] != A[0, 2]
    text = "[" + ", ".join("[" + ", ".join(repr(float(v)) for v in row) + "]" for row in A) + "]"
    got = parse_spec(_body1(f"A = {text}")).bodies[0].A
    for i in range(3):
        for j in range(3):
            assert got[i][j] == got[j][i]
            assert got[i][j] == (sp.Rational(repr(float(A[i, j]))) + sp.Rational(repr(float(A[j, i])))) / 2
    # the rule's edge: just above SYMMETRY_TOL of the largest entry is an error
    big = np.max(np.abs(A))
    A[1, 2] = A[2, 1] + 3 * SYMMETRY_TOL * big
    text = "[" + ", ".join("[" + ", ".join(repr(float(v)) for v in row) + "]" for row in A) + "]"
    try:
        parse_spec(_body1(f"A = {text}"))
    except Exception as exc:  # noqa: BLE001
        assert "not symmetric" in str(exc)
    else:
        raise AssertionError("an asymmetry of 3e-12 of the largest entry was accepted")


C0 = "[0.0, 0.0, -0.1]"


def test_rotor_is_lambda():
    A = "A = [[0.0042, 0.0, 0.0], [0.0, 0.0041, 0.0], [0.0, 0.0, 0.0002]]"
    r = parse_spec(_body1(A + "\nrotor = {axis = [0, 0, 2], inertia = 2e-4, speed = 500}", c=C0)).bodies[0].lam
    assert r == (0, 0, sp.Rational(1, 10))  # 2e-4 · 500 along the unit axis, exactly
    assert parse_spec(_body1(A + "\nlambda = [0, 0, 0.1]", c=C0)).bodies[0].lam == r
    r = parse_spec(_body1(A + '\nrotor = {axis = [1, 1, 0], inertia = "J", speed = "w*(1 - cos(t))"}', c=C0)).bodies[0].lam
    assert {s.name for s in r[0].free_symbols} == {"J", "w", "t"}
    assert sp.simplify(r[0] - r[1]) == 0 and r[2] == 0
    vals = {s: v for s in r[0].free_symbols for name, v in (("J", 2.0), ("w", 3.0), ("t", 1.0)) if s.name == name}
    assert abs(float(r[0].subs(vals)) - 2.0 * 3.0 * (1 - np.cos(1.0)) / np.sqrt(2.0)) < 1e-15
