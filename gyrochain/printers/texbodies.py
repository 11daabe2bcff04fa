"""A long chain's equations body by body: the paper's sums over the bodies p ≥ k with each body's
share written in a few quantities of its own frame p, each defined by a short formula from the
quantities before it, so that a referee evaluates M_kr, Q_k, Γ_k, G_k and U by hand where their
closed forms are too long to read (a Panda's M₁₁ has hundreds of terms).

With eᵏ in frame p the paper's α^{kp}_{1i} (its (13)), σ^{kp} the vector O^kO^p and
v^{kp} = eᵏ × (σ^{kp} + cᵖ) the velocity of the centre of mass Cᵖ per unit φ̇ᵏ, the first line of
(17)–(19) summed body by body is M_kr = Σ_p μᵖ_kr, μᵖ_kr = Jᵖ_ij α^{kp}_{1i} α^{rp}_{1j} + mᵖ v^{kp}·v^{rp}
(Jᵖ the inertia about Cᵖ); its velocity terms are Q_k = Σ_p νᵖ_k, νᵖ_k = α^{kp}_{1i} Nᵖ_i + mᵖ v^{kp}·wᵖ,
with Nᵖ = Jᵖεᵖ + ωᵖ × Jᵖωᵖ and wᵖ the acceleration of Cᵖ at φ̈ = 0 (aᵖ that of Oᵖ, āᵖ the same in
frame p − 1); Γ_k = Σ_p α^{kp}_{1i}(ωᵖ × λᵖ)_i, G_k = Σ_p ηᵖ_k with ηᵖ_k = g mᵖ γᵖ·v^{kp}, and
U = g Σ_p mᵖ dᵖ with dᵖ = γᵖ·(σ^{1p} + cᵖ) the depth of Cᵖ below O¹ (and the springs' part).  A quantity
that is zero, a number or one factor, or equal to one before it, is written as that where it is used."""
from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

from . import texcheck
from .texlayout import TEXT_WIDTH, TexEquation, block
from .texeom import m_name
from .texterms import TexWriter

ZERO3 = (sp.Integer(0),) * 3
E1 = (sp.Integer(1), sp.Integer(0), sp.Integer(0))


def applies(spec, kin, dyn) -> bool:
    """Whether the body-by-body form covers the document: a fixed base, no loop form (a chain that
    long prints its 6-vectors), no loads and no rotor spun up (their terms are not written here)."""
    return (kin.platform is None and dyn.loops is None and all(p.is_zero() for p in dyn.Phi)
            and all(p.is_zero() for p in dyn.Lamdot))


def _cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _dot(a, b):
    return sum((x * y for x, y in zip(a, b)), sp.Integer(0))


def _add(a, b):
    return tuple(x + y for x, y in zip(a, b))


def _times(M, x):
    return tuple(sum((M[i][j] * x[j] for j in range(3)), sp.Integer(0)) for i in range(3))


def _inline(expr: sp.Expr) -> bool:
    """Zero, a number, or a number times one factor: written where it is used."""
    terms = sp.Add.make_args(expr)
    if len(terms) != 1:
        return False
    _, rest = terms[0].as_coeff_Mul()
    return rest == 1 or len(sp.Mul.make_args(rest)) == 1 and not isinstance(rest, sp.Pow)


LINE_WIDTH = TEXT_WIDTH - 11  # ems of a definition's line: one to a row, beside its name and number
SHARE_LINES = 6  # a closed form longer than this is written as the sum of the bodies' shares, where that is shorter


class Choice:
    """Which printed quantities a document with closed forms writes as the sums of the bodies'
    shares instead: those whose closed form (or a coefficient of it) is longer than SHARE_LINES
    lines when the sum is shorter.  ``alt``: the sums, by key (M, Q, Gamma, G, U) and index."""

    def __init__(self, doc, alt: dict | None):
        self.doc, self.alt, self.chosen = doc, alt, []

    def start(self) -> dict:
        return dict(self.doc.used)

    def shown(self, key: str, i: int, shown, before: dict):
        """``shown`` (the closed form's lines), or the shares' sum's where the closed form is long."""
        return self.instead(key, i, len(shown), before) or shown

    def instead(self, key: str, i: int, lines: int, before: dict):
        """The shares' sum's lines where a closed form of ``lines`` lines (or its longest
        coefficient's) is long and the sum shorter, else None; the forms the closed form counted are
        then taken back (the document states their counts)."""
        if self.alt is None or lines <= SHARE_LINES:
            return None
        expr = self.alt[key] if key == "U" else self.alt[key][i]
        other = self.doc.lines(expr, expand=False)
        if len(other) >= lines:
            return None
        self.doc.used.clear()
        self.doc.used.update(before)
        self.chosen.append(expr)
        return other


@dataclass
class Shares:
    rows: list = field(default_factory=list)  # (p, its name, its symbol, its formula), in order
    M: list = field(default_factory=list)  # M's upper triangle, row by row
    Q: list = field(default_factory=list)
    Gamma: list = field(default_factory=list)
    G: list = field(default_factory=list)
    U: sp.Expr = sp.Integer(0)
    K_rotors: sp.Expr = sp.Integer(0)  # the rotors' share of the momentum ℓ: Σ_p α^{1p}_{1i} λᵖ_i
    defs: list = field(default_factory=list)  # (symbol, its formula), in order
    gyro: bool = False  # whether a body has a rotor (χᵖ = ωᵖ × λᵖ named)


class _Names:
    def __init__(self, doc, n: int):
        self.doc, self.sep, self.rows, self.defs, self.p, self.seen = doc, ("," if n > 9 else ""), [], [], 0, {}

    def pair(self, k: int, p: int) -> str:
        return f"{k}{self.sep}{p}"

    def let(self, tex: str, expr: sp.Expr, share: bool = False) -> sp.Expr:
        """``expr`` under the name ``tex`` (a definition of the current body); itself when it is
        short (zero, a number or one factor; a body's ``share`` of M, Q or G only when zero), and the
        quantity before it when it equals one."""
        expr = sp.expand(expr)
        if expr == 0 or (not share and _inline(expr)):
            return expr
        if not share and expr in self.seen:
            return self.seen[expr]
        sym = sp.Symbol(f"share{len(self.doc.w.names)}_{len(self.rows)}")
        self.doc.w.names[sym] = tex
        self.doc.w.rank[sym] = (TexWriter.QUANTITY, 10 ** 6 + len(self.rows))
        self.rows.append((self.p, tex, sym, expr))
        self.defs.append((sym, expr))
        self.seen.setdefault(expr, sym)
        return sym

    def vec(self, head: str, x, sub: str = "") -> tuple:
        """A 3-vector whose components are named ``head`` with the lower index ``sub`` i, i = 1, 2, 3."""
        return tuple(self.let(f"{head}_{{{sub}{i}}}", v) for i, v in zip((1, 2, 3), x))


def shares(spec, kin, doc) -> Shares:
    n, g = spec.n, spec.g
    w = _Names(doc, n)
    out = Shares()
    gamma, omega, eps, acc = E1, ZERO3, ZERO3, ZERO3  # frame 0: γ⁰ = ê⁰₁ (down), a fixed base
    a, sigma, v = {}, {}, {}
    s_prev = ZERO3
    mu, nu, chi = {}, {}, {}
    for p, body in enumerate(spec.bodies, start=1):
        al = kin.alpha[p]  # R₁(φᵖ) R₂(θᵖ) with the program's names of cos φᵖ, sin φᵖ: as sympy's functions here
        turn = kin.phi[p] + body.offset
        trig = {al[1, 1]: sp.cos(turn), -al[2, 1]: sp.sin(turn)}
        R = [[al[i, j].xreplace(trig) for j in range(3)] for i in range(3)]
        w.p = p
        if p > 1:  # O^p's acceleration at φ̈ = 0, by the previous body's motion
            acc = _times(R, w.vec(rf"\bar a^{{{p}}}", _add(_add(acc, _cross(eps, s_prev)), _cross(omega, _cross(omega, s_prev)))))
        gamma = w.vec(rf"\gamma^{{{p}}}", _times(R, gamma))
        for k in range(1, p):
            a[k, p] = w.vec(rf"\alpha^{{{w.pair(k, p)}}}", _times(R, a.get((k, p - 1), E1)), "1")
            sigma[k, p] = w.vec(rf"\sigma^{{{w.pair(k, p)}}}", _times(R, _add(sigma.get((k, p - 1), ZERO3), s_prev)))
        a[p, p], sigma[p, p] = E1, ZERO3
        m, c = body.m, body.c
        cc = _dot(c, c)
        J = [[body.A[i][j] - m * ((cc if i == j else 0) - c[i] * c[j]) for j in range(3)] for i in range(3)]
        for k in range(1, p + 1):
            v[k, p] = w.vec(rf"v^{{{w.pair(k, p)}}}", _cross(a[k, p], _add(sigma[k, p], c)))
        for k in range(1, p + 1):
            for r in range(k, p + 1):
                mu[k, r, p] = w.let(rf"\mu^{{{p}}}_{{{w.pair(k, r)}}}", _dot(a[k, p], _times(J, a[r, p])) + m * _dot(v[k, p], v[r, p]),
                                    share=True)
        omega = w.vec(rf"\omega^{{{p}}}", _add(_times(R, omega), (kin.phidot[p], 0, 0)))
        eps = w.vec(rf"\varepsilon^{{{p}}}", _add(_times(R, eps), (0, kin.phidot[p] * omega[2], -kin.phidot[p] * omega[1])))
        if p > 1:
            acc = w.vec(rf"a^{{{p}}}", acc)
        wp = w.vec(rf"w^{{{p}}}", _add(_add(acc, _cross(eps, c)), _cross(omega, _cross(omega, c))))
        N = w.vec(rf"N^{{{p}}}", _add(_times(J, eps), _cross(omega, _times(J, omega))))
        for k in range(1, p + 1):
            nu[k, p] = w.let(rf"\nu^{{{p}}}_{{{k}}}", _dot(a[k, p], N) + m * _dot(v[k, p], wp), share=True)
        if any(x != 0 for x in body.lam):
            out.gyro = True
            chi[p] = w.vec(rf"\chi^{{{p}}}", _cross(omega, body.lam))
        out.U += g * m * w.let(rf"d^{{{p}}}", _dot(gamma, _add(sigma[1, p], c)))
        for k in range(1, p + 1):
            out.G.append((k, w.let(rf"\eta^{{{p}}}_{{{k}}}", g * m * _dot(gamma, v[k, p]), share=True)))
        s_prev = body.s
    out.G = [sp.expand(sum((e for k0, e in out.G if k0 == k), sp.Integer(0))) for k in range(1, n + 1)]
    for k in range(1, n + 1):
        for r in range(k, n + 1):
            extra = spec.bodies[k - 1].armature if k == r else 0
            out.M.append(sum((mu[k, r, p] for p in range(r, n + 1)), sp.Integer(0)) + extra)
        out.Q.append(sum((nu[k, p] for p in range(k, n + 1)), sp.Integer(0)))
        out.Gamma.append(sp.expand(sum((_dot(a[k, p], chi[p]) for p in range(k, n + 1) if p in chi), sp.Integer(0))))
    out.U = sp.expand(out.U)
    out.K_rotors = sp.expand(sum((_dot(a[1, p], b.lam) for p, b in enumerate(spec.bodies, start=1)), sp.Integer(0)))
    out.defs, out.rows = w.defs, w.rows
    return out


def _at_check(shares: Shares, spec, kin, keep) -> dict | None:
    """Each quantity's value at the check's state (texcheck.state, t = 0, the parameters at their
    values), in floating point: a referee checks the definitions one by one.  None where a
    parameter has no value (no check is stated)."""
    params = texcheck.defaults(spec)
    if params is None:
        return None
    phi, phidot = texcheck.state(spec.n)
    env = {p: float(v) for p, v in zip(spec.params, (params[p.name] for p in spec.params))}
    env.update({kin.phi[k]: float(phi[k - 1]) for k in range(1, spec.n + 1)})
    env.update({kin.phidot[k]: float(phidot[k - 1]) for k in range(1, spec.n + 1)})
    out = {}
    for sym, expr in shares.defs:
        env[sym] = float(expr.xreplace(env))
        if keep is None or sym in keep:
            out[sym] = env[sym]
    return out


def layout(shares: Shares, doc, spec, kin, exprs: list | None = None) -> tuple[list, int]:
    """The bodies' definitions as displays, body by body, each with its quantities' values at the
    check's state, and how many: all of them, or those the printed ``exprs`` need (with those they
    need in turn)."""
    keep = None
    if exprs is not None:
        formula, keep = dict(shares.defs), set()
        todo = set().union(*(e.free_symbols for e in exprs))
        while todo:
            sym = todo.pop()
            if sym in formula and sym not in keep:
                keep.add(sym)
                todo |= formula[sym].free_symbols
    rows = [(p, TexEquation(tex, tuple(doc.lines(expr, LINE_WIDTH))), sym) for p, tex, sym, expr in shares.rows
            if keep is None or sym in keep]  # each in its own normal form, as the closed forms
    values = _at_check(shares, spec, kin, keep)
    bodies = [dict(p=p, block=block([row for q, row, _ in rows if q == p]),
                   stated=None if values is None else [(row.lhs, texcheck.number(values[sym])) for q, row, sym in rows if q == p])
              for p in sorted({p for p, _, _ in rows})]
    return bodies, len(rows)


def _springs(spec, kin) -> sp.Expr:
    """The springs' part of the force function U, −½ κᵏ (φᵏ − φᵏ_rest)² (the body-by-body form has
    no loads: no other part)."""
    return sum((-sp.Rational(1, 2) * b.spring * (kin.phi[k] - b.rest) ** 2 for k, b in enumerate(spec.bodies, start=1)
                if b.spring is not None), sp.Integer(0))


def values(spec, kin, dyn, ints, vals: dict, shares: Shares, doc) -> dict:
    """The printed quantities of the body-by-body form: sums of the bodies' shares,
    zero where the program's value is (G₁ of a vertical first axis is a sum of shares that cancel),
    ℓ as Σ_r M_1r φ̇ʳ plus the rotors' share, the joints' torques in closed form."""
    n = spec.n
    upper = [dyn.M[k][r] for k in range(n) for r in range(k, n)]

    def zero_where(exprs, polys):
        return [sp.Integer(0) if p.is_zero() else e for e, p in zip(exprs, polys)]

    out = dict(vals, M=zero_where(shares.M, upper), Q=zero_where(shares.Q, dyn.Q), Gamma=zero_where(shares.Gamma, dyn.Gamma),
               G=zero_where(shares.G, dyn.G), U=shares.U + _springs(spec, kin),
               joint=[(k, v) for k, v in zip([k for k, _ in vals["joint"]],
                                             kin.prog.inline([dyn.joint[k] for k, _ in vals["joint"]], symbolic=True))])
    if ints.momentum is not None:
        M1 = []
        for r in range(1, n + 1):
            sym = sp.Symbol(f"M_1_{r}")
            doc.w.names[sym], doc.w.rank[sym] = m_name(1, r, n), (TexWriter.QUANTITY, -n + r)
            M1.append(sym)
        out["K"] = sum((M1[r] * kin.phidot[r + 1] for r in range(n) if not upper[r].is_zero()), sp.Integer(0)) + shares.K_rotors
    return out
