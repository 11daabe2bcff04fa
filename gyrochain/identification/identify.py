"""``identify``: the base parameters estimated from a measured motion, the spec written with
them, and a check against held-out data (docs/identify.md).

The regressor of the generated C (generate --regressor) turns a measured motion (measured.py:
read, filtered, differentiated) into linear equations for the base parameters β: at each sample,
u − τ₀ = Y_B(φ, φ̇, φ̈) β, one row per joint, a passive joint's row with u = 0.  They are solved by
weighted least squares: each joint's rows weighted by the inverse of the standard deviation of its
residual after an ordinary fit, so a joint with a noisy torque or none does not swamp the others;
the standard errors come from the same weighted fit.  The spec written has each body's parameters
as symbols with their values in [values]: physically possible bodies (consistency.py) with these
base parameters, the directions the motion does not determine chosen near the spec's values.
"""
from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..models import files
from .consistency import consistent
from ..chainspec.errors import SpecError
from ..printers.common import signed_sum
from .measured import Filter, Motion, compiled, read, same_geometry, stack

PLOT_SUFFIXES = (".png", ".svg", ".pdf")
FAR = 3.0  # estimates this many standard errors from any physically possible bodies are not written without --physical


@dataclass(frozen=True)
class Estimate:
    beta: np.ndarray
    se: np.ndarray  # standard errors
    cond: float  # condition number of the weighted, stacked base regressor
    rms: np.ndarray  # residual RMS per joint (N m)
    sigma: np.ndarray  # the weights' standard deviations per joint
    rows: int
    filter_bias: bool = False  # se includes the change with a wider Savitzky–Golay window


def estimate(A: np.ndarray, y: np.ndarray, n: int, what: str = "data") -> Estimate:
    """Weighted least squares: each joint's rows weighted by 1/σₖ, σₖ its residual's standard
    deviation after an ordinary least-squares fit."""
    rows, nb = A.shape
    if rows - nb <= n:
        raise SpecError(what, f"{rows // n} samples give {rows} equations for {nb} base parameters; record longer")
    beta0 = np.linalg.lstsq(A, y, rcond=None)[0]
    r0 = (y - A @ beta0).reshape(-1, n)
    sigma = np.sqrt(np.sum(r0 ** 2, axis=0) / max(len(r0) - nb / n, 1.0))
    sigma = np.where(sigma > 0, sigma, max(sigma.max(), 1e-300))
    w = np.tile(1.0 / sigma, rows // n)
    Aw, yw = A * w[:, None], y * w
    rank = np.linalg.matrix_rank(Aw)
    if rank < nb:
        raise SpecError(what, f"the motion excites only {rank} of the {nb} base parameters (rank {rank}); "
                                "move every joint, faster and farther (gyrochain excite designs such a motion)")
    beta, *_ = np.linalg.lstsq(Aw, yw, rcond=None)
    res = yw - Aw @ beta
    s2 = float(res @ res) / (rows - nb)
    cov = s2 * np.linalg.inv(Aw.T @ Aw)
    rms = np.sqrt(np.mean((y - A @ beta).reshape(-1, n) ** 2, axis=0))
    return Estimate(beta, np.sqrt(np.diag(cov)), float(np.linalg.cond(Aw)), rms, sigma, rows)


def simulate(cm, model, beta, motion: Motion, params=None, rtol: float = 1e-7) -> np.ndarray:
    """φ at the motion's dense times (every sample but the filter's edges) of the model with base
    parameters β, from the motion's first state under its filtered torques (linear between the
    samples): φ̈ = M̂⁻¹(u − τ₀ − Y_B(φ, φ̇, 0) β), M̂'s columns Y_B(φ, φ̇, eⱼ) β − Y_B(φ, φ̇, 0) β."""
    from scipy.integrate import solve_ivp

    n = motion.phi.shape[1]
    eye = np.eye(n)
    td, _, ud = motion.dense

    def rhs(t, x):
        q, v = x[:n], x[n:]
        u = np.array([np.interp(t, td, ud[:, k]) for k in range(n)])
        Y0, tau0 = cm.regressor(q, v, np.zeros(n), params, t, base=True)
        b = Y0 @ beta
        M = np.column_stack([cm.regressor(q, v, eye[j], params, t, base=True)[0] @ beta - b for j in range(n)])
        return np.concatenate([v, np.linalg.solve(M, u - tau0 - b)])

    x0 = np.concatenate([motion.phi[0], motion.phidot[0]])
    sol = solve_ivp(rhs, (motion.t[0], td[-1]), x0, method="DOP853", t_eval=td[td >= motion.t[0]], rtol=rtol, atol=rtol * 1e-2)
    if not sol.success:
        raise SpecError("--validate", f"the identified model could not be integrated over the held-out motion ({sol.message})")
    return sol.y[:n].T


def symbol(p) -> str:
    """The name of standard parameter ``p`` in a written spec: m_2, hx_2, Axy_2, lamz_2, b_1."""
    return f"{p.name[:-len(str(p.body))]}_{p.body}"


def identified_spec(spec, model, pi: np.ndarray, note: str) -> str:
    """The spec's text with each body's m, c, A (and λ, damping) as symbols whose [values] are
    ``pi``; its other fields and values as they were (the comments are not kept).  ``note``: the
    first comment lines (where the values come from)."""
    import tomllib

    import tomli_w

    from ..chainspec.spec import parse_spec

    raw = tomllib.loads(spec.source)
    params = model.reg.params
    taken = {str(p) for p in spec.params}
    names = {p.name: symbol(p) for p in params}
    clash = sorted(taken & set(names.values()) & _used_beside_the_bodies(raw))
    if clash:  # a name identify writes, used for something else (a spec identify wrote may be identified again)
        raise SpecError(f"values.{clash[0]}", "the spec names a parameter as identify names the identified ones; rename it")
    raw["name"] = spec.name if spec.name.endswith("_identified") else f"{spec.name}_identified"
    for k, body in enumerate(raw["body"], start=1):
        own = {p.kind + "".join(map(str, p.index)): names[p.name] for p in params if p.body == k}
        body.pop("I_c", None)
        body["m"] = own["m"]
        body["c"] = [f"{own[f'h{i}']}/{own['m']}" for i in range(3)]
        body["A"] = [[own[f"A{min(i, j)}{max(i, j)}"] for j in range(3)] for i in range(3)]
        if "lam0" in own:
            body.pop("rotor", None)
            body["lambda"] = [own[f"lam{i}"] for i in range(3)]
        if "b" in own:
            body["damping"] = own["b"]
        if "a" in own:
            body["armature"] = own["a"]
    values = dict(raw.get("values", {}))
    values.update({names[p.name]: float(v) for p, v in zip(params, pi)})
    used = {str(p) for p in parse_spec(tomli_w.dumps({**raw, "values": {}})).params}
    raw["values"] = {k: v for k, v in values.items() if k in used}  # parameters only the old inertias read go
    text = "".join(f"# {line}\n" for line in note.splitlines()) + tomli_w.dumps(raw)
    parse_spec(text)  # what we write must load
    return text


REWRITTEN = ("m", "c", "A", "I_c", "lambda", "rotor", "damping", "armature")  # the body fields identify writes as symbols


def _used_beside_the_bodies(raw: dict) -> set:
    """The parameters the spec uses in anything but the fields identify rewrites."""
    import copy

    import tomli_w

    from ..chainspec.spec import parse_spec

    rest = copy.deepcopy(raw)
    for body in rest["body"]:
        for key in REWRITTEN:
            body.pop(key, None)
        body.update(m=1.0, c=[0.0, 0.0, 0.0], I_c=[1.0, 1.0, 1.0, 0.0, 0.0, 0.0])
    rest["values"] = {}
    return {str(p) for p in parse_spec(tomli_w.dumps(rest)).params}


def formula(model, i: int) -> str:
    """βᵢ in the standard parameters' names, as the command prints it (Axx1 + 0.04 m2 + 0.4 hx2)."""
    names = [p.name for p in model.reg.params]
    return signed_sum(model.base.K[i], lambda j, c: names[j] if float(c) == 1.0 else f"{float(c):.15g} {names[j]}")


def run(spec, data: str, values: dict, output: str, force: bool, validate: str | None = None, plot: str | None = None,
        how: Filter = Filter(), physical: bool = False, say=print, spec_path: str | None = None) -> dict:
    """``identify``: read, filter, stack, estimate, write the spec, print the table (and with
    ``validate``, compare the predicted torques and a simulated motion with held-out data).
    Returns the figures (the tests read them)."""
    how.check()
    if not spec.controls:
        raise SpecError(spec.name, "has no control torque: a motion without input determines the parameters only up to a "
                                   "common factor (mark the driven joints control = true)")
    inputs = [data, validate, spec_path]
    out_path = files.target(output, f"{spec.name}_identified.toml", force, inputs)
    if plot:
        if Path(plot).suffix.lower() not in PLOT_SUFFIXES:
            raise SpecError(f"--plot {plot}", "a picture is named .png, .svg or .pdf (a file is what its name says)")
        if not validate:
            raise SpecError("--plot", "draws the held-out comparison: give --validate HELD.csv too")
        files.target(plot, plot, force, inputs + [out_path], "--plot")
    params = values or None
    cm, model = compiled(spec)
    same_geometry(model, values)
    motion = read(data, spec, data, how)
    held = read(validate, spec, "--validate", how) if validate else None
    A, y = stack(cm, motion, params)
    pi0 = cm.standard_parameters(params)
    beta0 = cm.base_parameters(pi0)
    est = estimate(A, y, spec.n, data)
    _units_and_signs(A, y, beta0, spec, data)  # before anything is printed
    if how.kind == "savgol":  # its derivative filters are not its smoother: their bias joins the standard errors
        est = _with_filter_bias(est, cm, spec, data, how, params)
    _explains(A, y, est.beta, spec, data, "the estimates")
    pi, moved = consistent(model, est.beta, est.se, pi0)
    beta = cm.base_parameters(pi) if physical else est.beta
    if physical:
        _explains(A, y, beta, spec, data, "the physically consistent estimates", est.rms)
    elif moved > FAR:
        raise SpecError(out_path.name, f"not written, and no estimate printed: the estimates are {moved:.3g} standard "
                                       "errors from any physically possible bodies (model error, data in other units "
                                       "or signs, or too little excitation); --physical writes the nearest, or record "
                                       "a longer or richer motion (gyrochain excite)")
    n = spec.n
    passive = [k for k in range(1, n + 1) if k not in spec.controls]
    say(f"identify {spec.name} from {data}: {motion.rows} samples of {n} joints, {len(motion.t)} used (the filter's)"
        + (f"; joint{'s' if len(passive) > 1 else ''} {', '.join(map(str, passive))} passive (u = 0 in "
           f"{'their' if len(passive) > 1 else 'its'} equations)" if passive else ""))
    say(f"filter: {motion.how}")
    say(f"weighted least squares: {est.rows} equations, {model.base.count} base parameters, cond {est.cond:.4g}; "
        "residual RMS " + ", ".join(f"joint {k + 1} {r:.3g}" for k, r in enumerate(est.rms)) + " N m")
    if physical:
        say(f"physically consistent (--physical): every body possible; the estimates moved by at most {moved:.3g} "
            "standard errors" + (" (the unconstrained ones were already consistent)" if moved < 1e-3 else ""))
    _table(model, beta, est.se, beta0, say)
    if est.filter_bias:
        say(f"standard errors: of the noise the residuals show, and of the filter's bias (the estimates' change with a "
            f"window of {how.window * SAVGOL_SPREAD:g} s: the Savitzky-Golay derivative filters are not its smoothing "
            "filter); --validate on held-out data checks them")
    else:
        say("standard errors: of the noise the residuals show; they assume the filter adds no bias, which a motion near "
            + (f"its cutoff ({how.cutoff:g} Hz)" if how.kind == "butter" else
               f"its window ({how.window:g} s; the Savitzky-Golay derivative filters are not its smoothing filter)")
            + " adds, beyond them (--validate on held-out data checks it)")
    note = (f"{spec.name} with the parameters identified by gyrochain identify from {data}\n"
            f"(physically possible bodies whose base parameters are the estimates' to {moved:.2g} standard errors;\n"
            f"the parameters the motion does not determine chosen near {spec.name}'s values)")
    files.write_new(out_path, identified_spec(spec, model, pi, note), force)
    say(f"wrote {out_path}: physically possible bodies in [values], their base parameters "
        + ("the estimates'" if moved < 1e-3 or physical else f"within {moved:.2g} standard errors of the estimates"))
    figures = dict(beta=beta, beta_free=est.beta, moved=moved, se=est.se, cond=est.cond, rms=est.rms, beta_spec=beta0,
                   path=out_path, pi=pi)
    if held is not None:
        figures.update(_validate(cm, model, beta, held, params, validate, plot, say))
    return figures


SAVGOL_SPREAD = 1.5  # the second Savitzky-Golay fit's window, in windows of the first


def _with_filter_bias(est: Estimate, cm, spec, data: str, how: Filter, params) -> Estimate:
    """The estimates' change with a window SAVGOL_SPREAD times as long added to their standard
    errors (in quadrature): the Savitzky–Golay derivative filters' bias grows as the window's
    square, so the change bounds it, where the residuals' noise does not see it (exact data)."""
    from dataclasses import replace

    wide = Filter(kind="savgol", window=how.window * SAVGOL_SPREAD, order=how.order)
    try:
        A2, y2 = stack(cm, read(data, spec, data, wide), params)
        other = estimate(A2, y2, spec.n, data)
    except SpecError:  # a recording too short for the wider window: the first fit's errors as they are
        return est
    return replace(est, se=np.sqrt(est.se ** 2 + (other.beta - est.beta) ** 2), filter_bias=True)


UNITS = 30.0  # measured torques this many times the spec's model's (or this fraction of them): other units


def _units_and_signs(A, y, beta0, spec, data: str) -> None:
    """Each driven joint's measured torque against what the spec's own parameters give for the
    measured motion: the factor s of the best fit y ≈ s ŷ must be positive (a torque of the wrong
    sign) and within UNITS of 1 (N mm or kN m for N m)."""
    n = spec.n
    meas, model = y.reshape(-1, n), (A @ beta0).reshape(-1, n)
    for k in spec.controls:
        m, p = meas[:, k - 1], model[:, k - 1]
        if float(p @ p) <= 0 or float(m @ m) <= 0:
            continue
        s = float(m @ p) / float(p @ p)
        if s <= 0:
            raise SpecError(data, f"joint {k}'s measured torque runs against what the spec's parameters give for this "
                                  f"motion (the best factor between them is {s:.3g}): a torque of the wrong sign or "
                                  f"column? No estimate is printed")
        if not 1 / UNITS <= s <= UNITS:
            raise SpecError(data, f"joint {k}'s measured torque is {s:.3g} times what the spec's parameters give for this "
                                  "motion: the CSV's units are N m, rad, rad/s and s (N mm would be 1000 times)? No "
                                  "estimate is printed")


EXPLAINED = 0.9  # a fit must explain this fraction of each driven joint's torque variance to be printed
CONTRADICT = ("the data contradict the model; check the CSV's units (radians, rad/s, seconds, N m), the torques' signs "
              "and columns, and that the spec is the robot measured. No estimate is printed")
CANCEL = 0.5  # and leave a passive joint's equation unbalanced by less than this fraction of its terms' size


def _explains(A, y, beta, spec, data: str, what: str, free_rms=None) -> None:
    """The fit must explain the measured torques: each controlled joint's R² at least EXPLAINED,
    and the physically consistent estimates' residual at most twice the free fit's.  Otherwise
    the data contradict the model (angles in degrees, a torque of the wrong sign or joint, another
    robot) and nothing is printed as estimates."""
    n = spec.n
    res = (y - A @ beta).reshape(-1, n)
    meas = y.reshape(-1, n)
    for k in range(1, n + 1):  # a passive joint's terms must cancel (u = 0): its residual well below their size
        if k in spec.controls:
            continue
        rows = A[k - 1::n] * beta
        size = float(np.sqrt(np.mean(np.sum(rows ** 2, axis=1))))
        left = float(np.sqrt(np.mean(res[:, k - 1] ** 2)))
        if size > 0 and left > CANCEL * size:
            raise SpecError(data, f"{what} leave joint {k}'s equation (a passive joint: its terms cancel) unbalanced by "
                                  f"{100 * left / size:.3g}% of its terms: {CONTRADICT}")
    for k in spec.controls:
        j = k - 1
        spread = float(np.sum((meas[:, j] - meas[:, j].mean()) ** 2))
        r2 = 1.0 - float(np.sum(res[:, j] ** 2)) / spread if spread > 0 else 1.0
        rms = float(np.sqrt(np.mean(res[:, j] ** 2)))
        worse = free_rms is not None and rms > 2.0 * free_rms[j] + 1e-12 * np.sqrt(spread / len(meas))
        if r2 < EXPLAINED or worse:
            than = f" ({rms / free_rms[j]:.3g} times the free fit's residual)" if worse else ""
            raise SpecError(data, f"{what} explain {100 * max(r2, 0.0):.3g}% of joint {k}'s measured torque{than}: "
                                  f"{CONTRADICT}")


def _table(model, beta, se, beta0, say) -> None:
    names = [f"beta{i + 1}" for i in range(model.base.count)]
    forms = [formula(model, i) for i in range(model.base.count)]
    wide = max(len(f) for f in forms)
    say(f"  {'':7}{'= (standard parameters)':<{wide}}  {'estimate':>13}  {'std. error':>10}  {'rel.':>7}  {'spec':>13}")
    for i in range(model.base.count):
        rel = se[i] / abs(beta[i]) if beta[i] != 0 else np.inf
        say(f"  {names[i]:<7}{forms[i]:<{wide}}  {beta[i]:13.6g}  {se[i]:10.3g}  {100 * rel:6.2g}%  {beta0[i]:13.6g}")


def _validate(cm, model, beta, held: Motion, params, path: str, plot: str | None, say) -> dict:
    """Held-out data: the torques the estimates predict, and the motion they give under the
    measured torques, against what was measured."""
    A, y = stack(cm, held, params)
    n = held.phi.shape[1]
    pred = (A @ beta).reshape(-1, n)
    meas = y.reshape(-1, n)
    err = np.sqrt(np.mean((pred - meas) ** 2, axis=0))
    scale = np.sqrt(np.mean(meas ** 2, axis=0))
    sim = simulate(cm, model, beta, held, params)
    td, phid, _ = held.dense
    td, phid = td[td >= held.t[0]], phid[td >= held.t[0]]
    drift = np.sqrt(np.mean((sim - phid) ** 2, axis=0))
    span = phid.max(axis=0) - phid.min(axis=0)
    off = np.abs(sim - phid) > 0.05 * span  # where the replay leaves the measured motion by 5 % of its range
    stays = [float(td[np.argmax(off[:, k])] - td[0]) if off[:, k].any() else float(td[-1] - td[0]) for k in range(n)]
    say(f"validate on {path} ({td[-1] - td[0]:.4g} s): torque RMS error "
        + ", ".join(f"joint {k + 1} {err[k]:.3g} N m ({100 * err[k] / scale[k]:.2g}% of its RMS)" if scale[k] > 0 else
                    f"joint {k + 1} {err[k]:.3g} N m" for k in range(n)))
    say("  simulated with the estimates under the measured torques, phi RMS error "
        + ", ".join(f"joint {k + 1} {drift[k]:.3g} rad ({100 * drift[k] / span[k]:.2g}% of its range, within 5% for "
                    f"{stays[k]:.3g} s)" for k in range(n)))
    if min(stays) < 0.5 * (td[-1] - td[0]):
        say("  (a replay of recorded torques drifts where the motion is unstable or was held by a feedback loop; the "
            "torques are the check then)")
    if plot:
        _plot(held, pred, meas, (td, phid, sim), plot)
        say(f"wrote {plot}")
    return dict(torque_rms=err, torque_scale=scale, phi_rms=drift, phi_span=span, stays=stays, simulated=sim, held=held)


def _plot(held: Motion, pred, meas, sim, path: str) -> None:
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        raise SpecError("--plot", "needs matplotlib: pip install 'gyrochain[plot]'") from None
    n = held.phi.shape[1]
    fig, ax = plt.subplots(2, n, figsize=(4.5 * n, 6.0), squeeze=False, sharex=True)
    every = max(1, len(sim[0]) // 60)  # the measured angle as points, few enough to see the line through them
    for k in range(n):
        if np.any(meas[:, k]):
            ax[0, k].plot(held.t, pred[:, k], lw=1.4, color="C0", label="predicted by the estimates", zorder=1)
            ax[0, k].plot(held.t, meas[:, k], "o", ms=3, color="0.2", label="measured (filtered)", zorder=2)
            ax[0, k].set_title(f"joint {k + 1}: torque (N m)", fontsize=11)
        else:  # a passive joint: no torque was measured, and the model's should be zero
            ax[0, k].axhline(0.0, lw=1.0, color="0.2", label="measured: none (no motor)")
            ax[0, k].plot(held.t, pred[:, k], lw=1.0, color="C0", label="the estimates' residual")
            ax[0, k].set_title(f"joint {k + 1}, passive: residual torque (N m)", fontsize=11)
            ax[0, k].legend(fontsize=9)
        ax[1, k].plot(sim[0], sim[2][:, k], lw=1.4, color="C1", label="simulated with the estimates", zorder=1)
        ax[1, k].plot(sim[0][::every], sim[1][::every, k], "o", ms=3, color="0.2", label="measured (filtered)", zorder=2)
        ax[1, k].set_title(f"joint {k + 1}: angle (rad)", fontsize=11)
        ax[1, k].set_xlabel("t (s)", fontsize=11)
    ax[0, 0].legend(fontsize=9)
    ax[1, 0].legend(fontsize=9)
    fig.tight_layout()
    target = Path(path)
    tmp = target.parent / f".{target.name}.tmp"  # written beside and renamed, in the format its name says
    with files.folders_for(target):
        try:
            fig.savefig(tmp, dpi=110, format=target.suffix.lower().lstrip("."))
            os.replace(tmp, target)
        finally:
            plt.close(fig)
            tmp.unlink(missing_ok=True)
