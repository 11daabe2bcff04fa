"""Exact second derivatives of φ̈: forward mode over forward mode on the straight-line program.

An optimiser's exact Hessian (IPOPT's, SQP's) asks for the second derivative of a weighted sum
of the dynamics, H = ∇²_z (μ·φ̈) with z = (φ, φ̇, u) and μ the multipliers of the equations
φ̈ = …; H is symmetric, ndir × ndir (ndir = 2n + nu).  The first derivatives ∂φ̈ᵏ/∂zⱼ are the
forward-mode tangents of derivatives.py, quantities of the same program; their weighted sums
gⱼ = Σₖ μₖ ∂φ̈ᵏ/∂zⱼ are differentiated once more by the same forward mode, one tangent per
direction i, and H_ij = ∂gⱼ/∂zᵢ is kept for i ≤ j only (what only the other half needs is never
emitted).  Every quantity of both levels is named, folded when it is a number and absent when it
is zero, so the structure of the chain is used twice: φ̈ is affine in u (∂²φ̈/∂u² = 0 is never
formed), quadratic in φ̇, and nothing upstream of φᵏ depends on it.

The levels carry their own labels (``<quantity>_dA<label>`` for the first, ``…_dB<label>`` for the
second), so that they never meet the names of NAME_qdd_derivatives' own columns.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .algebra import Poly, ZERO
from ..chainspec.spec import T as TIME
from .derivatives import directions, tangent_poly, tangents
from .kinematics import appends_to
from .program import Program


@dataclass(frozen=True)
class Hessian:
    """``upper[(i, j)]`` (i ≤ j): ∂²(μ·φ̈)/∂zᵢ∂zⱼ with the directions ``labels`` (q1…qn, v1…vn,
    u1…, and t last for a model that reads t) and the weights ``mu`` (input symbols, one per joint); a pair absent is structurally zero."""

    labels: tuple
    mu: tuple
    upper: dict


def mu_symbols(n: int) -> tuple:
    return tuple(sp.Symbol(f"mu_{k}") for k in range(1, n + 1))


def derive(spec, prog: Program, kin, art, timed: bool = False) -> Hessian:
    """The weighted Hessian of the articulated recursion ``art``'s φ̈, appended to ``prog``;
    ``timed`` (a model that reads t): t is one more direction, the last."""
    appends_to(prog, kin)
    P = prog
    n = spec.n
    syms, labels = directions(spec, kin)
    if timed:
        syms, labels = [*syms, TIME], (*labels, "t")
    ndir = len(labels)
    seeds = {next(iter(P.input(s).terms))[0]: {j: Poly.const(1)} for j, s in enumerate(syms)}
    first = tangents(P, list(art.qdd), seeds, tuple(f"A{lab}" for lab in labels))
    mu = mu_symbols(n)
    weights = [P.input(m) for m in mu]
    grads = [ZERO] * ndir
    for k in range(n):
        for j, d in tangent_poly(art.qdd[k], first).items():
            grads[j] = grads[j] + weights[k] * d
    # μ is a weight, not a direction: the second level seeds φ, φ̇, u alone
    second = tangents(P, grads, seeds, tuple(f"B{lab}" for lab in labels))
    upper = {}
    for j in range(ndir):
        for i, d in tangent_poly(grads[j], second).items():
            if i <= j and not d.is_zero():
                upper[(i, j)] = d
    return Hessian(labels, mu, upper)
