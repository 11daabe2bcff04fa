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

Two forms of the same equations are derived.  The paper's split Q, Γ, G (for the LaTeX and the
proofs), and the form the generated code computes: one Newton–Euler recursion for the whole
bias b = Q + Γ − G, with gravity as an upward acceleration of the base and ωᵏ × λᵏ in the moment,
which needs neither the γᵏ recursion nor a separate Γ recursion.  M is built by composite bodies:
the force of the sub-chain k…n under a unit φ̈ᵏ is carried from Oᵏ back to each Oʲ, j < k.
"""
from __future__ import annotations

from dataclasses import dataclass

from .algebra import ZERO, Poly
from .kinematics import NULL, Kinematics
from .vec3 import add, cross, dot, matvec, scale
from .spec import T, ChainSpec


@dataclass(frozen=True)
class Dynamics:
    M: tuple  # n×n mass matrix (tuple of rows of Poly), symmetric positive definite
    Q: tuple  # velocity-quadratic terms (left side)
    Gamma: tuple  # gyroscopic terms from λ (left side)
    G: tuple  # gravity terms (right side)
    L: tuple  # control torque per joint (right side), 0 where the joint has none
    bias: tuple  # Q + Γ − G by the combined recursion (what the code computes)
    m_c: tuple  # composite mass of the sub-chain k..n
    h: tuple  # first moment of sub-chain k..n about Oᵏ, frame k (Σ_{p≥k} m^p(c^p + O^kO^p))
    I: tuple  # inertia of sub-chain k..n about Oᵏ, frame k
    Lam: tuple  # Σ_{p≥k} λ^p in frame k
    body_bias: tuple  # (force, moment about Oᵏ) of body k alone at φ̈ = 0, gravity and loads included
    joint: tuple = ()  # spring, damping and torque-expression torque per joint (right side; ZERO if none)
    Lamdot: tuple = ()  # eᵏ·Σ_{p≥k} λ̊ᵖ (left side; () when every λ is constant)
    Phi: tuple = ()  # generalized force of the external loads Fᵏ, Mᵏ (right side; () when none)
    loads: tuple = ()  # (force, moment about Oᵏ) of the external loads on body k, frame k
    force_vectors: tuple = ()  # per body, each [[body.force]] in frame k

    @property
    def torques(self) -> tuple:
        """The whole joint torque: control Lᵏ plus spring, damping and torque expression."""
        return tuple(l + j for l, j in zip(self.L, self.joint)) if self.joint else self.L

    @property
    def f(self) -> tuple:
        """Right side f of M φ̈ = f, as the code computes it."""
        return tuple(l - b for l, b in zip(self.torques, self.bias))


def _external(spec: ChainSpec, kin: Kinematics, k: int) -> tuple:
    """Force and moment about Oᵏ of body k's external loads (its [[body.force]] and
    [[body.moment]]), in frame k.  A "fixed" load's components are turned from the fixed frame into
    the platform frame (Rᵀ) and then down the chain."""
    P, pm, num = kin.prog, kin.platform, kin.prog.from_sympy
    b = spec.bodies[k - 1]
    F = N = NULL
    vecs = []

    def in_frame(load, tag):
        vec = load.vec
        if load.frame == "body":
            return [num(x) for x in vec]
        if pm is not None:
            vec = pm.to_platform(vec)
        return kin.to_frame(k, [num(x) for x in vec], tag)

    for i, load in enumerate(b.forces, start=1):
        f = P.vec(f"Fe{k}_{i}", in_frame(load, f"Fe{k}_{i}f"))
        vecs.append(f)
        F = add(F, f)
        N = add(N, cross([num(x) for x in load.point], f))
    for i, load in enumerate(b.moments, start=1):
        N = add(N, P.vec(f"Me{k}_{i}", in_frame(load, f"Me{k}_{i}f")))
    return F, N, tuple(vecs)


def joint_torque(spec: ChainSpec, kin: Kinematics, k: int) -> Poly:
    """Spring −kᵏ(φᵏ − restᵏ), damping −bᵏφ̇ᵏ and the torque expression of joint k."""
    b, num = spec.bodies[k - 1], kin.prog.from_sympy
    out = ZERO
    if b.spring is not None:
        out = out - num(b.spring) * (kin.prog.input(kin.phi[k]) - num(b.rest))
    if b.damping is not None:
        out = out - num(b.damping) * kin.qd[k]
    if b.torque is not None:
        out = out + num(b.torque)
    return out


def derive(spec: ChainSpec, kin: Kinematics) -> Dynamics:
    n = spec.n
    P = kin.prog
    J, w, qd = kin.joint, kin.omega, kin.qd
    num = P.from_sympy
    A = [None] + [[[num(x) for x in row] for row in b.A] for b in spec.bodies]
    c = [None] + [[num(x) for x in b.c] for b in spec.bodies]
    s = [None] + [[num(x) for x in b.s] for b in spec.bodies]
    lam = [None] + [[num(x) for x in b.lam] for b in spec.bodies]
    m = [None] + [num(b.m) for b in spec.bodies]
    g = num(spec.g)
    timed_lam = any(x.has(T) for b in spec.bodies for x in b.lam)
    lamdot = [None] + [[num(x) for x in b.lam_dot] for b in spec.bodies]
    has_loads = any(b.forces or b.moments for b in spec.bodies)
    ext = [None] + [_external(spec, kin, k) for k in range(1, n + 1)]

    # Forward recursions with φ̈ = 0: angular acceleration εᵏ (eq. (5), from ε⁰ of the platform)
    # and the acceleration of Oᵏ (eq. (6) summed over l < k, from v̇₀), in frame k; aOg also
    # carries gravity (base accelerating up with g), for the combined recursion.
    if kin.platform is None:
        eps = [NULL]
        acc_O, acc_Og = [None, NULL], [None, P.vec("aOg1", scale(-g, kin.gamma[1]))]
    else:
        eps = [kin.eps0]
        a1 = P.vec("aO1", J[1].down(kin.acc0), r"a^{1}")
        acc_O, acc_Og = [None, a1], [None, P.vec("aOg1", add(a1, scale(-g, kin.gamma[1])))]
    for k in range(1, n + 1):
        eps.append(P.vec(f"eps{k}", add(J[k].down(eps[k - 1]), cross(w[k], [qd[k], ZERO, ZERO])), rf"\varepsilon^{{{k}}}"))
        if k > 1:
            j = k - 1
            rel = P.vec(f"aOrel{k}in{j}", add(cross(eps[j], s[j]), cross(w[j], P.vec(f"ws{j}", cross(w[j], s[j])))))
            acc_O.append(P.vec(f"aO{k}", J[k].down(add(acc_O[j], rel)), rf"a^{{{k}}}"))
            acc_Og.append(P.vec(f"aOg{k}", J[k].down(add(acc_Og[j], rel))))

    # Backward recursions over the sub-chains p ≥ k.
    F_next = N_next = Gam_next = Lam_next = h_next = Fb_next = Nb_next = Ld_next = Fl_next = Nl_next = NULL
    m_next, I_next = ZERO, None
    Q, Gam, Gv, bias, m_c, h_c, I_c, Lam, body_bias = ([None] * (n + 1) for _ in range(9))
    Lamdot, Phi = [None] * (n + 1), [None] * (n + 1)
    for k in range(n, 0, -1):
        sk = s[k]
        if k < n:
            up = J[k + 1].up  # frame k+1 → frame k
            F_in = P.vec(f"F{k + 1}in{k}", up(F_next))
            N_in = P.vec(f"N{k + 1}in{k}", up(N_next))
            Gam_in = P.vec(f"Gm{k + 1}in{k}", up(Gam_next))
            Lam_in = P.vec(f"Lam{k + 1}in{k}", up(Lam_next))
            h_in = P.vec(f"h{k + 1}in{k}", up(h_next))  # about O^{k+1}, frame k
            I_in = J[k + 1].up_sym(I_next, f"I{k + 1}in{k}")
            Fb_in = P.vec(f"Fb{k + 1}in{k}", up(Fb_next))
            Nb_in = P.vec(f"Nb{k + 1}in{k}", up(Nb_next))
        else:
            F_in = N_in = Gam_in = Lam_in = h_in = Fb_in = Nb_in = NULL
            I_in = [[ZERO] * 3 for _ in range(3)]
        wcc = P.vec(f"wc{k}", cross(w[k], c[k]))
        rel_G = add(cross(eps[k], c[k]), cross(w[k], wcc))  # a_G − a_O
        Aw = P.vec(f"Aw{k}", matvec(A[k], w[k]))
        Aeps_wAw = add(matvec(A[k], eps[k]), cross(w[k], Aw))
        # the paper's split: velocity-quadratic part Σ_{p≥k} [(Aω)˙ + m c×a_O] + Σ_{q>k} d_kq × m a_G
        F = P.vec(f"F{k}", add(scale(m[k], add(acc_O[k], rel_G)), F_in), rf"F^{{{k}}}")
        N = P.vec(f"N{k}", add(Aeps_wAw, scale(m[k], cross(c[k], acc_O[k])), N_in, cross(sk, F_in)), rf"N^{{{k}}}")
        # gyroscopic part: Σ_{p≥k} ω^p × λ^p
        Gm = P.vec(f"Gm{k}", add(cross(w[k], lam[k]), Gam_in), rf"\Gamma^{{{k}}}")
        # the code's form: one recursion for Q + Γ − G; body k's own share first (force and
        # moment about Oᵏ of body k alone at the accelerations of φ̈ = 0, with gravity)
        # (the external loads on the right side of (2)–(4), λ̊ of (7) on the left)
        Fx, Nx, _ = ext[k]
        pF = P.vec(f"pF{k}", add(scale(m[k], add(acc_Og[k], rel_G)), scale(-1.0, Fx)))
        pN = P.vec(f"pN{k}", add(matvec(A[k], eps[k]), cross(w[k], add(Aw, lam[k])), scale(m[k], cross(c[k], acc_Og[k])),
                                 lamdot[k], scale(-1.0, Nx)))
        if timed_lam:  # the paper's split: e^k · Σ_{p≥k} λ̊^p
            Ld = P.vec(f"Ld{k}", add(lamdot[k], P.vec(f"Ld{k + 1}in{k}", up(Ld_next)) if k < n else NULL))
            Lamdot[k], Ld_next = Ld[0], Ld
        if has_loads:  # and the generalized force of the loads: Σ e^k·M^p + e^k·(s^p × Σ F^q)
            Fl_in = P.vec(f"Fl{k + 1}in{k}", up(Fl_next)) if k < n else NULL
            Nl_in = P.vec(f"Nl{k + 1}in{k}", up(Nl_next)) if k < n else NULL
            Fl = P.vec(f"Fl{k}", add(Fx, Fl_in))
            Nl = P.vec(f"Nl{k}", add(Nx, Nl_in, cross(sk, Fl_in)))
            Phi[k], Fl_next, Nl_next = Nl[0], Fl, Nl
        body_bias[k] = (pF, pN)
        Fb = P.vec(f"Fb{k}", add(pF, Fb_in))
        Nb = P.vec(f"Nb{k}", add(pN, Nb_in, cross(sk, Fb_in)))
        # composite mass, first moment and inertia about O^k (parallel-axis shift by s^k)
        mc = P.let(f"mc{k}", m[k] + m_next, rf"m_c^{{{k}}}")
        h = P.vec(f"h{k}", add(scale(m[k], c[k]), h_in, scale(m_next, sk)), rf"h^{{{k}}}")
        ss, sh = dot(sk, sk), dot(sk, h_in)
        I = P.sym_mat(
            f"I{k}",
            [
                [
                    A[k][i][j] + I_in[i][j]
                    + (m_next * ss + 2 * sh if i == j else ZERO)
                    - m_next * sk[i] * sk[j] - sk[i] * h_in[j] - h_in[i] * sk[j]
                    for j in range(3)
                ]
                for i in range(3)
            ],
            rf"I^{{{k}}}",
        )
        # gravity: e^k · (h × g ê⁰₁)  (right side of (17)–(19))
        Gv[k] = P.let(f"G{k}", g * (h[1] * kin.gamma[k][2] - h[2] * kin.gamma[k][1]), rf"G_{{{k}}}")
        Q[k], Gam[k], bias[k] = N[0], Gm[0], Nb[0]
        m_c[k], h_c[k], I_c[k] = mc, h, I
        Lam[k] = P.vec(f"Lam{k}", add(lam[k], Lam_in), rf"\Lambda^{{{k}}}")
        F_next, N_next, Gam_next, Lam_next, Fb_next, Nb_next = F, N, Gm, Lam[k], Fb, Nb
        m_next, h_next, I_next = mc, h, I

    # Mass matrix (composite bodies): a unit φ̈ᵏ, all else at rest, needs the force e¹ × hᵏ and
    # the moment Iᵏ e¹ about Oᵏ; carried back joint by joint, their moment about Oʲ projected
    # on eʲ is M_jk.
    M = [[ZERO] * n for _ in range(n)]
    for k in range(n, 0, -1):
        nm = [I_c[k][0][0], I_c[k][1][0], I_c[k][2][0]]
        fc = [ZERO, -h_c[k][2], h_c[k][1]]
        M[k - 1][k - 1] = nm[0]
        for j in range(k - 1, 0, -1):
            fc = P.vec(f"f{k}in{j}", J[j + 1].up(fc), rf"f^{{{k}|{j}}}")
            nm = P.vec(f"n{k}in{j}", add(J[j + 1].up(nm), cross(s[j], fc)), rf"n^{{{k}|{j}}}")
            M[j - 1][k - 1] = M[k - 1][j - 1] = nm[0]

    L = tuple(kin.tau[k] if spec.bodies[k - 1].control else ZERO for k in range(1, n + 1))
    joint = tuple(joint_torque(spec, kin, k) for k in range(1, n + 1))
    if all(j.is_zero() for j in joint):
        joint = ()
    return Dynamics(
        M=tuple(tuple(row) for row in M),
        Q=tuple(Q[1:]),
        Gamma=tuple(Gam[1:]),
        G=tuple(Gv[1:]),
        L=L,
        bias=tuple(bias[1:]),
        m_c=tuple(m_c[1:]),
        h=tuple(h_c[1:]),
        I=tuple(I_c[1:]),
        Lam=tuple(Lam[1:]),
        body_bias=tuple(body_bias[1:]),
        joint=joint,
        Lamdot=tuple(Lamdot[1:]) if timed_lam else (),
        Phi=tuple(Phi[1:]) if has_loads else (),
        loads=tuple(e[:2] for e in ext[1:]),
        force_vectors=tuple(e[2] for e in ext[1:]),
    )
