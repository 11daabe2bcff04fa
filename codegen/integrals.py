"""First integrals (digest §4): energy T − U (eq. (23)) and the momentum (27) about the
vertical axis l¹ when θ¹ = 0 (eq. (25))."""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .dynamics import Dynamics, dot
from .kinematics import Kinematics
from .spec import ChainSpec


@dataclass(frozen=True)
class Integrals:
    T: sp.Expr  # kinetic energy (21)/2
    U: sp.Expr  # force function of gravity (22); potential energy is −U
    energy: sp.Expr  # T − U (23)
    momentum: sp.Expr | None  # ê¹₁ · K_O¹ (27) = ∂ℒ/∂φ̇¹, only when θ¹ = 0
    has_energy_integral: bool  # T − U is conserved: fixed base and no control torque
    has_momentum_integral: bool  # (27) is conserved: θ¹ = 0 and no torque on joint 1


def derive(spec: ChainSpec, kin: Kinematics, dyn: Dynamics) -> Integrals:
    n = spec.n
    qd = sp.Matrix(kin.phidot[1:])
    T = sp.Rational(1, 2) * sum(
        (dyn.M[i, j] * (1 if i == j else 2) * qd[i] * qd[j] for i in range(n) for j in range(i, n)),
        sp.Integer(0),
    )
    U = spec.g * dot(dyn.h[0], kin.gamma[1])
    momentum = None
    if spec.bodies[0].theta == 0:
        momentum = sum((dyn.M[0, r] * qd[r] for r in range(n)), sp.Integer(0)) + dyn.Lam[0][0]
    return Integrals(
        T=T,
        U=U,
        energy=T - U,
        momentum=momentum,
        has_energy_integral=not spec.controls,
        has_momentum_integral=momentum is not None and 1 not in spec.controls,
    )
