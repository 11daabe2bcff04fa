"""The document's check at one state: M, the groups of each joint's equation and φ̈ as numbers,
so that a referee can evaluate one printed formula by hand and compare; with the residual of the
same φ̈ in the independent model (Newton–Euler in numpy, derive/reference.py), M's symmetry and
its smallest eigenvalue.

The numbers are the document's own quantities (the program's polynomials the formulas print),
evaluated in floating point at a state stated in the text: φᵏ = ±0.1(k + 2), φ̇ᵏ = ∓0.1(k + 1),
t = 0, every control torque 0 and every symbolic parameter at the spec's default value.
"""
from __future__ import annotations

import numpy as np
import sympy as sp

from ..derive import reference
from ..derive.algebra import Poly
from ..derive.exact import to_float
from ..derive.kinematics import platform_symbols
from ..chainspec.spec import T as TIME
from .texterms import number_text, param_tex

ROWS_SHOWN = 8  # a longer chain's table shows its first and last joints only
MATRIX_MAX_N = 3  # M is printed as a matrix up to this n, its upper triangle entry by entry up to ROWS_SHOWN


def state(n: int) -> tuple[np.ndarray, np.ndarray]:
    """The stated state: φᵏ = (−1)^(k+1) 0.1(k + 2), φ̇ᵏ = (−1)^k 0.1(k + 1)."""
    k = np.arange(1, n + 1)
    sign = np.where(k % 2 == 1, 1.0, -1.0)
    return np.round(sign * 0.1 * (k + 2), 10), np.round(-sign * 0.1 * (k + 1), 10)


class Evaluator:
    """The program's quantities in floating point at one state (each definition once, in order)."""

    def __init__(self, prog, inputs: dict):
        self.prog, self.inputs, self.values = prog, inputs, {}

    def __call__(self, p) -> float:
        p = Poly.lift(p)
        for a, rhs in self.prog.needed([p], have=frozenset(self.values)):
            self.values[a] = self._poly(rhs) if isinstance(rhs, Poly) else self._sympy(rhs)
        return self._poly(p)

    def _atom(self, a) -> float:
        v = self.values.get(a)
        return v if v is not None else self.inputs[a.sym]

    def _poly(self, p: Poly) -> float:
        total = 0.0
        for mono, c in p.terms.items():
            term = to_float(c)
            for a in mono:
                term *= self._atom(a)
            total += term
        return total

    def _sympy(self, expr) -> float:
        env = {}
        for s in expr.free_symbols:
            a = self.prog.source(s)
            env[s] = self._atom(a) if a is not None and (a in self.values or a.sym in self.inputs) else self.inputs[s]
        return float(expr.xreplace(env))


def defaults(spec) -> dict | None:
    """The symbolic parameters' default values, or None when one has none (no check is stated)."""
    out = {}
    for p in spec.params:
        v = spec.values.get(p.name, spec.values.get(p))
        if v is None:
            return None
        out[p.name] = float(v)
    return out


def check(spec, kin, dyn, groups: dict) -> dict | None:
    """The numbers of the check: the state, per joint the printed groups and φ̈, M (or for a long
    chain its diagonal), and the facts on M and the independent model.  ``groups``: name → (printed
    symbol, the program's polynomials, +1 on the right side / −1 on the left)."""
    params = defaults(spec)
    if params is None:
        return None
    n = spec.n
    phi, phidot = state(n)
    inputs = {TIME: 0.0}
    for k in range(1, n + 1):
        inputs[kin.phi[k]], inputs[kin.phidot[k]], inputs[kin.torque[k]] = phi[k - 1], phidot[k - 1], 0.0
    for p in spec.params:
        inputs[p] = params[p.name]
    if kin.platform is not None:  # the platform's motion at t = 0, as the document's ω⁰, ε⁰, v̇₀, γ⁰ state it
        pm = kin.platform
        for key, vals in (("omega", pm.omega), ("epsilon", pm.eps), ("vdot", pm.acc), ("gamma", pm.down)):
            for sym, v in zip(platform_symbols()[key], vals):
                inputs[sym] = float(sp.sympify(v).subs({TIME: 0, **{p: params[p.name] for p in spec.params}}))
    ev = Evaluator(kin.prog, inputs)
    M = np.array([[ev(dyn.M[k][r]) for r in range(n)] for k in range(n)])
    values = {key: np.array([ev(p) for p in polys]) for key, (_, polys, _) in groups.items()}
    f = sum((sign * values[key] for key, (_, _, sign) in groups.items()), np.zeros(n))
    qdd = np.linalg.solve(M, f)
    ch = reference.numeric(spec, params)
    x = np.concatenate([phi, phidot])
    residual = reference.mass_matrix(ch, phi) @ qdd - reference.forces(ch, x, np.zeros(len(spec.controls)) if spec.controls else None, 0.0)
    scale = max(1.0, float(np.max(np.abs(reference.forces(ch, x, None if not spec.controls else np.zeros(len(spec.controls)), 0.0)))))
    eig = np.linalg.eigvalsh(0.5 * (M + M.T))
    shown = list(range(n)) if n <= ROWS_SHOWN else [0, 1, 2, None, n - 2, n - 1]
    cols = [(sym, key) for key, (sym, polys, _) in groups.items() if not all(Poly.lift(p).is_zero() for p in polys)]
    rows = []
    for k in shown:
        if k is None:
            rows.append(None)
            continue
        diagonal = [number(M[k, k])] if n > ROWS_SHOWN else []
        rows.append(dict(k=k + 1, phi=number(phi[k]), phidot=number(phidot[k]),
                         cells=diagonal + [number(values[key][k]) for _, key in cols], f=number(f[k]), qdd=number(qdd[k])))
    return dict(
        phi=phi, rows=rows, state=None if n > ROWS_SHOWN else [r",\allowbreak ".join(number(v) for v in vec) for vec in (phi, phidot)], params_tex=[(param_tex(k), number(v)) for k, v in params.items()], heads=(["M_{kk}"] if n > ROWS_SHOWN else []) + [sym for sym, _ in cols], params=params,
        M=[[number(v) for v in row] for row in M] if n <= MATRIX_MAX_N else None, long=n > ROWS_SHOWN,
        entries=[(f"M_{{{k + 1}{r + 1}}}", number(M[k, r])) for k in range(n) for r in range(k, n)]
        if MATRIX_MAX_N < n <= ROWS_SHOWN else None,
        asymmetry=_sci(float(np.max(np.abs(M - M.T)))), eig_min=number(eig[0]), eig_max=number(eig[-1]),
        residual=_sci(float(np.max(np.abs(residual))) / scale),
    )


def number(v: float) -> str:
    """A number as the document prints it (10 significant digits, a minus as a sign)."""
    v = float(v)
    if v == 0:
        return "0"
    return ("-" if v < 0 else "") + number_text(abs(v))


def _sci(v: float) -> str:
    """A small error as $a \\times 10^{b}$ (0 as 0)."""
    if v == 0:
        return "0"
    mant, exp = f"{v:.1e}".split("e")
    return rf"{mant} \times 10^{{{int(exp)}}}"


def groups(spec, kin, dyn, split_platform: bool) -> dict:
    """The groups of the equations as the document prints them, as the program's polynomials:
    name → (symbol, polynomials, +1 on the right side, −1 on the left)."""
    Q, Gam, Pi = list(dyn.Q), list(dyn.Gamma), None
    if split_platform:  # Π_k: the terms with ω⁰, ε⁰, v̇₀ (the document's split of (8)–(10))
        sy = platform_symbols()
        platform = set(sy["omega"] + sy["epsilon"] + sy["vdot"])
        full = kin.prog.inline_poly(Q + Gam)
        parts = [(Poly({m: c for m, c in p.terms.items() if not any(a.sym in platform for a in m)}),
                  Poly({m: c for m, c in p.terms.items() if any(a.sym in platform for a in m)})) for p in full]
        n = spec.n
        Q, Gam = [r for r, _ in parts[:n]], [r for r, _ in parts[n:]]
        Pi = [parts[k][1] + parts[n + k][1] for k in range(n)]
    out = {"Q": ("Q_k", Q, -1), "Gamma": (r"\Gamma_k", Gam, -1)}
    if Pi is not None:
        out["Pi"] = (r"\Pi_k", Pi, -1)
    if dyn.Lamdot:
        out["Lamdot"] = (r"\mathring\Lambda_k", list(dyn.Lamdot), -1)
    out["G"] = ("G_k", list(dyn.G), 1)
    if dyn.Phi:
        out["Phi"] = ("W_k", list(dyn.Phi), 1)
    if any(not j.is_zero() for j in dyn.joint):
        out["joint"] = (r"\tau_k", list(dyn.joint), 1)
    return out
