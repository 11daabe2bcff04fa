"""The equations of compound spatial pendulums: derived from a spec, emitted as C, Python and LaTeX, and run.

The command line ``gyrochain {generate,check,simulate,steady,orbits,sweep,animate} SPEC``, ``gyrochain
plot STORE``, ``gyrochain examples`` and ``gyrochain new KIND`` (``python -m gyrochain`` is the same).
This module parses arguments and prints; every command is a library function it calls (generate.run,
simulate.run, steady.analyze, orbits.analyze, sweep.run, plot.store, animate.render, starter.copy,
starter.new_spec).  A bad input gets one line on stderr naming the field, exit status 2, and nothing
written; a bug of ours one line with exit status 1.
"""
from __future__ import annotations

import argparse
import math
import os
import re
import sys
import time
import warnings
from pathlib import Path

import numpy as np

from .. import caused_by_interrupt
from . import cliargs, parsers
from ..models.files import deliver, target
from ..chainspec.physical import run_values
from ..analysis.simulate import torques
from ..chainspec.spec import SpecError, load_spec

EXIT_BAD_INPUT = 2
MAX_RENORMALISATIONS = 10**6  # of a sweep's Lyapunov measures, per trajectory
MAX_CHUNK_BYTES = 1 << 30  # of the trajectories one sweep chunk holds in memory
EXIT_INTERNAL = 1


class _Progress:
    def __init__(self, quiet: bool):
        self.t0 = time.perf_counter()
        self.quiet = quiet

    def __call__(self, msg: str) -> None:
        if not self.quiet:
            print(f"  [{time.perf_counter() - self.t0:6.2f} s] {msg}", file=sys.stderr, flush=True)


def cmd_generate(args) -> int:
    from ..models import generate

    t0 = time.perf_counter()
    spec = load_spec(args.spec)
    if args.output is not None and not args.output.strip():
        raise SpecError("-o", "is empty; name a folder (default generated/<name>)")
    target = Path(args.output) if args.output is not None else Path("generated") / spec.name
    generate.check(spec, target, args.force, Path(args.spec), args.derivative_form, args.pdf)  # before any line: one line
    if args.casadi:
        from ..printers import casadi

        casadi.check(spec, args.real)
    if not args.quiet:
        print(f"generating {spec.name} (n = {spec.n}) from {args.spec}", file=sys.stderr)
    result = generate.run(spec, target, Path(args.spec).name, build=not args.no_build, force=args.force,
                          qdd_form=args.qdd_form, der_form=args.derivative_form, progress=_Progress(args.quiet),
                          real=args.real, source=Path(args.spec), regressor=args.regressor, paper=args.paper,
                          pdf=args.pdf, gpu=args.gpu, casadi=args.casadi, hessian=args.hessian)
    for line in generate.report(result):
        print(line)
    print(f"done in {time.perf_counter() - t0:.2f} s")
    return 0


def cmd_identify(args) -> int:
    from ..identification import identify
    from ..chainspec.physical import run_values

    spec = load_spec(args.spec)
    values = run_values(spec, cliargs.params_of(args.param))
    how = identify.Filter(args.filter, args.cutoff, args.window, args.order)
    identify.run(spec, args.data, values, args.output, args.force, args.validate, args.plot, how, args.physical,
                 spec_path=args.spec)
    return 0


def cmd_excite(args) -> int:
    from ..identification import excite
    from ..chainspec.physical import run_values

    spec = load_spec(args.spec)
    values = run_values(spec, cliargs.params_of(args.param))
    lim = {k: cliargs.float_list(getattr(args, k), f"--{k.replace('_', '-')}") for k in ("phi_max", "phidot_max", "u_max", "center")}
    excite.run_excite(spec, args.spec, values, args.output, args.force, lim, period=args.period, harmonics=args.harmonics,
                        samples=args.samples, evaluations=args.evaluations, seed=args.seed, experiment=args.experiment,
                        recording=(args.rate, args.noise, args.encoder))
    return 0


def cmd_check(args) -> int:
    spec = load_spec(args.spec)
    params = ", ".join(f"{p} = {spec.values[str(p)]:g}" if str(p) in spec.values else f"{p} (no value)"
                       for p in spec.params) or "none"
    print(f"{args.spec}: ok ({spec.name}, n = {spec.n}, symbolic parameters: {params})")
    return 0


def cmd_simulate(args) -> int:
    """Integrate a spec with the emitted C (or the independent reference model); CSV on stdout."""
    from ..analysis import simulate

    spec = load_spec(args.spec)
    simulate.check_applies(args.method, {"--h": args.h, "--rtol": args.rtol, "--atol": args.atol})
    h = 0.0 if args.h is None else args.h
    rtol = 1e-10 if args.rtol is None else args.rtol
    atol = 1e-12 if args.atol is None else args.atol
    simulate.check_options(args.t1, args.steps, args.method, h, rtol, atol)
    if not args.yes:
        simulate.check_size(spec.n, args.t1, args.steps, args.method, h or args.t1 / args.steps / 10)
    x0 = simulate.initial_state(spec, cliargs.float_list(args.phi, "--phi"), cliargs.float_list(args.phidot, "--phidot"))
    rows = simulate.run(spec, x0, args.t1, args.steps, cliargs.float_list(args.u, "--u"), cliargs.params_of(args.param),
                        method=args.method, h=h, rtol=rtol, atol=atol, use_reference=args.reference, yes=args.yes)
    print(",".join(simulate.columns(spec.n)))
    for row in rows:
        print(",".join(_shortest(v) for v in row))
    return 0


def _shortest(v) -> str:
    """The shortest text that reads back as the same double (0.3, not 0.29999999999999999; 2, not 2.0)."""
    text = repr(float(v))
    return text[:-2] if text.endswith(".0") else text


def cmd_steady(args) -> int:
    """Equilibria and steady rotations of a spec, with their stability."""
    from ..analysis import steady

    spec = load_spec(args.spec)
    given = cliargs.params_of(args.param)
    params = run_values(spec, given)
    u = torques(spec, cliargs.float_list(args.u, "--u"))
    starts = [cliargs.floats(s, "--start", spec.n) for s in args.start or []]
    cliargs.one("--vary", args.vary, "steady continues its equilibria over one parameter")
    for option, value in (("--omega", args.omega), ("--no-rotations", args.no_rotations), ("--start", args.start),
                          ("--vary", args.vary)):
        if args.at and value:
            raise SpecError(option, "--at asks for the one equilibrium Newton finds from there; drop one of them")
    if args.omega and args.no_rotations:
        raise SpecError("--omega", "is the grid of the steady rotations, which --no-rotations leaves out; give one of them")
    if args.max_equilibria is not None and args.max_equilibria < 1:
        raise SpecError("--max-equilibria", f"{args.max_equilibria}: expected at least 1 (leave it out to print them all)")
    if args.digits is not None and not 1 <= args.digits <= 17:
        raise SpecError("--digits", f"{args.digits}: expected 1 to 17 (a double holds 17 significant digits)")
    at = cliargs.at_phi(args.at, spec.n) if args.at else None
    args.vary = (args.vary or [""])[0]
    try:
        omegas = steady.parse_range(args.omega) if args.omega else None
        vary = steady.parse_vary(args.vary, spec) if args.vary else None
        if vary:
            steady.check_vary_values(spec, given, vary)
        an, eqs, branches, omegas = steady.analyze(spec, params or None, u, omegas, starts, rotations=not args.no_rotations,
                                                   period=args.period, vary=vary, at=at)
    except steady.SteadyError as exc:
        what, _, why = str(exc).partition(": ")
        raise SpecError(what, why) from None
    said = ", ".join(f"{k} = {v:.12g}" for k, v in params.items())
    print(f"{spec.name}: n = {spec.n}" + (f", u = [{', '.join(f'{v:.12g}' for v in u)}]" if u else "")
          + (f", {said}" if said else ""))
    print(steady.report(an, eqs, branches, omegas, digits=args.digits, most=args.max_equilibria, at=at))
    return 0


def cmd_continue(args) -> int:
    """Branches of equilibria over a parameter's range, their special points, and with a second
    parameter the curves those points trace."""
    from ..analysis import branches, steady
    from ..analysis.continuation import ContinuationError

    spec = load_spec(args.spec)
    given = cliargs.params_of(args.param)
    if len(args.vary) > 2:
        raise SpecError("--vary", f"given {len(args.vary)} times: one parameter for the branches, a second for the "
                                  "curves of their special points")
    if args.max_steps < 1:
        raise SpecError("--max-steps", f"{args.max_steps}: expected at least 1")
    if not (math.isfinite(args.step) and 0 < args.step <= 0.5):
        raise SpecError("--step", f"{args.step:g}: expected a step in (0, 0.5] (a parameter's whole range counts as 1)")
    store = args.output.lower().rstrip("/").endswith(".zarr")
    if store:
        try:
            branches.check_store(args.output, args.force)
        except ContinuationError as exc:  # (the store's path: why)
            what, _, why = str(exc).partition(": ")
            raise SpecError(what, why) from None
    elif args.output:
        target(args.output, "", args.force, source=args.spec)  # checked before the work, written after it
    for s in args.start or []:
        if args.orbits and len(s.split(",")) not in (spec.n, 2 * spec.n):
            raise SpecError("--from", f"expected {spec.n} angle{'s' * (spec.n > 1)}, or as many angles and then as many "
                                      f"rates (a periodic orbit's start), got {len(s.split(','))} numbers")
    starts = [cliargs.floats(s, "--from", spec.n if not args.orbits or s.count(",") + 1 != 2 * spec.n else 2 * spec.n)
              for s in args.start or []]  # a driven model's periodic orbit: phi, or phi and phidot
    if args.mode and not (args.orbits or any(v.partition("=")[0].strip() == branches.ENERGY for v in args.vary)):
        raise SpecError("--mode", f"belongs to the nonlinear normal modes (--orbits, --vary {branches.ENERGY}=lo:hi)")
    if any(m < 1 for m in args.mode or []):
        raise SpecError("--mode", f"{min(args.mode)}: the modes are numbered from 1, the slowest")
    u = torques(spec, cliargs.float_list(args.u, "--u"))
    try:
        ranges = [branches.parse_range(v, spec) for v in args.vary]
        names = [r[0] for r in ranges]
        for name, lo, hi in ranges:  # every value of a range is a run's: a mass positive, an inertia possible
            if name not in (branches.RATE, branches.ENERGY):
                steady.check_vary_values(spec, given, (name, np.array([lo, hi])))
        lo = {name: lo for name, lo, _ in ranges
              if name not in given and name not in spec.values and name not in (branches.RATE, branches.ENERGY)}
        params = run_values(spec, {**lo, **given})  # a varied parameter without a value starts at its lo

        def progress(k, point) -> None:
            values = point[0] if isinstance(point, tuple) else (point.alpha,)
            cliargs.Heartbeat.say(f"{k} points, " + ", ".join(f"{n} = {v:.6g}" for n, v in zip(names, values)))

        res = branches.run(spec, params, u or None, ranges, starts, args.max_steps, args.step, args.period, progress,
                           orbits=args.orbits, modes=args.mode or ())
    except (ContinuationError, steady.SteadyError) as exc:
        what, _, why = str(exc).partition(": ")
        raise SpecError(what, why) from None
    print(branches.report(res))
    if store:
        branches.write_store(res, spec.n, args.output)
        print(f"wrote {args.output}")
    elif args.output:
        path = deliver(branches.csv_text(res, spec.n), args.output, "", args.force, args.spec)
        print(f"wrote {path}")
    return 0


def cmd_orbits(args) -> int:
    """Periodic orbits of an autonomous spec: nonlinear normal modes, steady rotations as orbits."""
    from ..analysis import orbits, steady

    spec = load_spec(args.spec)
    params = run_values(spec, cliargs.params_of(args.param))
    u = torques(spec, cliargs.float_list(args.u, "--u"))
    at = cliargs.floats(args.at, "--at", spec.n) if args.at else None
    cliargs.one("--vary", args.vary, "orbits continues over one parameter")
    args.vary = (args.vary or [""])[0]
    if args.omega and (args.energy or args.vary or args.mode or args.at):
        given = next(o for o, v in (("--energy", args.energy), ("--vary", args.vary), ("--mode", args.mode), ("--at", args.at)) if v)
        raise SpecError(given, "belongs to the nonlinear normal modes of an equilibrium; --omega asks for the steady "
                               "rotations instead: give one or the other")
    try:
        energies = steady.parse_range(args.energy, "--energy", "0.1:5:20") if args.energy else None
        if energies is not None and energies[0] <= 0:
            raise steady.SteadyError("--energy: the energies above the equilibrium's must be positive")
        vary = steady.parse_vary(args.vary, spec) if args.vary else None
        if vary:
            steady.check_vary_values(spec, cliargs.params_of(args.param), vary)
        omegas = None
        if args.omega:
            try:
                omegas = (steady.parse_range(args.omega, "--omega", "1:10:10") if ":" in args.omega
                          else np.array(cliargs.finite([float(args.omega)], "--omega")))
            except ValueError as exc:
                if isinstance(exc, (SpecError, steady.SteadyError)):
                    raise
                raise SpecError("--omega", "expected a rate W or a grid lo:hi:N, for example 1:10:10") from None
            if np.any(omegas == 0):
                raise SpecError("--omega", "0: a rotation at rate 0 is an equilibrium, whose period has no end, not a "
                                           "periodic orbit (`gyrochain steady` finds the equilibria); give rates other than 0")
    except steady.SteadyError as exc:
        what, _, why = str(exc).partition(": ")
        raise SpecError(what, why) from None
    modes = [int(m) for m in args.mode] if args.mode else None
    families = orbits.analyze(spec, params or None, u, at, energies, modes, vary, omegas)
    print(f"{spec.name}: n = {spec.n}" + (f", {params}" if params else ""))
    print(orbits.report(families))
    return 0


def cmd_sweep(args) -> int:
    """A grid (or random samples) of initial states and parameters, integrated in chunks into a Zarr store."""
    from ..ensembles import sweep as sw

    spec = load_spec(args.spec)  # the spec's own errors first, naming its fields
    measures = args.measure or ["final"]
    for option, value, belongs in (("--flip", args.flip, ("flip_time",)), ("--angles", args.angles, ("flip_time",)),
                                   ("--samples", args.samples, ("flip_time", "energy_error")),
                                   ("--lyap-interval", args.lyap_interval, ("lyapunov", "lyapunov_spectrum")),
                                   ("--lyap-d0", args.lyap_d0, ("lyapunov",))):
        if value is not None and not set(belongs) & set(measures):
            raise SpecError(option, f"belongs to --measure {' or '.join(belongs)}, which this sweep does not ask for")
    if args.chunk < 1:
        raise SpecError("--chunk", f"must be at least 1 point, got {args.chunk}")
    if args.workers is not None and args.workers < 1:
        raise SpecError("--workers", f"{args.workers} workers: give 1 or more (without --workers the sweep runs on threads here)")
    args.device = sw.resolve_device(args.device, args.method, bool(args.workers or args.scheduler or args.threads is not None))
    if args.device == "cuda":
        from .. import gpu

        if args.workers or args.scheduler or args.threads is not None:
            option = "--workers" if args.workers else "--scheduler" if args.scheduler else "--threads"
            raise SpecError(option, "is the CPU's; --device cuda runs every trajectory on this machine's GPU")
        if args.method not in gpu.device.GPU_METHODS:
            raise SpecError("--method", f"{args.method} has no GPU kernel; with --device cuda give rk4 or dop853")
        why = gpu.unavailable()
        if why:
            raise SpecError("--device", f"cuda: {why}")
    if args.threads is not None and (args.workers or args.scheduler):
        raise SpecError("--threads", "are this machine's; with --workers or --scheduler the Dask workers do the work")
    lyap = 0.1 if args.lyap_interval is None else args.lyap_interval
    if args.lyap_interval is not None and math.isfinite(lyap) and lyap > 0:
        if args.method != "dop853" and args.h > 0 and lyap < args.h:
            raise SpecError("--lyap-interval", f"{lyap:g} s is shorter than the step --h {args.h:g} s")
        if args.t1 / lyap > MAX_RENORMALISATIONS:
            raise SpecError("--lyap-interval", f"{lyap:g} s over --t1 {args.t1:g} s is {args.t1 / lyap:.3g} renormalisations "
                                               f"per trajectory (at most {MAX_RENORMALISATIONS:.0e}); a longer interval")
    d0 = 1e-8 if args.lyap_d0 is None else args.lyap_d0
    if not (math.isfinite(d0) and 0 < d0 < 1):
        raise SpecError("--lyap-d0", f"{d0:g}: the separation must be in (0, 1)")
    rtol, atol, note = sw.tolerances(measures, args.rtol, args.atol, d0)
    vary = [sw.parse_vary(v, args.random > 0) for v in args.vary or []]
    sweep = sw.Sweep(
        spec_text=spec.source, vary=vary, t1=args.t1, measures=measures, random=args.random, seed=args.seed,
        method=args.method, h=args.h, rtol=rtol, atol=atol, lyap_d0=d0, samples=1000 if args.samples is None else args.samples,
        flip=args.flip or "", angles=args.angles or "auto",
        lyap_interval=lyap, phi=cliargs.floats(args.phi, "--phi", spec.n) if args.phi else [],
        phidot=cliargs.floats(args.phidot, "--phidot", spec.n) if args.phidot else [],
        u=cliargs.floats(args.u, "--u", len(spec.controls)) if args.u else [], params=cliargs.params_of(args.param), chunk=args.chunk,
    )
    plan = sw.Plan(sweep)
    if {"flip_time", "energy_error"} & set(measures):  # a chunk's trajectories are held at every sample
        per_chunk = int(np.prod(plan.shape[1:])) * plan.rows * (sweep.samples + 1) * 2 * spec.n * 8
        if per_chunk > MAX_CHUNK_BYTES:
            raise SpecError("--samples", f"{sweep.samples} samples of {plan.rows * int(np.prod(plan.shape[1:]))} trajectories "
                                         f"a chunk hold {per_chunk / 2**30:.3g} GiB (at most {MAX_CHUNK_BYTES >> 30} GiB per "
                                         "thread); fewer --samples or a smaller --chunk")
    if args.threads is not None and args.threads < 1:
        raise SpecError("--threads", "must be at least 1")
    if args.workers and args.scheduler:
        raise SpecError("--workers", "give --workers (a local Dask cluster) or --scheduler (an existing one), not both")
    sw.check_store(Path(args.output), plan)
    if args.scheduler:
        sw.reachable(args.scheduler)  # before the store is made: a wrong address leaves nothing behind
    if note:  # once the sweep is known to run
        print(note, file=sys.stderr)
    t0 = time.perf_counter()
    where = ("the GPU" if args.device == "cuda" else f"the Dask scheduler {args.scheduler}" if args.scheduler else f"a local Dask cluster of {args.workers} worker processes"
             if args.workers else f"{args.threads or os.cpu_count()} thread(s)")
    points = int(np.prod(plan.shape))
    print(f"sweep of {plan.spec.name}: {points} point{'s' * (points != 1)} in {plan.n_chunks} chunk{'s' * (plan.n_chunks != 1)} "
          f"on {where} -> {args.output}", file=sys.stderr)
    counts = sw.run(sweep, args.output, threads=args.threads, workers=args.workers or 0, scheduler=args.scheduler,
                    progress=not args.quiet, plan=plan, device=args.device)
    done = counts["written"]
    print(f"{done} chunk{'s' if done != 1 else ''} computed, {counts['skipped']} already done, in "
          f"{time.perf_counter() - t0:.1f} s", file=sys.stderr)
    if "lyapunov_spectrum" in sweep.measures:
        print(sw.spectrum_summary(args.output, plan), file=sys.stderr)
    return 0


def cmd_plot(args) -> int:
    """A heat map (two varied quantities) or a curve (one) of a sweep store."""
    from ..view import plot

    if args.store.lower().endswith(".csv") or _continue_store(args.store):  # continue's branches: a diagram
        from ..view import diagram

        if args.measure or args.cmap or args.log:
            given = next(o for o, v in (("--measure", args.measure), ("--cmap", args.cmap), ("--log", args.log)) if v)
            raise SpecError(given, "belongs to a sweep's store; the diagram of continue's file takes --component")
        path = diagram.plot(args.store, args.output, component=args.component, dpi=args.dpi)
        print(f"wrote {path}", file=sys.stderr)
        return 0
    path = plot.store(args.store, args.output, measure=args.measure, component=args.component, cmap=args.cmap,
                      log=args.log, dpi=args.dpi, note=lambda line: print(line, file=sys.stderr))
    print(f"wrote {path}", file=sys.stderr)
    return 0


def _continue_store(path: str) -> bool:
    from ..analysis import branches

    return Path(path).is_dir() and branches.is_store(path)


def cmd_animate(args) -> int:
    """The motion of a spec (or of a sweep's point) as a GIF, MP4, PNG still or an offline HTML viewer."""
    from ..view import animate

    t_start = time.perf_counter()
    animate.Output(args.output, force=args.force)  # the extension and an existing file first
    if args.frame is not None and args.t1 is not None:
        raise SpecError("--t1", "a still (--frame T) is the motion at one time and has no range [0, t1]; drop --t1")
    size = cliargs.size(args.size)
    view = cliargs.floats(args.view, "--view", 2) if args.view else None
    done = animate.render(
        args.spec, args.output, phi=cliargs.float_list(args.phi, "--phi"), phidot=cliargs.float_list(args.phidot, "--phidot"),
        u=cliargs.float_list(args.u, "--u"), params=cliargs.params_of(args.param), t1=args.t1, fps=args.fps, frame=args.frame,
        at=args.at, trajectory=args.trajectory, size=size, view=view, trace=args.trace, follow=args.follow,
        rtol=args.rtol, force=args.force, yes=args.yes)
    if done.get("note"):
        print(done["note"], file=sys.stderr)
    if not args.quiet:
        times = done["times"]
        span = f"t = {times[0]:g} s" if len(times) == 1 else f"{len(times)} frames over [{times[0]:g}, {times[-1]:g}] s"
        print(f"wrote {done['path']}: {span}, {done['bytes'] // 1024} KiB, in {time.perf_counter() - t_start:.1f} s",
              file=sys.stderr)
    return 0


def cmd_examples(args) -> int:
    """The example specs and robot descriptions that come with the package."""
    from . import starter

    return starter.examples_command(args.action, getattr(args, "names", None), getattr(args, "name", None),
                                    Path(getattr(args, "output", ".")), getattr(args, "force", False), _prog())


def cmd_new(args) -> int:
    """A new commented spec from a short description."""
    from . import starter

    text = starter.new_spec(args.kind, args.n, args.name, rotor=args.rotor, control=args.control, driven=args.driven,
                            mass=args.mass, length=args.length)
    path = deliver(text, args.output, text.split('name = "', 1)[1].split('"', 1)[0] + ".toml", args.force)
    if path is not None:
        print(f"wrote {path}: edit it, then `{_prog()} check {path}` and `{_prog()} generate {path}`")
    return 0


def cmd_import(args) -> int:
    """A robot description (URDF or MJCF) as a spec: the chain from the base to the tip."""
    from ..robots import exchange

    if args.list:
        given = [opt for opt, value in (("-o", args.output), ("--tip", args.tip), ("--lock", args.lock),
                                        ("--name", args.name), ("--g", args.g), ("--no-control", args.no_control),
                                        ("--force", args.force)) if value]
        if given:
            raise SpecError(f"import --list {given[0]}", "--list prints the tree and writes nothing: give "
                            f"{given[0]} without --list")
        print(exchange.tree_text(args.description, args.base))
        return 0
    text, lines = exchange.import_text(args.description, args.base, args.tip, args.lock, args.name or None,
                                       controls=not args.no_control, g=args.g)
    path = deliver(text, args.output, text.split('\nname = "', 1)[1].split('"', 1)[0] + ".toml", args.force, args.description)
    if path is not None:
        print("\n".join(lines + [f"wrote {path}: `{_prog()} generate {path}` derives its model"]))
    return 0


def cmd_export(args) -> int:
    """The spec as a robot description: URDF or MJCF."""
    from ..robots import exchange

    spec = load_spec(args.spec)
    text, lines = exchange.export_text(spec, args.spec, args.to, run_values(spec, cliargs.params_of(args.param)))
    path = deliver(text, args.output, spec.name + exchange.FORMATS[args.to][1], args.force, args.spec)
    if path is not None:
        print("\n".join(lines + [f"wrote {path}"]))
    return 0


def cmd_fmu(args) -> int:
    """The model as a Functional Mock-up Unit."""
    from ..fmi import fmu

    spec = load_spec(args.spec)
    asked = fmu.Asked(tuple(k.strip() for k in args.kind.split(",") if k.strip()), args.fmi, args.real,
                      tuple(args.input or ()), tuple(args.add_output or ()))
    fmu.check(spec, asked)  # the options first, then the file, then the build
    if args.output != "-":
        target(args.output, spec.name + ".fmu", args.force, args.spec)
    data, lines = fmu.make(spec, args.spec, run_values(spec, cliargs.params_of(args.param)), asked)
    path = deliver(data, args.output, spec.name + ".fmu", args.force, args.spec)
    print("\n".join(lines + [f"wrote {path}"]))
    return 0


def _prog() -> str:
    """The command as the user typed it: the console script, or python -m gyrochain."""
    from .. import DISTRIBUTION

    return DISTRIBUTION if Path(sys.argv[0]).name == DISTRIBUTION else "python -m gyrochain"


def main(argv=None) -> int:
    from .. import DISTRIBUTION, __version__

    from .starter import KINDS

    ap = parsers.build(_prog(), __doc__.splitlines()[0], f"{DISTRIBUTION} {__version__}", KINDS)
    sub = next(a for a in ap._actions if isinstance(a, argparse._SubParsersAction))
    words = list(sys.argv[1:] if argv is None else argv)
    debug = "--debug" in words or bool(os.environ.get(f"{DISTRIBUTION.upper()}_TRACEBACK"))
    words = [w for w in words if w != "--debug"]  # anywhere on the line: the traceback of an internal error
    args, extra = ap.parse_known_args(cliargs.join_negative(words, cliargs.valued_options(ap)))
    if extra:  # said by the command's own parser, with the nearest option it has
        sub.choices[args.cmd].error(cliargs.unrecognized(extra, sub.choices[args.cmd]))
    command = {"generate": cmd_generate, "check": cmd_check, "simulate": cmd_simulate, "steady": cmd_steady,
               "continue": cmd_continue, "orbits": cmd_orbits, "sweep": cmd_sweep, "plot": cmd_plot, "animate": cmd_animate,
               "examples": cmd_examples, "new": cmd_new, "import": cmd_import,
               "export": cmd_export, "fmu": cmd_fmu, "identify": cmd_identify, "excite": cmd_excite}[args.cmd]
    beat = cliargs.Heartbeat(args.cmd) if args.cmd in ("simulate", "steady", "continue", "orbits", "animate", "identify", "excite",
                                                       "fmu") else None
    stdout = sys.stdout
    if beat is not None and beat.running:
        sys.stdout = cliargs.ClearsFirst(stdout, beat)  # the results' first line ends the heartbeat's
    try:
        # numpy's floating-point warnings are not the user's words: every result is checked for
        # finiteness where it matters, and a failure is one line
        with np.errstate(all="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            return command(args)
    except SpecError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except BrokenPipeError:  # `simulate ... | head`: the reader has all it wanted; no traceback
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())  # Python's flush at exit must not fail again
        return 0
    except OSError as exc:  # the file system: a folder that cannot be made, a disk full, no permission
        if _ours(exc):  # a file of the package itself (a template, a kernel): not the user's doing
            return _internal(exc, debug)
        where = users_path(exc.filename) if exc.filename else args.cmd  # a file the user named, else the command
        print(f"error: {where}: {exc.strerror or exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except KeyboardInterrupt:  # the stack has unwound: every clean-up ran, nothing half-written is left
        return _interrupted()
    except Exception as exc:  # noqa: BLE001  (a bug of ours: one line, and where to report it)
        if caused_by_interrupt(exc):  # Ctrl-C that Python wrapped (in a class being made, say)
            return _interrupted()
        return _internal(exc, debug)
    finally:
        sys.stdout = stdout
        if beat is not None:
            beat.stop()


def _exit_if_held(code: int) -> None:
    """End the process now if another thread is still running: a worker of a sweep's pool inside
    a C call, which the interpreter would wait for at exit, or an abandoned C call
    (calls.interruptible), which must not run on while the interpreter is torn down."""
    import threading

    if any(t.is_alive() for t in threading.enumerate() if t is not threading.main_thread()):
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(code)


def _interrupted() -> int:
    print("error: interrupted", file=sys.stderr)
    _exit_if_held(130)
    return 130


# .NAME.tmp-XXXX (.STEM.tmp-PID.EXT, .NAME.tmp): where a command writes NAME before renaming it
TEMPORARY = re.compile(r"^\.(.+?)\.tmp(?:-[^./]*)?(\.[^/]*)?$")


def users_path(filename) -> str:
    """The file or folder the user named for a path of ours beside it: a temporary (.NAME.tmp-…,
    or a file inside one) is said as NAME, the output it stands for."""
    parts = Path(os.fsdecode(filename)).parts
    for i, part in enumerate(parts):
        m = TEMPORARY.match(part)
        if m:
            return str(Path(*parts[:i], m[1] + (m[2] or "")))
    return os.fsdecode(filename)


def _ours(exc: OSError) -> bool:
    """Whether a file-system error is about the package's own files (a template or kernel missing
    from an installation), not a file or folder the user named."""
    if type(exc).__module__.split(".")[0] == "jinja2":  # TemplateNotFound is an OSError
        return True
    if not exc.filename:
        return False
    package = Path(__file__).resolve().parent.parent  # the package, gyrochain/
    return Path(os.path.abspath(exc.filename)).is_relative_to(package)


def _internal(exc: BaseException, debug: bool) -> int:
    """A bug of ours, or a broken installation: one line that says so, with the version and what
    to do; the traceback with --debug or $GYROCHAIN_TRACEBACK."""
    from .. import DISTRIBUTION, __version__

    what = " ".join(str(exc).split()) or "(no message)"
    print(f"error: internal error in {DISTRIBUTION} {__version__}: {type(exc).__name__}: {what} — please report it "
          f"with the command (--debug or {DISTRIBUTION.upper()}_TRACEBACK=1 prints the traceback; \"Reporting a problem\" "
          f"in the documentation says what else helps)", file=sys.stderr)
    if debug:
        raise exc
    return EXIT_INTERNAL
