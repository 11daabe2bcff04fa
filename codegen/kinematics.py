"""Kinematics in the paper's notation (digest §3).

Symbols: ``phi[k]``, ``phidot[k]`` are φᵏ, φ̇ᵏ (index 0 unused: k is the paper's k, 0 is the
base).  ``alpha[k]`` is αᵏ'ᵏ⁻¹ of eq. (11)/(15): rows are êᵏᵢ in frame k−1, so a vector's
components go from frame k−1 to frame k as v⁽ᵏ⁾ = αᵏ'ᵏ⁻¹ v⁽ᵏ⁻¹⁾.  Products of these are the
recursion (13)/(14).  All vectors below are components in the body's own frame.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .program import Program
from .spec import ChainSpec

E1 = sp.Matrix([1, 0, 0])


def state_symbols(n: int):
    """φ, φ̇ and the joint torques Lᵏ as real sympy symbols, 1-based (index 0 is None)."""
    phi = [None] + [sp.Symbol(f"phi_{k}", real=True) for k in range(1, n + 1)]
    phidot = [None] + [sp.Symbol(f"phidot_{k}", real=True) for k in range(1, n + 1)]
    torque = [None] + [sp.Symbol(f"L_{k}", real=True) for k in range(1, n + 1)]
    return phi, phidot, torque


def folded_trig(theta: sp.Expr) -> tuple[sp.Expr, sp.Expr]:
    """cos θ, sin θ of a structural angle; a numeric angle is folded to a number now."""
    c, s = sp.cos(theta), sp.sin(theta)
    if theta.is_number:  # exact zeros and ones stay exact (θ = pi/2 gives 0 and 1)
        c = c if c.is_Rational else sp.Float(c.evalf(30), 30)
        s = s if s.is_Rational else sp.Float(s.evalf(30), 30)
    return c, s


def direction_cosines(theta: sp.Expr, phi: sp.Expr, cp=None, sph=None) -> sp.Matrix:
    """αᵏ'ᵏ⁻¹ of eq. (15) (with the digest's sign −sin θ in α₁₃) = R₁(φ) R₂(θ).
    ``cp``, ``sph`` may name cos φ and sin φ."""
    ct, st = folded_trig(theta)
    cp = sp.cos(phi) if cp is None else cp
    sph = sp.sin(phi) if sph is None else sph
    return sp.Matrix(
        [
            [ct, 0, -st],
            [st * sph, cp, ct * sph],
            [st * cp, -sph, ct * cp],
        ]
    )


@dataclass(frozen=True)
class Kinematics:
    prog: Program  # every quantity below is a value of this program
    n: int
    phi: list
    phidot: list
    torque: list
    alpha: list  # alpha[k] = αᵏ'ᵏ⁻¹ (eq. 15), k = 1..n
    gamma: list  # gamma[k] = ê⁰₁ (down) in frame k: the column (αᵏᵢ₁)ᵢ of eq. (14)
    omega: list  # omega[k] = ωᵏ of eq. (1) in frame k (fixed base: ω⁰ = 0)


def derive(spec: ChainSpec) -> Kinematics:
    n = spec.n
    prog = Program()
    phi, phidot, torque = state_symbols(n)
    alpha = [None]
    gamma = [E1]
    omega = [sp.zeros(3, 1)]
    for k, body in enumerate(spec.bodies, start=1):
        cp = prog.let(f"cos_phi{k}", sp.cos(phi[k]), rf"\mathrm{{c}}_{{{k}}}")
        sph = prog.let(f"sin_phi{k}", sp.sin(phi[k]), rf"\mathrm{{s}}_{{{k}}}")
        a = direction_cosines(body.theta, phi[k], cp, sph)
        alpha.append(a)
        gamma.append(prog.vec(f"gam{k}", a * gamma[k - 1], rf"\gamma^{{{k}}}"))  # (α^k_{i1})_i, eq. (14)
        omega.append(prog.vec(f"om{k}", a * omega[k - 1] + E1 * phidot[k], rf"\omega^{{{k}}}"))  # eq. (1)
    return Kinematics(prog, n, phi, phidot, torque, alpha, gamma, omega)
