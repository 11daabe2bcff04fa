"""First integrals (digest §4): energy T − U (eq. (23)) and the momentum (27) about the axis l¹.

Which of them exist is decided here, per spec, from the paper's conditions (the base is always
fixed in our spec format):

* energy (23): no control torque acts (any θ¹);
* momentum (27), ∂ℒ/∂φ̇¹ = ê¹₁·K_O¹: the axis l¹ is vertical, (25), i.e. sin θ¹ = 0 (θ¹ = 0 as in
  the paper, or θ¹ = π, the axis pointing up), and no torque acts in joint 1.  A torque in a
  later joint is internal (26).

When θ¹ is given by a parameter, whether (25) holds depends on its value: the momentum function
is still emitted (it is ∂ℒ/∂φ̇¹ for any θ¹) and the condition is stated instead of guessed.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .algebra import ZERO, Poly
from .dynamics import Dynamics
from .kinematics import Kinematics, dot
from .spec import ChainSpec


@dataclass(frozen=True)
class Integrals:
    T: Poly  # kinetic energy (21)/2
    U: Poly  # force function of gravity (22); potential energy is −U
    energy: Poly  # T − U (23)
    momentum: Poly | None  # ∂ℒ/∂φ̇¹ = ê¹₁ · K_O¹ (27); None when l¹ is surely not vertical
    has_energy_integral: bool  # T − U is conserved: fixed base and no control torque
    has_momentum_integral: bool  # (27) is conserved for every parameter value
    momentum_condition: str | None = None  # when (25) depends on a parameter: the condition, in words


def vertical_axis(spec: ChainSpec) -> bool | None:
    """Condition (25) for l¹: True, False, or None when it depends on a parameter."""
    s = sp.simplify(sp.sin(spec.bodies[0].theta))
    if s == 0:
        return True
    if s.is_number:
        return False
    return None


def derive(spec: ChainSpec, kin: Kinematics, dyn: Dynamics) -> Integrals:
    n = spec.n
    qd = kin.qd[1:]
    P = kin.prog
    # ½ φ̇ᵀ M φ̇ row by row: (M φ̇)_i named, so the sum is O(n²) and not a product of sums
    Mq = [P.let(f"Mqd{i + 1}", sum((dyn.M[i][j] * qd[j] for j in range(n)), ZERO)) for i in range(n)]
    T = 0.5 * sum((Mq[i] * qd[i] for i in range(n)), ZERO)
    U = P.from_sympy(spec.g) * dot(dyn.h[0], kin.gamma[1])
    vertical = vertical_axis(spec)
    momentum, condition = None, None
    if vertical is not False:
        momentum = Mq[0] + dyn.Lam[0][0]
    if vertical is None:
        th = spec.bodies[0].theta
        condition = f"sin(theta1) = 0 (theta1 = {th} is a parameter: conserved only for theta1 = 0 or pi)"
        if 1 in spec.controls:
            condition += ", and never here: joint 1 has a control torque"
    return Integrals(
        T=T,
        U=U,
        energy=T - U,
        momentum=momentum,
        has_energy_integral=not spec.controls,
        has_momentum_integral=vertical is True and 1 not in spec.controls,
        momentum_condition=condition,
    )
