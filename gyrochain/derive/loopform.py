"""The loop form of a long chain: per-joint quantities in frame 0, so that every emitted function
is O(n) straight-line code and the O(n²) work is loops of the template.

The straight-line forms name a quantity per pair of joints (the composite-rigid-body pass carries
the force and moment of joint k back to every joint j < k, (Mφ̇)ⱼ and its tangent sum over the
row): code of size O(n²), which gcc needs minutes for at n = 32 (its unrolled LDLᵀ is O(n³)).
Past ``LOOP_MIN_N`` joints the model takes instead, in frame 0 (the platform's frame, about O¹):

    Sᵏ = (eᵏ, Oᵏ × eᵏ)   joint k's axis as a twist,
    Iᵏ = (Aᵏ, hᵏ, mᵏ)   body k's inertia about O¹ (the parallel-axis rule from Oᵏ),
    z1ᵏ = Iᶜᵏ Sᵏ         with Iᶜᵏ = Σ_{p≥k} Iᵖ the sub-chain's,
    M_kj = z1ᵏ · Sʲ      (k ≥ j; the composite-rigid-body algorithm as a 6-dot per pair),
    vᵏ = vᵏ⁻¹ + Sᵏ φ̇ᵏ    the motion of body k relative to the platform,
    T₂ = ½ Σₖ vᵏ · Iᵏvᵏ   (= ½ φ̇ᵀ M φ̇),

(T₂ is Jacobi's on a moving platform; on a fixed base the energy, the momenta and their rate
come from the sub-chains' momenta in frame k instead, integrals.py and derivatives.py: fewer
operations per joint than in frame 0.)

S and z1 are the straight line's outputs (6n numbers each, folded and with zeros gone per joint);
M's lower triangle is the template's loop over the pairs, its LDLᵀ a loop too.  The same S and z1
are world.py's (there with the velocity terms of the derivatives).  Below ``LOOP_MIN_N`` the model
keeps the straight-line forms, byte for byte.
"""
from __future__ import annotations

from dataclasses import dataclass

from .algebra import ONE, ZERO, Poly
from .kinematics import Kinematics, appends_to
from .vec3 import cross, dot, dot6, inertia_apply

# From this many joints on, the mass matrix, the energy, the momenta and their rate, and the
# velocities from the momenta are emitted in the loop form (chosen by measured cost: see
# docs/benchmarks.md, "Long chains").
LOOP_MIN_N = 12

# From this many joints on, the LDLᵀ of velocities (the template's ldlt_checked_columns_) updates
# each column's sums row-contiguously, four k at a time, with L kept transposed above the diagonal;
# below, and always in mass_matrix, one sum per entry (ldlt_checked_).  Both give the same bits.
# Measured alone (µs, gcc -O2 / -O3 -march=native, 2026-11-26): n = 24 per entry 1.5 against 2.0 by
# columns; n = 32 5.7 / 1.8 against 3.6 / 1.7; n = 64 45 against 20; n = 128 174 / 145 against 99 / 58.
# In mass_matrix, where the factors go to a local array, gcc -O3 vectorises the per-entry form
# across the rows (n = 128: 26 µs against 29 µs by columns), so it keeps that form.
LDLT_COLUMNS_MIN_N = 32

LOOP_FORMS = ("auto", "straight", "loops")


def uses_loops(n: int, form: str = "auto", armature: bool = False) -> bool:
    """Whether a chain of n joints gets the loop form (``form`` forces it either way).  A chain
    with motor armature keeps the straight-line forms at every n (the loop form's M is the
    template's sum of pairs, which has no diagonal term of its own)."""
    if form not in LOOP_FORMS:
        raise ValueError(f"loop form must be one of {', '.join(LOOP_FORMS)}, not {form!r}")
    if armature and form == "loops":
        raise ValueError("the loop form does not take motor armature (the straight-line forms do, at every n)")
    return form == "loops" or (form == "auto" and n >= LOOP_MIN_N and not armature)


@dataclass(frozen=True)
class LoopForm:
    """Per joint (index k − 1) the 6-vectors S and z1; T₂ (see the module)."""

    S: tuple
    z1: tuple
    T2: Poly

    def mass_matrix(self) -> "PairMatrix":
        """M as polynomials of S and z1 (what the LaTeX and a forced composite form read), each
        entry formed when first read."""
        return PairMatrix(self)


class PairMatrix:
    """M[i][j] = z1^max(i,j) · S^min(i,j), formed on first reading (a long chain's n² entries are
    read only by the LaTeX)."""

    def __init__(self, lf: LoopForm):
        self._lf, self._n, self._done = lf, len(lf.S), {}

    def __len__(self) -> int:
        return self._n

    def __getitem__(self, i: int) -> "PairMatrix._Row":
        if not 0 <= i < self._n:
            raise IndexError(i)
        return PairMatrix._Row(self, i)

    def entry(self, i: int, j: int) -> Poly:
        key = (max(i, j), min(i, j))
        if key not in self._done:
            self._done[key] = dot6(self._lf.z1[key[0]], self._lf.S[key[1]])
        return self._done[key]

    class _Row:
        def __init__(self, m: "PairMatrix", i: int):
            self._m, self._i = m, i

        def __len__(self) -> int:
            return self._m._n

        def __getitem__(self, j: int) -> Poly:
            if not 0 <= j < self._m._n:
                raise IndexError(j)
            return self._m.entry(self._i, j)


ROWS0 = [[ONE, ZERO, ZERO], [ZERO, ONE, ZERO], [ZERO, ZERO, ONE]]  # R_0: the platform's own frame


def place_joint(spec, kin: Kinematics, k: int, rows, O, tag: str) -> tuple:
    """Joint k in frame 0, from joint k − 1's ``rows`` and ``O``: (rows of R_k, Oᵏ, Sᵏ), named
    ``{tag}R…``, ``{tag}O…``, ``{tag}Sv…``.  Row i of R_k is ê⁰ᵢ in frame k, R_k[i][j] = ê⁰ᵢ·êᵏⱼ."""
    P, num = kin.prog, kin.prog.from_sympy
    if k > 1:  # Oᵏ = Oᵏ⁻¹ + R_{k−1} sᵏ⁻¹ (the LaTeX's ρᵏ)
        s = [num(x) for x in spec.bodies[k - 2].s]
        O = P.vec(f"{tag}O{k}", [O[i] + dot(rows[i], s) for i in range(3)], rf"\rho^{{{k}}}")
    # row i of R_k: the paper's α^k_{ji}, j = 1, 2, 3 (its third component in the frame of joint k at φᵏ = 0 on the way)
    rows = [[P.let(f"{tag}R{k}r{i + 1}_{j + 1}", x, rf"\alpha^{{{k}}}_{{{j + 1}{i + 1}}}")
             for j, x in enumerate(kin.joint[k].down(rows[i], tex=rf"\alpha^{{\bar{{{k}}}}}_{{3{i + 1}}}"))] for i in range(3)]
    e = [rows[i][0] for i in range(3)]
    return rows, O, e + P.vec(f"{tag}Sv{k}", cross(O, e))


def body_inertia(spec, kin: Kinematics, k: int, rows, O, tag: str) -> tuple:
    """Body k's spatial inertia (A, h, m) about O¹ in frame 0: A_w = R A Rᵀ, h = R m c, then moved
    from Oᵏ to O¹ (names ``{tag}A…``, ``{tag}h…``)."""
    P, num, b = kin.prog, kin.prog.from_sympy, spec.bodies[k - 1]
    m = num(b.m)
    A = [[num(x) for x in row] for row in b.A]
    Ar = [[dot(A[i], rows[j]) for i in range(3)] for j in range(3)]  # Ar[j] = A (row j of R)ᵀ
    Aw = [[dot(rows[i], Ar[j]) for j in range(3)] for i in range(3)]
    hw = [dot(rows[i], [m * num(x) for x in b.c]) for i in range(3)]
    diag = m * dot(O, O) + 2 * dot(O, hw)
    A0 = P.sym_mat(f"{tag}A{k}", [[Aw[i][j] + (diag if i == j else ZERO) - m * O[i] * O[j] - hw[i] * O[j] - O[i] * hw[j]
                                  for j in range(3)] for i in range(3)], rf"\Theta^{{{k}}}")
    return A0, P.vec(f"{tag}h{k}", [hw[i] + m * O[i] for i in range(3)], rf"\eta^{{{k}}}"), m


def derive(spec, kin: Kinematics) -> LoopForm:
    """S, z1 and T₂, appended to ``kin.prog`` (names C…)."""
    appends_to(kin.prog, kin)
    P, n = kin.prog, spec.n
    rows, O = ROWS0, [ZERO] * 3
    v = [ZERO] * 6
    S, body, mom = [], [], []
    for k in range(1, n + 1):
        rows, O, Sk = place_joint(spec, kin, k, rows, O, "C")
        S.append(Sk)
        body.append(body_inertia(spec, kin, k, rows, O, "C"))
        v = P.vec(f"Cv{k}a", [v[i] + S[-1][i] * kin.qd[k] for i in range(3)]) + \
            P.vec(f"Cv{k}l", [v[3 + i] + S[-1][3 + i] * kin.qd[k] for i in range(3)])
        hk = inertia_apply(body[-1], v)
        mom.append((v, P.vec(f"Cm{k}a", hk[:3]) + P.vec(f"Cm{k}l", hk[3:])))  # Iᵏvᵏ
    T2 = 0.5 * sum((dot6(vk, hk) for vk, hk in mom), ZERO)
    z1 = [None] * n
    IC = None
    for k in range(n, 0, -1):
        A0, h0, m = body[k - 1]
        IC = (A0, h0, m) if IC is None else (
            P.sym_mat(f"CIC{k}", [[A0[i][j] + IC[0][i][j] for j in range(3)] for i in range(3)], rf"\bar\Theta^{{{k}}}"),
            P.vec(f"ChC{k}", [h0[i] + IC[1][i] for i in range(3)], rf"\bar\eta^{{{k}}}"), P.let(f"CmC{k}", m + IC[2]))
        z1[k - 1] = [Poly.lift(x) for x in inertia_apply(IC, S[k - 1])]
    return LoopForm(tuple(tuple(Poly.lift(x) for x in s) for s in S), tuple(tuple(z) for z in z1), T2)
