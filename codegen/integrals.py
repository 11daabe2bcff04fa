"""First integrals (digest §4): energy T − U (eq. (23)) and the momentum (27) about the
vertical axis l¹ when θ¹ = 0 (eq. (25))."""
from __future__ import annotations

from dataclasses import dataclass

from .algebra import ZERO, Poly
from .dynamics import Dynamics
from .kinematics import Kinematics, dot
from .spec import ChainSpec


@dataclass(frozen=True)
class Integrals:
    T: Poly  # kinetic energy (21)/2
    U: Poly  # force function of gravity (22); potential energy is −U
    energy: Poly  # T − U (23)
    momentum: Poly | None  # ê¹₁ · K_O¹ (27) = ∂ℒ/∂φ̇¹, only when θ¹ = 0
    has_energy_integral: bool  # T − U is conserved: fixed base and no control torque
    has_momentum_integral: bool  # (27) is conserved: θ¹ = 0 and no torque on joint 1


def derive(spec: ChainSpec, kin: Kinematics, dyn: Dynamics) -> Integrals:
    n = spec.n
    qd = kin.qd[1:]
    P = kin.prog
    # ½ φ̇ᵀ M φ̇ row by row: (M φ̇)_i named, so the sum is O(n²) and not a product of sums
    Mq = [P.let(f"Mqd{i + 1}", sum((dyn.M[i][j] * qd[j] for j in range(n)), ZERO)) for i in range(n)]
    T = 0.5 * sum((Mq[i] * qd[i] for i in range(n)), ZERO)
    U = P.from_sympy(spec.g) * dot(dyn.h[0], kin.gamma[1])
    momentum = None
    if spec.bodies[0].theta == 0:
        momentum = Mq[0] + dyn.Lam[0][0]
    return Integrals(
        T=T,
        U=U,
        energy=T - U,
        momentum=momentum,
        has_energy_integral=not spec.controls,
        has_momentum_integral=momentum is not None and 1 not in spec.controls,
    )
