"""The equations of motion as linear functions of the inertial parameters: u = Y(φ, φ̇, φ̈)·π + τ₀.

The left side of (17)–(19) is linear in each body's mass mᵏ, first moment hᵏ = mᵏcᵏ, inertia Aᵏ
about Oᵏ and rotor momentum λᵏ (all in frame k), and in the joints' damping bᵏ: the k-th
equation is eᵏ · (the moment about Oᵏ of the sub-chain k…n's rates of momentum, gravity
included), and each body's share of that is a sum of its parameters times known vectors.  So
the regressor is derived from the same stages as the dynamics: the forward pass of dynamics.py,
here with φ̈ (the angular accelerations εᵏ and the accelerations of Oᵏ, gravity as the base
accelerating up), then for each parameter of body k the force and moment about Oᵏ its unit
value gives,

    m:      F = a_Oᵏ − g γᵏ,                     N = 0
    hᵢ:     F = εᵏ × eᵢ + ωᵏ × (ωᵏ × eᵢ),        N = eᵢ × (a_Oᵏ − g γᵏ)
    Aᵢⱼ:    F = 0,                               N = Eᵢⱼ εᵏ + ωᵏ × Eᵢⱼ ωᵏ      (Eᵢⱼ symmetric)
    λᵢ:     F = 0,                               N = ωᵏ × eᵢ

carried back joint by joint as the composite-body pass of the mass matrix carries its forces
(moment about Oʲ projected on eʲ is row j).  What is not a parameter is τ₀: the springs, the
torque expressions and the external loads' generalized force, known from the spec.

The energy T − U is linear in the same parameters (digest §7: ½mv² + m v·(ω×c) + ½ω·Aω, and
U = g ê⁰₁·Σ mᵏ r_{Gᵏ}); its regressor h(φ, φ̇) with the known e₀ (springs and potential loads)
lets identification use the energy balance, which needs no φ̈.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .algebra import ONE, ZERO
from .dynamics import Dynamics, joint_torque
from .integrals import Integrals, _velocities
from .kinematics import NULL, Kinematics, appends_to
from .program import Program
from ..chainspec.errors import SpecError
from ..chainspec.spec import T, ChainSpec
from .vec3 import add, cross, dot, matvec, scale

# the standard parameters of body k, in this order (Pinocchio's order is m, mc, Ixx Ixy Iyy Ixz Iyz Izz)
INERTIAL = ("m", "hx", "hy", "hz", "Axx", "Axy", "Axz", "Ayy", "Ayz", "Azz")
ROTOR = ("lamx", "lamy", "lamz")
_AXES = "xyz"


@dataclass(frozen=True)
class Parameter:
    """One standard parameter: its name (``m2``, ``hz2``, ``Axy1``, ``lamz2``, ``b1``, ``a1``), the
    body (joint) it belongs to, its kind (``m``, ``h``, ``A``, ``lam``, ``b``, ``a``), the component
    indices (0-based), and its value in the spec (sympy)."""

    name: str
    body: int
    kind: str
    index: tuple
    value: sp.Expr

    @property
    def tex(self) -> str:
        k = self.body
        if self.kind == "m":
            return rf"m^{{{k}}}"
        if self.kind == "h":
            return rf"(mc)^{{{k}}}_{{{self.index[0] + 1}}}"
        if self.kind == "A":
            return rf"A^{{{k}}}_{{{self.index[0] + 1}{self.index[1] + 1}}}"
        if self.kind == "lam":
            return rf"\lambda^{{{k}}}_{{{self.index[0] + 1}}}"
        if self.kind == "a":
            return rf"a^{{{k}}}"
        return rf"b^{{{k}}}"


@dataclass(frozen=True)
class Regressor:
    params: tuple  # Parameter, the columns of Y in order
    Y: tuple  # n rows of len(params) Polys: u = Y π + τ₀ (rows of uncontrolled joints: 0 = Y π + τ₀)
    tau0: tuple  # n Polys: minus the springs, torque expressions and loads' generalized force
    h: tuple  # len(params) Polys: T − U = h π + e₀
    e0: object  # Poly: the springs' and potential loads' −U
    phidd: tuple  # the φ̈ symbols (inputs of Y), 1-based (index 0 None)


def parameters(spec: ChainSpec) -> tuple:
    """The standard parameters of this spec: per body m, h = m c (3), A about Oᵏ (6), λ (3, only
    for a body with a rotor), then the damping bᵏ of each joint the spec gives one, then the
    armature aᵏ of each joint the spec gives one."""
    out = []
    for k, b in enumerate(spec.bodies, start=1):
        h = [sp.expand(b.m * x) for x in b.c]
        out.append(Parameter(f"m{k}", k, "m", (), b.m))
        out += [Parameter(f"h{_AXES[i]}{k}", k, "h", (i,), h[i]) for i in range(3)]
        out += [Parameter(f"A{_AXES[i]}{_AXES[j]}{k}", k, "A", (i, j), b.A[i][j]) for i in range(3) for j in range(i, 3)]
        if any(x != 0 for x in b.lam):
            out += [Parameter(f"lam{_AXES[i]}{k}", k, "lam", (i,), b.lam[i]) for i in range(3)]
    for k, b in enumerate(spec.bodies, start=1):
        if b.damping is not None:
            out.append(Parameter(f"b{k}", k, "b", (), b.damping))
    for k, b in enumerate(spec.bodies, start=1):
        if b.armature != 0:
            out.append(Parameter(f"a{k}", k, "a", (), b.armature))
    return tuple(out)


def check(spec: ChainSpec) -> None:
    """Refuse what has no constant-parameter regressor: a rotor whose momentum changes in time."""
    for k, b in enumerate(spec.bodies, start=1):
        if any(sp.sympify(x).has(T) for x in b.lam):
            raise SpecError(f"body[{k}].lambda", "depends on t: the regressor needs a constant rotor momentum "
                                                 "(identify its inertia and speed apart, or give lambda as a number)")


def _accelerations(spec: ChainSpec, kin: Kinematics, phidd: list) -> tuple[list, list]:
    """εᵏ and a_Oᵏ − g γᵏ in frame k with φ̈ (eqs. (5), (6)); gravity as the base accelerating up."""
    P, J, w, qd, num = kin.prog, kin.joint, kin.omega, kin.qd, kin.prog.from_sympy
    g = num(spec.g)
    eps = [kin.eps0 if kin.platform is not None else NULL]
    a1 = J[1].down(kin.acc0) if kin.platform is not None else NULL
    acc = [None, P.vec("ra1", add(a1, scale(-g, kin.gamma[1])))]
    for k in range(1, kin.n + 1):
        eps.append(P.vec(f"reps{k}", add(J[k].down(eps[k - 1]), cross(w[k], [qd[k], ZERO, ZERO]), [phidd[k], ZERO, ZERO])))
        if k > 1:
            j, sj = k - 1, [num(x) for x in spec.bodies[k - 2].s]
            rel = add(cross(eps[j], sj), cross(w[j], P.vec(f"rws{j}", cross(w[j], sj))))
            acc.append(P.vec(f"ra{k}", J[k].down(add(acc[j], rel))))
    return eps, acc


def _unit(i: int) -> list:
    return [ONE if r == i else ZERO for r in range(3)]


def _wrench(p: Parameter, w: list, eps: list, acc: list) -> tuple[list, list]:
    """Force and moment about Oᵏ (frame k) of a unit value of parameter ``p``."""
    if p.kind == "m":
        return acc, NULL
    if p.kind == "h":
        e = _unit(p.index[0])
        return add(cross(eps, e), cross(w, cross(w, e))), cross(e, acc)
    if p.kind == "A":
        i, j = p.index
        E = [[ONE if (r, c) in ((i, j), (j, i)) else ZERO for c in range(3)] for r in range(3)]
        return NULL, add(matvec(E, eps), cross(w, matvec(E, w)))
    return NULL, cross(w, _unit(p.index[0]))  # λ


def derive(spec: ChainSpec, prog: Program, kin: Kinematics, dyn: Dynamics, ints: Integrals) -> Regressor:
    """Y, τ₀, h and e₀, appended to ``prog`` (after every other stage: their names do not move)."""
    appends_to(prog, kin)
    check(spec)
    P, J, n, num = prog, kin.joint, spec.n, prog.from_sympy
    phidd = [None] + [sp.Symbol(f"phidd_{k}", real=True) for k in range(1, n + 1)]
    eps, acc = _accelerations(spec, kin, [None] + [P.input(phidd[k]) for k in range(1, n + 1)])
    params = parameters(spec)
    Y = [[ZERO] * len(params) for _ in range(n)]
    s = [None] + [[num(x) for x in b.s] for b in spec.bodies]
    for col, p in enumerate(params):
        k = p.body
        if p.kind in ("b", "a"):  # damping bᵏφ̇ᵏ, armature aᵏφ̈ᵏ: joint k alone
            Y[k - 1][col] = kin.qd[k] if p.kind == "b" else P.input(phidd[k])
            continue
        F, N = _wrench(p, kin.omega[k], eps[k], acc[k])
        F, N = P.vec(f"rF{p.name}", F), P.vec(f"rN{p.name}", N)
        Y[k - 1][col] = N[0]
        for j in range(k - 1, 0, -1):  # carried back to Oʲ in frame j
            F = P.vec(f"rF{p.name}in{j}", J[j + 1].up(F))
            N = P.vec(f"rN{p.name}in{j}", add(J[j + 1].up(N), cross(s[j], F)))
            Y[j - 1][col] = N[0]
    # what the spec knows: springs and torque expressions (damping is a parameter), and the loads
    tau0 = []
    for k, b in enumerate(spec.bodies, start=1):
        known = joint_torque(spec, kin, k) + (num(b.damping) * kin.qd[k] if b.damping is not None else ZERO)
        tau0.append(-known - (dyn.Phi[k - 1] if dyn.Phi else ZERO))
    h, e0 = _energy(spec, kin, ints, params)
    return Regressor(params, tuple(tuple(r) for r in Y), tuple(tau0), h, e0, tuple(phidd))


def _energy(spec: ChainSpec, kin: Kinematics, ints: Integrals, params: tuple) -> tuple:
    """T − U = h π + e₀: per body ½v² − g (ê⁰₁·Oᵏ) for m, v·(ω × eᵢ) − g γᵏᵢ for hᵢ, ½ ω·Eᵢⱼω for
    Aᵢⱼ (the velocities absolute, frame k), ½(φ̇ᵏ)² for aᵏ; λ and b do not enter."""
    P, J, num = kin.prog, kin.joint, kin.prog.from_sympy
    g = num(spec.g)
    vel = _velocities(spec, kin, "rabs", transport=False)
    base = num(kin.platform.height) if kin.platform is not None else ZERO
    height = [None, base]  # ê⁰₁·Oᵏ (down), from the platform's point O¹
    for k in range(2, spec.n + 1):
        height.append(P.let(f"rz{k}", height[k - 1] + dot([num(x) for x in spec.bodies[k - 2].s], kin.gamma[k - 1])))
    h = []
    for p in params:
        k = p.body
        w, v = vel[k - 1]
        if p.kind == "m":
            h.append(0.5 * dot(v, v) - g * height[k])
        elif p.kind == "h":
            i = p.index[0]
            h.append(dot(v, cross(w, _unit(i))) - g * kin.gamma[k][i])
        elif p.kind == "A":
            i, j = p.index
            h.append(w[i] * w[j] * (ONE if i != j else 0.5))
        elif p.kind == "a":
            h.append(0.5 * kin.qd[k] * kin.qd[k])
        else:
            h.append(ZERO)
    e0 = ZERO
    for _, term in ints.U_extra:  # springs and potential loads, as the energy's U has them
        e0 = e0 - term
    return tuple(h), e0
