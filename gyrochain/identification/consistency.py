"""Physically possible bodies with given base parameters (identify's spec, and --physical).

A body's mass m, first moment h and inertia A about its joint point are physically possible
(some distribution of positive mass has them) exactly when the pseudo-inertia
J = [[½ tr(A) 1 − A, h], [hᵀ, m]] is positive definite (Wensing, Kim and Slotine 2017).  Writing
J = U Uᵀ with U upper triangular and its diagonal exp(·) (the log-Cholesky parameters of Rucker
and Wensing 2022) makes every parameter vector a possible body, so the nearest possible bodies
are an unconstrained least-squares problem, solved by scipy's trust-region method: a light,
maintained solver in place of a semidefinite program.
"""
from __future__ import annotations

import numpy as np


def _body_columns(params) -> dict:
    """Per body k: the indices into π of m, h (3) and A (6: xx xy xz yy yz zz)."""
    out: dict = {}
    for j, p in enumerate(params):
        if p.kind in ("m", "h", "A"):
            out.setdefault(p.body, {})[p.kind + "".join(map(str, p.index))] = j
    return out


_A_KEYS = ("A00", "A01", "A02", "A11", "A12", "A22")


def _pseudo(m, h, A) -> np.ndarray:
    """The pseudo-inertia J = [[½ tr(A) 1 − A, h], [hᵀ, m]]: a body is physically possible exactly
    when J is positive definite (Wensing, Kim, Slotine 2017)."""
    J = np.zeros((4, 4))
    J[:3, :3] = 0.5 * np.trace(A) * np.eye(3) - A
    J[:3, 3] = J[3, :3] = h
    J[3, 3] = m
    return J


def _from_u(x: np.ndarray) -> tuple:
    """(m, h, A) of J = U Uᵀ, U upper triangular with diagonal exp(x[:4]) (log-Cholesky: every x
    is a physically possible body, Rucker and Wensing 2022)."""
    U = np.zeros((4, 4))
    U[np.diag_indices(4)] = np.exp(np.clip(x[:4], -300.0, 300.0))  # a trial step of the solver may go far
    U[np.triu_indices(4, 1)] = x[4:]
    J = U @ U.T
    S = J[:3, :3]
    return J[3, 3], J[:3, 3], np.trace(S) * np.eye(3) - S


def _to_u(m, h, A) -> np.ndarray:
    J = _pseudo(m, h, A)
    J = J + 1e-9 * max(np.trace(J), 1e-300) * np.eye(4)  # a point mass or a rod: J only semidefinite
    P = np.eye(4)[::-1]
    L = np.linalg.cholesky(P @ J @ P)  # J = (P L P)(P L P)ᵀ with P L P upper triangular
    U = P @ L @ P
    return np.concatenate([np.log(np.diag(U)), U[np.triu_indices(4, 1)]])


def consistent(model, beta: np.ndarray, se: np.ndarray, pi0: np.ndarray) -> tuple[np.ndarray, float]:
    """Standard parameters whose bodies are physically possible (positive mass, inertia about the
    centre of mass positive definite and satisfying the triangle inequalities) with base
    parameters as near ``beta`` as they can be, in standard errors, and near the spec's π₀ in the
    directions the motion does not determine: min Σ((Kπ − β)/se)² + 10⁻⁸ Σ((π − π₀)/unit)² over
    the log-Cholesky parameters of every body (λ, damping and armature free).  Returns π and the largest
    |Kπ − β|/se (0 when consistent bodies give these β exactly)."""
    from scipy.optimize import least_squares

    params = model.reg.params
    K = model.base.matrix(len(params))
    cols = _body_columns(params)
    free = [j for j, p in enumerate(params) if p.kind in ("lam", "b", "a")]
    # the pull towards π₀ in each kind's own unit (the largest of the spec's values of that kind)
    unit = {kind: max([abs(v) for v, q in zip(pi0, params) if q.kind == kind] + [0.0]) or 1.0 for kind in {q.kind for q in params}}
    scale = np.array([unit[p.kind] for p in params])

    def pi_of(x):
        pi = np.array(pi0, dtype=float)
        for b, (k, c) in enumerate(sorted(cols.items())):
            m, h, A = _from_u(x[10 * b:10 * b + 10])
            pi[c["m"]] = m
            for i in range(3):
                pi[c[f"h{i}"]] = h[i]
            for key in _A_KEYS:
                pi[c[key]] = A[int(key[1]), int(key[2])]
        pi[free] = x[10 * len(cols):]
        return pi

    def res(x):
        pi = pi_of(x)
        return np.concatenate([(K @ pi - beta) / se, 1e-4 * (pi - pi0) / scale])

    se = np.maximum(se, 1e-12 * np.maximum(np.abs(beta), 1e-300))
    # first the nearest π to π₀ with K π = β exactly (a weighted minimum-norm step): often its
    # bodies are possible already, and nothing more is needed
    Ks = K * scale
    pi = pi0 + scale * (Ks.T @ np.linalg.solve(Ks @ Ks.T, beta - K @ pi0))
    if all(np.linalg.eigvalsh(_pseudo(*body))[0] > 0 for body in _bodies(pi, cols)):
        return pi, float(np.max(np.abs(K @ pi - beta) / se))
    x0 = np.concatenate([_to_u(*body) for body in _bodies(pi0, cols)] + [pi0[free]])
    sol = least_squares(res, x0, method="trf", x_scale="jac", xtol=1e-12, ftol=1e-12, gtol=1e-12, max_nfev=400)
    pi = pi_of(sol.x)
    return pi, float(np.max(np.abs(K @ pi - beta) / se))


def _bodies(pi, cols) -> list:
    """(m, h, A) of every body of π, in the order of the bodies."""
    out = []
    for _k, c in sorted(cols.items()):
        A = np.array([[pi[c[f"A{min(i, j)}{max(i, j)}"]] for j in range(3)] for i in range(3)])
        out.append((pi[c["m"]], np.array([pi[c[f"h{i}"]] for i in range(3)]), A))
    return out
