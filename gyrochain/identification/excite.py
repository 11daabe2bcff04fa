"""``excite``: a periodic motion that determines the base parameters well, and a simulated
measurement of it (docs/identify.md).

With every joint controlled, the joints' trajectories are Swevers' finite Fourier series (Swevers,
Ganseman, Tükel, De Schutter and Van Brussel 1997), scaled to the joint and speed limits; with
passive joints (a Furuta pendulum) the controlled joints' torques are such series and the motion
is what the model makes of them.  The coefficients minimise the condition number of the stacked
base regressor over one period.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..models import files
from ..chainspec.errors import SpecError
from ..chainspec.tables import spec_limits
from .measured import columns, compiled, same_geometry


@dataclass(frozen=True)
class Design:
    """An excitation: samples t over one period, φ, φ̇, φ̈ (samples × n), the controlled joints'
    torques u (samples × nu), cond(Y_B) of the stacked samples, and what was designed."""

    t: np.ndarray
    phi: np.ndarray
    phidot: np.ndarray
    phidd: np.ndarray
    u: np.ndarray
    cond: float
    cond_start: float
    mode: str
    start: np.ndarray  # the state the designed motion starts from (with the torques' design: rest at the centre)


def fourier(coef: np.ndarray, t: np.ndarray, wf: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Swevers' finite Fourier series of the rates: q̇ = Σₗ aₗ cos(l ω t) + bₗ sin(l ω t), so q is
    periodic with zero mean about its centre: q = Σₗ (aₗ sin(l ω t) − bₗ cos(l ω t))/(l ω).
    ``coef``: (joints, harmonics, 2).  Returns q − centre, q̇, q̈ (samples × joints)."""
    L = coef.shape[1]
    lw = wf * np.arange(1, L + 1)
    s, c = np.sin(np.outer(t, lw)), np.cos(np.outer(t, lw))
    a, b = coef[..., 0], coef[..., 1]
    q = s @ (a / lw).T - c @ (b / lw).T
    qd = c @ a.T + s @ b.T
    qdd = (-s * lw) @ a.T + (c * lw) @ b.T
    return q, qd, qdd


NO_CONTROLS = "the spec has no control torque: no motion can be imposed (give a joint control = true)"
MARGIN = 0.9  # the defaults keep this fraction of the way to a limit the spec gives


def spec_defaults(spec, center=None, phi_max=None, phidot_max=None, u_max=None) -> tuple:
    """(centre, phi_max, phidot_max, u_max) per joint (u_max per control): those given, else from
    the spec's joint limits, else 0, 1 rad, 2 rad/s and 1 N m.  A range: the middle, MARGIN of the
    way to its ends; one bound alone: 1 rad, the centre moved inside it where 0 is too near; the
    velocity and the effort: MARGIN of them.  A centre outside a joint's bounds, or a given
    --phi-max that reaches past them, is one line."""
    n, lim = spec.n, spec_limits(spec)
    lo = [-np.inf if v is None else v for v in lim.get("lower", [None] * n)]
    hi = [np.inf if v is None else v for v in lim.get("upper", [None] * n)]
    if center is None:
        centre = np.array([(a + b) / 2 if np.isfinite(a) and np.isfinite(b) else
                           max(0.0, a + 1.0 / MARGIN) if np.isfinite(a) else min(0.0, b - 1.0 / MARGIN) if np.isfinite(b)
                           else 0.0 for a, b in zip(lo, hi)])
    else:
        centre = np.asarray(center, dtype=float)
        centre = np.full(n, centre[0]) if centre.shape == (1,) else centre
        if centre.shape != (n,):
            raise SpecError("--center", f"expected one number or {n} of them (one per joint)")
    for k in range(n):
        if not lo[k] < centre[k] < hi[k]:
            raise SpecError("--center", f"{centre[k]:g} lies outside joint {k + 1}'s range, {_range(lo[k], hi[k])} "
                                        "(the spec's limits)")
    room = [min(centre[k] - lo[k], hi[k] - centre[k]) for k in range(n)]
    reach = [MARGIN * room[k] if np.isfinite(lo[k]) and np.isfinite(hi[k]) else min(1.0, MARGIN * room[k]) for k in range(n)]
    pmax = _limits(phi_max, n, "--phi-max", reach)
    for k in range(n):
        if phi_max is not None and pmax[k] > room[k]:
            raise SpecError("--phi-max", f"{pmax[k]:g} about the centre {centre[k]:g} reaches past joint {k + 1}'s range, "
                                         f"{_range(lo[k], hi[k])} (the spec's limits)")
    speed = [MARGIN * v if v is not None else 2.0 for v in lim.get("velocity", [None] * n)]
    effort = [MARGIN * e if e is not None else 1.0 for e in lim.get("effort", [None] * n)]
    return (centre, pmax, _limits(phidot_max, n, "--phidot-max", speed),
            _limits(u_max, len(spec.controls), "--u-max", [effort[k - 1] for k in spec.controls]))


def _range(lo: float, hi: float) -> str:
    return (f"{lo:g} to {hi:g} rad" if np.isfinite(lo) and np.isfinite(hi) else
            f"at least {lo:g} rad" if np.isfinite(lo) else f"at most {hi:g} rad")


def _limits(value, n: int, what: str, default) -> np.ndarray:
    v = np.array(default, dtype=float) * np.ones(n) if value is None else np.asarray(value, dtype=float)
    if v.shape == (1,):
        v = np.full(n, v[0])
    if v.shape != (n,) or not np.all(v > 0):
        raise SpecError(what, f"expected one positive number or {n} of them (one per joint)")
    return v


class _Problem:
    """One excitation problem: the samples of a period, the limits, and for coefficients x the
    motion (``motion``) and its cost (log cond(Y_B), plus a penalty beyond the limits)."""

    def __init__(self, spec, cm, period, harmonics, samples, pmax, vmax, umax, centre, params):
        self.spec, self.cm, self.params, self.harmonics, self.samples = spec, cm, params, harmonics, samples
        self.pmax, self.vmax, self.umax, self.centre = pmax, vmax, umax, centre
        self.n, self.wf = spec.n, 2 * np.pi / period
        self.t = np.arange(samples) * period / samples
        self.full = len(spec.controls) == spec.n  # every joint controlled: design the trajectories
        self.ctl = [k - 1 for k in spec.controls]
        self.pi0 = cm.standard_parameters(params)  # the spec's own parameters (the feedforward torques)
        self.uscale = 1.0  # the torques' scale below u_max, where the motion at u_max leaves the limits

    def over(self, q, qd) -> float:
        """The largest of |φ − centre|/φ_max and |φ̇|/φ̇_max over the period (≤ 1: within the limits)."""
        return float(np.maximum(np.abs(q - self.centre) / self.pmax, np.abs(qd) / self.vmax).max())

    def cond(self, q, qd, qdd) -> float:
        cm, p = self.cm, self.params
        A = np.vstack([cm.regressor(q[i], qd[i], qdd[i], p, float(self.t[i]), base=True)[0] for i in range(len(self.t))])
        return float(np.linalg.cond(A))

    def motion(self, x) -> tuple:
        """(φ, φ̇, φ̈, u) over the period; u: the controlled joints' torques."""
        n, L = self.n, self.harmonics
        if self.full:  # Swevers' series scaled to the limits; u what the spec's own parameters need
            q, qd, qdd = fourier(x.reshape(n, L, 2), self.t, self.wf)
            k = min(np.min(self.pmax / np.maximum(np.abs(q).max(axis=0), 1e-300)),
                    np.min(self.vmax / np.maximum(np.abs(qd).max(axis=0), 1e-300)))
            q, qd, qdd = q * k + self.centre, qd * k, qdd * k
            u = np.array([Y @ self.pi0 + tau0 for Y, tau0 in (self.cm.regressor(q[i], qd[i], qdd[i], self.params, float(self.t[i]))
                                                          for i in range(self.samples))])
            return q, qd, qdd, u[:, self.ctl]
        # the torques' series (scaled to |u| ≤ u_max) over two periods from rest; the second is used
        tt = np.arange(2 * self.samples) * (self.t[1] - self.t[0])
        lw = self.wf * np.arange(1, L + 1)
        coef = x.reshape(len(self.ctl), L, 2)
        u = np.sin(np.outer(tt, lw)) @ coef[..., 0].T + np.cos(np.outer(tt, lw)) @ coef[..., 1].T
        u = u * np.min(self.umax / np.maximum(np.abs(u).max(axis=0), 1e-300)) * self.uscale
        X = np.empty((len(tt), 2 * n))
        X[0] = np.concatenate([self.centre, np.zeros(n)])
        for i in range(1, len(tt)):
            X[i] = self.cm.integrate([tt[i - 1], tt[i]], X[i - 1], u=u[i - 1], params=self.params, rtol=1e-9, atol=1e-11)[-1]
        half = slice(self.samples, 2 * self.samples)
        self.from_rest = (X[:, :n], X[:, n:])  # both periods: the start from rest is part of a recording too
        acc = np.array([self.cm.qdd(X[i], u[i], self.params, float(tt[i])) for i in range(len(tt))[half]])
        return X[half, :n], X[half, n:], acc, u[half]

    def cost(self, x) -> float:
        try:
            q, qd, qdd, _ = self.motion(x)
        except Exception:  # noqa: BLE001  (a motion the integrator cannot follow is a bad design)
            return 1e3
        c = self.cond(q, qd, qdd)
        over = 0.0 if self.full else self.over(*self.from_rest)
        return (np.log(c) if np.isfinite(c) else 1e3) + (10.0 * (over - 1.0) ** 2 if over > 1.0 else 0.0)


def excite(spec, cm, period: float = 10.0, harmonics: int = 5, phi_max=None, phidot_max=None, u_max=None,
           samples: int = 200, evaluations: int = 400, seed: int = 0, center=None, params=None) -> Design:
    """A periodic excitation that minimises cond(Y_B) over ``samples`` samples of a period, within
    |φ − centre| ≤ phi_max and |φ̇| ≤ phidot_max: for a chain whose every joint has a control, the
    joints' trajectories as Swevers' Fourier series (scaled to the limits); otherwise the controlled
    joints' torques as such series (|u| ≤ u_max), the motion simulated from rest at the centre
    over two periods (the second one is used), the limits a penalty."""
    from scipy.optimize import minimize

    n = spec.n
    check_options(period, harmonics, samples, evaluations)
    if not spec.controls:
        raise SpecError("excite", NO_CONTROLS)
    centre, pmax, vmax, umax = spec_defaults(spec, center, phi_max, phidot_max, u_max)
    pb = _Problem(spec, cm, period, harmonics, samples, pmax, vmax, umax, centre, params)
    shape = (n if pb.full else len(spec.controls), harmonics, 2)
    x0 = (np.random.default_rng(seed).normal(size=shape) / np.arange(1, harmonics + 1)[None, :, None]).ravel()
    start = pb.cost(x0)
    small = x0.size <= 8
    best = minimize(pb.cost, x0, method="Nelder-Mead" if small else "Powell",
                    options=dict(maxfev=evaluations, **({"xatol": 1e-4, "fatol": 1e-4} if small else {"xtol": 1e-4, "ftol": 1e-4})))
    x = best.x if best.fun <= start else x0
    scaled = "" if pb.full else _within_limits(pb, x)
    q, qd, qdd, u = pb.motion(x)
    mode = (f"joint trajectories: {harmonics} harmonics of {period:g} s per joint (Swevers et al. 1997)" if pb.full else
            f"torques of the controlled joints: {harmonics} harmonics of {period:g} s (the chain has passive joints); "
            f"the motion simulated from rest, its second period{scaled}")
    first = pb.motion(x0)
    begin = np.concatenate([q[0], qd[0]]) if pb.full else np.concatenate([centre, np.zeros(n)])
    return Design(pb.t, q, qd, qdd, u, pb.cond(q, qd, qdd), pb.cond(*first[:3]), mode, begin)


def _within_limits(pb: _Problem, x) -> str:
    """Where the best torques at u_max drive the passive motion beyond --phi-max or --phidot-max,
    the torques scaled down until it stays within (bisection on the scale); where no scale does,
    one line.  Returns what the report adds."""
    def over(scale: float) -> float:
        pb.uscale = scale
        try:
            pb.motion(x)
        except Exception:  # noqa: BLE001  (a motion the integrator cannot follow is beyond every limit)
            return np.inf
        return pb.over(*pb.from_rest)

    if over(1.0) <= 1.0:
        return ""
    lo, hi = 0.0, 1.0
    for _ in range(24):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if over(mid) <= 1.0 else (lo, mid)
    if lo < 1e-6:
        pb.uscale = 1.0
        raise SpecError("--phi-max", "no torque within --u-max keeps the passive joints' motion within --phi-max and "
                                     "--phidot-max (the motion about the centre is unstable?); widen the limits or move "
                                     "the --center")
    over(lo)
    return f"; the torques scaled to {lo:.3g} of --u-max to keep phi and phidot within their limits"


def _beyond(phi: np.ndarray, limits: dict, spec) -> str:
    """Where a recorded φ leaves |φ − centre| ≤ phi_max: the joints and how far ("" if nowhere)."""
    n = spec.n
    centre, pmax, _, _ = spec_defaults(spec, limits.get("center"), limits.get("phi_max"))
    reach = np.abs(phi - centre).max(axis=0)
    return ", ".join(f"|phi{k + 1} - centre| reaches {reach[k]:.4g} rad, --phi-max {pmax[k]:g}"
                     for k in range(n) if reach[k] > pmax[k] * (1 + 1e-9))


def write_design(design: Design, spec) -> str:
    """The excitation as CSV: t, phi, phidot, phidd and the controlled joints' u (one period)."""
    n = spec.n
    head = ["t"] + [f"phi{k}" for k in range(1, n + 1)] + [f"phidot{k}" for k in range(1, n + 1)]
    head += [f"phidd{k}" for k in range(1, n + 1)] + [f"u{i}" for i in range(1, len(spec.controls) + 1)]
    rows = np.column_stack([design.t, design.phi, design.phidot, design.phidd, design.u])
    return ",".join(head) + "\n" + "".join(",".join(f"{v:.17g}" for v in row) + "\n" for row in rows)


def simulate_recording(spec, cm, d: Design, duration: float, rate: float, noise: float, counts: int, seed: int,
               params=None) -> np.ndarray:
    """A simulated measurement of the design on the spec's own model: the torques held over each
    sample (1/rate s); with every joint controlled, the design's torques plus a PD loop on its
    trajectory (as a bench's controller tracks it), else the design's torques alone from rest at
    the start.  The recorded u has Gaussian noise of ``noise`` times its RMS, φ is quantised to
    2π/``counts``.  Rows: t, φ (n), u (nu)."""
    n, ctl = spec.n, [k - 1 for k in spec.controls]
    check_options(experiment=duration, recording=(rate, noise, counts))
    steps = int(round(duration * rate))
    period = d.t[-1] + d.t[1] - d.t[0]
    t = np.arange(steps + 1) / rate
    cyc = lambda y: np.interp(t % period, np.append(d.t, period), np.append(y, y[:1]))  # noqa: E731  (periodic)
    U = np.column_stack([cyc(d.u[:, i]) for i in range(len(ctl))])
    full = len(ctl) == n
    if full:
        Q = np.column_stack([cyc(d.phi[:, k]) for k in range(n)])
        V = np.column_stack([cyc(d.phidot[:, k]) for k in range(n)])
        Md = np.diag(cm.mass_matrix(d.phi[0], params))
        kp, kd = (2 * np.pi * 5.0) ** 2 * Md, 2 * 0.7 * (2 * np.pi * 5.0) * Md  # a 5 Hz loop, damping 0.7
    x = d.start.copy()
    rows = np.empty((steps + 1, 1 + n + len(ctl)))
    for i in range(steps + 1):
        u = U[i] + (kp * (Q[i] - x[:n]) + kd * (V[i] - x[n:]) if full else 0.0)
        rows[i, 0], rows[i, 1:1 + n], rows[i, 1 + n:] = t[i], x[:n], u
        if i < steps:
            x = cm.integrate([t[i], t[i + 1]], x, u=u, params=params, rtol=1e-10, atol=1e-12)[-1]
    rng = np.random.default_rng(seed)
    # what a torque sensor sampled at tᵢ reads of the held torques: the mean of the two held on
    # either side (the torque jumps there); the value held after tᵢ alone would lag the motion by
    # half a sample, which biases the estimates where a loop changes the torque quickly
    applied = rows[:, 1 + n:].copy()
    applied[1:] = 0.5 * (applied[1:] + rows[:-1, 1 + n:])
    rows[:, 1 + n:] = applied + noise * np.sqrt(np.mean(applied ** 2, axis=0)) * rng.standard_normal(applied.shape)
    if counts:
        q = 2 * np.pi / counts
        rows[:, 1:1 + n] = np.round(rows[:, 1:1 + n] / q) * q + 0.0  # + 0.0: no -0 in the file
    return rows


MAX_SAMPLES = 2_000_000  # a simulated recording longer than this is refused
COND_HOPELESS = 1e6  # a design whose base regressor is worse conditioned than this is refused (good ones: 10 to 1e4)
RECORDING = (1000.0, 0.01, 4096)  # --experiment's defaults: samples per second, the torques' noise, encoder counts


def check_options(period: float = 10.0, harmonics: int = 5, samples: int = 200, evaluations: int = 1,
                  experiment: float | None = None, recording: tuple = (1000.0, 0.01, 4096)) -> None:
    """Every option of excite checked before any work: one line naming the first that cannot be."""
    rate, noise, counts = recording
    for what, value, ok, want in (
            ("--period", period, period > 0, "a positive number of seconds"),
            ("--harmonics", harmonics, harmonics >= 1, "at least 1"),
            ("--samples", samples, samples >= 2 * harmonics + 1,
             f"at least {2 * harmonics + 1} (more than two per period of the highest of the {harmonics} harmonics)"),
            ("--evaluations", evaluations, evaluations >= 1, "at least 1"),
            ("--experiment", experiment, experiment is None or experiment > 0, "a positive number of seconds"),
            ("--rate", rate, rate > 0, "a positive number of samples per second"),
            ("--noise", noise, noise >= 0, "a fraction of the torques' RMS, not negative"),
            ("--encoder", counts, counts >= 0, "counts per turn, not negative (0: exact angles)")):
        if not ok:
            raise SpecError(what, f"{value:g}: expected {want}")
    if experiment is not None and experiment * rate > MAX_SAMPLES:
        raise SpecError("--experiment", f"{experiment * rate:.0f} samples: more than {MAX_SAMPLES} (a shorter duration "
                                        "or a lower --rate)")


def run_excite(spec, source: str, values: dict, output: str, force: bool, limits: dict, say=print,
               experiment: float | None = None, recording: tuple = (1000.0, 0.01, 4096), **options) -> Design:
    """``excite``: the design written as CSV (``output`` "-": printed, the report on stderr); with
    ``experiment`` (seconds), a simulated measurement of it instead, ``recording`` = (rate, noise,
    encoder counts)."""
    import sys

    given = [name for name, value in zip(("--rate", "--noise", "--encoder"), recording) if value is not None]
    if experiment is None and given:
        raise SpecError(given[0], "applies to --experiment (a simulated measurement); give --experiment SECONDS, "
                                  f"or drop {given[0]}")
    recording = tuple(default if value is None else value for value, default in zip(recording, RECORDING))
    check_options(options.get("period", 10.0), options.get("harmonics", 5), options.get("samples", 200),
                  options.get("evaluations", 1), experiment, recording)
    if not spec.controls:  # the cheap checks before the model is built
        raise SpecError("excite", NO_CONTROLS)
    if limits.get("u_max") is not None and len(spec.controls) == spec.n:
        raise SpecError("--u-max", f"applies to a chain with passive joints (excite designs their torques); every joint of "
                                   f"{spec.name} is driven, so it designs the joints' trajectories within --phi-max and "
                                   "--phidot-max: drop --u-max")
    default = f"{spec.name}_{'experiment' if experiment is not None else 'excite'}.csv"
    if output != "-":
        files.target(output, default, force, source)
    cm, model = compiled(spec)
    same_geometry(model, values)
    d = excite(spec, cm, phi_max=limits["phi_max"], phidot_max=limits["phidot_max"], u_max=limits["u_max"],
               center=limits["center"], params=values or None, **options)
    if len(spec.controls) == spec.n:  # every joint driven: the torques follow from the design, checked against the efforts
        effort = spec_limits(spec).get("effort", [None] * spec.n)
        for k in range(spec.n):
            top = float(np.max(np.abs(d.u[:, k])))
            if effort[k] is not None and top > effort[k]:
                raise SpecError("excite", f"the design's torque u{k + 1} reaches {top:.4g} N m, beyond joint {k + 1}'s effort "
                                          f"limit {effort[k]:g} N m (the spec's limits): narrow --phi-max or --phidot-max, or "
                                          "give a longer --period")
    if not d.cond <= COND_HOPELESS:
        raise SpecError("excite", f"the best design found has cond {d.cond:.3g} of the base regressor: its motion does not "
                                  "determine the base parameters (a fit would multiply the data's errors by that much); "
                                  "widen --phi-max and --phidot-max, or give more --harmonics, a longer --period or more "
                                  "--evaluations")
    rows = None
    if experiment is not None:
        rows = simulate_recording(spec, cm, d, experiment, *recording, options.get("seed", 0), params=values or None)
        head = ["t"] + columns(spec)[0] + columns(spec)[2]
        text = ",".join(head) + "\n" + "".join(",".join(f"{v:.17g}" for v in row) + "\n" for row in rows)
    else:
        text = write_design(d, spec)
    path = files.deliver(text, output, default, force, source)
    tell = say if path is not None else (lambda line: print(line, file=sys.stderr))
    tell(f"excite {spec.name}: {d.mode}; cond of the base regressor {d.cond:.4g} over the period")
    have = spec_limits(spec)
    taken = [f"--{k.replace('_', '-')}" for k, keys in (("center", ("lower", "upper")), ("phi_max", ("lower", "upper")),
                                                      ("phidot_max", ("velocity",)), ("u_max", ("effort",)))
             if limits.get(k) is None and any(key in have for key in keys) and (k != "u_max" or len(spec.controls) < spec.n)]
    if taken:
        tell(f"  from the spec's joint limits: {', '.join(taken)} (the middle of each range, {100 * MARGIN:.0f}% of the way "
             "to its ends, its velocity and its effort)" + ("; the torques the design needs are within the efforts"
                                                            if len(spec.controls) == spec.n and "effort" in have else ""))
    if path is not None and rows is not None:
        rate, noise, counts = recording
        tell(f"wrote {path}: a simulated measurement of {experiment:g} s at {rate:g} Hz (t, phi, u): noise {100 * noise:g}% "
             "of u's RMS, " + (f"phi quantised to {counts} counts per turn" if counts else "phi exact"))
        left = _beyond(rows[:, 1:1 + spec.n], limits, spec)
        if left:
            tell(f"  the recording leaves the design's limits ({left}): the motion from its start is not the designed "
                 "period; a bench's limits must allow for it, or record fewer periods")
    elif path is not None:
        tell(f"wrote {path}: {len(d.t)} samples of one period (t, phi, phidot, phidd, u)")
    return d
