"""First integrals (digest §4): energy T − U (eq. (23)) and the momentum (27) about the axis l¹.

Which of them exist is decided here, per spec, from the paper's conditions (the base is always
fixed in our spec format):

* energy (23): no control torque acts (any θ¹);
* momentum (27), ∂ℒ/∂φ̇¹ = ê¹₁·K_O¹: the axis l¹ is vertical, (25), i.e. sin θ¹ = 0 (θ¹ = 0 as in
  the paper, or θ¹ = π, the axis pointing up), and no torque acts in joint 1.  A torque in a
  later joint is internal (26).

When θ¹ is given by a parameter, whether (25) holds depends on its value: the momentum function
is still emitted (it is ∂ℒ/∂φ̇¹ for any θ¹) and the condition is stated instead of guessed.

The general case (a moving platform, loads, springs, dampers, λ(t)) adds, with
ℒ = Σ[Tₖ + λᵏ·ωᵏ] + U (digest §7) and U the force function of gravity, of the springs
(−½kᵏ(φᵏ − restᵏ)²) and of every constant force of fixed direction (F·r_P):

* energy T − U is conserved only when nothing else does work: a moving platform, a λ that changes
  in time, a follower ("body") force, a moment, a force that varies, damping, a torque expression
  or a control torque each remove it (``energy_reasons`` names the fields);
* the Jacobi integral h = T₂ − T₀ − U − Σλᵏ·ω⁰ (T₂ = ½φ̇ᵀMφ̇, T₀ the kinetic energy of the chain
  carried with the platform at rest in it) is h = φ̇·∂ℒ/∂φ̇ − ℒ, conserved when ℒ has no explicit t:
  the platform moves, but its ω⁰, v₀, the direction of gravity and the height of O¹ seen in the
  platform frame stay constant (a table turning uniformly about the vertical), and no other load
  does work;
* the momentum (27) = ê¹₁·K_O¹ (absolute velocities) stays an integral when l¹ keeps a fixed
  vertical direction (sin θ¹ = 0, the platform turns only about it and O¹ moves only along it), no
  torque acts in joint 1, and every external load has no moment about the vertical.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from . import platform as platform_motion
from .algebra import ZERO, Poly
from .dynamics import Dynamics
from .kinematics import NULL, Kinematics, appends_to
from .program import Program
from .vec3 import add, cross, dot, matvec, scale
from ..chainspec.spec import T as TIME, ChainSpec


@dataclass(frozen=True)
class Integrals:
    T: Poly  # kinetic energy (21)/2
    U: Poly  # force function of gravity (22); potential energy is −U
    energy: Poly  # T − U (23)
    momentum: Poly | None  # ∂ℒ/∂φ̇¹ = ê¹₁ · K_O¹ (27); None when l¹ is surely not vertical
    has_energy_integral: bool  # T − U is conserved: fixed base and no control torque
    has_momentum_integral: bool  # (27) is conserved for every parameter value
    momentum_condition: str | None = None  # when (25) depends on a parameter: the condition, in words
    jacobi: Poly | None = None  # T₂ − T₀ − U − Σλ·ω⁰ where it is an integral
    energy_reasons: tuple = ()  # the fields that remove the energy integral
    momentum_reasons: tuple = ()  # the fields that remove the momentum integral (l¹ vertical)
    U_extra: tuple = ()  # (what, Poly) of U beyond gravity: springs, constant fixed forces (LaTeX)
    # a long chain on a fixed base (the loop form): per joint k, in frame k, (ωᵏ, v_Oᵏ, Kᵏ, Pᵏ) with
    # Kᵏ, Pᵏ the angular momentum about Oᵏ (rotors included) and the momentum of the sub-chain k…n
    subchain: tuple = ()


def vertical_axis(spec: ChainSpec) -> bool | None:
    """Condition (25) for l¹: True, False, or None when it depends on a parameter."""
    s = sp.simplify(sp.sin(spec.bodies[0].theta))
    if s == 0:
        return True
    if s.is_number:
        return False
    return None


def _has_state(e) -> bool:
    return any(s.name.startswith(("phi_", "phidot_")) or s == TIME for s in sp.sympify(e).free_symbols)


def potential_force(load) -> bool:
    """A force with a force function: fixed direction and constant components (U += F·r_P)."""
    return load.is_force and load.frame == "fixed" and not any(_has_state(x) for x in load.vec)


def energy_reasons(spec: ChainSpec) -> list[str]:
    """The fields that do work other than gravity, springs and constant fixed-direction forces."""
    out = []
    if spec.base is not None and spec.base.moves:
        out.append("base (the platform moves)")
    if spec.controls:
        out.append("control torques (joints " + ", ".join(map(str, spec.controls)) + ")")
    for k, b in enumerate(spec.bodies, start=1):
        if any(x.has(TIME) for x in b.lam):
            out.append(f"body[{k}].lambda (changes in time)")
        if b.damping is not None:
            out.append(f"body[{k}].damping")
        if b.torque is not None:
            out.append(f"body[{k}].torque")
        for i, f in enumerate(b.forces, start=1):
            if not potential_force(f):
                out.append(f"body[{k}].force[{i}] (" + ("a follower force" if f.frame == "body" else "it varies") + ")")
        for i, _ in enumerate(b.moments, start=1):
            out.append(f"body[{k}].moment[{i}]")
    return out


def _momentum_reasons(spec: ChainSpec, pm) -> list[str]:
    """What keeps (27) from being conserved when l¹ is vertical in the platform (sin θ¹ = 0)."""
    out = []
    if pm is not None:
        zero = platform_motion.is_zero
        if not (zero(pm.down[1]) and zero(pm.down[2])):
            out.append("base.rotation (l1 does not stay vertical)")
        elif not (zero(pm.omega[1]) and zero(pm.omega[2])):
            out.append("base.rotation (the platform turns about another axis than l1)")
        if not all(zero(v) for v in pm.vel[1:]):
            out.append("base.position (O1 moves across the axis l1, not only along it)")
    b1 = spec.bodies[0]
    if b1.control:
        out.append("control torque in joint 1")
    for key in ("spring", "damping", "torque"):
        if getattr(b1, key) is not None:
            out.append(f"body[1].{key}")
    for k, b in enumerate(spec.bodies, start=1):
        for i, f in enumerate(b.forces, start=1):
            vert = pm.to_platform(f.vec) if (pm is not None and f.frame == "fixed") else f.vec
            if f.frame == "body" or not all(platform_motion.is_zero(x) for x in vert[1:]):
                out.append(f"body[{k}].force[{i}] (a moment about the vertical)")
        for i, mo in enumerate(b.moments, start=1):
            vert = pm.to_platform(mo.vec) if (pm is not None and mo.frame == "fixed") else mo.vec
            if mo.frame == "body" or not platform_motion.is_zero(vert[0]):
                out.append(f"body[{k}].moment[{i}] (a moment about the vertical)")
    return out


def _jacobi_exists(spec: ChainSpec, pm) -> bool:
    """ℒ without explicit t although the platform moves (a uniformly turning table)."""
    if pm is None or not spec.base.moves:
        return False
    if [r for r in energy_reasons(spec) if not r.startswith("base")]:
        return False
    const = platform_motion.is_constant
    if not (const(pm.omega) and const(pm.down) and const(pm.vel) and const(pm.height)):
        return False
    for b in spec.bodies:
        for f in b.forces:  # potential forces: F·r_P = F·r₀ + (RᵀF)·(r_P − r₀)_platform
            if not (const(pm.to_platform(f.vec)) and const(sum(a * b for a, b in zip(f.vec, pm.position)))):
                return False
    return True


def _velocities(spec: ChainSpec, kin: Kinematics, tag: str, transport: bool) -> tuple:
    """ωᵏ and v_Oᵏ (absolute, frame k) of every body; ``transport``: with φ̇ = 0, the motion the
    platform alone gives the chain."""
    P, J, num = kin.prog, kin.joint, kin.prog.from_sympy
    w, v, out = kin.omega[0], kin.vel0, []
    for k in range(1, spec.n + 1):
        if k > 1:
            s = [num(x) for x in spec.bodies[k - 2].s]
            v = add(v, cross(w, s))
        if transport:
            w = P.vec(f"{tag}w{k}", J[k].down(w))
        else:
            w = kin.omega[k]
        v = P.vec(f"{tag}v{k}", J[k].down(v))
        out.append((w, v))
    return out


def _kinetic(spec: ChainSpec, kin: Kinematics, vel) -> Poly:
    """Σₖ ½mᵏ v_Oᵏ² + mᵏ v_Oᵏ·(ωᵏ × cᵏ) + ½ ωᵏ·Aᵏωᵏ (digest §7)."""
    num = kin.prog.from_sympy
    T = ZERO
    for b, (w, v) in zip(spec.bodies, vel):
        m, c = num(b.m), [num(x) for x in b.c]
        A = [[num(x) for x in row] for row in b.A]
        T = T + 0.5 * m * dot(v, v) + m * dot(v, cross(w, c)) + 0.5 * dot(w, matvec(A, w))
    return T


def _abs_momentum(spec: ChainSpec, kin: Kinematics, vel) -> list:
    """(Kᵏ, Pᵏ) per joint with absolute velocities: the angular momentum (rotors included) of the
    sub-chain k…n about Oᵏ and its momentum, carried back joint by joint; ê¹₁·K¹ is (27)."""
    P, J, num = kin.prog, kin.joint, kin.prog.from_sympy
    K = Pm = None
    out = []
    for k in range(spec.n, 0, -1):
        b = spec.bodies[k - 1]
        w, v = vel[k - 1]
        m, c, s = num(b.m), [num(x) for x in b.c], [num(x) for x in b.s]
        A = [[num(x) for x in row] for row in b.A]
        lam = [num(x) for x in b.lam]
        Kk = add(matvec(A, w), lam, scale(m, cross(c, v)))
        Pk = scale(m, add(v, cross(w, c)))
        if K is not None:
            Kin, Pin = J[k + 1].up(K), J[k + 1].up(Pm)
            Kk, Pk = add(Kk, Kin, cross(s, Pin)), add(Pk, Pin)
        K, Pm = P.vec(f"Kabs{k}", Kk), P.vec(f"Pabs{k}", Pk)
        out.append((K, Pm))
    return out[::-1]


def _potential(spec: ChainSpec, kin: Kinematics, dyn: Dynamics) -> list:
    """(what, Poly) of the force function beyond gravity: springs and constant fixed forces."""
    P, J, num = kin.prog, kin.joint, kin.prog.from_sympy
    out = []
    for k, b in enumerate(spec.bodies, start=1):
        if b.spring is not None:
            d = kin.prog.input(kin.phi[k]) - num(b.rest)
            out.append((f"spring {k}", -0.5 * num(b.spring) * d * d))
    d = NULL  # O¹Oᵏ in frame k
    pm = kin.platform
    if not any(potential_force(f) for b in spec.bodies for f in b.forces):
        return out
    for k, b in enumerate(spec.bodies, start=1):
        if k > 1:
            d = P.vec(f"dO{k}", J[k].down(add(d, [num(x) for x in spec.bodies[k - 2].s])))
        for i, f in enumerate(b.forces, start=1):
            if potential_force(f):
                Fk = dyn.force_vectors[k - 1][i - 1]  # Fᵏ in frame k, as the dynamics turned it
                term = dot(Fk, add(d, [num(x) for x in f.point]))
                if pm is not None:
                    term = term + num(sum(a * r for a, r in zip(f.vec, pm.position)))
                out.append((f"force {k}.{i}", term))
    return out


def derive(spec: ChainSpec, prog: Program, kin: Kinematics, dyn: Dynamics) -> Integrals:
    """T, U, the energy (23), the momentum (27) and Jacobi's integral, appended to ``prog``, and
    whether each is an integral of this spec (with the reasons when not)."""
    appends_to(prog, kin)
    n = spec.n
    qd = kin.qd[1:]
    P = prog
    pm = kin.platform
    subchain = ()
    if dyn.loops is not None and pm is None:
        # a long chain on a fixed base: T and the sub-chains' momenta by O(n) recursions in frame k
        # (the velocities are the absolute ones), not by M φ̇ (O(n²))
        vel = _velocities(spec, kin, "abs", transport=False)
        KP = _abs_momentum(spec, kin, vel)
        subchain = tuple((w, v, K, Pm) for (w, v), (K, Pm) in zip(vel, KP))
        Mq, T2 = None, _kinetic(spec, kin, vel)
    elif dyn.loops is not None:  # on a platform: T₂ (Jacobi's integral) by loopform.py, in frame 0
        Mq, T2 = None, dyn.loops.T2
    else:  # ½ φ̇ᵀ M φ̇ row by row: (M φ̇)_i named, so the sum is O(n²) and not a product of sums
        Mq = [P.let(f"Mqd{i + 1}", sum((dyn.M[i][j] * qd[j] for j in range(n)), ZERO)) for i in range(n)]
        T2 = 0.5 * sum((Mq[i] * qd[i] for i in range(n)), ZERO)
    U = P.from_sympy(spec.g) * dot(dyn.h[0], kin.gamma[1])
    extra = _potential(spec, kin, dyn)
    if pm is not None:
        mtot = P.from_sympy(sum(b.m for b in spec.bodies))
        U = U + P.from_sympy(spec.g) * mtot * P.from_sympy(pm.height)
    for _, term in extra:
        U = U + term
    if pm is None:
        T = T2
    else:  # the absolute velocities, and the motors' ½aᵏ(φ̇ᵏ)² (M's diagonal alone: in T₂ already)
        vel = _velocities(spec, kin, "abs", transport=False)
        T = _kinetic(spec, kin, vel) + 0.5 * sum((a * q * q for a, q in zip(dyn.armature, qd)), ZERO)
    vertical = vertical_axis(spec)
    momentum, condition = None, None
    if vertical is not False:
        if subchain:
            momentum = subchain[0][2][0]
        else:
            momentum = Mq[0] + dyn.Lam[0][0] if pm is None else \
                _abs_momentum(spec, kin, vel)[0][0][0] + (dyn.armature[0] * qd[0] if dyn.armature else ZERO)
    if vertical is None:
        th = spec.bodies[0].theta
        condition = f"sin(theta1) = 0 (theta1 = {th} is a parameter: conserved only for theta1 = 0 or pi)"
        if 1 in spec.controls:
            condition += ", and never here: joint 1 has a control torque"
    reasons = energy_reasons(spec)
    m_reasons = _momentum_reasons(spec, pm) if vertical is not False else []
    jacobi = None
    if _jacobi_exists(spec, pm):
        tr = _velocities(spec, kin, "tr", transport=True)
        lam_w = ZERO
        for b, (w, _v) in zip(spec.bodies, tr):
            lam_w = lam_w + dot([P.from_sympy(x) for x in b.lam], w)
        jacobi = T2 - _kinetic(spec, kin, tr) - U - lam_w
    return Integrals(
        T=T,
        U=U,
        energy=T - U,
        momentum=momentum,
        has_energy_integral=not reasons,
        has_momentum_integral=vertical is True and not m_reasons,
        momentum_condition=condition,
        jacobi=jacobi,
        energy_reasons=tuple(reasons),
        momentum_reasons=tuple(m_reasons),
        U_extra=tuple(extra),
        subchain=subchain,
    )


def energy_verdict(spec: ChainSpec, ints: Integrals) -> str:
    """What generate's report and the header say of the energy (23), from the facts (the LaTeX
    states the same in its words: printers/texintegrals.py statements)."""
    if not ints.has_energy_integral and all(r.startswith("control torques") for r in ints.energy_reasons):
        return ("energy T - U (23): not conserved for every input: conserved when the control torques are 0, in general "
                f"dE/dt = sum L^k phidot^k over the controlled joint{'s' if len(spec.controls) > 1 else ''} {', '.join(map(str, spec.controls))}")
    if not spec.general:
        return "energy T - U (23): conserved (fixed base, no control torque)"
    if ints.has_energy_integral:
        why = "U includes " + ", ".join(w for w, _ in ints.U_extra) if ints.U_extra else "no load but gravity does work"
        return f"energy T - U (23): conserved ({why})"
    return "energy T - U (23): not conserved: " + "; ".join(ints.energy_reasons) + " removed it"


def momentum_verdict(ints: Integrals) -> str:
    """What generate's report and the header say of the momentum (27)."""
    if ints.momentum_condition:
        return f"momentum (27): conserved only if {ints.momentum_condition}"
    if ints.momentum is None:
        return "momentum (27): not an integral (theta1 is not 0 or pi: the axis l1 is not vertical)"
    if ints.has_momentum_integral:
        return "momentum (27): conserved (axis l1 vertical, no torque in joint 1)"
    if ints.momentum_reasons:
        return "momentum (27): not conserved: " + "; ".join(ints.momentum_reasons)
    return "momentum (27): not conserved (a control torque acts in joint 1)"
