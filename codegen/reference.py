"""Independent numeric reference model: the paper's vector equations (1)–(4), in numpy.

Nothing here uses the sympy derivation.  Every vector is taken into the fixed frame ê⁰
with the direction cosines (11)/(14), and equation (3) is evaluated as printed, with the
sums over p ≥ k and q > k written out:

    eᵏ·{ Σ_{p≥k} [(Aᵖωᵖ+λᵖ)˙ + mᵖ cᵖ × a_{Oᵖ} − Mᵖ] + Σ_{q>k} O^kO^q × (m^q a_{G^q} − F^q) } = Lᵏ

This gives the inverse dynamics τ(φ, φ̇, φ̈); the mass matrix and the forces follow from it
(M e_r = τ(φ, φ̇, e_r) − τ(φ, φ̇, 0)).  ``simulate`` integrates the result with scipy's DOP853.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .spec import ChainSpec


@dataclass(frozen=True)
class NumericChain:
    g: float
    theta: np.ndarray  # (n,)
    m: np.ndarray  # (n,)
    c: np.ndarray  # (n, 3)
    A: np.ndarray  # (n, 3, 3) about O^k
    s: np.ndarray  # (n, 3)
    lam: np.ndarray  # (n, 3)
    controls: tuple  # 1-based joints with a torque

    @property
    def n(self) -> int:
        return len(self.m)


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
    return NumericChain(
        g=ev(spec.g),
        theta=np.array([ev(b.theta) for b in B]),
        m=np.array([ev(b.m) for b in B]),
        c=np.array([[ev(x) for x in b.c] for b in B]),
        A=np.array([[[ev(x) for x in row] for row in b.A] for b in B]),
        s=np.array([[ev(x) for x in b.s] for b in B]),
        lam=np.array([[ev(x) for x in b.lam] for b in B]),
        controls=spec.controls,
    )


def frames(ch: NumericChain, phi) -> np.ndarray:
    """αᵏ (eq. 14) for k = 1..n: R[k-1] has rows êᵏᵢ in the fixed frame."""
    R = np.empty((ch.n, 3, 3))
    prev = np.eye(3)
    for k in range(ch.n):
        ct, st = np.cos(ch.theta[k]), np.sin(ch.theta[k])
        cp, sp_ = np.cos(phi[k]), np.sin(phi[k])
        a = np.array([[ct, 0.0, -st], [st * sp_, cp, ct * sp_], [st * cp, -sp_, ct * cp]])  # eq. (15)
        prev = a @ prev
        R[k] = prev
    return R


def _world(ch: NumericChain, phi):
    R = frames(ch, phi)
    e = R[:, 0, :]  # e^k = ê^k_1
    c = np.einsum("kij,ki->kj", R, ch.c)  # c^k in the fixed frame
    s = np.einsum("kij,ki->kj", R, ch.s)
    lam = np.einsum("kij,ki->kj", R, ch.lam)
    A = np.einsum("kia,kij,kjb->kab", R, ch.A, R)
    # O^1 is the fixed origin; O^k = Σ_{l<k} s^l
    O = np.zeros((ch.n, 3))
    for k in range(1, ch.n):
        O[k] = O[k - 1] + s[k - 1]
    return e, c, s, lam, A, O


def inverse_dynamics(ch: NumericChain, phi, phidot, phiddot, torque=None) -> np.ndarray:
    """Residual of eq. (3) per joint: LHS − (external moments) − Lᵏ; zero on a motion."""
    n = ch.n
    e, c, s, lam, A, O = _world(ch, phi)
    down = np.array([1.0, 0.0, 0.0])
    omega = np.cumsum(e * phidot[:, None], axis=0)  # eq. (1), fixed base
    # eq. (5): ε^k = Σ_{p≤k} (e^p φ̈^p + ω^{p-1} × e^p φ̇^p)
    omega_prev = np.vstack([np.zeros(3), omega[:-1]])
    eps = np.cumsum(e * phiddot[:, None] + np.cross(omega_prev, e) * phidot[:, None], axis=0)
    # acceleration of O^p: Σ_{l<p} (ε^l × s^l + ω^l × (ω^l × s^l)), eq. (6)
    terms = np.cross(eps, s) + np.cross(omega, np.cross(omega, s))
    aO = np.vstack([np.zeros(3), np.cumsum(terms, axis=0)[:-1]])
    aG = aO + np.cross(eps, c) + np.cross(omega, np.cross(omega, c))
    Aw = np.einsum("kab,kb->ka", A, omega)
    dH = np.einsum("kab,kb->ka", A, eps) + np.cross(omega, Aw + lam)  # eq. (7), λ constant in body
    Mg = np.cross(c, ch.g * ch.m[:, None] * down)  # moment of gravity about O^p
    Fg = ch.g * ch.m[:, None] * down
    tau = np.empty(n)
    for k in range(n):
        total = np.zeros(3)
        for p in range(k, n):
            total += dH[p] + ch.m[p] * np.cross(c[p], aO[p]) - Mg[p]
        for q in range(k + 1, n):
            total += np.cross(O[q] - O[k], ch.m[q] * aG[q] - Fg[q])
        tau[k] = e[k] @ total
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
    n = ch.n
    zero = np.zeros(n)
    b = inverse_dynamics(ch, phi, zero, zero)
    return np.column_stack([inverse_dynamics(ch, phi, zero, np.eye(n)[r]) - b for r in range(n)])


def forces(ch: NumericChain, x, u=None) -> np.ndarray:
    """f of M φ̈ = f."""
    n = ch.n
    x = np.asarray(x, dtype=float)
    return joint_torques(ch, u) - inverse_dynamics(ch, x[:n], x[n:], np.zeros(n))


def qdd(ch: NumericChain, x, u=None) -> np.ndarray:
    x = np.asarray(x, dtype=float)
    return np.linalg.solve(mass_matrix(ch, x[: ch.n]), forces(ch, x, u))


def rhs(ch: NumericChain, t, x, u=None) -> np.ndarray:
    x = np.asarray(x, dtype=float)
    return np.concatenate([x[ch.n :], qdd(ch, x, u)])


def energy(ch: NumericChain, x) -> float:
    """T − U with T of digest §4 and U = g ê⁰₁ · Σ mᵏ r_{Gᵏ}."""
    n = ch.n
    x = np.asarray(x, dtype=float)
    e, c, s, lam, A, O = _world(ch, x[:n])
    omega = np.cumsum(e * x[n:, None], axis=0)
    vO = np.vstack([np.zeros(3), np.cumsum(np.cross(omega, s), axis=0)[:-1]])
    T = sum(
        0.5 * ch.m[k] * vO[k] @ vO[k] + ch.m[k] * vO[k] @ np.cross(omega[k], c[k]) + 0.5 * omega[k] @ A[k] @ omega[k]
        for k in range(n)
    )
    U = ch.g * sum(ch.m[k] * (O[k][0] + c[k][0]) for k in range(n))
    return float(T - U)


def momentum(ch: NumericChain, x) -> float:
    """ê¹₁ · K_{O¹} of eq. (24): the angular momentum about O¹ projected on the axis l¹."""
    n = ch.n
    x = np.asarray(x, dtype=float)
    e, c, s, lam, A, O = _world(ch, x[:n])
    omega = np.cumsum(e * x[n:, None], axis=0)
    vO = np.vstack([np.zeros(3), np.cumsum(np.cross(omega, s), axis=0)[:-1]])
    K = np.zeros(3)
    for p in range(n):
        vG = vO[p] + np.cross(omega[p], c[p])
        K += A[p] @ omega[p] + lam[p] + ch.m[p] * np.cross(O[p], vG) + ch.m[p] * np.cross(c[p], vO[p])
    return float(e[0] @ K)


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
