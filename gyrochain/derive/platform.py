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

All are sympy expressions of t and the spec's parameters.  They are not trig-simplified (that
costs minutes for three rotations about oblique axes); a rotation about a coordinate axis gives
exact zeros and ones by itself, so a turntable about the vertical has γ⁰ = (1, 0, 0) exactly.
Whether a quantity is constant or zero (the integrals' rules) is decided by ``is_constant`` and
``is_zero``: exactly where sympy can, else by evaluating at random times and parameter values
(an identity test that a non-identity passes with probability zero).
"""
from __future__ import annotations

from dataclasses import dataclass

import random

import sympy as sp

from ..chainspec.spec import T, ChainSpec


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
        return _transpose_times(self.R, v)

    @property
    def rotates(self) -> bool:
        return any(x != 0 for x in self.omega)


def _simp(e: sp.Expr) -> sp.Expr:
    return sp.expand(e)


def _transpose_times(R, v) -> tuple:
    return tuple(_simp(sum(R[j, i] * v[j] for j in range(3))) for i in range(3))


def _rotation(axis, angle) -> sp.Matrix:
    """Rodrigues: the rotation by ``angle`` about the unit vector ``axis`` (a numeric oblique axis
    is normalized to 30 digits; a coordinate axis stays exact)."""
    a = sp.Matrix(axis)
    norm = sp.sqrt(sum(x * x for x in axis))
    if norm.is_number and sum(1 for x in axis if x != 0) > 1:
        a = a.applyfunc(lambda x: sp.Float((x / norm).evalf(30), 30))
    else:
        a = (a / norm).applyfunc(sp.simplify)
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
    vel = _transpose_times(R, [sp.diff(x, T) for x in r0])
    acc = _transpose_times(R, [sp.diff(x, T, 2) for x in r0])
    down = tuple(_simp(R[0, i]) for i in range(3))
    return PlatformMotion(R=R, omega=omega, eps=eps, vel=vel, acc=acc, down=down, height=_simp(r0[0]), position=r0)


def is_zero(e, samples: int = 4) -> bool:
    """Whether a sympy expression of t and parameters vanishes identically: exactly when it
    expands to 0, else by its value at random (t, parameters) relative to the size of its terms."""
    e = sp.expand(sp.sympify(e))
    if e == 0:
        return True
    if e.is_number:
        return abs(complex(e)) < 1e-25
    syms = sorted(e.free_symbols, key=str)
    rnd = random.Random(20261123)
    f = sp.lambdify(syms, [e, sum(abs(a) for a in sp.Add.make_args(e))], modules="math")
    for _ in range(samples):
        val, size = f(*(rnd.uniform(0.3, 2.0) for _ in syms))
        if abs(val) > 1e-12 * max(size, 1e-300):
            return False
    return True


def is_constant(e) -> bool:
    """Whether a sympy expression (or a tuple of them) is free of t."""
    if isinstance(e, (tuple, list)):
        return all(is_constant(x) for x in e)
    e = sp.sympify(e)
    if not e.has(T):
        return True
    return is_zero(sp.diff(e, T))
