"""The measures of a sweep's trajectories, from arrays of states and the compiled model: the energy
(23) along each, the first time a link flips over (its absolute angle, or a joint angle, passes
the upright) and the largest Lyapunov exponent by Benettin's two-trajectory method."""
from __future__ import annotations

import math

import numpy as np
import sympy as sp

from ..models.paramtable import ParamTable


def energies(model, X: np.ndarray, params) -> np.ndarray:
    """T − U at every state of X (nb, nt, 2N) by the C NAME_energy, through cffi pointers (NaN
    rows, past a failure, give NaN)."""
    nb, nt, dim = X.shape
    X = np.ascontiguousarray(X)
    ffi, f = model.ffi, model._fn("energy")
    base = ffi.cast(model._ptr, ffi.from_buffer(X))
    per_point = isinstance(params, (list, ParamTable))
    p = None if per_point else model._p(params)
    out = np.empty(nb * nt)
    for b in range(nb):
        if per_point:
            p = model._p(params[b])
        for j in range(nt):
            out[b * nt + j] = f(base + (b * nt + j) * dim, p)
    return out.reshape(nb, nt)


def link_signs(spec) -> list[int] | None:
    """For a planar chain (every axis parallel or antiparallel to the one before: θᵏ = 0 or π for
    k ≥ 2) the sign sₖ = ±1 with which φᵏ turns link k about ê¹₁, so that the absolute angle of
    link k is θᵏ_abs = s₁φ¹ + … + sₖφᵏ (measured from where φ = 0 puts it); None for a spatial
    chain, whose links have no one angle each."""
    signs = [1]
    for body in spec.bodies[1:]:
        try:
            c = float(sp.cos(body.theta))
        except TypeError:  # a symbolic θ
            return None
        if abs(abs(c) - 1.0) > 1e-15:
            return None
        signs.append(signs[-1] * (1 if c > 0 else -1))
    return signs


def angles_of(Q: np.ndarray, signs: list[int] | None) -> np.ndarray:
    """The joint angles Q (nb, nt, n) as absolute link angles (signs from link_signs), or as they
    are (signs None)."""
    return Q if signs is None else np.cumsum(Q * np.asarray(signs, float), axis=2)


def joint_angles(theta: np.ndarray, signs: list[int]) -> np.ndarray:
    """The inverse of angles_of: link angles (..., n) back to joint angles φᵏ = sₖ(θₖ − θₖ₋₁)."""
    return np.asarray(signs, float) * np.diff(theta, axis=-1, prepend=0.0)


def flip_times(t: np.ndarray, Q: np.ndarray, k: int | None) -> np.ndarray:
    """The first time an angle passes the upright, i.e. reaches an odd multiple of π (k None:
    any of the angles, else angle k), linear between the output times; NaN when none does within
    the run.  Q has shape (nb, nt, n): joint angles, or link angles (angles_of).  Each angle is
    measured from the multiple of 2π nearest its start, so a start in (−π, π) flips when |angle|
    reaches π, and a start beyond (a link angle summed from joint angles) is not a flip at t = 0."""
    Q = Q if k is None else Q[:, :, k:k + 1]
    start = np.nan_to_num(Q[:, :1, :], nan=0.0)
    A = np.abs(Q - 2 * np.pi * np.round(start / (2 * np.pi)))
    over = np.nan_to_num(A, nan=0.0) >= np.pi
    out = np.full(Q.shape[0], np.nan)
    for b in range(Q.shape[0]):
        hits = np.nonzero(over[b].any(axis=1))[0]
        if not len(hits):
            continue
        j = hits[0]
        if j == 0:
            out[b] = t[0]
            continue
        best = t[j]
        for c in np.nonzero(over[b, j])[0]:
            a0, a1 = A[b, j - 1, c], A[b, j, c]
            tc = t[j - 1] + (t[j] - t[j - 1]) * (np.pi - a0) / (a1 - a0) if a1 != a0 else t[j]
            best = min(best, tc)
        out[b] = best
    return out


def lyapunov(model, X0, sw, kw: dict, prm) -> tuple[np.ndarray, np.ndarray]:
    """The largest Lyapunov exponent by two trajectories d0 apart (Benettin's method): every
    lyap_interval the distance is measured, its log summed and the pair brought back to d0."""
    nb, dim = X0.shape
    direction = np.ones(dim) / math.sqrt(dim)
    x, y = X0.copy(), X0 + sw.lyap_d0 * direction
    total = np.zeros(nb)
    codes = np.zeros(nb, dtype=np.int32)
    steps = max(1, int(round(sw.t1 / sw.lyap_interval)))
    dt = sw.t1 / steps
    both_p = (ParamTable(prm.base, prm.names, np.vstack([prm.values] * 2)) if isinstance(prm, ParamTable)
              else list(prm) * 2 if isinstance(prm, list) else prm)
    for s in range(steps):
        t = np.array([s * dt, (s + 1) * dt])
        XY, c = model.integrate_batch(t, np.vstack([x, y]), **dict(kw, params=both_p))
        codes = np.maximum(codes, np.maximum(c[:nb], c[nb:]))
        x, y = XY[:nb, -1], XY[nb:, -1]
        d = np.linalg.norm(y - x, axis=1)
        ok = np.isfinite(d) & (d > 0)
        total[ok] += np.log(d[ok] / sw.lyap_d0)
        scale = np.where(ok, sw.lyap_d0 / np.where(ok, d, 1.0), 0.0)
        y = np.where(ok[:, None], x + (y - x) * scale[:, None], x + sw.lyap_d0 * direction)
        x = np.where(np.isfinite(x), x, X0)
        y = np.where(np.isfinite(y), y, X0)
    lam = total / sw.t1
    lam[codes != 0] = np.nan
    return lam, codes


def lyapunov_spectrum(model, X0, t1: float, interval: float, prm, u=None, rtol: float = 1e-8,
                      atol: float = 1e-10) -> tuple[np.ndarray, np.ndarray]:
    """All 2n Lyapunov exponents of each trajectory by the QR (Benettin–Shimada–Nagashima) method on
    the emitted variational equations: every ``interval`` the tangent basis Q is carried on by
    NAME_integrate_variational (Φ = ∂x/∂x₀ · Q), factored Φ = Q R, and log Rᵢᵢ summed; λᵢ = the sums
    / t1, in decreasing order.  (X0: (nb, 2n); prm: one parameter dict, or one per trajectory.)
    Returns the exponents (nb, 2n), NaN rows where the integration failed, and the codes."""
    nb, dim = X0.shape
    steps = max(1, int(round(t1 / interval)))
    dt = t1 / steps
    lam = np.zeros((nb, dim))
    codes = np.zeros(nb, dtype=np.int32)
    for b in range(nb):
        x, Q = np.array(X0[b], float), np.eye(dim)
        p = prm[b] if isinstance(prm, (list, ParamTable)) else prm
        try:
            for s in range(steps):
                x, Phi = model.integrate_variational(s * dt, (s + 1) * dt, x, Phi0=Q, u=u, params=p, rtol=rtol, atol=atol)
                Q, R = np.linalg.qr(Phi)
                d = np.diag(R)
                lam[b] += np.log(np.abs(d))
                Q = Q * np.sign(d)  # keep the basis oriented as Φ (R with a positive diagonal)
        except ArithmeticError as exc:  # gyrochain.build.IntegrationError / ModelError
            codes[b] = getattr(exc, "code", 1)
            lam[b] = np.nan
    return lam / t1, codes


def lyapunov_spectrum_batch(model, X0, t1: float, interval: float, prm, u=None, rtol: float = 1e-8,
                            atol: float = 1e-10) -> tuple[np.ndarray, np.ndarray]:
    """lyapunov_spectrum with every trajectory's QR steps in one launch of the GPU's kernel
    (``model.lyapunov_batch``: Gram-Schmidt, twice, in each thread, so that only the sums of
    log Rᵢᵢ come back); a trajectory that fails keeps its code and NaN exponents."""
    steps = max(1, int(round(t1 / interval)))
    sums, codes = model.lyapunov_batch(np.asarray(X0, float), t1 / steps, steps, u=u, params=prm, rtol=rtol, atol=atol)
    lam = np.array(sums, float)
    lam[codes != 0] = np.nan
    return lam / t1, codes


def pairing(lam: np.ndarray) -> tuple[float, float]:
    """For a conservative model the exponents come in pairs λᵢ = −λ₂ₙ₊₁₋ᵢ and sum to zero: the
    largest |λᵢ + λ₂ₙ₊₁₋ᵢ| (the pairing error) and |Σ λᵢ| of one spectrum (sorted decreasing)."""
    lam = np.sort(np.asarray(lam, float))[::-1]
    return float(np.max(np.abs(lam + lam[::-1]))), float(abs(np.sum(lam)))


def pairing_summary(lam: np.ndarray, energy_reasons, conservative: bool) -> str:
    """What spectra (one a row) say of their pairing: the largest max|λᵢ + λ₂ₙ₊₁₋ᵢ| and |Σλᵢ| over
    the rows, and whether the model pairs them (``conservative``: its energy is an integral;
    ``energy_reasons``: why it is not, the derivation's integrals.energy_reasons)."""
    ok = lam[np.all(np.isfinite(lam), axis=1)]
    if not len(ok):
        return "lyapunov_spectrum: no point has a spectrum (every integration failed)"
    errs = np.array([pairing(s) for s in ok])
    # a moving platform and constant joint torques leave the flow Hamiltonian (L depends on t; a constant
    # torque has the potential -u phi), so symplectic: only the other reasons break the pairing
    reasons = [r for r in energy_reasons if not r.startswith("base") and "control" not in r]
    if conservative:
        why = "the model is conservative: its spectra come in pairs ±lambda summing to 0 as t1 grows"
    elif not reasons:
        why = ("the energy (23) is not conserved here (the platform moves or a torque acts), but the flow is still "
               "Hamiltonian: its spectra come in pairs ±lambda summing to 0 as t1 grows")
    else:
        why = f"the flow is not Hamiltonian ({', '.join(reasons)}): no pairing is expected"
    return (f"lyapunov_spectrum: over {len(ok)} points the largest pairing error max|lambda_i + lambda_(2n+1-i)| is "
            f"{errs[:, 0].max():.2g} /s and the largest |sum of lambda_i| {errs[:, 1].max():.2g} /s; {why}")
