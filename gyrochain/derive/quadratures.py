"""The integrable two-body case (digest §5): reduction to the quadratures (28)–(30).

For n = 2 on a fixed base with the axis l¹ vertical (sin θ¹ = 0, (25)) and no control torque,
ψ = φ¹ is cyclic and the energy (23) and momentum (27) integrals read

    J(φ) ψ̇² + 2 C(φ) ψ̇ φ̇ + A φ̇² = E(φ) = 2 (E + U(φ))            (28)
    J(φ) ψ̇ + C(φ) φ̇ = K(φ) = k − β(φ)                                (29)

with φ = φ², J = M₁₁, C = M₁₂, A = M₂₂ = A²₁₁ (constant), U the force function (22) and
β = ê¹₁·(λ¹ + λ²).  Eliminating ψ̇: (A J − C²) φ̇² = E(φ) J − K², hence (30)

    t = ∫ Φ dφ,   Φ = √((A J − C²)/(E(φ) J − K²)),   ψ − ψ₀ = ∫ (K Φ − C) dφ / J.

The paper writes J, C, E(φ), K(φ) for its frame choices (s¹ along ê¹₂, c²₃ = 0); here they are
the generated mass matrix, force function and gyrostatic moment of the spec, so any offsets and
tensors are allowed.  J, U, β are trigonometric polynomials in φ of degree 2, 1, 1, so
E(φ)J − K² has degree 3: the emitted code finds its Fourier coefficients from 8 samples and its
roots (the turning points) by a walk that cannot step over a root (see gyrochain/kernels/quad.c).

This module only decides whether the case applies and names the five functions of φ; the
numerical method lives in the templates, written once for C and once for Python.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .algebra import Poly
from .dynamics import Dynamics
from .integrals import Integrals, vertical_axis
from .kinematics import Kinematics
from ..chainspec.spec import ChainSpec


@dataclass(frozen=True)
class TwoBody:
    J: Poly  # M₁₁ = J(φ) of (29)
    C: Poly  # M₁₂ = C(φ)
    A: Poly  # M₂₂ = A²₁₁
    U: Poly  # force function of gravity (22), a function of φ alone here
    beta: Poly  # ê¹₁·(λ¹ + λ²), so that K(φ) = k − β(φ)
    nikolai: bool  # Nikolai's balanced gyroscope in a Cardan suspension: c² = 0, s¹ = 0, θ² = π/2

    @property
    def terms(self) -> list[Poly]:
        """The order of the emitted quad_terms_ outputs."""
        return [self.J, self.C, self.A, self.U, self.beta]


def why_not(spec: ChainSpec) -> str | None:
    """None when the quadratures (30) apply to the spec, else the reason, in words."""
    if spec.n != 2:
        return f"n = {spec.n} (they need n = 2)"
    if spec.general:
        from .integrals import energy_reasons

        why = energy_reasons(spec)
        if why:
            return f"{why[0]} does work (they need the energy integral (23) with a fixed base)"
        fields = [f"body[{k}].{key}" for k, b in enumerate(spec.bodies, start=1) for key in ("spring", "force")
                  if (b.spring is not None if key == "spring" else b.forces)]
        return (f"{', '.join(fields) or 'base'}: (30) still holds, but the emitted method needs E(phi) J - K^2 to be "
                "a trigonometric polynomial, which a spring or a force makes it not")
    if spec.controls:
        return "a control torque acts (they need the energy integral)"
    vertical = vertical_axis(spec)
    if vertical is None:
        return f"theta1 = {spec.bodies[0].theta} is a parameter (they need sin theta1 = 0; give theta1 = 0 in the spec)"
    if not vertical:
        return "theta1 is not 0 or pi (the axis l1 is not vertical, (25))"
    return None


def derive(spec: ChainSpec, kin: Kinematics, dyn: Dynamics, ints: Integrals) -> TwoBody | None:
    if why_not(spec) is not None:
        return None
    M = dyn.M
    out = TwoBody(
        J=M[0][0],
        C=M[1][0],
        A=M[1][1],
        U=ints.U,
        beta=dyn.Lam[0][0],
        nikolai=_is_nikolai(spec),
    )
    # ψ is cyclic: nothing of the five may read φ¹ or a velocity (a check of the derivation)
    stray = {kin.phi[1], *kin.phidot[1:]}
    for expr in kin.prog.inline(out.terms):
        if expr.free_symbols & stray:
            raise AssertionError(f"two-body quadratures: a term depends on {expr.free_symbols & stray}")
    return out


def _is_nikolai(spec: ChainSpec) -> bool:
    b1, b2 = spec.bodies
    return (
        all(sp.simplify(x) == 0 for x in (*b1.s, *b2.c))
        and sp.simplify(b2.theta - sp.pi / 2) == 0
    )
