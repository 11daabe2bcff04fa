"""A measured motion for identification: the CSV read, φ filtered and differentiated, and the
equations u − τ₀ = Y_B(φ, φ̇, φ̈) β stacked over its samples (identify, excite; docs/identify.md).

φ̇ and φ̈ come from the sampled φ by a Savitzky–Golay filter (the local polynomial's derivatives,
zero phase), and the torques are smoothed by the same filter, so both sides of the equations see
the same delay-free filtering (Gautier's parallel filtering).  The filter's output is correlated
over its window, so only every (window/4)-th sample is kept: closer samples would make the
standard errors of the estimates too small (they assume independent residuals).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import files, pipeline
from .errors import SpecError

WINDOW_S = 0.2  # the default Savitzky–Golay window (s)
ORDER = 4  # its polynomial order
UNIFORM_TOL = 1e-3  # the sampling step may vary by this fraction of its median


@dataclass(frozen=True)
class Motion:
    """A measured motion after filtering: times, φ, φ̇, φ̈ (samples × n) and the joint torques u
    (samples × n, zero where a joint has no control), and how it was filtered."""

    t: np.ndarray
    phi: np.ndarray
    phidot: np.ndarray
    phidd: np.ndarray
    u: np.ndarray
    how: str


def columns(spec) -> tuple[list[str], list[str], list[str]]:
    """The CSV's columns: phi1..phin, phidot1..phidotn (optional), u1..u_nu (one per controlled
    joint, in chain order: the C's u)."""
    n = spec.n
    return ([f"phi{k}" for k in range(1, n + 1)], [f"phidot{k}" for k in range(1, n + 1)],
            [f"u{i}" for i in range(1, len(spec.controls) + 1)])


def read(path: str, spec, what: str, window_s: float = WINDOW_S, order: int = ORDER) -> Motion:
    """A measured motion from a CSV (t, phi1..phin[, phidot1..phidotn], u1..u_nu), filtered and
    differentiated; a file that cannot be one is one line naming ``what`` and the file."""
    from scipy.signal import savgol_filter

    phis, rates, us = columns(spec)
    expected = f"t, {phis[0]}..{phis[-1]}" + (f", {us[0]}..{us[-1]}" if us else "") + " (and optionally phidot1..)"
    names, data = files.read_table(path, what, ["t"] + phis + us, expected)
    t = data[:, names.index("t")]
    dt = np.diff(t)
    step = float(np.median(dt)) if len(dt) else 0.0
    if len(dt) and np.max(np.abs(dt - step)) > UNIFORM_TOL * step:
        raise SpecError(what, f"{path}: t is not sampled uniformly (steps from {dt.min():g} to {dt.max():g} s); "
                              "resample it at one rate")
    w = int(round(window_s / step)) if step > 0 else 0
    w = max(w + (w % 2 == 0), order + 3 - (order % 2))  # odd, longer than the polynomial
    if len(t) < 2 * w + 1:
        raise SpecError(what, f"{path}: {len(t)} samples; the filter's window is {w} samples, so at least {2 * w + 1} "
                              "are needed (a longer record, or a shorter --window)")
    col = lambda c: data[:, names.index(c)]  # noqa: E731
    phi = np.column_stack([col(c) for c in phis])
    sg = lambda y, d=0: savgol_filter(y, w, order, deriv=d, delta=step, axis=0)  # noqa: E731
    if all(c in names for c in rates):
        rate = np.column_stack([col(c) for c in rates])
        phidot, phidd, how_rate = sg(rate), sg(rate, 1), "phidot measured (smoothed), phidd its derivative"
    else:
        phidot, phidd, how_rate = sg(phi, 1), sg(phi, 2), "phidot and phidd the derivatives of phi's"
    u = np.zeros_like(phi)
    for i, k in enumerate(spec.controls):
        u[:, k - 1] = sg(col(us[i]))
    # the edges, where the window is one-sided, dropped; then every (w/4)-th sample kept: the
    # filter's output is correlated over its window, and samples closer than that would make the
    # standard errors too small (they assume independent residuals)
    keep = max(1, w // 4)
    cut = slice(w // 2, len(t) - w // 2, keep)
    how = (f"Savitzky-Golay filter: window {w} samples ({w * step:.4g} s), order {order}, zero phase; "
           f"{how_rate}; u smoothed by the same filter; {w // 2} samples dropped at each end, then every {keep}th kept")
    return Motion(t[cut], sg(phi)[cut], phidot[cut], phidd[cut], u[cut], how)


def stack(cm, motion: Motion, params=None) -> tuple[np.ndarray, np.ndarray]:
    """Y_B and u − τ₀ stacked over the samples (rows sample-major, n per sample)."""
    n = motion.phi.shape[1]
    A = np.empty((len(motion.t) * n, cm.regressor(np.zeros(n), np.zeros(n), np.zeros(n), params, base=True)[0].shape[1]))
    y = np.empty(len(motion.t) * n)
    for i in range(len(motion.t)):
        Yb, tau0 = cm.regressor(motion.phi[i], motion.phidot[i], motion.phidd[i], params, float(motion.t[i]), base=True)
        A[i * n:(i + 1) * n] = Yb
        y[i * n:(i + 1) * n] = motion.u[i] - tau0
    return A, y




def compiled(spec):
    """The spec's model with its regressor, compiled (once per user), and its derivation."""
    return pipeline.compiled(spec, regressor=True)
