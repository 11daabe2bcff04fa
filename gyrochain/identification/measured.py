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

from ..models import files, pipeline
from ..chainspec.errors import SpecError

CUTOFF_HZ = 5.0  # the default cutoff of the Butterworth filter (motions of a few Hz; an encoder's noise in φ̈ grows as its cube)
WINDOW_S = 0.2  # the default Savitzky–Golay window (s)
ORDER = 4  # the Butterworth's poles, or the Savitzky–Golay polynomial's order
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
    rows: int = 0  # the file's samples, before the edges were dropped and the rest thinned
    dense: tuple = ()  # (t, φ, u) filtered at every sample but the edges (a simulation follows these torques)


def columns(spec) -> tuple[list[str], list[str], list[str]]:
    """The CSV's columns: phi1..phin, phidot1..phidotn (optional), u1..u_nu (one per controlled
    joint, in chain order: the C's u)."""
    n = spec.n
    return ([f"phi{k}" for k in range(1, n + 1)], [f"phidot{k}" for k in range(1, n + 1)],
            [f"u{i}" for i in range(1, len(spec.controls) + 1)])


@dataclass(frozen=True)
class Filter:
    """How φ is smoothed and differentiated (and u smoothed alike): ``butter``, a zero-phase
    Butterworth low-pass (scipy's sosfiltfilt, ``order`` poles, ``cutoff`` Hz) then central
    differences, which commute with it, so φ̈ is the filtered φ̈ exactly as u is the filtered u;
    or ``savgol``, a Savitzky–Golay filter of ``window`` seconds and polynomial ``order``, whose
    derivative filters are not its smoothing filter (a motion faster than the window is then
    seen differently in φ̈ and in u)."""

    kind: str = "butter"
    cutoff: float | None = None  # None: CUTOFF_HZ (the Butterworth's only)
    window: float | None = None  # None: WINDOW_S (the Savitzky–Golay filter's only)
    order: int = ORDER

    def __post_init__(self):
        for name, value, default, own in (("cutoff", self.cutoff, CUTOFF_HZ, "butter"), ("window", self.window, WINDOW_S, "savgol")):
            if value is not None and self.kind != own and self.kind in ("butter", "savgol"):
                raise SpecError(f"--{name}", f"applies to --filter {own}; the {self.kind} filter takes "
                                f"--{'window' if name == 'cutoff' else 'cutoff'} (give --filter {own}, or drop --{name})")
            if value is None:
                object.__setattr__(self, name, default)

    def check(self) -> None:
        if self.kind not in ("butter", "savgol"):
            raise SpecError("--filter", f"{self.kind!r}: expected butter or savgol")
        if not (self.cutoff > 0 and self.window > 0):
            raise SpecError("--cutoff" if not self.cutoff > 0 else "--window", "must be positive")
        if not 2 <= self.order <= 8:
            raise SpecError("--order", f"{self.order}: expected 2 to 8")


def _fail(what: str, path: str, message: str) -> SpecError:
    """The one-line error about the file ``path`` read for ``what`` (the file named once)."""
    return SpecError(path, message) if what == path else SpecError(what, f"{path}: {message}")


def read(path: str, spec, what: str, how: Filter = Filter()) -> Motion:
    """A measured motion from a CSV (t, phi1..phin[, phidot1..phidotn], u1..u_nu), filtered and
    differentiated; a file that cannot be one is one line naming ``what`` and the file."""
    phis, rates, us = columns(spec)
    expected = f"t, {phis[0]}..{phis[-1]}" + (f", {us[0]}..{us[-1]}" if us else "") + " (and optionally phidot1..)"
    names, data = files.read_table(path, what, ["t"] + phis + us, expected)
    _no_foreign_columns(names, spec, what, path)
    t = data[:, names.index("t")]
    dt = np.diff(t)
    step = float(np.median(dt)) if len(dt) else 0.0
    if len(dt) and np.max(np.abs(dt - step)) > UNIFORM_TOL * step:
        raise _fail(what, path, f"t is not sampled uniformly (steps from {dt.min():g} to {dt.max():g} s); "
                              "resample it at one rate")
    col = lambda c: data[:, names.index(c)]  # noqa: E731
    phi = np.column_stack([col(c) for c in phis])
    u = np.zeros_like(phi)
    for i, k in enumerate(spec.controls):
        u[:, k - 1] = col(us[i])
    rate = np.column_stack([col(c) for c in rates]) if all(c in names for c in rates) else None
    _within_the_spec_limits(spec, phi, rate, u, what, path)
    edge, keep, derive, said = (_butter if how.kind == "butter" else _savgol)(how, step, len(t), path, what)
    phi_f, phidot, phidd = derive(phi)
    if rate is not None:
        rate_f, rate_d, _ = derive(rate)
        _rates_are_derivatives(rate_f, phidot, edge, what, path)
        phidot, phidd = rate_f, rate_d
        how_rate = "phidot measured (filtered), phidd its derivative"
    else:
        how_rate = "phidot and phidd the derivatives of the filtered phi"
    # the edges, where the filter sees one side, dropped; then every keep-th sample kept: the
    # filter's output is correlated over about keep samples, and closer samples would make the
    # standard errors too small (they assume independent residuals)
    cut = slice(edge, len(t) - edge, keep)
    text = f"{said}; {how_rate}; u filtered alike; {edge} samples dropped at each end, then every {keep}th kept"
    u_f, inner = derive(u)[0], slice(edge, len(t) - edge)
    return Motion(t[cut], phi_f[cut], phidot[cut], phidd[cut], u_f[cut], text, len(t), (t[inner], phi_f[inner], u_f[inner]))


RATE_TOL = 0.2  # a measured phidot may differ from the filtered dphi/dt by this fraction of its RMS
RANGE_SLACK = 0.1  # rad a recorded angle may pass a range the spec gives (a soft limit, an encoder's offset)
BEYOND = 2.0  # times a velocity or effort limit a recorded rate or torque may not reach


def _within_the_spec_limits(spec, phi, rate, u, what: str, path: str) -> None:
    """A robot does not leave its joints' ranges, nor run at twice their velocity or effort limits:
    data that do are in other units or columns (degrees, N mm, another joint's), one line."""
    from ..chainspec.tables import spec_limits

    lim = spec_limits(spec)
    n = spec.n
    for k in range(n):
        lo, hi = lim.get("lower", [None] * n)[k], lim.get("upper", [None] * n)[k]
        if lo is None and hi is None:
            continue
        past = np.maximum(phi[:, k] - (np.inf if hi is None else hi), (-np.inf if lo is None else lo) - phi[:, k])
        if float(np.max(past)) > RANGE_SLACK:
            side = (f"range {lo:g} to {hi:g} rad" if lo is not None and hi is not None else
                    f"lower limit {lo:g} rad" if lo is not None else f"upper limit {hi:g} rad")
            raise _fail(what, path, f"phi{k + 1} reaches {phi[np.argmax(past), k]:.4g} rad, beyond joint {k + 1}'s {side} "
                                    f"by more than {RANGE_SLACK:g} rad (the spec's limits): other units (degrees?), "
                                    "another joint's column, or limits the spec states too tightly?")
    for key, data, name, unit in (("velocity", rate, "phidot", "rad/s"), ("effort", u, "u", "N m")):
        for k in range(n):
            bound = lim.get(key, [None] * n)[k]
            if data is None or bound is None or (key == "effort" and k + 1 not in spec.controls):
                continue
            top = float(np.max(np.abs(data[:, k])))
            if top > BEYOND * bound:
                column = f"{name}{k + 1}" if key == "velocity" else f"u{spec.controls.index(k + 1) + 1}"
                raise _fail(what, path, f"{column} reaches {top:.4g} {unit}, {top / bound:.3g} times joint {k + 1}'s {key} "
                                        f"limit {bound:g} {unit} (the spec's limits): other units "
                                        f"({'deg/s' if key == 'velocity' else 'N mm'}?), another joint's column, or limits the "
                                        "spec states too tightly?")


def _no_foreign_columns(names: list, spec, what: str, path: str) -> None:
    """A column named for a joint or a control the spec does not have (u2 of a passive joint,
    phi3 of a two-joint chain) is refused: its data would be dropped without a word."""
    import re

    n, nu = spec.n, len(spec.controls)
    passive = [k for k in range(1, n + 1) if k not in spec.controls]
    for name in names:
        m = re.fullmatch(r"(phi|phidot|phidd|u)(\d+)", name)
        if m is None:
            continue
        kind, k = m.group(1), int(m.group(2))
        if kind == "u" and not 1 <= k <= nu:
            why = (f"the spec has {nu} control torque{'s' if nu != 1 else ''} (u1..u{nu}, of joints "
                   f"{', '.join(map(str, spec.controls))}); joint{'s' if len(passive) > 1 else ''} "
                   f"{', '.join(map(str, passive))} {'are' if len(passive) > 1 else 'is'} passive: mark it control = true "
                   "in the spec, or drop the column") if passive else f"the spec has {nu} control torques (u1..u{nu})"
            raise _fail(what, path, f"column {name!r}: {why}")
        if kind != "u" and not 1 <= k <= n:
            raise _fail(what, path, f"column {name!r}: the spec has {n} joints ({kind}1..{kind}{n})")
        if kind == "phidd":
            raise _fail(what, path, f"column {name!r}: identify reads phi (and phidot) and derives phidd itself; drop it")


def _rates_are_derivatives(rate, phidot, edge: int, what: str, path: str) -> None:
    """A measured phidot must be the derivative of phi: rates in deg/s, or of another joint, or
    a time in other units are refused, not fitted."""
    inner = slice(edge, len(rate) - edge) if len(rate) > 2 * edge + 2 else slice(None)
    for k in range(rate.shape[1]):
        d, r = phidot[inner, k], rate[inner, k]
        scale = float(np.sqrt(np.mean(d ** 2)))
        if scale == 0:
            continue
        off = float(np.sqrt(np.mean((r - d) ** 2))) / scale
        if off > RATE_TOL:
            ratio = float(np.sqrt(np.mean(r ** 2))) / scale
            hint = " (degrees per second? the rates must be rad/s)" if 40 < ratio < 80 else (
                " (is t in seconds?)" if ratio > 200 or ratio < 1 / 200 else "")
            raise _fail(what, path, f"column 'phidot{k + 1}' is not the derivative of phi{k + 1}: they differ by "
                                    f"{100 * off:.0f}% of its RMS, the RMS ratio is {ratio:.3g}{hint}")


def _butter(how: Filter, step: float, count: int, path, what) -> tuple:
    from scipy.signal import butter, sosfiltfilt

    fs = 1.0 / step if step > 0 else 0.0
    if not how.cutoff < 0.5 * fs:
        raise _fail(what, path, f"t steps by {step:g} s ({fs:g} samples per second), too slow for the filter's cutoff "
                                f"of {how.cutoff:g} Hz, which must be below half the rate: is t in seconds (milliseconds "
                                "read as seconds do this)? Else a lower --cutoff")
    sos = butter(how.order, how.cutoff, fs=fs, output="sos")
    edge = int(np.ceil(3 * fs / how.cutoff))
    keep = max(1, int(round(fs / (2 * how.cutoff))))
    if count < 2 * edge + 1:
        raise _fail(what, path, f"{count} samples; the filter's edges take {edge} at each end, so at least "
                              f"{2 * edge + 1} are needed (a longer record, or a higher --cutoff)")
    d = lambda y: np.gradient(y, step, axis=0, edge_order=2)  # noqa: E731

    def derive(y):
        f = sosfiltfilt(sos, y, axis=0)
        return f, d(f), d(d(f))

    return edge, keep, derive, (f"zero-phase Butterworth low-pass: order {how.order}, cutoff {how.cutoff:g} Hz; "
                                "derivatives by central differences")


def _savgol(how: Filter, step: float, count: int, path, what) -> tuple:
    from scipy.signal import savgol_filter

    w = int(round(how.window / step)) if step > 0 else 0
    w = max(w + (w % 2 == 0), how.order + 3 - (how.order % 2))  # odd, longer than the polynomial
    if count < 2 * w + 1:
        raise _fail(what, path, f"{count} samples; the filter's window is {w} samples, so at least {2 * w + 1} "
                              "are needed (a longer record, or a shorter --window)")
    sg = lambda y, d=0: savgol_filter(y, w, how.order, deriv=d, delta=step, axis=0)  # noqa: E731
    return (w // 2, max(1, w // 4), lambda y: (sg(y), sg(y, 1), sg(y, 2)),
            f"Savitzky-Golay filter: window {w} samples ({w * step:.4g} s), order {how.order}, zero phase")


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


def same_geometry(model, values: dict) -> None:
    """The run's values of the geometry's parameters must be those the base parameters were found
    at (the spec's [values]): at others, the same columns may group differently."""
    for name, value in model.base.at:
        if name in values and values[name] != value:
            raise SpecError(f"--param {name}", f"the base parameters were found at the spec's [values] {name} = {value:g}; "
                                               "set [values] to the geometry of the run")


def compiled(spec):
    """The spec's model with its regressor, compiled (once per user), and its derivation."""
    return pipeline.compiled(spec, regressor=True)
