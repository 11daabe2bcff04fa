"""``gyrochain continue``: the branches of equilibria over a parameter's range, their special points,
and with a second parameter the curves those points trace (continuation.py, boundary.py); the
report and the CSV file."""
from __future__ import annotations

import io
from dataclasses import dataclass, field

import numpy as np

from . import floquet, steady
from .boundary import Boundary, Curve
from . import cycles
from .continuation import BRANCHES, KINDS, RATE, Branch, ContinuationError, Equilibria, Tracer
from .cycles import ENERGY, Orbits
from .floquet import fmt_phi, wrap

MONODROMY_TOL = 1e-14  # rtol = atol of a period's variational integration: multipliers to ~1e-13, boundaries to ~1e-11
TRACED = ("LP", "BP", "KC", "H", "+1", "PD", "NS", "KCm")  # the kinds whose curves a second parameter traces


@dataclass
class Result:
    name: str  # the spec's
    names: list  # the parameters: the branch's, then the boundary's second
    ranges: list
    held: dict  # the other parameters' values
    driven: bool
    branches: list = field(default_factory=list)
    curves: list = field(default_factory=list)
    starts: str = ""  # how the first points were found
    second: float = float("nan")  # the second parameter's value along the branches
    skipped: list = field(default_factory=list)  # the normal modes the run's steps did not reach
    orbits: str = ""  # periodic orbits: "driven" (of the drive's period) or "modes" (nonlinear normal modes); "": equilibria


def parse_range(text: str, spec, what: str = "--vary") -> tuple[str, float, float]:
    """``NAME=lo:hi``: a symbolic parameter of the spec and its range."""
    name, eq, rng = text.partition("=")
    name = name.strip()
    if not eq or not name:
        raise ContinuationError(f"{what}: expected NAME=lo:hi, for example P=0:12")
    names = [str(p) for p in spec.params]
    if name not in names and name not in (RATE, ENERGY):
        from ..chainspec.errors import did_you_mean

        raise ContinuationError(f"{what} {name}: not a symbolic parameter of the spec ({did_you_mean(name, names)}"
                                + (f"its parameters: {', '.join(names)}; or {RATE}, the rate of a steady rotation, or "
                                   f"{ENERGY}, of the nonlinear normal modes)" if names else
                                   f"it has none; {RATE} is the rate of a steady rotation, {ENERGY} the energy of the "
                                   "nonlinear normal modes)"))
    try:
        lo, hi = (float(v) for v in rng.split(":"))
    except ValueError:
        raise ContinuationError(f"{what} {name}: expected lo:hi, for example {name}=0:12") from None
    if not (np.isfinite(lo) and np.isfinite(hi) and lo < hi):
        raise ContinuationError(f"{what} {name}: expected finite lo < hi")
    return name, lo, hi


def run(spec, params: dict, u, ranges: list, starts=(), max_steps: int = 400, step: float = 0.02, period=None,
        progress=None, orbits: bool = False, modes=()) -> Result:
    """Trace the branches over ``ranges[0]`` = (name, lo, hi), both ways from their first points:
    Newton from ``starts`` (φ each; default: every equilibrium steady finds) at the parameter's value
    in ``params`` when it is in the range, else at lo; the branches of their branch points; and with
    ``ranges[1]`` the curves of their special points in the two parameters.  With ``orbits`` (or
    the energy varied) the branches of periodic orbits instead (cycles.py)."""
    from ..derive.assemble import time_dependent

    cm, model = steady.compile_spec(spec, driven_ok=True)
    names = [r[0] for r in ranges]
    if len(set(names)) < len(names):
        raise ContinuationError(f"--vary {names[0]}: given twice; the second --vary names another parameter")
    if orbits or names[0] == ENERGY:
        return _run_orbits(spec, cm, model, params, u, ranges, starts, max_steps, step, period, progress, modes)
    lo, hi = ranges[0][1:]
    given = 0.0 if names[0] == RATE else params.get(names[0])  # a rate starts at rest when it can
    alpha0 = float(given) if given is not None and lo <= given <= hi else lo
    second = (0.0 if names[1] == RATE else params[names[1]]) if len(ranges) > 1 else None
    if len(ranges) > 1 and not ranges[1][1] <= second <= ranges[1][2]:
        raise ContinuationError(f"--vary {names[1]}: its value on the branch, {second:g} (--param or the "
                                f"spec's values), is outside {ranges[1][1]:g}:{ranges[1][2]:g}")
    driven = time_dependent(model)
    start = params if names[0] == RATE else {**params, names[0]: alpha0}  # the parameters where the branches start
    an, st, dr = _analysis(cm, model, start, u, period, driven)
    out = Result(spec.name, names, [r[1:] for r in ranges], {k: v for k, v in params.items() if k not in names}, driven)
    if len(ranges) > 1:
        out.second = float(second)
    eq = Equilibria(cm, model, start, u, names[:1], [ranges[0][1:]], steady=st, driven=dr)
    tracer = Tracer(eq, max_steps, step, progress)
    firsts = _firsts(an, tracer, starts, alpha0, out)
    _trace_from(out, tracer, [(p, f"phi = {fmt_phi(p.phi)} at {names[0]} = {p.alpha:.10g}") for p in firsts])
    if len(ranges) > 1:
        eq2 = Equilibria(cm, model, params, u, names, [r[1:] for r in ranges], steady=st, driven=dr)
        eq2.reversible = eq.reversible
        out.curves = _curves(out, eq2, second, max_steps, step, progress)
    return out


def _run_orbits(spec, cm, model, params, u, ranges, starts, max_steps, step, period, progress, modes) -> Result:
    """The branches of periodic orbits: of the drive's period from the starts (at rest at φ = 0 by
    default), or the nonlinear normal modes of the stable equilibrium (``--from``, else the one
    of least energy) over the energy above it."""
    from ..derive.assemble import time_dependent

    name, lo, hi = ranges[0]
    if len(ranges) > 1:
        raise ContinuationError(f"--vary {ranges[1][0]}: the curves of special points in two parameters are traced for "
                                "equilibria; a branch of periodic orbits takes one --vary")
    if not cm.has_variational:
        raise ContinuationError(f"--orbits: periodic orbits need NAME_integrate_variational, emitted up to n = 16 (n = {cm.n})")
    if name == RATE:
        raise ContinuationError(f"--vary {RATE}: the steady rotations are equilibria of the reduced model; drop --orbits")
    driven = time_dependent(model)
    out = Result(spec.name, [name], [(lo, hi)], {k: v for k, v in params.items() if k != name}, driven,
                 orbits="driven" if driven else "modes")
    if driven:
        tracers = _driven_tracers(cm, model, params, u, ranges[0], starts, max_steps, step, period, progress, modes, out)
    else:
        tracers = _mode_tracers(cm, model, params, u, ranges[0], starts, max_steps, step, period, progress, modes, out)
    used = 0
    for tracer, first, origin in tracers:
        tracer.max_steps = max_steps - used
        if tracer.max_steps <= 0:
            out.skipped.append(origin)
            continue
        _trace_from(out, tracer, [(first, origin)])
        used += tracer.steps
        _why_it_stopped(out.branches, tracer.eq)
        for br in out.branches:  # each point written: its amplitude, once
            for p in [*br.points, *(s.point for s in br.specials)]:
                if p.amplitude is None:
                    p.amplitude = tracer.eq.swing(p)
    return out


def _why_it_stopped(brs, eq) -> None:
    """A family of normal modes that Newton could not follow on: what its last orbit shows."""
    for br in brs:
        last = br.points[-1]
        if eq.driven or "could not go on" not in br.end or br.end.endswith(")."):
            continue
        _x1, Phi, _T = eq.shoot(last.y)
        growth = float(np.max(np.abs(np.linalg.eigvals(Phi))))
        br.end += (f" (there the period is {last.period:.4g} s, {last.period / eq.T_ref:.3g} times the first orbit's, "
                   f"and the largest multiplier {growth:.3g}: the family nears an orbit of infinite period or one too "
                   "unstable for single shooting).")


def _trace_from(out: Result, tracer: Tracer, firsts) -> None:
    """Trace the branch through each (first point, origin) both ways, and the branches that cross
    them at their branch points, into out.branches (BRANCHES at most, within the tracer's steps)."""
    queue = [(p, origin, None) for p, origin in firsts]
    while queue and len(out.branches) < BRANCHES and tracer.steps < tracer.max_steps:
        p, origin, at = queue.pop(0)
        if any(_on(p, br) for br in out.branches):
            continue  # already traced (a branch met again, the other side of a branch point)
        br = tracer.trace(p, origin, at) if at is not None else tracer.trace_both(p, origin)
        out.branches.append(br)
        queue += [(q, f"the branch point at {tracer.eq.name} = {s.point.alpha:.10g}", s.point)
                  for s in br.specials if s.kind == "BP" for q in tracer.switch(s)]


def _driven_tracers(cm, model, params, u, rng, starts, max_steps, step, period, progress, modes, out) -> list:
    """(tracer, first point, origin) of each start of a driven model's orbits."""
    name, lo, hi = rng
    if name == ENERGY:
        raise ContinuationError(f"--vary {ENERGY}: the model depends on t: its periodic orbits have the drive's period "
                                "and follow a parameter (--orbits --vary NAME=lo:hi)")
    if modes:
        raise ContinuationError("--mode: belongs to the nonlinear normal modes of an autonomous model (--vary energy=lo:hi)")
    if period is not None and _period_varies(model, params, rng):
        raise ContinuationError(f"--period: the drive's period changes with {name}; leave --period out and it follows "
                                f"{name}")
    alpha0 = float(params[name]) if name in params and lo <= params[name] <= hi else lo
    _an, _st, dr = _analysis(cm, model, {**params, name: alpha0}, u, period, True)
    if dr.cyclic:
        raise ContinuationError("--orbits: phi1 is cyclic (l1 vertical, nothing acting in joint 1): the orbits of the "
                                "drive's period come in families turned about l1, which continue does not trace")
    eq = Orbits(cm, params, u, name, lo, hi, period=lambda p: (dr.set_params(p), dr.period)[1])
    out.starts = "the --from starts" if starts else "rest at phi = 0"
    return [(Tracer(eq, max_steps, step, progress), p, f"phi = {fmt_phi(p.phi)}, phidot = {fmt_phi(p.phidot)} at "
             f"{name} = {p.alpha:.10g}") for p in cycles.driven_firsts(eq, starts, alpha0)]


def _period_varies(model, params, rng) -> bool:
    """Whether the drive's own period differs at the range's two ends."""
    name, lo, hi = rng
    try:
        ends = [floquet.time_period(model, {**params, name: v}, "continue")[0] for v in (lo, hi)]
    except Exception:  # noqa: BLE001  (no period of its own: the user's holds)
        return False
    return abs(ends[0] - ends[1]) > 1e-12 * max(ends)


def _mode_tracers(cm, model, params, u, rng, starts, max_steps, step, period, progress, modes, out) -> list:
    """(tracer, first orbit, origin) of each nonlinear normal mode of an autonomous model."""
    from . import orbits as shooting

    name, lo, hi = rng
    why = shooting.removed(model.integrals.energy_reasons, u is not None and np.any(np.asarray(u) != 0))
    if why:
        raise ContinuationError(f"{'--vary ' + ENERGY if name == ENERGY else '--orbits'}: the energy is not conserved here ({'; '.join(why)}): continue traces the "
                                "periodic orbits of a conservative model (over their energy) or of a driven one (over a "
                                "parameter)")
    if name != ENERGY:
        raise ContinuationError(f"--vary {name}: an autonomous model's periodic orbits are continued over "
                                f"{ENERGY}=lo:hi, the energy above the stable equilibrium's, J")
    if period is not None:
        raise ContinuationError("--period: the model does not depend on t")
    if lo <= 0:
        raise ContinuationError(f"--vary {ENERGY}: {lo:g}: the energy above the equilibrium's starts above 0 (at 0 the "
                                "orbit is the equilibrium itself)")
    if _analysis(cm, model, params, u, None, False)[1].cyclic:
        raise ContinuationError(f"--vary {ENERGY}: phi1 is cyclic (l1 vertical, nothing acting in joint 1): the orbits "
                                "come in families turned about l1, which continue does not trace (orbits --omega gives "
                                "the steady rotations)")
    phi = _stable_equilibrium(cm, params, u, starts)
    tracers = []
    for k, (x0, T, phase, E0, origin) in cycles.mode_starts(cm, params, u, phi, lo, modes):
        eq = Orbits(cm, params, u, ENERGY, lo, hi, phase=phase, E0=E0, T_ref=T)
        tracers.append((Tracer(eq, max_steps, step, progress), eq.start(x0, lo, T), origin))
    out.starts = f"the linear modes of the equilibrium phi = {fmt_phi(phi)}"
    return tracers


def _stable_equilibrium(cm, params, u, starts):
    """The equilibrium whose normal modes are traced: Newton from --from, or the stable one of
    least energy."""
    from ..chainspec.errors import SpecError
    from . import orbits as shooting

    if len(starts) > 1:
        raise ContinuationError("--from: the nonlinear normal modes start at one equilibrium; give one")
    if not starts:
        try:
            return shooting.stable_equilibrium(cm, params or None, u)[0]
        except SpecError as exc:
            raise ContinuationError(f"--vary {ENERGY}: {exc.message} (give one with --from)") from None
    got = floquet.equilibrium(cm, np.asarray(starts[0], float)[:cm.n], (0.0,), params or None, u)
    if got is None:
        raise ContinuationError(f"--from: Newton found no equilibrium from phi = {fmt_phi(starts[0])}")
    return wrap(got[0])


def _analysis(cm, model, params, u, period, driven):
    """(the analysis, steady's or None, floquet's or None) at the start's parameters."""
    from ..chainspec.errors import SpecError

    try:
        if driven:
            an = floquet.DrivenAnalysis(cm, model, params, u, period, what="continue")
            an.tol = MONODROMY_TOL
            return an, None, an
        if period is not None:
            raise ContinuationError("--period: the model does not depend on t")
        an = steady.Analysis(cm, model, params, u)
        return an, an, None
    except SpecError as exc:
        raise ContinuationError(f"{exc.field}: {exc.message}") from None
    except steady.SteadyError as exc:
        raise ContinuationError(str(exc)) from None


def _firsts(an, tracer: Tracer, starts, alpha0: float, out: Result) -> list:
    """The branches' first points: Newton from the user's starts, or every equilibrium found."""
    name = tracer.eq.name
    if starts:
        out.starts = "the --from starts"
        return [tracer.start(np.asarray(s, float), alpha0) for s in starts]
    if name == RATE and alpha0 != 0.0:  # steady rotations at that rate, from steady's starts
        found = floquet.distinct(an.starts(), lambda s: an.solve(s, alpha0))
    else:
        found = [e.phi for e in an.equilibria()]
    if not found:
        raise ContinuationError(f"--vary {name}: no equilibrium at {name} = {alpha0:g} (Newton from "
                                f"{floquet.STARTS}); give a start with --from"
                                + (", or trace the periodic orbits of the drive's period with --orbits" if out.driven else ""))
    out.starts = f"every equilibrium at {name} = {alpha0:g}"
    firsts = []
    for phi in found:
        try:
            firsts.append(tracer.start(phi, alpha0))
        except ContinuationError:
            continue  # a singular one (a family of equilibria, a fold where it starts): not a branch's start
    if not firsts:
        raise ContinuationError(f"--vary {name}: every equilibrium at {name} = {alpha0:g} has a singular "
                                "Jacobian: start a little away from it (--param)")
    return firsts


def _curves(out: Result, eq2: Equilibria, second: float, max_steps: int, step: float, progress) -> list:
    """The curve of each special point that bounds stability, in the two parameters (once per curve)."""
    curves = []
    for br in out.branches:
        for s in br.specials:
            if s.kind not in TRACED or any(_near(s, c) for c in curves):
                continue
            y0 = eq2.y_of(s.point.phi, [s.point.alpha, second])
            try:
                curves.append(Boundary(eq2, s.kind, max_steps, step, progress).trace(y0))
            except ArithmeticError:
                continue
    return curves


def _on(p, br: Branch, tol: float = 1e-6) -> bool:
    """Whether the point p lies on the branch's polyline (within tol in y)."""
    ys = np.array([q.y for q in br.points] + ([br.points[0].y] if br.end == "closed on itself" else []))
    for a, b in zip(ys, ys[1:]):  # (a loop's last chord closes it)
        d = b - a
        w = np.clip(((p.y - a) @ d) / max(d @ d, 1e-300), 0.0, 1.0)
        if np.linalg.norm(wrap(p.y - (a + w * d))) < max(tol, 0.05 * np.linalg.norm(d)):  # a chord's sagitta
            return True
    return False


def _near(s, curve: Curve) -> bool:
    return curve.kind == s.kind and any(abs(v[0] - s.point.alpha) <= 1e-8 * max(1.0, abs(s.point.alpha))
                                        for v, _phi, _y in curve.points)


# --------------------------------------------------------------------------- report
def _segments(br: Branch, name: str) -> str:
    """The verdict along the branch, by stretches between the changes; a stretch through a fold or
    a branch point where the branch turns back says so."""
    opened = br.points[0].verdict == "degenerate" or br.origin.startswith("the branch point")
    first = br.points[1] if len(br.points) > 1 and opened else br.points[0]
    parts, start, verdict, turns = [], br.points[0].alpha, first.verdict, []  # (a branch point opening a branch is degenerate)
    for s in br.specials:
        if s.before != s.after:
            parts.append(f"{verdict} from {name} = {start:.10g} to {s.point.alpha:.10g}" + _turning(turns, name))
            start, verdict, turns = s.point.alpha, s.after, []
        elif s.kind in ("LP", "BP"):
            turns.append(s.point.alpha)
    parts.append(f"{verdict} from {name} = {start:.10g} to {br.points[-1].alpha:.10g}" + _turning(turns, name))
    return "; ".join(parts)


def _turning(turns, name: str) -> str:
    """Where a stretch turns back in the parameter (a fold, a pitchfork's branch point)."""
    return f" (turning back at {name} = {', '.join(f'{t:.10g}' for t in turns)})" if turns else ""


def report(res: Result) -> str:
    name = res.names[0]
    lo, hi = res.ranges[0]
    held = ", ".join(f"{k} = {v:.12g}" for k, v in res.held.items())
    what = {"": f"equilibria{' for all t' if res.driven else ''}", "driven": "periodic orbits of the drive's period",
            "modes": "nonlinear normal modes (periodic orbits; energy above the equilibrium's, J)"}[res.orbits]
    lines = [f"{res.name}: {what} continued in {name} over [{lo:g}, {hi:g}]"
             + (f" ({held})" if held else "") + f"; {len(res.branches)} branch{'es' if len(res.branches) != 1 else ''} "
             f"from {res.starts}" + ("" if res.orbits == "modes" else " and the branch points met")]
    for i, br in enumerate(res.branches, 1):
        lines.append(f"branch {i}, from {br.origin}: {len(br.points)} points; {br.end}")
        lines.append(f"  {_segments(br, name)}")
        for s in br.specials:
            period = f", period {s.point.period:.12g} s" if res.orbits else ""
            lines.append(f"  {s.kind:<3} {name} = {s.point.alpha:.12g}, phi = {fmt_phi(s.point.phi)}{period}: {KINDS[s.kind]}"
                         + (f" {s.detail}" if s.detail else "") + f"; {s.before} -> {s.after}")
    for origin in res.skipped:
        lines.append(f"{origin}: not traced, the run's steps were spent (--max-steps raises them)")
    for j, c in enumerate(res.curves, 1):
        (a0, b0), (a1, b1) = c.points[0][0], c.points[-1][0]
        lines.append(f"curve {j}: the {KINDS[c.kind]} in ({res.names[0]}, {res.names[1]}), {len(c.points)} points from "
                     f"({a0:.10g}, {b0:.10g}) to ({a1:.10g}, {b1:.10g}); ends: {c.ends[0]}, {c.ends[1]}")
    return "\n".join(lines)


def table(res: Result):
    """The rows of the file: (part, kind, values of the parameters, φ, verdict, spectrum) for each
    point of each branch with its special points in order (kind set), then each curve's points."""
    second = [res.second] if len(res.names) > 1 else []  # the second parameter, held along the branches
    for i, br in enumerate(res.branches, 1):
        for _, kind, p in _in_order(br):
            orbit = [*p.phidot, p.period, *p.amplitude] if res.orbits else []  # a periodic orbit's rates, period, swing
            yield f"branch {i}", kind, [p.alpha, *second], [*p.phi, *orbit], p.verdict, p.spectrum
    for j, c in enumerate(res.curves, 1):
        for values, phi, _y in c.points:
            yield f"curve {j}", c.kind, list(values), phi, "", []


def _columns(res: Result, n: int) -> list[str]:
    """The state's columns: the angles, and for periodic orbits the start's rates and the period."""
    ks = range(1, n + 1)
    return [f"phi{k}" for k in ks] + ([*(f"phidot{k}" for k in ks), "period", *(f"amp{k}" for k in ks)] if res.orbits else [])


def csv_text(res: Result, n: int) -> str:
    """The branches, their special points (kind set) and the curves, one row each."""
    out = io.StringIO()
    out.write(",".join(["part", "kind", *res.names, *_columns(res, n), "verdict", "spectrum"]) + "\n")
    for part, kind, values, phi, verdict, spectrum in table(res):
        sp = " ".join(f"{z.real:.17g}{z.imag:+.17g}j" for z in spectrum)
        out.write(",".join([part, kind, *[f"{v:.17g}" for v in values], *[f"{v:.17g}" for v in phi], verdict, sp]) + "\n")
    return out.getvalue()


STORE = "gyrochain_continue"  # the attribute that marks a store of continue


def _zarr():
    try:
        import zarr
    except ImportError:
        raise ContinuationError("-o: a Zarr store needs the sweep extra: pip install 'gyrochain[sweep]'") from None
    return zarr


def is_store(path) -> bool:
    """Whether ``path`` is a Zarr store that continue wrote."""
    from pathlib import Path

    if not (Path(path) / "zarr.json").is_file():
        return False
    try:
        return STORE in dict(_zarr().open_group(str(path), mode="r").attrs)
    except Exception:  # noqa: BLE001  (any unreadable store is not ours)
        return False


def check_store(path, force: bool) -> None:
    """Before the work: a store may replace only a store of continue, and only with --force."""
    from pathlib import Path

    path = Path(path)
    _zarr()
    if path.exists() and not force:
        raise ContinuationError(f"{path}: exists; pass --force to replace it")
    if path.exists() and not is_store(path):
        raise ContinuationError(f"{path}: exists and is not a store of continue; choose another path")


def write_store(res: Result, n: int, path) -> None:
    """The table as a Zarr store (the format sweep writes), one array a column over the rows:
    part (branch k as k, curve j as −j), kind and verdict (indices into the attributes' lists,
    −1 for none), each parameter, phi (rows × n), spectrum (rows × 2n × [re, im], NaN padded),
    and for periodic orbits phidot (rows × n), period and amp (rows × n).
    Written beside and renamed: never half a store."""
    import os
    import shutil
    from pathlib import Path

    zarr, path = _zarr(), Path(path)
    rows = list(table(res))
    kinds, verdicts = list(KINDS), sorted({r[4] for r in rows if r[4]})
    m = len(rows)
    spectrum = np.full((m, 2 * n, 2), np.nan)
    for i, r in enumerate(rows):
        z = np.asarray(r[5], complex)
        spectrum[i, :len(z), 0], spectrum[i, :len(z), 1] = z.real, z.imag
    columns = {
        "part": np.array([int(r[0].split()[1]) * (1 if r[0].startswith("branch") else -1) for r in rows], "i4"),
        "kind": np.array([kinds.index(r[1]) if r[1] else -1 for r in rows], "i1"),
        "verdict": np.array([verdicts.index(r[4]) if r[4] else -1 for r in rows], "i1"),
        "spectrum": spectrum, **{name: np.array([r[2][k] for r in rows], float) for k, name in enumerate(res.names)}}
    state = np.array([r[3] for r in rows], float).reshape(m, -1)
    columns["phi"] = state[:, :n]
    if res.orbits:  # a periodic orbit's start rates and its period
        columns["phidot"], columns["period"], columns["amp"] = state[:, n:2 * n], state[:, 2 * n], state[:, 2 * n + 1:]
    tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
    try:
        g = zarr.open_group(str(tmp), mode="w")
        g.attrs[STORE] = {"spec_name": res.name, "names": res.names, "ranges": [list(r) for r in res.ranges],
                          "kinds": kinds, "verdicts": verdicts, "n": n, "orbits": res.orbits}
        for name, values in columns.items():
            g.create_array(name, data=values, chunks=values.shape or (1,))
        if path.exists():
            shutil.rmtree(path)  # a store of continue (check_store), replaced with --force
        tmp.rename(path)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def read_store(path) -> tuple[list[str], list[dict]]:
    """A store of continue as the CSV's header and rows (the diagram reads either)."""
    g = _zarr().open_group(str(path), mode="r")
    a = dict(g.attrs)[STORE]
    n, names = int(a["n"]), a["names"]
    orbits = a.get("orbits", "")
    cols = {k: np.asarray(g[k][...]) for k in ("part", "kind", "verdict", "phi", "spectrum", *names,
                                                *(("phidot", "period", "amp") if orbits else ()))}
    state = _columns(Result("", names, [], {}, False, orbits=orbits), n)
    header = ["part", "kind", *names, *state, "verdict", "spectrum"]
    rows = []
    for i, part in enumerate(cols["part"]):
        z = [complex(re_, im) for re_, im in cols["spectrum"][i] if not np.isnan(re_)]
        row = {"part": f"branch {part}" if part > 0 else f"curve {-part}",
               "kind": a["kinds"][cols["kind"][i]] if cols["kind"][i] >= 0 else "",
               **{nm: repr(float(cols[nm][i])) for nm in names},
               **{f"phi{k + 1}": repr(float(v)) for k, v in enumerate(cols["phi"][i])},
               **({f"phidot{k + 1}": repr(float(v)) for k, v in enumerate(cols["phidot"][i])} if orbits else {}),
               **({"period": repr(float(cols["period"][i]))} if orbits else {}),
               **({f"amp{k + 1}": repr(float(v)) for k, v in enumerate(cols["amp"][i])} if orbits else {}),
               "verdict": a["verdicts"][cols["verdict"][i]] if cols["verdict"][i] >= 0 else "",
               "spectrum": " ".join(f"{v.real!r}{v.imag:+}j" for v in z)}
        rows.append(row)
    return header, rows


def _in_order(br: Branch):
    """The branch's points and its special points, in the order of the branch (by arclength)."""
    out, specials = [], list(br.specials)
    for a, b in zip(br.points, br.points[1:] + [None]):
        out.append((0, "", a))
        if b is None:
            break
        for s in list(specials):
            if _between(s.point, a, b):
                out.append((0, s.kind, s.point))
                specials.remove(s)
    out += [(0, s.kind, s.point) for s in specials]
    return out


def _between(p, a, b) -> bool:
    d = b.y - a.y
    w = ((p.y - a.y) @ d) / max(d @ d, 1e-300)
    return -1e-9 <= w <= 1 + 1e-9
