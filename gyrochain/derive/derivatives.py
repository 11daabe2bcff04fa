"""Exact derivatives of φ̈: forward-mode differentiation of the straight-line program.

φ̈ is the articulated-body recursion of aba.py, a straight-line program of named quantities.
Differentiating each definition in program order (the chain rule, one tangent per input
direction) gives the derivative of exactly the code that is emitted, not of a closed form and not
a finite difference.  The tangents are quantities of the same program: named when they are not
simple, folded when they are numbers, and absent when they are zero, so the sparsity of the
chain is used by construction (nothing upstream of φᵏ depends on it, the inertias do not depend
on φ̇ at all, a control torque only enters its joint's bias).  The directions are φ¹…φⁿ, φ̇¹…φ̇ⁿ
and the controls u; per direction the cost is O(n) (the recursion is O(n)), so the whole
Jacobian is O(n²).

A polynomial definition c·a₁a₂⋯ differentiates term by term (product rule); a non-polynomial one
(cos φᵏ, a reciprocal 1/Dᵏ, a user's expression) by sympy's ``diff`` of its right side, with the
result written in the program's quantities where they exist (−sin φᵏ is the existing sin_phi;
d(1/D) = −(1/D)² dD reuses the reciprocal).

``derive`` gives one tangent per direction (emitted as one C function per column of the Jacobian,
sparse); ``derive_tangent`` one tangent along a direction given at run time (one compact function
called per column), which assemble.py uses when the specialised columns together grow too long to
compile quickly (long chains).
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .algebra import Atom, Poly, ZERO
from ..chainspec.spec import T as TIME
from .exact import exact
from .kinematics import appends_to
from .program import Program, Var


@dataclass(frozen=True)
class Tangent:
    """The generic form for long chains: ``jvp[k]`` = Σⱼ ∂φ̈ᵏ⁺¹/∂(direction j)·dⱼ, the forward-mode
    tangent along a direction d given at run time (``dirs``: its input symbols, one per label).
    One compact function called once per column instead of one specialised function per column:
    the same exact numbers, a few times less code for gcc."""

    labels: tuple
    dirs: tuple
    jvp: tuple


@dataclass(frozen=True)
class Derivatives:
    """``dqdd[k][j]``: ∂φ̈ᵏ⁺¹/∂(direction j) with the directions ``labels`` (q1…qn, v1…vn,
    u1…): φ, φ̇, then the controls in order."""

    labels: tuple
    dqdd: tuple


def _to_poly(P: Program, expr: sp.Expr, atom: Atom, rhs: sp.Expr, name: str) -> Poly:
    """A partial derivative (sympy) as a polynomial of the program's quantities.  Powers of the
    definition's own right side reuse its atom (d(1/D)/dD = −(1/D)²); cos φ, sin φ and the user's
    expressions the program already has are found by their alias; anything else is named."""
    if expr.is_number:
        return Poly.const(exact(expr))
    if isinstance(expr, Var):
        return Poly.atom(P.atom(expr.name))
    if expr.is_Symbol:
        return P.input(expr)
    if expr == rhs:
        return Poly.atom(atom)
    if expr.is_Add:
        return sum((_to_poly(P, a, atom, rhs, name) for a in expr.args), ZERO)
    if expr.is_Mul:
        out = Poly.const(1)
        for a in expr.args:
            out = out * _to_poly(P, a, atom, rhs, name)
        return out
    if expr.is_Pow and expr.exp.is_Integer:
        e = int(expr.exp)
        if e > 0:
            base = _to_poly(P, expr.base, atom, rhs, name)
        elif sp.Pow(expr.base, -1) == rhs:
            base, e = Poly.atom(atom), -e
        else:
            base = None
        if base is not None:
            out = Poly.const(1)
            for _ in range(e):
                out = out * base
            return out
    known = P.known(expr)
    if known is not None:
        return known
    k = 1
    while P.defines(f"{name}_{k}"):
        k += 1
    value = P.let_sympy(f"{name}_{k}", expr)
    P.alias(expr, value)
    return value


def tangent_poly(rhs: Poly, tan: dict) -> dict:
    out: dict = {}
    for m, c in rhs.terms.items():
        for i, a in enumerate(m):
            ta = tan.get(a)
            if not ta:
                continue
            rest = Poly({m[:i] + m[i + 1:]: c})
            for j, d in ta.items():
                out[j] = out.get(j, ZERO) + rest * d
    return out


def _tangent_sympy(P: Program, a: Atom, rhs: sp.Expr, tan: dict) -> dict:
    out: dict = {}
    for s in sorted(rhs.free_symbols, key=str):
        src = P.source(s)
        ts = tan.get(src)
        if not ts:
            continue
        partial = _to_poly(P, sp.diff(rhs, s), a, rhs, f"{a.name}_p")
        for j, d in ts.items():
            out[j] = out.get(j, ZERO) + partial * d
    return out


def tangents(P: Program, outputs, seeds: dict, labels) -> dict:
    """Forward mode over the definitions the outputs need: atom → {direction: Poly}.  ``seeds``
    gives the inputs' tangents (φᵏ ↦ {j: 1}).  Every nonzero tangent that is not simple is a
    named quantity ``<name>_d<label>``."""
    tan = dict(seeds)
    for a, rhs in P.needed(outputs):
        d = tangent_poly(rhs, tan) if isinstance(rhs, Poly) else _tangent_sympy(P, a, rhs, tan)
        named = {}
        for j in sorted(d):
            if not d[j].is_zero():
                named[j] = P.let(f"{a.name}_d{labels[j]}", d[j])
        if named:
            tan[a] = named
    return tan


def directions(spec, kin):
    n = spec.n
    syms = [kin.phi[k] for k in range(1, n + 1)] + [kin.phidot[k] for k in range(1, n + 1)]
    syms += [kin.torque[k] for k in spec.controls]
    labels = tuple([f"q{k}" for k in range(1, n + 1)] + [f"v{k}" for k in range(1, n + 1)]
                   + [f"u{i + 1}" for i in range(len(spec.controls))])
    return syms, labels


def derive_tangent(spec, prog: Program, kin, art) -> Tangent:
    """The tangent of φ̈ along a run-time direction d (the generic form), appended to ``prog``."""
    appends_to(prog, kin)
    P = prog
    syms, labels = directions(spec, kin)
    dirs = tuple(sp.Symbol(f"dir_{lab}") for lab in labels)
    seeds = {next(iter(P.input(s).terms))[0]: {0: P.input(d)} for s, d in zip(syms, dirs)}
    tan = tangents(P, list(art.qdd), seeds, ("t",))
    jvp = tuple(tangent_poly(q, tan).get(0, ZERO) for q in art.qdd)
    return Tangent(labels, dirs, jvp)


def derive(spec, prog: Program, kin, art) -> Derivatives:
    """∂φ̈/∂(φ, φ̇, u) of the articulated recursion ``art`` (aba.derive), one tangent per
    direction, appended to ``prog``."""
    appends_to(prog, kin)
    P = prog
    n = spec.n
    syms, labels = directions(spec, kin)
    seeds = {}
    for j, s in enumerate(syms):
        seeds[next(iter(P.input(s).terms))[0]] = {j: Poly.const(1)}
    outs = list(art.qdd)
    tan = tangents(P, outs, seeds, labels)

    dqdd = []
    for k in range(n):
        row = tangent_poly(art.qdd[k], tan)
        dqdd.append(tuple(row.get(j, ZERO) for j in range(len(labels))))
    return Derivatives(labels, tuple(dqdd))


@dataclass(frozen=True)
class Canonical:
    """Hamilton's variables of a chain on a fixed base: the momenta p = ∂ℒ/∂φ̇ = M φ̇ + k(φ) with
    kⱼ = eʲ·Σ_{p≥j} λᵖ (ℒ = T + Σλᵏ·ωᵏ + U, digest §7, and ∂ωᵏ/∂φ̇ʲ = eʲ for k ≥ j), and their
    rate ṗ = ∂ℒ/∂φ + (the torques that have no force function).  ṗ is computed as
    (∂p/∂φ)·φ̇ + M φ̈ = (∂p/∂φ)·φ̇ + f: by Lagrange's equations that is the same, and it needs
    only the forward-mode tangent of p along (φ̇, 0) next to the f the model already has.  A long
    chain (the loop form) takes p from the sub-chains' momenta and ṗ = ∂(T + Σλ·ω)/∂φ + the
    generalized forces of gravity, the loads and the joint torques instead: O(n) code, where
    M φ̇ and its tangent are O(n²).  ``k`` is what φ̇ = M⁻¹(p − k) needs besides M."""

    p: tuple
    k: tuple
    pdot: tuple


def _canonical_local(dyn, subchain) -> tuple:
    """(p, ṗ) of a long chain, O(n): pⱼ = eʲ·Kʲ, and ṗⱼ = ∂(T + Σλ·ω)/∂φʲ + the generalized forces
    of gravity, the loads and the joint torques, where turning joint j by δ turns the sub-chain j…n
    and its rotors about eʲ through Oʲ, so that everything cancels but the motion of the joint's
    base: ∂(T + Σλ·ω)/∂φʲ = −(eʲ × ωʲ⁻¹)·Kʲ − (eʲ × v_Oʲ)·Pʲ (frame j, where eʲ = (1, 0, 0) and
    ωʲ⁻¹ has ωʲ's 2nd and 3rd components)."""
    p = tuple(K[0] for _w, _v, K, _P in subchain)
    dL = [-(w[1] * K[2] - w[2] * K[1] + v[1] * P[2] - v[2] * P[1]) for w, v, K, P in subchain]
    loads = dyn.Phi or (ZERO,) * len(subchain)
    return p, tuple(tq + g + ph + d for tq, g, ph, d in zip(dyn.torques, dyn.G, loads, dL))


def canonical(spec, prog: Program, kin, dyn, subchain: tuple = ()) -> Canonical:
    """p, k and ṗ (see Canonical), appended to ``prog``; ``subchain``: a long chain's momenta of
    the sub-chains (Integrals.subchain), the O(n) form."""
    appends_to(prog, kin)
    n = spec.n
    P = prog
    qd = [P.input(kin.phidot[j]) for j in range(1, n + 1)]
    k = tuple(dyn.Lam[i][0] for i in range(n))
    if subchain:  # a long chain: p and ṗ from the sub-chains' momenta in frame j (integrals.py)
        p, pdot = _canonical_local(dyn, subchain)
        return Canonical(p, k, pdot)
    p = tuple(sum((dyn.M[i][j] * qd[j] for j in range(n)), ZERO) + k[i] for i in range(n))
    # the tangent along (φ, φ̇) ↦ (φ̇, 0): each φʲ's tangent is φ̇ʲ (label "p": names <quantity>_dp)
    seeds = {next(iter(P.input(kin.phi[j]).terms))[0]: {0: qd[j - 1]} for j in range(1, n + 1)}
    tan = tangents(P, list(p), seeds, ("p",))
    pdot = tuple(f + tangent_poly(pi, tan).get(0, ZERO) for f, pi in zip(dyn.f, p))
    return Canonical(p, k, pdot)


@dataclass(frozen=True)
class ParamDerivatives:
    """``dqdd[k][j]``: ∂φ̈ᵏ⁺¹/∂pⱼ of the articulated recursion, pⱼ the spec's symbolic parameters
    in their order (a mass, a length, an inertia, a rotor's momentum, a spring's constant)."""

    params: tuple
    dqdd: tuple


def derive_params(spec, prog: Program, kin, art, symbols: tuple | None = None, label: str = "P") -> ParamDerivatives:
    """∂φ̈/∂p: the forward mode of ``tangents`` seeded at the parameters instead of the state, one
    tangent per parameter (label ``P<j>``), appended to ``prog``.  A parameter that φ̈ does not read
    has a zero column, a true zero.  ``symbols``: other inputs to seed instead (t, for ∂φ̈/∂t)."""
    appends_to(prog, kin)
    P = prog
    params = tuple(spec.params) if symbols is None else tuple(symbols)
    seeds = {}
    for j, s in enumerate(params):
        seeds[next(iter(P.input(s).terms))[0]] = {j: Poly.const(1)}
    tan = tangents(P, list(art.qdd), seeds, tuple(f"{label}{j + 1}" for j in range(len(params))))
    dqdd = tuple(tuple(tangent_poly(q, tan).get(j, ZERO) for j in range(len(params))) for q in art.qdd)
    return ParamDerivatives(params, dqdd)


def derive_time(spec, prog: Program, kin, art) -> tuple:
    """∂φ̈ᵏ/∂t of a model that reads t (a moving platform, λ(t), a load of t): the same forward
    mode seeded at t, one entry per joint, appended to ``prog``."""
    return tuple(row[0] for row in derive_params(spec, prog, kin, art, symbols=(TIME,), label="T").dqdd)
