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

from dataclasses import dataclass, field

from .algebra import ZERO, Poly
from . import loopform
from .kinematics import NULL, Kinematics, appends_to
from .program import Program
from .vec3 import add, cross, dot, matvec, scale
from ..chainspec.spec import T, ChainSpec


@dataclass(frozen=True)
class Dynamics:
    M: tuple  # n×n mass matrix (rows of Poly; loopform.PairMatrix for a long chain), symmetric positive definite
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
    loops: object = None  # loopform.LoopForm of a long chain (M is then z1ᵏ·Sʲ in frame 0), else None
    armature: tuple = ()  # per joint the reflected motor inertia aᵏ on M_kk (ZERO where none); () when none

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


@dataclass
class _Inertial:
    """The bodies' data as program polynomials (index 0 unused: bodies 1..n, as in the paper).
    Fields in the order the program defines them (a name's number follows that order)."""

    A: list
    c: list
    s: list
    lam: list
    lamdot: list
    m: list
    g: Poly
    timed_lam: bool  # some λᵏ depends on t: λ̊ terms
    has_loads: bool  # some body carries [[body.force]] or [[body.moment]]
    ext: list  # per body: (force, moment about Oᵏ, the force vectors) of its external loads


@dataclass
class _SubChain:
    """The running totals of the backward pass: the sub-chain k+1…n as seen from Oᵏ⁺¹ in frame
    k+1 (the paper's sums over p > k).  Names follow the paper: F, N force and moment of the
    velocity-quadratic part, Gm the gyroscopic Σ ωᵖ × λᵖ, Lam Σ λᵖ, m, h, I the composite mass,
    first moment and inertia; Fb, Nb the code's combined bias; Ld Σ λ̊ᵖ; Fl, Nl the loads."""

    F: list = field(default_factory=lambda: NULL)
    N: list = field(default_factory=lambda: NULL)
    Gm: list = field(default_factory=lambda: NULL)
    Lam: list = field(default_factory=lambda: NULL)
    h: list = field(default_factory=lambda: NULL)
    Fb: list = field(default_factory=lambda: NULL)
    Nb: list = field(default_factory=lambda: NULL)
    Ld: list = field(default_factory=lambda: NULL)
    Fl: list = field(default_factory=lambda: NULL)
    Nl: list = field(default_factory=lambda: NULL)
    m: Poly = ZERO
    I: list | None = None


def _inertial(spec: ChainSpec, kin: Kinematics) -> _Inertial:
    num = kin.prog.from_sympy
    B = spec.bodies
    return _Inertial(
        A=[None] + [[[num(x) for x in row] for row in b.A] for b in B], c=[None] + [[num(x) for x in b.c] for b in B],
        s=[None] + [[num(x) for x in b.s] for b in B], lam=[None] + [[num(x) for x in b.lam] for b in B],
        m=[None] + [num(b.m) for b in B], g=num(spec.g), timed_lam=any(x.has(T) for b in B for x in b.lam),
        lamdot=[None] + [[num(x) for x in b.lam_dot] for b in B], has_loads=any(b.forces or b.moments for b in B),
        ext=[None] + [_external(spec, kin, k) for k in range(1, spec.n + 1)])


def _forward_pass(kin: Kinematics, bd: _Inertial) -> tuple[list, list, list]:
    """Forward pass with φ̈ = 0: the angular accelerations εᵏ (eq. (5), from the platform's ε⁰) and
    the accelerations of Oᵏ (eq. (6) summed over l < k, from v̇₀), in frame k; aOg also carries
    gravity (the base accelerating up with g), for the combined recursion."""
    P, J, w, qd = kin.prog, kin.joint, kin.omega, kin.qd
    if kin.platform is None:
        eps = [NULL]
        acc_O, acc_Og = [None, NULL], [None, P.vec("aOg1", scale(-bd.g, kin.gamma[1]))]
    else:
        eps = [kin.eps0]
        a1 = P.vec("aO1", J[1].down(kin.acc0), r"a^{1}")
        acc_O, acc_Og = [None, a1], [None, P.vec("aOg1", add(a1, scale(-bd.g, kin.gamma[1])))]
    for k in range(1, kin.n + 1):
        eps.append(P.vec(f"eps{k}", add(J[k].down(eps[k - 1], rf"\varepsilon^{{{k - 1}}}"), cross(w[k], [qd[k], ZERO, ZERO])),
                         rf"\varepsilon^{{{k}}}"))
        if k > 1:
            j, sj = k - 1, bd.s[k - 1]
            ws = P.vec(f"ws{j}", cross(w[j], sj), rf"(\boldsymbol\omega\times\mathbf s)^{{{j}}}")
            rel = P.vec(f"aOrel{k}in{j}", add(cross(eps[j], sj), cross(w[j], ws)), rf"\tilde a^{{{k}}}")
            acc_O.append(P.vec(f"aO{k}", J[k].down(add(acc_O[j], rel), rf"a^{{{k}}}"), rf"a^{{{k}}}"))
            acc_Og.append(P.vec(f"aOg{k}", J[k].down(add(acc_Og[j], rel))))
    return eps, acc_O, acc_Og


def _carried_in(kin: Kinematics, k: int, nxt: _SubChain) -> _SubChain:
    """The sub-chain k+1…n's totals turned from frame k+1 into frame k (still about Oᵏ⁺¹)."""
    if k == kin.n:
        return _SubChain(I=[[ZERO] * 3 for _ in range(3)])
    P, up = kin.prog, kin.joint[k + 1].up  # frame k+1 → frame k
    F, N, Gm, Lam, h = (P.vec(f"{nm}{k + 1}in{k}", up(v, rf"{tex}^{{{k + 1}}}"), rf"{tex}^{{{k + 1}|{k}}}") for nm, v, tex in
                        (("F", nxt.F, "F"), ("N", nxt.N, "N"), ("Gm", nxt.Gm, r"\Gamma"), ("Lam", nxt.Lam, r"\Lambda"),
                         ("h", nxt.h, "h")))
    I = kin.joint[k + 1].up_sym(nxt.I, f"I{k + 1}in{k}", rf"I^{{{k + 1}}}")
    Fb, Nb = P.vec(f"Fb{k + 1}in{k}", up(nxt.Fb)), P.vec(f"Nb{k + 1}in{k}", up(nxt.Nb))
    return _SubChain(F=F, N=N, Gm=Gm, Lam=Lam, h=h, I=I, Fb=Fb, Nb=Nb, m=nxt.m, Ld=nxt.Ld, Fl=nxt.Fl, Nl=nxt.Nl)


def _composite(P, k: int, bd: _Inertial, inn: _SubChain) -> tuple:
    """Composite mass, first moment and inertia of the sub-chain k…n about Oᵏ (the parallel-axis
    shift of the sub-chain k+1…n by sᵏ)."""
    A, c, sk, m, m_next, h_in, I_in = bd.A[k], bd.c[k], bd.s[k], bd.m[k], inn.m, inn.h, inn.I
    mc = P.let(f"mc{k}", m + m_next, rf"m_c^{{{k}}}")
    h = P.vec(f"h{k}", add(scale(m, c), h_in, scale(m_next, sk)), rf"h^{{{k}}}")
    ss, sh = dot(sk, sk), dot(sk, h_in)
    I = P.sym_mat(f"I{k}", [[A[i][j] + I_in[i][j] + (m_next * ss + 2 * sh if i == j else ZERO)
                             - m_next * sk[i] * sk[j] - sk[i] * h_in[j] - h_in[i] * sk[j] for j in range(3)]
                            for i in range(3)], rf"I^{{{k}}}")
    return mc, h, I


def _backward_step(kin: Kinematics, k: int, bd: _Inertial, acc: tuple, nxt: _SubChain, out: dict) -> _SubChain:
    """Body k joins the sub-chain k+1…n: the totals about Oᵏ in frame k; the k-th equation's
    terms into ``out``."""
    P, w = kin.prog, kin.omega[k]
    eps, acc_O, acc_Og = acc
    A, c, sk, m = bd.A[k], bd.c[k], bd.s[k], bd.m[k]
    inn = _carried_in(kin, k, nxt)
    wcc = P.vec(f"wc{k}", cross(w, c), rf"(\boldsymbol\omega\times\mathbf c)^{{{k}}}")
    rel_G = add(cross(eps[k], c), cross(w, wcc))  # a_G − a_O
    Aw = P.vec(f"Aw{k}", matvec(A, w), rf"(\mathbf A\boldsymbol\omega)^{{{k}}}")
    # the paper's split: velocity-quadratic part Σ_{p≥k} [(Aω)˙ + m c×a_O] + Σ_{q>k} d_kq × m a_G
    F = P.vec(f"F{k}", add(scale(m, add(acc_O[k], rel_G)), inn.F), rf"F^{{{k}}}")
    N = P.vec(f"N{k}", add(add(matvec(A, eps[k]), cross(w, Aw)), scale(m, cross(c, acc_O[k])), inn.N, cross(sk, inn.F)),
              rf"N^{{{k}}}")
    Gm = P.vec(f"Gm{k}", add(cross(w, bd.lam[k]), inn.Gm), rf"\Gamma^{{{k}}}")  # gyroscopic: Σ_{p≥k} ωᵖ × λᵖ
    # the code's form: one recursion for Q + Γ − G; body k's own share first (force and moment
    # about Oᵏ of body k alone at the accelerations of φ̈ = 0, with gravity, the external loads
    # of the right side of (2)–(4) and λ̊ of (7))
    Fx, Nx, _ = bd.ext[k]
    pF = P.vec(f"pF{k}", add(scale(m, add(acc_Og[k], rel_G)), scale(-1.0, Fx)))
    pN = P.vec(f"pN{k}", add(matvec(A, eps[k]), cross(w, add(Aw, bd.lam[k])), scale(m, cross(c, acc_Og[k])),
                             bd.lamdot[k], scale(-1.0, Nx)))
    Ld = Fl = Nl = NULL
    if bd.timed_lam:  # the paper's split: eᵏ · Σ_{p≥k} λ̊ᵖ
        Ld = P.vec(f"Ld{k}", add(bd.lamdot[k], P.vec(f"Ld{k + 1}in{k}", kin.joint[k + 1].up(nxt.Ld)) if k < kin.n else NULL))
        out["Lamdot"][k] = Ld[0]
    if bd.has_loads:  # and the loads' generalized force: Σ eᵏ·Mᵖ + eᵏ·(sᵖ × Σ F^q)
        Fl_in = P.vec(f"Fl{k + 1}in{k}", kin.joint[k + 1].up(nxt.Fl)) if k < kin.n else NULL
        Nl_in = P.vec(f"Nl{k + 1}in{k}", kin.joint[k + 1].up(nxt.Nl)) if k < kin.n else NULL
        Fl = P.vec(f"Fl{k}", add(Fx, Fl_in))
        Nl = P.vec(f"Nl{k}", add(Nx, Nl_in, cross(sk, Fl_in)))
        out["Phi"][k] = Nl[0]
    out["body_bias"][k] = (pF, pN)
    Fb = P.vec(f"Fb{k}", add(pF, inn.Fb))
    Nb = P.vec(f"Nb{k}", add(pN, inn.Nb, cross(sk, inn.Fb)))
    mc, h, I = _composite(P, k, bd, inn)
    # gravity: eᵏ · (h × g ê⁰₁)  (right side of (17)–(19))
    out["G"][k] = P.let(f"G{k}", bd.g * (h[1] * kin.gamma[k][2] - h[2] * kin.gamma[k][1]), rf"G_{{{k}}}")
    Lam = P.vec(f"Lam{k}", add(bd.lam[k], inn.Lam), rf"\Lambda^{{{k}}}")
    out["Q"][k], out["Gamma"][k], out["bias"][k] = N[0], Gm[0], Nb[0]
    out["m_c"][k], out["h"][k], out["I"][k], out["Lam"][k] = mc, h, I, Lam
    return _SubChain(F=F, N=N, Gm=Gm, Lam=Lam, h=h, Fb=Fb, Nb=Nb, Ld=Ld, Fl=Fl, Nl=Nl, m=mc, I=I)


def armature(spec: ChainSpec, kin: Kinematics) -> tuple:
    """aᵏ per joint as Poly (a motor's inertia reflected through its gear: ½aᵏ(φ̇ᵏ)² of kinetic
    energy, aᵏφ̈ᵏ in joint k's equation alone), () when every aᵏ is 0."""
    if all(b.armature == 0 for b in spec.bodies):
        return ()
    return tuple(kin.prog.from_sympy(b.armature) for b in spec.bodies)


def _mass_matrix(kin: Kinematics, s: list, I_c: list, h_c: list) -> list:
    """Composite-rigid-body pass: a unit φ̈ᵏ, all else at rest, needs the force e¹ × hᵏ and the
    moment Iᵏ e¹ about Oᵏ; carried back joint by joint, their moment about Oʲ projected on eʲ is
    M_jk."""
    P, J, n = kin.prog, kin.joint, kin.n
    M = [[ZERO] * n for _ in range(n)]
    for k in range(n, 0, -1):
        nm = [I_c[k][0][0], I_c[k][1][0], I_c[k][2][0]]
        fc = [ZERO, -h_c[k][2], h_c[k][1]]
        M[k - 1][k - 1] = nm[0]
        for j in range(k - 1, 0, -1):
            fc = P.vec(f"f{k}in{j}", J[j + 1].up(fc, rf"f^{{{k}}}"), rf"f^{{{k}|{j}}}")
            nm = P.vec(f"n{k}in{j}", add(J[j + 1].up(nm, rf"n^{{{k}}}"), cross(s[j], fc)), rf"n^{{{k}|{j}}}")
            M[j - 1][k - 1] = M[k - 1][j - 1] = nm[0]
    return M


def derive(spec: ChainSpec, prog: Program, kin: Kinematics, loops: bool = False) -> Dynamics:
    """(17)–(19), or (8)–(10) in the general case, in three passes over the chain (named as
    Pinocchio names its passes): the forward pass of the accelerations at φ̈ = 0, the backward
    pass over the sub-chains p ≥ k (the paper's sums; Q, Γ, G, the code's bias, the composite
    bodies), and the composite-rigid-body pass of the mass matrix; the quantities appended to
    ``prog``.  ``loops``: the mass matrix of loopform.py instead of the composite-rigid-body pass
    (a long chain: O(n) quantities, the pairs left to the template's loops)."""
    appends_to(prog, kin)
    n = spec.n
    bd = _inertial(spec, kin)
    acc = _forward_pass(kin, bd)
    out = {key: [None] * (n + 1) for key in ("Q", "Gamma", "G", "bias", "m_c", "h", "I", "Lam", "body_bias", "Lamdot", "Phi")}
    nxt = _SubChain()
    for k in range(n, 0, -1):
        nxt = _backward_step(kin, k, bd, acc, nxt, out)
    lf = loopform.derive(spec, kin) if loops else None
    M = lf.mass_matrix() if loops else _mass_matrix(kin, bd.s, out["I"], out["h"])
    arm = armature(spec, kin)
    if arm:  # the motors' reflected inertias: aᵏ on the diagonal alone (the loop form is not taken then)
        assert not loops, "the loop form has no armature"
        for k in range(n):
            M[k][k] = M[k][k] + arm[k]
    joint = tuple(joint_torque(spec, kin, k) for k in range(1, n + 1))
    return Dynamics(
        M=M if loops else tuple(tuple(row) for row in M),
        L=tuple(kin.tau[k] if spec.bodies[k - 1].control else ZERO for k in range(1, n + 1)),
        joint=() if all(j.is_zero() for j in joint) else joint,
        Lamdot=tuple(out["Lamdot"][1:]) if bd.timed_lam else (),
        Phi=tuple(out["Phi"][1:]) if bd.has_loads else (),
        loads=tuple(e[:2] for e in bd.ext[1:]),
        force_vectors=tuple(e[2] for e in bd.ext[1:]),
        loops=lf,
        armature=arm,
        **{key: tuple(out[key][1:]) for key in ("Q", "Gamma", "G", "bias", "m_c", "h", "I", "Lam", "body_bias")},
    )
