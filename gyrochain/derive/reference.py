"""Independent numeric reference model: the paper's vector equations (1)–(7), in numpy.

Nothing here uses the sympy derivation.  Every vector is taken into the fixed frame ê⁰
with the direction cosines (11)/(14) (and the platform's attitude R(t)), and equation (3) is
evaluated as printed, with the sums over p ≥ k and q > k written out (summed from the tip):

    eᵏ·{ Σ_{p≥k} [(Aᵖωᵖ+λᵖ)˙ + mᵖ cᵖ × a_{Oᵖ} − Mᵖ] + Σ_{q>k} O^kO^q × (m^q a_{G^q} − F^q) } = Lᵏ

with (Aω+λ)˙ = Aε + ω×(Aω+λ) + λ̊ (7), ω, ε from (1), (5) with the platform's ω⁰, ε⁰, and
a_{O¹} = r̈₀.  The platform's ω⁰, ε⁰ come from Ṙ Rᵀ and its derivative, computed numerically
from the product of the spec's rotations; the spec's own scalar expressions (angles, r₀, λ, loads)
are evaluated with sympy's lambdify and differentiated in t with sympy.diff, nothing more.

This gives the inverse dynamics τ(φ, φ̇, φ̈); the mass matrix and the forces follow from it
(M e_r = τ(φ, φ̇, e_r) − τ(φ, φ̇, 0)).  ``simulate`` integrates the result with scipy's DOP853;
``powers`` splits the rate of T − U into the work of each kind of load (work–energy checks).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import sympy as sp

from ..chainspec.spec import T, ChainSpec, phi_symbol, phidot_symbol


def cross(a, b) -> np.ndarray:
    """a × b over the last axis of 3-vectors (broadcast as np.cross): numpy's own formula, term for
    term, so the same bits, without np.cross's generic axis handling, which took half of this
    model's time on its small arrays (nor its shape and type checks: the reference model's
    vectors are float arrays)."""
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    x = a1 * b2
    x -= a2 * b1
    y = a2 * b0
    y -= a0 * b2
    z = a0 * b1
    z -= a1 * b0
    out = np.empty(x.shape + (3,))
    out[..., 0], out[..., 1], out[..., 2] = x, y, z
    return out


@dataclass(frozen=True)
class NumericChain:
    g: float
    theta: np.ndarray  # (n,)
    offset: np.ndarray  # (n,): the paper's φᵏ = the joint angle + offset
    m: np.ndarray  # (n,)
    c: np.ndarray  # (n, 3)
    A: np.ndarray  # (n, 3, 3) about O^k
    s: np.ndarray  # (n, 3)
    lam: np.ndarray  # (n, 3) (at t = 0 when λ depends on t)
    controls: tuple  # 1-based joints with a torque
    general: object = field(default=None)  # _General: platform, λ(t), loads, springs (None: none)
    armature: np.ndarray | None = None  # (n,): the joints' reflected motor inertias on M's diagonal (None: none)

    @property
    def n(self) -> int:
        return len(self.m)


@dataclass(frozen=True)
class _General:
    rotations: list  # (unit axis, angle(t), angle'(t), angle''(t))
    r0: list  # three callables of t each for r₀, ṙ₀, r̈₀
    lam: list  # per body: (λ(t), λ̊(t)) callables → (3,)
    spring: np.ndarray  # (n,), 0 where none
    rest: np.ndarray
    damping: np.ndarray
    torque: list  # per body: callable (t, φ, φ̇) → float, or None
    forces: list  # per body: list of (point (3,), F(t, φ, φ̇) → (3,), frame, potential)
    moments: list  # per body: list of (M(t, φ, φ̇) → (3,), frame)


def _fn(exprs, subs: dict, n: int):
    """A numpy function f(t, φ, φ̇) of spec expressions (parameters substituted)."""
    args = [T] + [phi_symbol(k) for k in range(1, n + 1)] + [phidot_symbol(k) for k in range(1, n + 1)]
    vals = [sp.sympify(e).subs(subs) for e in exprs]
    f = sp.lambdify(args, vals, modules="numpy")
    return lambda t, phi, phidot: np.array(f(t, *phi, *phidot), dtype=float)


def _general(spec: ChainSpec, subs: dict, ev) -> _General | None:
    if not spec.general:
        return None
    n = spec.n
    base = spec.base
    rotations, r0 = [], [lambda t: np.zeros(3)] * 3
    if base is not None:
        for axis, angle in zip(base.axes, base.angles):
            a = np.array([ev(x) for x in axis])
            a = a / np.linalg.norm(a)
            fs = [_fn([sp.diff(angle, T, d)], subs, n) for d in range(3)]
            rotations.append((a, *(lambda t, f=f: float(f(t, [0] * n, [0] * n)[0]) for f in fs)))
        r0 = [(lambda t, f=_fn([sp.diff(x, T, d) for x in base.position], subs, n): f(t, [0] * n, [0] * n)) for d in range(3)]
    lam = [tuple((lambda t, f=_fn(v, subs, n): f(t, [0] * n, [0] * n)) for v in (b.lam, b.lam_dot)) for b in spec.bodies]
    return _General(
        rotations=rotations,
        r0=r0,
        lam=lam,
        spring=np.array([ev(b.spring) if b.spring is not None else 0.0 for b in spec.bodies]),
        rest=np.array([ev(b.rest) for b in spec.bodies]),
        damping=np.array([ev(b.damping) if b.damping is not None else 0.0 for b in spec.bodies]),
        torque=[_scalar_fn(b.torque, subs, n) if b.torque is not None else None for b in spec.bodies],
        forces=[[(np.array([ev(x) for x in f.point]), _fn(f.vec, subs, n), f.frame, _potential(f)) for f in b.forces]
                for b in spec.bodies],
        moments=[[(_fn(mo.vec, subs, n), mo.frame) for mo in b.moments] for b in spec.bodies],
    )


def _scalar_fn(expr, subs, n):
    f = _fn([expr], subs, n)
    return lambda t, phi, phidot: float(f(t, phi, phidot)[0])


def _potential(load) -> bool:
    """Constant components in the fixed frame: the force has the force function F·r_P."""
    syms = sp.Matrix(load.vec).free_symbols
    return load.frame == "fixed" and not any(s == T or s.name.startswith(("phi_", "phidot_")) for s in syms)


def _skew(v):
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def _vee(W):
    return np.array([W[2, 1], W[0, 2], W[1, 0]])


def platform(ch: NumericChain, t: float):
    """R (platform → fixed), ω⁰, ε⁰ (fixed frame), r₀, ṙ₀, r̈₀ at time t."""
    gen = ch.general
    if gen is None or not gen.rotations:
        R, Rd, Rdd = np.eye(3), np.zeros((3, 3)), np.zeros((3, 3))
    else:
        # product rule over R = R₁R₂⋯R_m, each Rᵢ = exp(θᵢ[aᵢ]×): Ṙᵢ = θ̇ᵢ[a]×Rᵢ, R̈ᵢ = (θ̈ᵢ[a]× + θ̇ᵢ²[a]×²)Rᵢ
        facs = []
        for a, th, thd, thdd in gen.rotations:
            K = _skew(a)
            q = th(t)
            Ri = np.eye(3) + np.sin(q) * K + (1.0 - np.cos(q)) * K @ K
            facs.append((Ri, thd(t) * K @ Ri, (thdd(t) * K + thd(t) ** 2 * K @ K) @ Ri))
        m = len(facs)

        def prod(choice):
            out = np.eye(3)
            for i, f in enumerate(facs):
                out = out @ f[choice.get(i, 0)]
            return out

        R = prod({})
        Rd = sum(prod({i: 1}) for i in range(m))
        Rdd = sum(prod({i: 2}) for i in range(m)) + sum(prod({i: 1, j: 1}) for i in range(m) for j in range(m) if i != j)
    omega0 = _vee(Rd @ R.T)
    eps0 = _vee(Rdd @ R.T + Rd @ Rd.T)
    if gen is None:
        r = (np.zeros(3),) * 3
    else:
        r = tuple(np.asarray(f(t), dtype=float) for f in gen.r0)
    return R, omega0, eps0, r[0], r[1], r[2]


def numeric(spec: ChainSpec, params: dict | None = None) -> NumericChain:
    """Evaluate a spec's fields with values for its symbolic parameters."""
    params = params or {}
    missing = [str(p) for p in spec.params if str(p) not in params]
    if missing:
        raise ValueError(f"values missing for parameters: {', '.join(missing)}")
    subs = {p: params[str(p)] for p in spec.params}

    def ev(x):
        return float(x.subs(subs)) if subs else float(x)

    B = spec.bodies
    general = _general(spec, subs, ev)
    return NumericChain(
        g=ev(spec.g),
        theta=np.array([ev(b.theta) for b in B]),
        offset=np.array([ev(b.offset) for b in B]),
        m=np.array([ev(b.m) for b in B]),
        c=np.array([[ev(x) for x in b.c] for b in B]),
        A=np.array([[[ev(x) for x in row] for row in b.A] for b in B]),
        s=np.array([[ev(x) for x in b.s] for b in B]),
        lam=np.array([[ev(x.subs(T, 0)) for x in b.lam] for b in B]),
        controls=spec.controls,
        general=general,
        armature=np.array([ev(b.armature) for b in B]) if any(b.armature != 0 for b in B) else None,
    )


def frames(ch: NumericChain, phi) -> np.ndarray:
    """αᵏ (eq. 14) for k = 1..n: R[k-1] has rows êᵏᵢ in the fixed frame."""
    R = np.empty((ch.n, 3, 3))
    prev = np.eye(3)
    for k in range(ch.n):
        ct, st = np.cos(ch.theta[k]), np.sin(ch.theta[k])
        cp, sp_ = np.cos(phi[k] + ch.offset[k]), np.sin(phi[k] + ch.offset[k])
        a = np.array([[ct, 0.0, -st], [st * sp_, cp, ct * sp_], [st * cp, -sp_, ct * cp]])  # eq. (15)
        prev = a @ prev
        R[k] = prev
    return R


def world(ch: NumericChain, phi, t: float = 0.0):
    """Fixed-frame e, c, s, λ, A of every body and the joint points Oᵏ, at (φ, t)."""
    R0, omega0, eps0, r0, v0, a0 = platform(ch, t)
    R = frames(ch, phi) @ R0.T  # rows êᵏᵢ in the fixed frame: αᵏ'⁰ of (14) after the platform's Rᵀ
    e = R[:, 0, :]  # e^k = ê^k_1
    c = np.einsum("kij,ki->kj", R, ch.c)  # c^k in the fixed frame
    s = np.einsum("kij,ki->kj", R, ch.s)
    lam_b, lamdot_b = _lam(ch, t)
    lam = np.einsum("kij,ki->kj", R, lam_b)
    A = np.einsum("kia,kij,kjb->kab", R, ch.A, R)
    # O^1 is at r₀(t); O^k = O^1 + Σ_{l<k} s^l
    O = np.zeros((ch.n, 3))
    O[0] = r0
    for k in range(1, ch.n):
        O[k] = O[k - 1] + s[k - 1]
    return e, c, s, lam, A, O


def _lam(ch: NumericChain, t: float):
    """λᵏ and λ̊ᵏ (body components) at t."""
    if ch.general is None:
        return ch.lam, np.zeros_like(ch.lam)
    return (np.array([f[0](t) for f in ch.general.lam]), np.array([f[1](t) for f in ch.general.lam]))


def _before(a: np.ndarray) -> np.ndarray:
    """Row k: the sum of the rows < k (over the bodies' axis, the last but one)."""
    sums = np.cumsum(a, axis=-2)
    return np.concatenate([np.zeros_like(sums[..., :1, :]), sums[..., :-1, :]], axis=-2)


def _motion(ch: NumericChain, phi, phidot, phiddot, t: float) -> dict:
    """Every fixed-frame vector of the chain's motion at (φ, φ̇, φ̈, t): eqs. (1), (5), (6).
    φ̈ may hold several rows (m, n): then the accelerations carry that axis first (the mass
    matrix's columns at once); the rest depends on (φ, φ̇, t) only."""
    R0, omega0, eps0, r0, v0, a0 = platform(ch, t)
    e, c, s, lam, A, O = world(ch, phi, t)
    R = frames(ch, phi) @ R0.T
    omega = omega0 + np.cumsum(e * phidot[:, None], axis=0)  # eq. (1)
    # eq. (5): ε^k = ε⁰ + Σ_{p≤k} (e^p φ̈^p + ω^{p-1} × e^p φ̇^p)
    omega_prev = np.vstack([omega0, omega[:-1]])
    eps = eps0 + np.cumsum(e * phiddot[..., None] + cross(omega_prev, e) * phidot[:, None], axis=-2)
    # acceleration of O^p: r̈₀ + Σ_{l<p} (ε^l × s^l + ω^l × (ω^l × s^l)), eq. (6)
    terms = cross(eps, s) + cross(omega, cross(omega, s))
    aO = a0 + _before(terms)
    vO = v0 + _before(cross(omega, s))
    aG = aO + cross(eps, c) + cross(omega, cross(omega, c))
    _, lamdot_b = _lam(ch, t)
    lamdot = np.einsum("kij,ki->kj", R, lamdot_b)
    return dict(R=R, e=e, c=c, s=s, lam=lam, lamdot=lamdot, A=A, O=O, omega=omega, eps=eps, aO=aO, vO=vO, aG=aG,
                omega0=omega0, v0=v0)


def _loads(ch: NumericChain, mo: dict, t, phi, phidot):
    """Per body: the external force, its moment about Oᵏ (fixed frame), and the power of the
    loads without a force function (follower, varying, moments)."""
    n = ch.n
    F, N, power = np.zeros((n, 3)), np.zeros((n, 3)), 0.0
    gen = ch.general
    if gen is None:
        return F, N, power
    for k in range(n):
        Rk = mo["R"][k]
        for point, fn, frame, potential in gen.forces[k]:
            v = fn(t, phi, phidot)
            Fk = Rk.T @ v if frame == "body" else v
            r = Rk.T @ point
            F[k] += Fk
            N[k] += cross(r, Fk)
            if not potential:
                power += Fk @ (mo["vO"][k] + cross(mo["omega"][k], r))
        for fn, frame in gen.moments[k]:
            v = fn(t, phi, phidot)
            Mk = Rk.T @ v if frame == "body" else v
            N[k] += Mk
            power += Mk @ mo["omega"][k]
    return F, N, power


def joint_torque_terms(ch: NumericChain, t, phi, phidot) -> tuple:
    """(spring torques, the other joint torques: damping and torque expressions), per joint."""
    gen = ch.general
    n = ch.n
    if gen is None:
        return np.zeros(n), np.zeros(n)
    spring = -gen.spring * (phi - gen.rest)
    other = -gen.damping * phidot
    for k in range(n):
        if gen.torque[k] is not None:
            other[k] += gen.torque[k](t, phi, phidot)
    return spring, other


def _wrenches(ch: NumericChain, phi, phidot, phiddot, t: float):
    """The vector of eq. (3) before its projection on eᵏ, for every k: the moment about Oᵏ that
    the rest of the system must apply to the sub-chain k…n; and the force on the whole chain."""
    n = ch.n
    mo = _motion(ch, phi, phidot, phiddot, t)
    c, A, O, omega, eps, lam = mo["c"], mo["A"], mo["O"], mo["omega"], mo["eps"], mo["lam"]
    down = np.array([1.0, 0.0, 0.0])
    Aw = np.einsum("kab,kb->ka", A, omega)
    dH = np.einsum("kab,...kb->...ka", A, eps) + cross(omega, Aw + lam) + mo["lamdot"]  # eq. (7)
    Mg = cross(c, ch.g * ch.m[:, None] * down)  # moment of gravity about O^p
    Fg = ch.g * ch.m[:, None] * down
    Fx, Nx, _ = _loads(ch, mo, t, phi, phidot)
    # Σ_{p≥k} X_p + Σ_{q>k} (O^q − O^k) × Y_q, as suffix sums from the tip (O(n), not O(n²)):
    # Σ_{p≥k} X_p + Σ_{q>k} O^q × Y_q − O^k × Σ_{q>k} Y_q
    X = dH + ch.m[:, None] * cross(c, mo["aO"]) - Mg - Nx
    Y = ch.m[:, None] * mo["aG"] - Fg - Fx
    tip = lambda a: np.flip(np.cumsum(np.flip(a, -2), axis=-2), -2)  # noqa: E731  (row k: the sum over rows ≥ k)
    after = lambda a: np.concatenate([tip(a)[..., 1:, :], np.zeros_like(a[..., :1, :])], axis=-2)  # noqa: E731  (rows > k)
    totals = tip(X) + after(cross(O, Y)) - cross(O, after(Y))
    force = np.sum(ch.m[:, None] * mo["aG"] - Fg - Fx, axis=-2)
    return totals, force, mo


def inverse_dynamics(ch: NumericChain, phi, phidot, phiddot, torque=None, t: float = 0.0) -> np.ndarray:
    """Residual of eq. (3) per joint: LHS − (external moments) − Lᵏ; zero on a motion.  ``torque``
    are the control torques; springs, dampers and torque expressions of the spec are added here."""
    totals, _, mo = _wrenches(ch, np.asarray(phi, float), np.asarray(phidot, float), np.asarray(phiddot, float), t)
    tau = np.einsum("ki,...ki->...k", mo["e"], totals)
    spring, other = joint_torque_terms(ch, t, np.asarray(phi, float), np.asarray(phidot, float))
    tau = tau - spring - other
    if ch.armature is not None:  # a motor's reflected inertia: aᵏ φ̈ᵏ in joint k alone
        tau = tau + ch.armature * np.asarray(phiddot, float)
    if torque is not None:
        tau = tau - torque
    return tau


def joint_torques(ch: NumericChain, u) -> np.ndarray:
    L = np.zeros(ch.n)
    if ch.controls:
        u = np.zeros(len(ch.controls)) if u is None else np.asarray(u, dtype=float)
        for i, k in enumerate(ch.controls):
            L[k - 1] = u[i]
    return L


def mass_matrix(ch: NumericChain, phi) -> np.ndarray:
    """M(φ) as the differences of the inverse dynamics at unit φ̈, without gravity (which M does not
    hold: with g = 1e20 its terms would swamp the differences)."""
    import dataclasses

    n = ch.n
    zero = np.zeros(n)
    ch = dataclasses.replace(ch, g=0.0)
    tau = inverse_dynamics(ch, phi, zero, np.vstack([zero, np.eye(n)]))  # rows: φ̈ = 0, then each unit φ̈
    return (tau[1:] - tau[0]).T


def forces(ch: NumericChain, x, u=None, t: float = 0.0) -> np.ndarray:
    """f of M φ̈ = f."""
    n = ch.n
    x = np.asarray(x, dtype=float)
    return joint_torques(ch, u) - inverse_dynamics(ch, x[:n], x[n:], np.zeros(n), t=t)


def qdd(ch: NumericChain, x, u=None, t: float = 0.0) -> np.ndarray:
    x = np.asarray(x, dtype=float)
    return np.linalg.solve(mass_matrix(ch, x[: ch.n]), forces(ch, x, u, t))


def rhs(ch: NumericChain, t, x, u=None) -> np.ndarray:
    x = np.asarray(x, dtype=float)
    return np.concatenate([x[ch.n :], qdd(ch, x, u, t)])


def energy(ch: NumericChain, x, t: float = 0.0) -> float:
    """T − U with T of digest §7 (absolute velocities) and U = g ê⁰₁ · Σ mᵏ r_{Gᵏ}, plus the
    springs' −½k(φ − rest)² and F·r_P of every constant fixed-direction force."""
    n = ch.n
    x = np.asarray(x, dtype=float)
    mo = _motion(ch, x[:n], x[n:], np.zeros(n), t)
    omega, vO, c, A, O = mo["omega"], mo["vO"], mo["c"], mo["A"], mo["O"]
    T = sum(
        0.5 * ch.m[k] * vO[k] @ vO[k] + ch.m[k] * vO[k] @ cross(omega[k], c[k]) + 0.5 * omega[k] @ A[k] @ omega[k]
        for k in range(n)
    )
    if ch.armature is not None:
        T += 0.5 * float(ch.armature @ x[n:] ** 2)
    return float(T - _force_function(ch, x, t, mo))


def potential(ch: NumericChain, x, t: float = 0.0) -> float:
    """The force function U of energy(): T − U is the energy, −U the potential energy."""
    n = ch.n
    x = np.asarray(x, dtype=float)
    return _force_function(ch, x, t, _motion(ch, x[:n], x[n:], np.zeros(n), t))


def _force_function(ch: NumericChain, x, t: float, mo: dict) -> float:
    n = ch.n
    c, O = mo["c"], mo["O"]
    U = ch.g * sum(ch.m[k] * (O[k][0] + c[k][0]) for k in range(n))
    gen = ch.general
    if gen is not None:
        U -= 0.5 * np.sum(gen.spring * (x[:n] - gen.rest) ** 2)
        for k in range(n):
            for point, fn, frame, potential in gen.forces[k]:
                if potential:
                    U += fn(t, x[:n], x[n:]) @ (O[k] + mo["R"][k].T @ point)
    return float(U)


def powers(ch: NumericChain, t, x, u=None) -> dict:
    """The rate of work of each kind of load along a motion through (t, x), at its φ̈:
    ``joints`` (control torques, damping, torque expressions; springs are in U), ``loads``
    (forces without a force function, moments), ``rotors`` (−Σ λ̊ᵏ·ωᵏ, the motors spinning the
    rotors up) and ``platform`` (the platform's force and moment on body 1 at O¹, F·v₀ + M·ω⁰).
    Their sum is d(T − U)/dt."""
    n = ch.n
    x = np.asarray(x, dtype=float)
    phi, phidot = x[:n], x[n:]
    acc = qdd(ch, x, u, t)
    totals, force, mo = _wrenches(ch, phi, phidot, acc, t)
    _, other = joint_torque_terms(ch, t, phi, phidot)
    _, _, p_loads = _loads(ch, mo, t, phi, phidot)
    return dict(
        joints=float((joint_torques(ch, u) + other) @ phidot),
        loads=float(p_loads),
        rotors=float(-np.einsum("ki,ki->", mo["lamdot"], mo["omega"])),
        platform=float(force @ mo["v0"] + totals[0] @ mo["omega0"]),
    )


def momentum(ch: NumericChain, x, t: float = 0.0) -> float:
    """ê¹₁ · K_{O¹} of eq. (24): the angular momentum about O¹ (absolute velocities) projected on
    the axis l¹."""
    n = ch.n
    x = np.asarray(x, dtype=float)
    mo = _motion(ch, x[:n], x[n:], np.zeros(n), t)
    omega, vO, c, A, O, lam, e = mo["omega"], mo["vO"], mo["c"], mo["A"], mo["O"], mo["lam"], mo["e"]
    K = np.zeros(3)
    for p in range(n):
        vG = vO[p] + cross(omega[p], c[p])
        K += A[p] @ omega[p] + lam[p] + ch.m[p] * cross(O[p] - O[0], vG) + ch.m[p] * cross(c[p], vO[p])
    return float(e[0] @ K) + (float(ch.armature[0] * x[n]) if ch.armature is not None else 0.0)


def simulate(ch: NumericChain, x0, t_eval, u=None, rtol=1e-12, atol=1e-12):
    """Integrate the reference model with DOP853; returns an array (len(t_eval), 2n)."""
    from scipy.integrate import solve_ivp

    t_eval = np.asarray(t_eval, dtype=float)
    sol = solve_ivp(
        lambda t, x: rhs(ch, t, x, u), (t_eval[0], t_eval[-1]), np.asarray(x0, float),
        method="DOP853", t_eval=t_eval, rtol=rtol, atol=atol,
    )
    if not sol.success:
        raise RuntimeError(f"reference integration failed: {sol.message}")
    return sol.y.T


def regressor(ch: NumericChain, params, phi, phidot, phiddot, t: float = 0.0) -> np.ndarray:
    """Y of τ = Y π (the inverse dynamics' part linear in the standard parameters), column by
    column from the fixed-frame vectors of ``_motion``: each parameter's unit value gives body k
    a force and a moment about Oᵏ, and row j is eʲ · (that moment carried to Oʲ).  ``params``:
    (kind, body, index) of each column (regressor.parameters): kind m, h, A (body-frame
    components), lam, b (damping) or a (armature)."""
    phi, phidot, phiddot = (np.asarray(v, dtype=float) for v in (phi, phidot, phiddot))
    mo = _motion(ch, phi, phidot, phiddot, t)
    R, O, omega, eps, e = mo["R"], mo["O"], mo["omega"], mo["eps"], mo["e"]
    acc = mo["aO"] - ch.g * np.array([1.0, 0.0, 0.0])  # gravity: the base accelerating up
    Y = np.zeros((ch.n, len(params)))
    for col, (kind, k, index) in enumerate(params):
        p = k - 1
        F = N = np.zeros(3)
        if kind in ("b", "a"):
            Y[p, col] = (phidot if kind == "b" else phiddot)[p]
            continue
        if kind == "m":
            F = acc[p]
        elif kind == "h":
            u = R[p][index[0]]
            F = cross(eps[p], u) + cross(omega[p], cross(omega[p], u))
            N = cross(u, acc[p])
        elif kind == "A":
            i, j = index
            E = np.outer(R[p][i], R[p][j])
            A = E + E.T if i != j else E
            N = A @ eps[p] + cross(omega[p], A @ omega[p])
        else:
            N = cross(omega[p], R[p][index[0]])
        for j in range(p + 1):
            Y[j, col] = e[j] @ (N + cross(O[p] - O[j], F))
    return Y
