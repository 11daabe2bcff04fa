"""The platform's prescribed motion (digest §1–2): what the general equations (8)–(10) read of it.

The base of the pendulum is body 0, a platform whose motion is given: the point O¹ at r₀(t) in the
fixed frame ê⁰ (ê⁰₁ down, along gravity), and an attitude R(t) = R₁R₂⋯R_m, rotations about
platform-fixed unit axes aᵢ by angles θᵢ(t) applied in order (intrinsic).  R takes platform
components to fixed ones.  Everything below is in the platform frame, the frame the joint axis l¹
is fixed in (the frame "0" of α¹'⁰ in (15)):

    ω⁰ = Wₘ with W₀ = 0, Wᵢ = Rᵢᵀ Wᵢ₋₁ + aᵢ θ̇ᵢ (the angular velocity of each partial frame),
    ε⁰ = dω⁰/dt (components in a frame turning with ω⁰: the absolute derivative, as ω⁰ × ω⁰ = 0),
    v₀ = Rᵀ ṙ₀,  v̇₀ = Rᵀ r̈₀ (the absolute velocity and acceleration of O¹),
    γ⁰ = Rᵀ ê⁰₁ (down), and the height ê⁰₁·r₀ that enters the force function U.

All are sympy expressions of t and the spec's parameters, simplified once here (so that a turntable
about the vertical gives a constant γ⁰ and ω⁰, which the integrals' rules rely on).
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .spec import T, ChainSpec


@dataclass(frozen=True)
class PlatformMotion:
    R: sp.Matrix  # attitude: platform components → fixed components
    omega: tuple  # ω⁰
    eps: tuple  # ε⁰
    vel: tuple  # v₀
    acc: tuple  # v̇₀
    down: tuple  # γ⁰ = ê⁰₁ in the platform frame
    height: sp.Expr  # ê⁰₁ · r₀ (fixed frame)
    position: tuple  # r₀ (fixed frame)

    def to_platform(self, v) -> tuple:
        """Rᵀ v: fixed-frame components of a vector → platform components."""
        return tuple(_simp(sum(self.R[j, i] * v[j] for j in range(3))) for i in range(3))

    @property
    def rotates(self) -> bool:
        return any(x != 0 for x in self.omega)


def _simp(e: sp.Expr) -> sp.Expr:
    e = sp.expand(e)
    if e.has(sp.sin, sp.cos):
        e = sp.trigsimp(e)
    return e


def _rotation(axis, angle) -> sp.Matrix:
    """Rodrigues: the rotation by ``angle`` about the unit vector ``axis``."""
    a = sp.Matrix(axis)
    norm = sp.sqrt(sum(x * x for x in axis))
    a = (a / norm).applyfunc(sp.nsimplify if norm.is_number and not norm.is_Rational else (lambda x: x))
    a = a.applyfunc(sp.simplify)
    c, s = sp.cos(angle), sp.sin(angle)
    K = sp.Matrix([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return (c * sp.eye(3) + s * K + (1 - c) * a * a.T).applyfunc(sp.expand), a


def derive(spec: ChainSpec) -> PlatformMotion | None:
    """The platform's motion, or None for a fixed base (no [base], or one that does not move)."""
    base = spec.base
    if base is None:
        return None
    R = sp.eye(3)
    W = sp.zeros(3, 1)
    for axis, angle in zip(base.axes, base.angles):
        Ri, a = _rotation(axis, angle)
        R = R * Ri
        W = Ri.T * W + a * sp.diff(angle, T)
    R = R.applyfunc(_simp)
    omega = tuple(_simp(x) for x in W)
    eps = tuple(_simp(sp.diff(x, T)) for x in omega)
    r0 = tuple(sp.sympify(x) for x in base.position)
    pm = PlatformMotion(R=R, omega=omega, eps=eps, vel=(), acc=(), down=(), height=_simp(r0[0]), position=r0)
    vel = pm.to_platform([sp.diff(x, T) for x in r0])
    acc = pm.to_platform([sp.diff(x, T, 2) for x in r0])
    down = tuple(_simp(R[0, i]) for i in range(3))
    return PlatformMotion(R=R, omega=omega, eps=eps, vel=vel, acc=acc, down=down, height=pm.height, position=r0)


def is_constant(e) -> bool:
    """Whether a sympy expression (or a tuple of them) is free of t."""
    if isinstance(e, (tuple, list)):
        return all(is_constant(x) for x in e)
    e = sp.sympify(e)
    if not e.has(T):
        return True
    return _simp(sp.diff(e, T)) == 0
