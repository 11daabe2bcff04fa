"""Kinematics in the paper's notation (digest §3).

Symbols: ``phi[k]``, ``phidot[k]`` are φᵏ, φ̇ᵏ (index 0 unused: k is the paper's k, 0 is the
base).  ``joint[k]`` applies αᵏ'ᵏ⁻¹ of eq. (11)/(15): rows are êᵏᵢ in frame k−1, so a vector's
components go from frame k−1 to frame k as v⁽ᵏ⁾ = αᵏ'ᵏ⁻¹ v⁽ᵏ⁻¹⁾.  Products of these are the
recursion (13)/(14).  All vectors below are components in the body's own frame, lists of three
polynomials (algebra.Poly).
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from . import platform as platform_motion
from .algebra import ONE, ZERO, Poly
from .program import Program
from ..chainspec.spec import ChainSpec
from .vec3 import add, scale

E1 = [ONE, ZERO, ZERO]
NULL = [ZERO, ZERO, ZERO]


def state_symbols(n: int):
    """φ, φ̇ and the joint torques Lᵏ as real sympy symbols, 1-based (index 0 is None)."""
    phi = [None] + [sp.Symbol(f"phi_{k}", real=True) for k in range(1, n + 1)]
    phidot = [None] + [sp.Symbol(f"phidot_{k}", real=True) for k in range(1, n + 1)]
    torque = [None] + [sp.Symbol(f"L_{k}", real=True) for k in range(1, n + 1)]
    return phi, phidot, torque


def folded_trig(theta: sp.Expr) -> tuple[sp.Expr, sp.Expr]:
    """cos θ, sin θ of a structural angle, exact (θ = pi/2 gives 0 and 1, pi/4 gives sqrt(2)/2;
    a numeric θ that sympy does not reduce stays cos(3/10), a constant of exact.py)."""
    return sp.cos(theta), sp.sin(theta)


def direction_cosines(theta: sp.Expr, phi: sp.Expr, cp=None, sph=None) -> sp.Matrix:
    """αᵏ'ᵏ⁻¹ of eq. (15) (with the digest's sign −sin θ in α₁₃) = R₁(φ) R₂(θ), in sympy
    (for LaTeX).  ``cp``, ``sph`` may name cos φ and sin φ."""
    ct, st = folded_trig(theta)
    cp = sp.cos(phi) if cp is None else cp
    sph = sp.sin(phi) if sph is None else sph
    return sp.Matrix(
        [
            [ct, 0, -st],
            [st * sph, cp, ct * sph],
            [st * cp, -sph, ct * cp],
        ]
    )


class Joint:
    """Joint k: αᵏ'ᵏ⁻¹ = R₁(φᵏ) R₂(θᵏ) (eq. (15)), applied factor by factor.  R₂(θ) has numbers
    when θ is numeric (and is the identity for θ = 0: a planar chain costs less); the one
    component both rows of R₁ read is named so it is computed once."""

    def __init__(self, prog: Program, k: int, ct: Poly, st: Poly, cp: Poly, sph: Poly):
        self.P, self.k, self.ct, self.st, self.cp, self.sp = prog, k, ct, st, cp, sph
        self._n = 0
        self._double = None  # (cos 2φ, sin 2φ), named when a tensor is first turned
        self._double_cost = 0  # their operations, until a tensor rotation uses them

    def is_planar(self) -> bool:
        """Whether R₂(θᵏ) is the identity: θᵏ = 0, the axis parallel to the one before and
        pointing the same way.  θᵏ = ±π (sin θ = 0 too) is R₂ = diag(−1, 1, −1), not the identity."""
        return self.st.is_zero() and self.ct.constant() == 1

    def _tmp(self, value: Poly, of: str | None, tex: str | None = None) -> Poly:
        self._n += 1
        return self.P.let(f"j{self.k}r{self._n}", value, tex or of and in_frame(of, rf"\bar{{{self.k}}}") + "_{3}")

    def down(self, v, of: str | None = None, tex: str | None = None) -> list:
        """v⁽ᵏ⁾ = αᵏ'ᵏ⁻¹ v⁽ᵏ⁻¹⁾.  ``of``: the vector's TeX (\\omega^{2}), which names the component both
        rows of R₁ read: its third in the frame of joint k at φᵏ = 0 (\\omega^{2|\\bar{3}}_{3}); or
        ``tex``, that component's TeX itself."""
        ct, st, c, s = self.ct, self.st, self.cp, self.sp
        w1, w2, w3 = ct * v[0] - st * v[2], v[1], self._tmp(st * v[0] + ct * v[2], of, tex)
        return [w1, c * w2 + s * w3, c * w3 - s * w2]

    def up(self, v, of: str | None = None) -> list:
        """v⁽ᵏ⁻¹⁾ = (αᵏ'ᵏ⁻¹)ᵀ v⁽ᵏ⁾ (``of`` as in ``down``)."""
        ct, st, c, s = self.ct, self.st, self.cp, self.sp
        y1, y2, y3 = v[0], c * v[1] - s * v[2], self._tmp(s * v[1] + c * v[2], of)
        return [ct * y1 + st * y3, y2, ct * y3 - st * y1]

    def up_sym(self, I, name: str, of: str | None = None) -> list:
        """αᵀ I α of a symmetric 3×3 matrix (a tensor of frame k seen in frame k−1), lower
        triangle named.  Two ways, the cheaper one kept (the other is dead code): products
        by R₁(φ) then R₂(θ), or the same two plane rotations by the double angle (cos 2φ,
        sin 2φ computed once per joint), which wins for full tensors and loses for sparse ones."""
        P, k = self.P, self.k
        start = len(P.defs)
        plain = self._conj(I, name, symmetric=True, of=of)
        cost_plain = _cost(P.defs[start:])
        if self._double is None:
            c, s = self.cp, self.sp
            start = len(P.defs)
            angle = P.tex.get(next(iter(c.terms))[0].sym, rf"\cos\varphi^{{{k}}}").removeprefix(r"\cos")
            self._double = (P.let(f"c2phi{k}", c * c - s * s, rf"\cos\left(2{angle}\right)"),
                            P.let(f"s2phi{k}", 2 * c * s, rf"\sin\left(2{angle}\right)"))
            self._double_cost = _cost(P.defs[start:])
        start = len(P.defs)
        X = _plane_sym(P, I, 1, 2, (self.cp, self.sp), self._double, f"{name}dr", of and in_frame(of, rf"\bar{{{k}}}"))
        if not self.is_planar():
            ct, st = self.ct, -self.st  # R₂(θ) is a plane rotation of (e₁, e₃) by −θ
            X = _plane_sym(P, X, 0, 2, (ct, st), (ct * ct - st * st, 2 * ct * st), f"{name}d", of and in_frame(of, str(k - 1)))
        if _cost(P.defs[start:]) + self._double_cost < cost_plain:
            self._double_cost = 0
            return X
        return plain

    def up_mat(self, X, name: str) -> list:
        """αᵀ X α of a general 3×3 matrix: R₁(φ) stage, then R₂(θ)."""
        return self._conj(X, name, symmetric=False)

    def _conj(self, X, name: str, symmetric: bool, of: str | None = None) -> list:
        P = self.P
        c, s, ct, st = self.cp, self.sp, self.ct, self.st
        R1 = [[ONE, ZERO, ZERO], [ZERO, c, s], [ZERO, -s, c]]
        R2 = [[ct, ZERO, -st], [ZERO, ONE, ZERO], [st, ZERO, ct]]

        def conj(R, X, tag, tex):  # Rᵀ X R
            T = [[P.let(f"{name}{tag}a_{i + 1}{j + 1}", sum((X[i][l] * R[l][j] for l in range(3)), ZERO)) for j in range(3)] for i in range(3)]
            out = [[None] * 3 for _ in range(3)]
            for i in range(3):
                for j in range(i + 1 if symmetric else 3):
                    out[i][j] = P.let(f"{name}{tag}_{i + 1}{j + 1}", sum((R[l][i] * T[l][j] for l in range(3)), ZERO),
                                      tex and f"{tex}_{{{i + 1}{j + 1}}}")
                    if symmetric:
                        out[j][i] = out[i][j]
            return out

        k = self.k
        return conj(R2, conj(R1, X, "r", of and in_frame(of, rf"\bar{{{k}}}")), "", of and in_frame(of, str(k - 1)))


def _cost(defs) -> int:
    """Operations of freshly made definitions (an estimate: some may be dead code)."""
    return sum(rhs.op_count() for _, rhs in defs if isinstance(rhs, Poly))


def in_frame(tex: str, frame: str) -> str:
    """The TeX of a vector or tensor of the paper's notation in another frame: \\omega^{2} in the
    frame \\bar{3} is \\omega^{2|\\bar{3}} (the n^{k|r} of Appendix A, the frame after the bar)."""
    head, sep, tail = tex.rpartition("^{")
    if not sep or not tail.endswith("}"):
        raise ValueError(f"not an upper-indexed name: {tex}")
    return f"{head}^{{{tail[:-1]}|{frame}}}"


def _plane_sym(P, X, i: int, j: int, cs: tuple, double: tuple, name: str, tex: str | None = None) -> list:
    """Rᵀ X R for a symmetric X and the plane rotation R = [[c, s], [−s, c]] of axes (i, j):
    with σ = (Xᵢᵢ + Xⱼⱼ)/2, δ = (Xᵢᵢ − Xⱼⱼ)/2 and the double angle (cos 2, sin 2),
    X'ᵢᵢ = σ + δ cos 2 − Xᵢⱼ sin 2, X'ⱼⱼ = σ − (…), X'ᵢⱼ = δ sin 2 + Xᵢⱼ cos 2: 12 operations
    instead of 27; the row of the third axis turns as a vector."""
    c, s = cs
    C2, S2 = double
    l = 3 - i - j
    out = [row[:] for row in X]
    sig = P.let(f"{name}sig", 0.5 * (X[i][i] + X[j][j]))
    dlt = P.let(f"{name}dlt", 0.5 * (X[i][i] - X[j][j]))
    t = P.let(f"{name}t", dlt * C2 - X[i][j] * S2)
    nm = lambda a, b: f"{name}_{max(a, b) + 1}{min(a, b) + 1}"  # noqa: E731
    tx = lambda a, b: tex and f"{tex}_{{{max(a, b) + 1}{min(a, b) + 1}}}"  # noqa: E731
    out[i][i] = P.let(nm(i, i), sig + t, tx(i, i))
    out[j][j] = P.let(nm(j, j), sig - t, tx(j, j))
    out[i][j] = out[j][i] = P.let(nm(i, j), dlt * S2 + X[i][j] * C2, tx(i, j))
    out[l][i] = out[i][l] = P.let(nm(l, i), X[l][i] * c - X[l][j] * s, tx(l, i))
    out[l][j] = out[j][l] = P.let(nm(l, j), X[l][i] * s + X[l][j] * c, tx(l, j))
    return out


@dataclass(frozen=True)
class Kinematics:
    prog: Program  # every quantity below is a value of this program
    n: int
    phi: list
    phidot: list
    torque: list
    alpha: list  # alpha[k] = αᵏ'ᵏ⁻¹ (eq. 15) in sympy, for LaTeX
    joint: list  # joint[k] applies αᵏ'ᵏ⁻¹ and its transpose to polynomial vectors
    gamma: list  # gamma[k] = ê⁰₁ (down) in frame k: the column (αᵏᵢ₁)ᵢ of eq. (14)
    omega: list  # omega[k] = ωᵏ of eq. (1) in frame k (omega[0] = ω⁰, the platform's)
    qd: list  # qd[k] = φ̇ᵏ as a polynomial
    tau: list  # tau[k] = Lᵏ as a polynomial
    # the platform (frame 0; all NULL for a fixed base): ε⁰, v₀, v̇₀ in the platform frame
    platform: platform_motion.PlatformMotion | None = None
    eps0: list = None
    vel0: list = None
    acc0: list = None
    symbolic_platform: bool = False  # ω⁰, ε⁰, v̇₀, γ⁰ are the symbols of PLATFORM_SYMBOLS (LaTeX)

    def to_frame(self, k: int, v, name: str) -> list:
        """A vector of the platform frame (frame 0) in frame k, by the joints' αʲ'ʲ⁻¹, j ≤ k."""
        for j in range(1, k + 1):
            v = self.prog.vec(f"{name}in{j}", self.joint[j].down(v))
        return v


def platform_symbols() -> dict:
    """The symbols ω⁰ᵢ, ε⁰ᵢ, v̇₀ᵢ, γ⁰ᵢ stand for in the LaTeX's grouped equations (8)–(10)."""
    return {key: [sp.Symbol(f"{key}0_{i}", real=True) for i in range(1, 4)] for key in ("omega", "epsilon", "vdot", "gamma")}


def appends_to(prog: Program, kin: Kinematics) -> None:
    """The check every later stage makes: it appends its quantities to the program passed to it,
    which must be the one the kinematics' quantities live in."""
    if prog is not kin.prog:
        raise ValueError("a stage must append to the program of the kinematics it reads (kin.prog)")


def derive(spec: ChainSpec, prog: Program | None = None, symbolic_platform: bool = False) -> Kinematics:
    """The kinematics, its quantities appended to ``prog`` (a new program if None), which the
    later stages are passed and append to in turn (the order of the calls is the order of the
    names); with ``symbolic_platform``, the platform's ω⁰, ε⁰, v̇₀ and γ⁰ stay symbols (for the
    LaTeX, which shows the platform terms apart and their values as functions of t)."""
    n = spec.n
    P = Program() if prog is None else prog
    phi, phidot, torque = state_symbols(n)
    qd = [None] + [P.input(phidot[k]) for k in range(1, n + 1)]
    tau = [None] + [P.input(torque[k]) for k in range(1, n + 1)]
    alpha, joint = [None], [None]
    gamma = [E1]
    omega = [NULL]
    pm = platform_motion.derive(spec)
    eps0 = vel0 = acc0 = NULL
    if pm is not None:
        num = P.from_sympy
        if symbolic_platform:
            sy = platform_symbols()
            pick = lambda key, vals: [ZERO if v == 0 else P.input(s) for s, v in zip(sy[key], vals)]  # noqa: E731
            omega = [pick("omega", pm.omega)]
            eps0 = pick("epsilon", pm.eps)
            acc0 = pick("vdot", pm.acc)
            gamma = [pick("gamma", pm.down) if pm.rotates else [num(x) for x in pm.down]]
        else:
            gamma = [P.vec("gam0", [num(x) for x in pm.down], r"\gamma^{0}")]
            omega = [P.vec("om0", [num(x) for x in pm.omega], r"\omega^{0}")]
            eps0 = P.vec("eps0", [num(x) for x in pm.eps], r"\varepsilon^{0}")
            acc0 = P.vec("a0", [num(x) for x in pm.acc], r"\dot{v}_{0}")
        vel0 = P.vec("v0", [num(x) for x in pm.vel], r"v_{0}")
    for k, body in enumerate(spec.bodies, start=1):
        # the paper's angle is the joint angle plus the joint's offset (zero but for imported robots)
        turn, tex = phi[k] + body.offset, (rf"\varphi^{{{k}}}" if body.offset == 0 else rf"\left(\varphi^{{{k}}} + \delta^{{{k}}}\right)")
        cp = P.let_sympy(f"cos_phi{k}", sp.cos(turn), rf"\cos{tex}")
        sph = P.let_sympy(f"sin_phi{k}", sp.sin(turn), rf"\sin{tex}")
        P.alias(sp.cos(turn), cp)
        P.alias(sp.sin(turn), sph)
        ct, st = (P.from_sympy(v) for v in folded_trig(body.theta))
        j = Joint(P, k, ct, st, cp, sph)
        joint.append(j)
        alpha.append(direction_cosines(body.theta, phi[k], *(next(iter(v.terms))[0].sym for v in (cp, sph))))
        gamma.append(P.vec(f"gam{k}", j.down(gamma[k - 1], rf"\gamma^{{{k - 1}}}"), rf"\gamma^{{{k}}}"))  # (α^k_{i1})_i, eq. (14)
        omega.append(P.vec(f"om{k}", add(j.down(omega[k - 1], rf"\omega^{{{k - 1}}}"), scale(qd[k], E1)), rf"\omega^{{{k}}}"))  # eq. (1)
    return Kinematics(P, n, phi, phidot, torque, alpha, joint, gamma, omega, qd, tau, pm, eps0, vel0, acc0,
                      symbolic_platform and pm is not None)
