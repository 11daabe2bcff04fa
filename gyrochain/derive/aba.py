"""φ̈ by articulated bodies: the O(n) form of M φ̈ = f that long chains are emitted in.

The composite-body form (dynamics.py) builds M (O(n²) entries) and solves it by LDLᵀ (O(n³));
past a few bodies it costs more than eliminating the joints one by one from the tip, which is
Featherstone's articulated-body algorithm.  Both solve the same equations (17)–(19); the
generator emits whichever has fewer operations for the spec (assemble.build_model), and the tests
check either against the reference model.

Spatial vectors at Oᵏ in frame k (the paper's body frame, joint axis eᵏ₁ = (1, 0, 0)): a motion
is (ω, v_O), a force (moment about Oᵏ, force).  Body k's spatial inertia about Oᵏ is
[[Aᵏ, [h]×], [−[h]×, mᵏ]] with h = mᵏcᵏ.  The velocity terms are body k's own share of the
combined Newton–Euler bias (dynamics.body_bias: the accelerations of φ̈ = 0, gravity as an upward
base acceleration, ωᵏ×λᵏ), so the recursion only carries the φ̈-dependent accelerations Δa.

Backward (k = n … 1): IAᵏ = body inertia + the articulated inertia of k+1…n carried to Oᵏ;
pᵏ likewise; U = IAᵏ S (S = (eᵏ₁, 0)), Dᵏ = U₁, uᵏ = Lᵏ − pᵏ₁.  What sub-chain k…n passes on to
joint k−1 is IAᵏ − U Uᵀ/Dᵏ (row and column 1 vanish exactly) and pᵏ + U uᵏ/Dᵏ (first moment
component Lᵏ exactly).  Forward: Δaᵏ = Xᵏ Δaᵏ⁻¹, φ̈ᵏ = (uᵏ − Uᵀ Δaᵏ)/Dᵏ, Δaᵏ += S φ̈ᵏ.
The Dᵏ are the pivots of M eliminated from the tip; the code tests them as it tests LDLᵀ's.
"""
from __future__ import annotations

from dataclasses import dataclass

from .algebra import ONE, ZERO
from .dynamics import Dynamics
from .kinematics import Kinematics, appends_to
from .program import Program
from .vec3 import add, cross, skew
from ..chainspec.spec import ChainSpec


@dataclass(frozen=True)
class Articulated:
    qdd: tuple  # φ̈ᵏ, k = 1..n
    pivots: tuple  # Dᵏ


def _blocks(X) -> tuple:
    """A symmetric 6×6 as its blocks: angular Ia, coupling H (Ia ω + H v is the moment), Mm."""
    Ia = [[X[i][j] for j in range(3)] for i in range(3)]
    H = [[X[i][3 + j] for j in range(3)] for i in range(3)]
    Mm = [[X[3 + i][3 + j] for j in range(3)] for i in range(3)]
    return Ia, H, Mm


def _from_blocks(Ia, H, Mm) -> list:
    X = [[ZERO] * 6 for _ in range(6)]
    for i in range(3):
        for j in range(3):
            X[i][j], X[3 + i][3 + j] = Ia[i][j], Mm[i][j]
            X[i][3 + j] = X[3 + j][i] = H[i][j]
    return X


def _name6(P, name: str, X) -> list:
    out = [[None] * 6 for _ in range(6)]
    for i in range(6):
        for j in range(i + 1):
            out[i][j] = out[j][i] = P.let(f"{name}_{i + 1}{j + 1}", X[i][j])
    return out


def derive(spec: ChainSpec, prog: Program, kin: Kinematics, dyn: Dynamics) -> Articulated:
    """φ̈ and the pivots Dᵏ by the articulated-body recursion, appended to ``prog``."""
    appends_to(prog, kin)
    n = spec.n
    P = prog
    J = kin.joint
    num = P.from_sympy
    s = [None] + [[num(x) for x in b.s] for b in spec.bodies]

    W, u, rD, D = ([None] * (n + 1) for _ in range(4))
    carried = None  # (inertia, bias) of k+1…n at Oᵏ in frame k
    for k in range(n, 0, -1):
        b = spec.bodies[k - 1]
        m = num(b.m)
        h = [m * num(x) for x in b.c]
        A = [[num(x) for x in row] for row in b.A]
        # moment Aω + h × v, force m v − h × ω: the coupling block H is [h]×
        X = _from_blocks(A, skew(h), [[m if i == j else ZERO for j in range(3)] for i in range(3)])
        pF, pN = dyn.body_bias[k - 1]
        p = list(pN) + list(pF)
        if carried is not None:
            X = [[X[i][j] + carried[0][i][j] for j in range(6)] for i in range(6)]
            p = [p[i] + carried[1][i] for i in range(6)]
        X = _name6(P, f"IA{k}", X)
        p = [P.let(f"pA{k}_{i + 1}", p[i]) for i in range(6)]
        U = [X[i][0] for i in range(6)]
        a = dyn.armature[k - 1] if dyn.armature else ZERO  # the motor's reflected inertia: Dᵏ = Uᵏ₁ + aᵏ
        armed = not a.is_zero()
        D[k] = P.let(f"D{k}", U[0] + a) if armed else U[0]
        rD[k] = P.reciprocal(f"rD{k}", D[k])
        tau = dyn.torques[k - 1]
        u[k] = P.let(f"u{k}", tau - p[0])
        # U/Dᵏ (its first entry 1 without armature)
        W[k] = [P.let(f"W{k}_1", U[0] * rD[k]) if armed else ONE] + [P.let(f"W{k}_{i + 1}", U[i] * rD[k]) for i in range(1, 6)]
        if k == 1:
            break
        # what k…n passes to joint k−1: X − W Uᵀ and p + W u; without armature row and column 1 are
        # zero and the first moment is Lᵏ
        Xa = [[ZERO if (i == 0 or j == 0) and not armed else X[i][j] - W[k][i] * U[j] for j in range(6)] for i in range(6)]
        Xa = _name6(P, f"Ja{k}", Xa)
        pa = [P.let(f"pa{k}_1", p[0] + W[k][0] * u[k]) if armed else tau] + \
            [P.let(f"pa{k}_{i + 1}", p[i] + W[k][i] * u[k]) for i in range(1, 6)]
        carried = _carry(P, J[k], s[k - 1], k, Xa, pa)

    # forward: φ̈-dependent accelerations Δa, frame k at Oᵏ
    qdd = [None] * (n + 1)
    dw = dv = None
    for k in range(1, n + 1):
        if k == 1:
            dwk, dvk = [ZERO] * 3, [ZERO] * 3
        else:
            dwk = P.vec(f"dw{k}", J[k].down(dw))
            dvk = P.vec(f"dv{k}", J[k].down(add(dv, cross(dw, s[k - 1]))))
        da = dwk + dvk
        qdd[k] = P.let(f"qdd{k}", u[k] * rD[k] - sum((W[k][i] * da[i] for i in range(6)), ZERO))
        dw, dv = [dwk[0] + qdd[k], dwk[1], dwk[2]], dvk
    return Articulated(qdd=tuple(qdd[1:]), pivots=tuple(D[1:]))


def _carry(P, joint, s, k: int, X, p) -> tuple:
    """Inertia and bias of sub-chain k…n from (Oᵏ, frame k) to (Oᵏ⁻¹, frame k−1): turned by
    αᵏ'ᵏ⁻¹ transposed, then moved by sᵏ⁻¹ (n' = n + s × f; for the inertia Ia' = Ia − H[s]× +
    [s]×Hᵀ − [s]×Mm[s]×, H' = H + [s]×Mm)."""
    Ia, H, Mm = _blocks(X)
    Ia = joint.up_sym(Ia, f"Ja{k}r")
    H = joint.up_mat(H, f"Jh{k}r")
    Mm = joint.up_sym(Mm, f"Jm{k}r")
    nn = P.vec(f"pc{k}n", joint.up(p[:3]))
    ff = P.vec(f"pc{k}f", joint.up(p[3:]))
    # H' = H + [s]× Mm (Mm symmetric: its column j is its row j); Ia' = Ia + [s]×Hᵀ + ([s]×H'ᵀ)ᵀ
    sM = [cross(s, Mm[j]) for j in range(3)]  # column j of [s]× Mm
    H2 = [[P.let(f"Jh{k}s_{i + 1}{j + 1}", H[i][j] + sM[j][i]) for j in range(3)] for i in range(3)]
    sH, sH2 = [cross(s, row) for row in H], [cross(s, row) for row in H2]  # columns of [s]×Hᵀ, [s]×H'ᵀ
    Ia2 = [[None] * 3 for _ in range(3)]
    for i in range(3):
        for j in range(i + 1):
            Ia2[i][j] = Ia2[j][i] = Ia[i][j] + sH[j][i] + sH2[i][j]
    n2 = add(nn, cross(s, ff))
    return _from_blocks(Ia2, H2, Mm), n2 + ff
