"""Equations of motion M(φ) φ̈ = f(φ, φ̇, L), grouped as in the paper's (17)–(19).

The k-th equation is the moment equation (2)–(4) of the sub-chain Sᵏ…Sⁿ about Oᵏ, projected on
eᵏ; fixed base, gravity, constant gyrostatic moments (digest §3, "Specialization").  The
paper's sums over p ≥ k are written here as the backward recursions they are: a quantity of the
sub-chain k…n is that of body k plus the sub-chain k+1…n moved from Oᵏ⁺¹ to Oᵏ (by sᵏ) and
turned into frame k (by αᵏ⁺¹'ᵏ transposed).  Every vector is in its body's frame, so eᵏ = (1,0,0)
and a projection on eᵏ is the first component.

    Σ_r M_kr φ̈ʳ + Q_k(φ, φ̇) + Γ_k(φ, φ̇) = G_k(φ) + Lᵏ            (k = 1..n)

Q: terms quadratic in φ̇ (eq. (17)–(19), lines 2–3), Γ: gyroscopic terms linear in φ̇ from λ
(last line of the left side), G: gravity (right side), L: the control torque of joint k.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .kinematics import E1, Kinematics
from .spec import ChainSpec


def cross(a: sp.Matrix, b: sp.Matrix) -> sp.Matrix:
    return sp.Matrix([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


def dot(a: sp.Matrix, b: sp.Matrix) -> sp.Expr:
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@dataclass(frozen=True)
class Dynamics:
    M: sp.Matrix  # n×n mass matrix, symmetric positive definite
    Q: tuple  # velocity-quadratic terms (left side)
    Gamma: tuple  # gyroscopic terms from λ (left side)
    G: tuple  # gravity terms (right side)
    L: tuple  # control torque per joint (right side), 0 where the joint has none
    m_c: tuple  # composite mass of the sub-chain k..n
    h: tuple  # first moment of sub-chain k..n about Oᵏ, frame k (Σ_{p≥k} m^p(c^p + O^kO^p))
    I: tuple  # inertia of sub-chain k..n about Oᵏ, frame k
    Lam: tuple  # Σ_{p≥k} λ^p in frame k

    @property
    def f(self) -> tuple:
        """Right side f of M φ̈ = f."""
        return tuple(g + l - q - gm for q, gm, g, l in zip(self.Q, self.Gamma, self.G, self.L))


def derive(spec: ChainSpec, kin: Kinematics) -> Dynamics:
    n = spec.n
    P = kin.prog
    B = [None, *spec.bodies]
    a, w = kin.alpha, kin.omega
    A = [None] + [sp.Matrix(b.A) for b in spec.bodies]
    c = [None] + [sp.Matrix(b.c) for b in spec.bodies]
    s = [None] + [sp.Matrix(b.s) for b in spec.bodies]
    lam = [None] + [sp.Matrix(b.lam) for b in spec.bodies]
    m = [None] + [b.m for b in spec.bodies]
    zero = sp.zeros(3, 1)

    # Forward recursions with φ̈ = 0: angular acceleration εᵏ (eq. (5)) and the acceleration of
    # Oᵏ (eq. (6) summed over l < k), in frame k.
    eps = [zero]
    acc_O = [None, zero]
    for k in range(1, n + 1):
        eps.append(P.vec(f"eps{k}", a[k] * eps[k - 1] + cross(w[k], E1 * kin.phidot[k]), rf"\varepsilon^{{{k}}}"))
        if k > 1:
            j = k - 1
            acc = acc_O[j] + cross(eps[j], s[j]) + cross(w[j], cross(w[j], s[j]))
            acc_O.append(P.vec(f"aO{k}", a[k] * P.vec(f"aO{k}in{j}", acc), rf"a^{{{k}}}"))

    # Backward recursions over the sub-chains p ≥ k.
    F_next = N_next = Gam_next = Lam_next = h_next = zero
    m_next, I_next = sp.Integer(0), sp.zeros(3, 3)
    Q, Gam, Gv, m_c, h_c, I_c, Lam = ([None] * (n + 1) for _ in range(7))
    for k in range(n, 0, -1):
        if k < n:
            R = a[k + 1].T  # frame k+1 → frame k
            F_in = P.vec(f"F{k + 1}in{k}", R * F_next)
            N_in = P.vec(f"N{k + 1}in{k}", R * N_next)
            Gam_in = P.vec(f"Gm{k + 1}in{k}", R * Gam_next)
            Lam_in = P.vec(f"Lam{k + 1}in{k}", R * Lam_next)
            h_in = P.vec(f"h{k + 1}in{k}", R * h_next)  # about O^{k+1}, frame k
            I_in = P.sym_mat(f"I{k + 1}in{k}", R * I_next * R.T)
        else:
            F_in = N_in = Gam_in = Lam_in = h_in = zero
            I_in = sp.zeros(3, 3)
        sk = s[k]
        # velocity-quadratic part: Σ_{p≥k} [(Aω)˙ + m c×a_O] + Σ_{q>k} d_kq × m a_G  (eqs. (3), (7))
        acc_G = acc_O[k] + cross(eps[k], c[k]) + cross(w[k], cross(w[k], c[k]))
        F = P.vec(f"F{k}", m[k] * acc_G + F_in, rf"F^{{{k}}}")
        Aw = A[k] * w[k]
        N = P.vec(
            f"N{k}",
            A[k] * eps[k] + cross(w[k], Aw) + m[k] * cross(c[k], acc_O[k]) + N_in + cross(sk, F_in),
            rf"N^{{{k}}}",
        )
        # gyroscopic part: Σ_{p≥k} ω^p × λ^p
        Gm = P.vec(f"Gm{k}", cross(w[k], lam[k]) + Gam_in, rf"\Gamma^{{{k}}}")
        # composite mass, first moment and inertia about O^k (parallel-axis shift by s^k)
        mc = P.let(f"mc{k}", m[k] + m_next, rf"m_c^{{{k}}}")
        h = P.vec(f"h{k}", m[k] * c[k] + h_in + m_next * sk, rf"h^{{{k}}}")
        I = P.sym_mat(
            f"I{k}",
            A[k]
            + I_in
            + m_next * (dot(sk, sk) * sp.eye(3) - sk * sk.T)
            + 2 * dot(sk, h_in) * sp.eye(3)
            - sk * h_in.T
            - h_in * sk.T,
            rf"I^{{{k}}}",
        )
        # gravity: e^k · (h × g ê⁰₁)  (right side of (17)–(19))
        Gv[k] = P.let(f"G{k}", spec.g * (h[1] * kin.gamma[k][2] - h[2] * kin.gamma[k][1]), rf"G_{{{k}}}")
        Q[k], Gam[k] = N[0], Gm[0]
        m_c[k], h_c[k], I_c[k] = mc, h, I
        Lam[k] = P.vec(f"Lam{k}", lam[k] + Lam_in, rf"\Lambda^{{{k}}}")
        F_next, N_next, Gam_next, Lam_next = F, N, Gm, Lam[k]
        m_next, h_next, I_next = mc, h, I

    # Mass matrix (composite bodies): for r ≤ k, a unit φ̈ʳ turns the sub-chain k..n with
    # angular acceleration eʳ and accelerates Oᵏ by eʳ × d_rk, d_rk = Σ_{l=r}^{k-1} sˡ.
    M = sp.zeros(n, n)
    for r in range(1, n + 1):
        u, d = E1, zero  # e^r and d_rk in frame k, starting at k = r
        for k in range(r, n + 1):
            if k > r:
                u = P.vec(f"e{r}in{k}", a[k] * u, rf"e^{{{r}|{k}}}")
                d = P.vec(f"d{r}in{k}", a[k] * (d + s[k - 1]), rf"d^{{{r}{k}}}")
            M[k - 1, r - 1] = M[r - 1, k - 1] = P.let(
                f"M{k}_{r}", (I_c[k] * u + cross(h_c[k], cross(u, d)))[0], rf"M_{{{k}{r}}}"
            )

    L = tuple(kin.torque[k] if B[k].control else sp.Integer(0) for k in range(1, n + 1))
    return Dynamics(
        M=M,
        Q=tuple(Q[1:]),
        Gamma=tuple(Gam[1:]),
        G=tuple(Gv[1:]),
        L=L,
        m_c=tuple(m_c[1:]),
        h=tuple(h_c[1:]),
        I=tuple(I_c[1:]),
        Lam=tuple(Lam[1:]),
    )
