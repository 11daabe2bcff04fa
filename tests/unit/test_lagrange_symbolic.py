"""The derived equations are the Lagrange equations of ℒ = Σ[T_k + λᵏ·ωᵏ] + U, proved
symbolically for n = 2 with every parameter symbolic (the stages alone: kinematics, dynamics,
integrals; no printer, no compiler).  tests/models/test_lagrange.py checks the compiled models
numerically for n = 3, 4."""
from __future__ import annotations

import sympy as sp

from gyrochain import dynamics, integrals, kinematics
from gyrochain.spec import parse_spec
from lagrange import lagrange_terms


def symbolic_two_body_spec():
    def vec(name):
        return "[" + ", ".join(f'"{name}{i}"' for i in (1, 2, 3)) + "]"

    def mat(name):
        idx = lambda i, j: f"{min(i, j)}{max(i, j)}"  # noqa: E731  symmetric by construction
        return "[" + ", ".join("[" + ", ".join(f'"{name}{idx(i, j)}"' for j in (1, 2, 3)) + "]" for i in (1, 2, 3)) + "]"

    text = 'name = "sym2"\ng = "g"\n'
    for k in (1, 2):
        text += f'[[body]]\ntheta = "th{k}"\nm = "m{k}"\nc = {vec(f"c{k}_")}\nA = {mat(f"A{k}_")}\n'
        if k == 1:
            text += f"s = {vec('s1_')}\n"
        text += f"lambda = {vec(f'lam{k}_')}\ncontrol = true\n"
    return parse_spec(text)


def reduce_trig(expr, angles):
    """Replace cos, sin of each angle by symbols and reduce modulo s² + c² − 1: the result is 0
    exactly when the trigonometric identity holds.  The expression is multiplied out in sympy's
    sparse polynomial ring over the rationals (from_expr evaluates its tree there node by node,
    many times quicker than expand), and divided by the s² + c² − 1, a Gröbner basis (their leading terms
    s² have no common factor)."""
    reps, gens = {}, []
    for i, a in enumerate(angles):
        c, s = sp.Symbol(f"C{i}"), sp.Symbol(f"S{i}")
        reps[sp.cos(a)], reps[sp.sin(a)] = c, s
        gens += [s, c]
    poly = expr.xreplace(reps)
    assert not poly.atoms(sp.sin, sp.cos), "trig left after substitution"
    rest = sorted(poly.free_symbols - set(gens), key=str)
    R, *xs = sp.ring(gens + rest, sp.QQ, sp.lex)
    ideal = [xs[2 * i] ** 2 + xs[2 * i + 1] ** 2 - 1 for i in range(len(angles))]
    return R.from_expr(poly).rem(ideal)


def test_symbolic_two_body_equals_lagrange():
    spec = symbolic_two_body_spec()
    assert len(spec.params) == 1 + 2 * (1 + 1 + 3 + 6 + 3) + 3  # g, θ, m, c, A, λ per body, s¹
    kin = kinematics.derive(spec)
    dyn = dynamics.derive(spec, kin.prog, kin)
    n = spec.n
    phi, phidot = kin.phi[1:], kin.phidot[1:]
    H, b = lagrange_terms(spec, phi, phidot)
    ours = kin.prog.inline([dyn.M[i][j] for i in range(n) for j in range(n)] + [dyn.Q[k] + dyn.Gamma[k] - dyn.G[k] for k in range(n)])
    angles = phi + [body.theta for body in spec.bodies]
    for i in range(n):
        for j in range(n):
            assert reduce_trig(ours[i * n + j] - H[i, j], angles) == 0, f"M[{i + 1},{j + 1}]"
    for k in range(n):
        # M φ̈ + Q + Γ − G = Lᵏ  ⇔  H φ̈ + b = Lᵏ
        assert reduce_trig(ours[n * n + k] - b[k], angles) == 0, f"equation {k + 1}"
    # the control torques enter as +Lᵏ on the right side
    assert kin.prog.inline(dyn.L) == [kin.torque[k + 1] for k in range(n)]
    # the code's form: one Newton–Euler recursion for Q + Γ − G (gravity as base acceleration)
    bias = kin.prog.inline(dyn.bias)
    for k in range(n):
        assert reduce_trig(bias[k] - b[k], angles) == 0, f"combined bias {k + 1}"


def test_symbolic_two_body_energy_and_momentum():
    """T of the generated integrals is ½ φ̇ᵀHφ̇ (digest §7, check 2) and, with θ¹ = 0, the momentum
    (27) is ∂ℒ/∂φ̇¹."""
    spec = symbolic_two_body_spec()
    text = spec.source.replace('theta = "th1"', "theta = 0", 1)
    spec = parse_spec(text)
    kin = kinematics.derive(spec)
    dyn = dynamics.derive(spec, kin.prog, kin)
    ints = integrals.derive(spec, kin.prog, kin, dyn)
    phi, phidot = kin.phi[1:], kin.phidot[1:]
    from lagrange import lagrangian

    L = lagrangian(spec, phi, phidot)
    T_ref = sum(sp.diff(L, v, 2) * v**2 for v in phidot) / 2 + sp.diff(L, phidot[0], phidot[1]) * phidot[0] * phidot[1]
    T, K = kin.prog.inline([ints.T, ints.momentum])
    angles = phi + [body.theta for body in spec.bodies]
    assert reduce_trig(T - T_ref, angles) == 0
    assert reduce_trig(K - sp.diff(L, phidot[0]), angles) == 0
