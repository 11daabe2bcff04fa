"""An independent Lagrangian of a chain, in the fixed frame (digest §7):

    ℒ = Σ_k [T_k + λᵏ·ωᵏ] + U,   T_k = ½ mᵏ v_Oᵏ² + mᵏ v_Oᵏ·(ωᵏ × cᵏ) + ½ ωᵏ·Aᵏ·ωᵏ,
    U = g ê⁰₁ · Σ_k mᵏ r_Gᵏ.

It shares nothing with gyrochain's recursions but the convention (15) for the frames."""
from __future__ import annotations

import sympy as sp


def frames(thetas, phis, offsets=None):
    """αᵏ (rows êᵏᵢ in the fixed frame), by (15) and (14); the paper's angle is φ + offset."""
    out, prev = [], sp.eye(3)
    for th, ph, d in zip(thetas, phis, offsets or [0] * len(phis)):
        ph = ph + d
        ct, st, cp, s = sp.cos(th), sp.sin(th), sp.cos(ph), sp.sin(ph)
        a = sp.Matrix([[ct, 0, -st], [st * s, cp, ct * s], [st * cp, -s, ct * cp]])
        prev = a * prev
        out.append(prev)
    return out


def lagrangian(spec, phi, phidot):
    n = spec.n
    R = frames([b.theta for b in spec.bodies], phi, [b.offset for b in spec.bodies])
    e = [R[k][0, :].T for k in range(n)]
    w = []
    acc = sp.zeros(3, 1)
    for k in range(n):
        acc = acc + e[k] * phidot[k]
        w.append(acc)
    L = 0
    rO, vO = sp.zeros(3, 1), sp.zeros(3, 1)
    for k, b in enumerate(spec.bodies):
        cw = R[k].T * sp.Matrix(b.c)
        sw = R[k].T * sp.Matrix(b.s)
        lw = R[k].T * sp.Matrix(b.lam)
        Aw = R[k].T * sp.Matrix(b.A) * R[k]
        T = b.m * vO.dot(vO) / 2 + b.m * vO.dot(w[k].cross(cw)) + (w[k].T * Aw * w[k])[0] / 2
        U = spec.g * b.m * (rO + cw)[0]
        L += T + lw.dot(w[k]) + U
        rO = rO + sw
        vO = vO + w[k].cross(sw)
    return L


def lagrange_terms(spec, phi, phidot):
    """(H, b): d/dt ∂ℒ/∂φ̇ − ∂ℒ/∂φ = H φ̈ + b, with H = ∂²ℒ/∂φ̇∂φ̇ and
    b_k = Σ_r ∂²ℒ/∂φ̇ₖ∂φʳ φ̇ʳ − ∂ℒ/∂φᵏ."""
    L = lagrangian(spec, phi, phidot)
    n = spec.n
    p = [sp.diff(L, v) for v in phidot]
    H = sp.Matrix(n, n, lambda i, j: sp.diff(p[i], phidot[j]))
    b = [sum(sp.diff(p[i], phi[r]) * phidot[r] for r in range(n)) - sp.diff(L, phi[i]) for i in range(n)]
    return H, b


# --------------------------------------------------------------------------- numeric (numpy)
def lagrangian_np(ch, phi, v, sign13=-1.0):
    """The same ℒ in numpy, for a NumericChain; phi may be complex (complex-step derivatives).
    ``sign13=+1`` is the OCR's misprint of (15), for negative controls."""
    import numpy as np

    prev = np.eye(3, dtype=complex)
    L = 0.0
    rO = np.zeros(3, complex)
    vO = np.zeros(3, complex)
    w = np.zeros(3, complex)
    for k in range(ch.n):
        ct, st = np.cos(ch.theta[k]), np.sin(ch.theta[k])
        cp, s = np.cos(phi[k] + ch.offset[k]), np.sin(phi[k] + ch.offset[k])
        a = np.array([[ct, 0, sign13 * st], [st * s, cp, ct * s], [st * cp, -s, ct * cp]])
        prev = a @ prev
        R = prev
        w = w + R[0] * v[k]
        cw, sw, lw = R.T @ ch.c[k], R.T @ ch.s[k], R.T @ ch.lam[k]
        Aw = R.T @ ch.A[k] @ R
        T = ch.m[k] * (vO @ vO) / 2 + ch.m[k] * (vO @ np.cross(w, cw)) + (w @ Aw @ w) / 2
        L = L + T + lw @ w + ch.g * ch.m[k] * (rO + cw)[0]
        rO = rO + sw
        vO = vO + np.cross(w, sw)
    return L


def lagrange_terms_np(ch, phi, v, t=1e-30, sign13=-1.0):
    """(H, b) of ``lagrange_terms`` at one state, without truncation error: ℒ is quadratic in φ̇,
    so unit-step polarization gives H and p = ∂ℒ/∂φ̇ exactly, and complex steps give the
    φ-derivatives (d/dφ along φ̇ of p, and ∂ℒ/∂φ)."""
    import numpy as np

    n = ch.n
    phi = np.asarray(phi, complex)
    v = np.asarray(v, float)
    E = np.eye(n)
    Lr = lambda ph, vv: lagrangian_np(ch, ph, vv, sign13)  # noqa: E731
    L0 = Lr(phi, v).real
    H = np.empty((n, n))
    for i in range(n):
        H[i, i] = (Lr(phi, v + E[i]) + Lr(phi, v - E[i])).real - 2 * L0
        for j in range(i):
            H[i, j] = H[j, i] = (Lr(phi, v + E[i] + E[j]) - Lr(phi, v + E[i]) - Lr(phi, v + E[j])).real + L0

    def p(ph):  # ∂ℒ/∂φ̇, exact for a quadratic
        return np.array([(Lr(ph, v + E[i]) - Lr(ph, v - E[i])) / 2 for i in range(n)])

    dp_along_v = p(phi + 1j * t * v).imag / t
    dL_dphi = np.array([Lr(phi + 1j * t * E[k], v).imag / t for k in range(n)])
    return H, dp_along_v - dL_dphi
