"""∂φ̈/∂(φ, φ̇, u) by inverse dynamics in the fixed frame: the O(n²) form for long chains.

M(φ) φ̈ + b(φ, φ̇) = τ(φ, φ̇, u) holds for every state, so at the state's φ̈

    ∂φ̈/∂x = M⁻¹ (∂τ/∂x − ∂ID/∂x),     ID(φ, φ̇, a) = M(φ) a + b(φ, φ̇) with a held at φ̈,

the identity Pinocchio's ``computeABADerivatives`` rests on (Carpentier & Mansard 2018).  The
forward mode of derivatives.py differentiates the articulated recursion itself: every column
carries tangents of the 6×6 articulated inertias, O(n) 6×6 work per column.  Here ∂ID/∂x has a
closed form in frame 0, where every quantity of the bodies k ≥ j turns rigidly with joint j:

    δ(any vector of body k ≥ j) / δφʲ = Sʲ × (that vector) + (what does not turn with it),

and what does not turn is only the motion of the base of joint j (v_{j−1}, a_{j−1}, gravity as
the upward acceleration a₀).  Summed over the sub-chain, the derivatives become two 6-dot
products per pair (k, j) of per-joint vectors (world.py's quantities, O(n) to compute):

    ∂ID_k/∂φʲ  = z1ᵏ·βʲ + z2ᵏ·wʲ        (k > j),   Sᵏ·Gʲ  (k ≤ j)
    ∂ID_k/∂φ̇ʲ = −2 z1ᵏ·wʲ − z2ᵏ·Sʲ     (k > j),   Sᵏ·Kʲ  (k ≤ j)
    M_kj        = z1ᵏ·Sʲ                (k ≥ j)

with, in frame 0 at O¹ (motions (ω, v), forces (moment, force); × and ×* the spatial cross
products; Iᶜ, Hᶜ, Fᶜ, Λᶜ, Dᶜ sums over the sub-chain k…n):
  Sᵏ = (eᵏ, Oᵏ × eᵏ) the joint's twist, vᵏ = vᵏ⁻¹ + Sᵏφ̇ᵏ, aᵏ = aᵏ⁻¹ + Sᵏφ̈ᵏ + vᵏ × Sᵏ φ̇ᵏ;
  fᵏ = Iᵏaᵏ + vᵏ ×* Iᵏvᵏ + (ωᵏ × λᵏ, 0) body k's inertial force (λᵏ the rotor, as in (17)–(19));
  Dᵏ = Σ (Iᵖ[vᵖ×] + (Iᵖ[vᵖ×])ᵀ), symmetric with a zero force–force block;
  wʲ = Sʲ × vʲ⁻¹, βʲ = −Sʲ × aʲ⁻¹ + wʲ × vʲ⁻¹;
  z1ᵏ = Iᶜᵏ Sᵏ, z2ᵏ = Dᵏ Sᵏ + Sᵏ ×* Hᶜᵏ − (Λᶜᵏ × eᵏ, 0);
  Gʲ = Sʲ ×* Fᶜʲ + Iᶜʲ βʲ + Dʲ wʲ − wʲ ×* Hᶜʲ − (wʲ_ω × Λᶜʲ, 0);
  Kʲ = −2 Iᶜʲ wʲ − Dʲ Sʲ + Sʲ ×* Hᶜʲ + (eʲ × Λᶜʲ, 0).
(Derived for this generator from δ(vector of body k ≥ j)/δφʲ = Sʲ × vector − the non-turning part,
summed with Σ Iᵖ[vᵖ×] = −(Σ [vᵖ×*] Iᵖ)ᵀ; the tests check every entry against the forward mode of
the articulated recursion to round-off, both against differences, and bench/derivatives.py
--symbolic against the exact derivatives of the sympy Lagrangian.)

φ̈ itself comes from the same LDLᵀ of M as the derivatives: the outward pass runs at φ̈ = 0
(aᵏ⁰, gravity and the velocity products only), so ID_k(φ, φ̇, 0) = Sᵏ·Fᶜᵏ⁰ and M φ̈ = τ − ID(0)
(``rhs``).  β and G are then the only vectors that depend on φ̈, and linearly: with
Aʲ = Σ_{i<j} Sⁱφ̈ⁱ (what φ̈ adds to aʲ⁻¹) and Zʲ = Σ_{i≥j} z1ⁱφ̈ⁱ,

    βʲ = βʲ⁰ − Sʲ × Aʲ,    Gʲ = Gʲ⁰ + Sʲ ×* (Iᶜʲ Aʲ + Zʲ) − Iᶜʲ (Sʲ × Aʲ)

(Σ_{p≥j} Iᵖ Σ_{i≤p} Sⁱφ̈ⁱ = Iᶜʲ Aʲ + Σ_{i≥j} Iᶜⁱ Sⁱ φ̈ⁱ), an O(n) loop of the template that reads
Iᶜ (``IC``, ten numbers per joint).  The articulated recursion is not repeated here.

The per-joint vectors are straight-line code (numbers folded, zeros gone); the pairs, M's LDLᵀ,
the solve for φ̈, φ̈'s share of β and G, and the solve with the 2n + nu columns are loops in the
template (O(n²) code would be too long to compile for n = 32).  ∂τ/∂x, the joint torques' own
derivatives (springs, dampers, controls, torque expressions), is the forward mode of
derivatives.py on τ alone: a few entries.

It applies where ID is that of a fixed-base chain with constant rotors and joint torques only
(``applies``); a platform, body loads or λ(t) keep the forward mode.
"""
from __future__ import annotations

from dataclasses import dataclass

from . import derivatives, loopform
from .algebra import ZERO, Poly
from .kinematics import appends_to
from .vec3 import add, cross, dot, fcross as _fcross, inertia_apply as _inertia, mcross as _mcross, scale, skew

VECTORS = ("S", "z1", "z2", "beta", "w", "G", "K")  # per joint, 6 components each (the C arrays)
IC_PARTS = 10  # Iᶜᵏ per joint as (A₁₁, A₁₂, A₁₃, A₂₂, A₂₃, A₃₃, h₁, h₂, h₃, m), the array IC
# From this many joints on, the template's LDLᵀ of M (ldlt_factor_) goes column by column with
# contiguous updates, four k at a time; below, row by row.  Both give the same bits.  Measured alone
# (gcc -O3 -march=native / -O2, 2026-11-26): n = 8 the columns 0.69 / 0.83 of the rows' speed,
# n = 16 1.24 / 0.97, n = 24 1.61 / 1.30, n = 128 1.9 / 1.4.
FACTOR_COLUMNS_MIN_N = 16


@dataclass(frozen=True)
class World:
    """``vec[name][k]``: the 6-vector ``name`` of joint k+1 (names ``VECTORS``; β and G at
    φ̈ = 0); ``ic[k]``: Iᶜ of joint k+1 (``IC_PARTS``); ``rhs[k]``: τ_k − ID_k(φ, φ̇, 0);
    ``ext``: the nonzero ∂τ_k/∂(direction c) as (k, c, Poly), directions φ, φ̇, u in that order."""

    vec: dict
    ic: tuple
    rhs: tuple
    ext: tuple
    labels: tuple


def applies(spec, kin, dyn) -> bool:
    """A fixed base, constant λ, no body loads and no armature: ID is rigid bodies, rotors and
    gravity (its M is the template's sum of pairs)."""
    return kin.platform is None and not dyn.Lamdot and not dyn.Phi and not dyn.armature


def _dmul(D, m6) -> list:
    """D m for D = [[D11, D12], [D12ᵀ, 0]] (D11 symmetric)."""
    D11, D12 = D
    top = [sum((D11[i][j] * m6[j] + D12[i][j] * m6[3 + j] for j in range(3)), ZERO) for i in range(3)]
    return top + [sum((D12[j][i] * m6[j] for j in range(3)), ZERO) for i in range(3)]


def _body_D(I, v) -> tuple:
    """Iᵏ[vᵏ×] + its transpose as (D11, D12): D11 = A[ω×] − [ω×]A + h uᵀ + u hᵀ − 2(h·u)1,
    D12 = [(h × ω)×] − m[u×] (v = (ω, u))."""
    A, h, m = I
    om, u = v[:3], v[3:]
    Aw = [[sum((A[i][l] * skew(om)[l][j] for l in range(3)), ZERO) for j in range(3)] for i in range(3)]
    hu = dot(h, u)
    D11 = [[Aw[i][j] + Aw[j][i] + h[i] * u[j] + u[i] * h[j] - (2 * hu if i == j else ZERO) for j in range(3)] for i in range(3)]
    hw = cross(h, om)
    D12 = [[skew(hw)[i][j] - m * skew(u)[i][j] for j in range(3)] for i in range(3)]
    return D11, D12


def _outward(spec, kin) -> tuple:
    """The outward pass in frame 0 at φ̈ = 0, joint by joint: the axis Sᵏ, wᵏ, βᵏ⁰, body k's
    inertia about O¹ (A, h, m), its momentum Iᵏvᵏ, its bias force, λᵏ and Dᵏ."""
    n = spec.n
    P = kin.prog
    num = P.from_sympy
    qd = kin.qd
    rows, O = loopform.ROWS0, [ZERO] * 3
    v = [ZERO] * 6
    a = [ZERO] * 3 + scale(-num(spec.g), kin.gamma[0])  # gravity as an upward acceleration of the base
    S, w, beta, Iw, mom, fb, lam, D = ({} for _ in range(8))
    for k in range(1, n + 1):
        b = spec.bodies[k - 1]
        rows, O, S[k] = loopform.place_joint(spec, kin, k, rows, O, "W")
        wk = _mcross(S[k], v)
        w[k] = P.vec(f"Ww{k}a", wk[:3]) + P.vec(f"Ww{k}l", wk[3:])
        al, wv = _mcross(S[k], a), _mcross(w[k], v)  # with v = vᵏ⁻¹, a = aᵏ⁻¹
        beta[k] = P.vec(f"Wb{k}a", [wv[i] - al[i] for i in range(3)]) + P.vec(f"Wb{k}l", [wv[3 + i] - al[3 + i] for i in range(3)])
        Iw[k] = loopform.body_inertia(spec, kin, k, rows, O, "W")  # body k about O¹ in frame 0
        lam[k] = P.vec(f"Wl{k}", [dot(rows[i], [num(x) for x in b.lam]) for i in range(3)])
        v = P.vec(f"Wv{k}a", [v[i] + S[k][i] * qd[k] for i in range(3)]) + P.vec(f"Wv{k}l", [v[3 + i] + S[k][3 + i] * qd[k] for i in range(3)])
        # aᵏ⁰ = aᵏ⁻¹⁰ − wᵏφ̇ᵏ  (aᵏ = aᵏ⁻¹ + Sᵏφ̈ᵏ + vᵏ × Sᵏφ̇ᵏ at φ̈ = 0; vᵏ × Sᵏ = vᵏ⁻¹ × Sᵏ = −wᵏ)
        a = P.vec(f"Wa{k}a", [a[i] - w[k][i] * qd[k] for i in range(3)]) + \
            P.vec(f"Wa{k}l", [a[3 + i] - w[k][3 + i] * qd[k] for i in range(3)])
        hk = _inertia(Iw[k], v)
        mom[k] = P.vec(f"Wm{k}a", hk[:3]) + P.vec(f"Wm{k}l", hk[3:])  # Iᵏvᵏ
        Ia, vh = _inertia(Iw[k], a), _fcross(v, mom[k])
        fb[k] = add(Ia[:3], vh[:3], cross(v[:3], lam[k])) + add(Ia[3:], vh[3:])
        D[k] = _body_D(Iw[k], v)
    return S, w, beta, Iw, mom, fb, lam, D


def _inward(P, n: int, outward: tuple, torques) -> tuple:
    """The inward pass: the composite sums over the bodies p ≥ k and what they give per joint:
    the vectors of VECTORS (S, z1, z2, β⁰, w, G⁰, K), Iᶜ (IC_PARTS) and τ_k − Sᵏ·Fᶜᵏ⁰."""
    S, w, beta, Iw, mom, fb, lam, D = outward
    vec = {name: [None] * n for name in VECTORS}
    ic, rhs = [None] * n, [None] * n
    IC = HC = FC = LC = DC = None
    for k in range(n, 0, -1):
        A0, h0, m = Iw[k]
        if IC is None:
            IC, HC, FC, LC, DC = Iw[k], mom[k], fb[k], lam[k], D[k]
        else:
            IC = ([[A0[i][j] + IC[0][i][j] for j in range(3)] for i in range(3)], add(h0, IC[1]), m + IC[2])
            HC = [mom[k][i] + HC[i] for i in range(6)]
            FC = [fb[k][i] + FC[i] for i in range(6)]
            LC = add(lam[k], LC)
            DC = tuple([[D[k][b][i][j] + DC[b][i][j] for j in range(3)] for i in range(3)] for b in range(2))
        IC = (P.sym_mat(f"WIC{k}", IC[0]), P.vec(f"WhC{k}", IC[1]), P.let(f"WmC{k}", IC[2]))
        HC = P.vec(f"WHC{k}a", HC[:3]) + P.vec(f"WHC{k}l", HC[3:])
        FC = P.vec(f"WFC{k}a", FC[:3]) + P.vec(f"WFC{k}l", FC[3:])
        LC = P.vec(f"WLC{k}", LC)
        DC = (P.sym_mat(f"WD{k}a", DC[0]), [[P.let(f"WD{k}b_{i + 1}{j + 1}", DC[1][i][j]) for j in range(3)] for i in range(3)])
        Sk, wk, e = S[k], w[k], S[k][:3]
        z1 = _inertia(IC, Sk)
        DS = _dmul(DC, Sk)
        y = _fcross(Sk, HC)
        rho = cross(LC, e)
        DS = P.vec(f"WDS{k}a", DS[:3]) + P.vec(f"WDS{k}l", DS[3:])
        y = P.vec(f"Wy{k}a", y[:3]) + P.vec(f"Wy{k}l", y[3:])
        z2 = [DS[i] + y[i] - (rho[i] if i < 3 else ZERO) for i in range(6)]
        Gv = [p + q + r - s for p, q, r, s in zip(_fcross(Sk, FC), _inertia(IC, beta[k]), _dmul(DC, wk), _fcross(wk, HC))]
        Gv = [g - r for g, r in zip(Gv, cross(wk[:3], LC) + [ZERO] * 3)]
        Kv = [-2 * x - d + yy + r for x, d, yy, r in zip(_inertia(IC, wk), DS, y, cross(e, LC) + [ZERO] * 3)]
        for name, val in zip(VECTORS, (Sk, z1, z2, beta[k], wk, Gv, Kv)):
            vec[name][k - 1] = [Poly.lift(x) for x in val]
        Ac = IC[0]
        ic[k - 1] = [Poly.lift(x) for x in (Ac[0][0], Ac[0][1], Ac[0][2], Ac[1][1], Ac[1][2], Ac[2][2], *IC[1], IC[2])]
        rhs[k - 1] = Poly.lift(torques[k - 1]) - Poly.lift(sum((Sk[i] * FC[i] for i in range(6)), ZERO))
    return vec, ic, rhs


def _torque_tangents(spec, kin, dyn) -> tuple:
    """∂τ/∂x: the forward mode of derivatives.py on the joint torques alone; ((joint, direction,
    derivative) of every nonzero entry, the directions' labels)."""
    P = kin.prog
    syms, labels = derivatives.directions(spec, kin)
    seeds = {next(iter(P.input(s_).terms))[0]: {j: Poly.const(1)} for j, s_ in enumerate(syms)}
    torques = list(dyn.torques)
    tan = derivatives.tangents(P, torques, seeds, tuple(f"W{lab}" for lab in labels))
    ext = []
    for k, tk in enumerate(torques):
        for c, d in sorted(derivatives.tangent_poly(Poly.lift(tk), tan).items()):
            if not d.is_zero():
                ext.append((k, c, d))
    return tuple(ext), labels


def derive(spec, prog, kin, dyn) -> World:
    """The per-joint vectors of the pairs' formulas, M φ̈'s right side and ∂τ/∂x, appended to
    ``prog``."""
    appends_to(prog, kin)
    vec, ic, rhs = _inward(prog, spec.n, _outward(spec, kin), dyn.torques)
    ext, labels = _torque_tangents(spec, kin, dyn)
    return World({name: tuple(tuple(x) for x in vec[name]) for name in VECTORS}, tuple(tuple(x) for x in ic),
                 tuple(rhs), ext, labels)
