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
import sys
import time
import warnings
from pathlib import Path

import numpy as np

from . import caused_by_interrupt, cliargs
from .files import deliver, target
from .physical import run_values
from .simulate import torques
from .spec import SpecError, load_spec

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
    from . import generate

    t0 = time.perf_counter()
    spec = load_spec(args.spec)
    if args.output is not None and not args.output.strip():
        raise SpecError("-o", "is empty; name a folder (default generated/<name>)")
    target = Path(args.output) if args.output is not None else Path("generated") / spec.name
    generate.check(spec, target, args.force, Path(args.spec), args.derivative_form)  # before the first line: one line
    if not args.quiet:
        print(f"generating {spec.name} (n = {spec.n}) from {args.spec}", file=sys.stderr)
    result = generate.run(spec, target, Path(args.spec).name, build=not args.no_build, force=args.force,
                          qdd_form=args.qdd_form, der_form=args.derivative_form, progress=_Progress(args.quiet),
                          real=args.real, source=Path(args.spec), regressor=args.regressor)
    for line in generate.report(result):
        print(line)
    print(f"done in {time.perf_counter() - t0:.2f} s")
    return 0


def cmd_identify(args) -> int:
    from . import identify
    from .physical import run_values

    spec = load_spec(args.spec)
    values = run_values(spec, cliargs.params_of(args.param))
    how = identify.Filter(args.filter, args.cutoff, args.window, args.order)
    identify.run(spec, args.data, values, args.output, args.force, args.validate, args.plot, how, args.physical)
    return 0


def cmd_excite(args) -> int:
    from . import excite
    from .physical import run_values

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
    from . import simulate

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
        print(",".join(f"{v:.17g}" for v in row))
    return 0


def cmd_steady(args) -> int:
    """Equilibria and steady rotations of a spec, with their stability."""
    from . import steady

    spec = load_spec(args.spec)
    given = cliargs.params_of(args.param)
    params = run_values(spec, given)
    u = torques(spec, cliargs.float_list(args.u, "--u"))
    starts = [cliargs.floats(s, "--start", spec.n) for s in args.start or []]
    cliargs.one("--vary", args.vary, "steady continues its equilibria over one parameter")
    if args.omega and args.no_rotations:
        raise SpecError("--omega", "is the grid of the steady rotations, which --no-rotations leaves out; give one of them")
    args.vary = (args.vary or [""])[0]
    try:
        omegas = steady.parse_range(args.omega) if args.omega else None
        vary = steady.parse_vary(args.vary, spec) if args.vary else None
        if vary:
            steady.check_vary_values(spec, given, vary)
        an, eqs, branches, omegas = steady.analyze(spec, params or None, u, omegas, starts, rotations=not args.no_rotations,
                                                   period=args.period, vary=vary)
    except steady.SteadyError as exc:
        what, _, why = str(exc).partition(": ")
        raise SpecError(what, why) from None
    print(f"{spec.name}: n = {spec.n}" + (f", u = {u}" if u else "") + (f", {params}" if params else ""))
    print(steady.report(an, eqs, branches, omegas))
    return 0


def cmd_orbits(args) -> int:
    """Periodic orbits of an autonomous spec: nonlinear normal modes, steady rotations as orbits."""
    from . import orbits, steady

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
                raise SpecError("--omega", "expected a rate W or a grid a:b:N, for example 1:10:10") from None
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
    from . import sweep as sw

    spec = load_spec(args.spec)  # the spec's own errors first, naming its fields
    measures = args.measure or ["final"]
    for option, value, belongs in (("--flip", args.flip, ("flip_time",)), ("--angles", args.angles, ("flip_time",)),
                                   ("--samples", args.samples, ("flip_time", "energy_error")),
                                   ("--lyap-interval", args.lyap_interval, ("lyapunov", "lyapunov_spectrum"))):
        if value is not None and not set(belongs) & set(measures):
            raise SpecError(option, f"belongs to --measure {' or '.join(belongs)}, which this sweep does not ask for")
    if args.chunk < 1:
        raise SpecError("--chunk", f"must be at least 1 point, got {args.chunk}")
    if args.workers is not None and args.workers < 1:
        raise SpecError("--workers", f"{args.workers} workers: give 1 or more (without --workers the sweep runs on threads here)")
    if args.threads is not None and (args.workers or args.scheduler):
        raise SpecError("--threads", "are this machine's; with --workers or --scheduler the Dask workers do the work")
    lyap = 0.1 if args.lyap_interval is None else args.lyap_interval
    if args.lyap_interval is not None and math.isfinite(lyap) and lyap > 0:
        if args.method != "dop853" and args.h > 0 and lyap < args.h:
            raise SpecError("--lyap-interval", f"{lyap:g} s is shorter than the step --h {args.h:g} s")
        if args.t1 / lyap > MAX_RENORMALISATIONS:
            raise SpecError("--lyap-interval", f"{lyap:g} s over --t1 {args.t1:g} s is {args.t1 / lyap:.3g} renormalisations "
                                               f"per trajectory (at most {MAX_RENORMALISATIONS:.0e}); a longer interval")
    vary = [sw.parse_vary(v, args.random > 0) for v in args.vary or []]
    sweep = sw.Sweep(
        spec_text=spec.source, vary=vary, t1=args.t1, measures=measures, random=args.random, seed=args.seed,
        method=args.method, h=args.h, rtol=args.rtol, atol=args.atol, samples=1000 if args.samples is None else args.samples,
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
    t0 = time.perf_counter()
    where = (f"the Dask scheduler {args.scheduler}" if args.scheduler else f"a local Dask cluster of {args.workers} worker processes"
             if args.workers else f"{args.threads or os.cpu_count()} thread(s)")
    print(f"sweep of {plan.spec.name}: {int(np.prod(plan.shape))} points in {plan.n_chunks} chunks on {where} -> {args.output}",
          file=sys.stderr)
    counts = sw.run(sweep, args.output, threads=args.threads, workers=args.workers or 0, scheduler=args.scheduler,
                    progress=not args.quiet, plan=plan)
    print(f"{counts['written']} chunks computed, {counts['skipped']} already done, in {time.perf_counter() - t0:.1f} s",
          file=sys.stderr)
    if "lyapunov_spectrum" in sweep.measures:
        print(sw.spectrum_summary(args.output, plan), file=sys.stderr)
    return 0


def cmd_plot(args) -> int:
    """A heat map (two varied quantities) or a curve (one) of a sweep store."""
    from . import plot

    path = plot.store(args.store, args.output, measure=args.measure, component=args.component, cmap=args.cmap,
                      log=args.log, dpi=args.dpi, note=lambda line: print(line, file=sys.stderr))
    print(f"wrote {path}", file=sys.stderr)
    return 0


def cmd_animate(args) -> int:
    """The motion of a spec (or of a sweep's point) as a GIF, MP4, PNG still or an offline HTML viewer."""
    from . import animate

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
    """A robot description (URDF) as a spec: the chain from the base to the tip."""
    from . import exchange

    text, lines = exchange.import_text(args.description, args.base, args.tip, args.lock, args.name or None,
                                       controls=not args.no_control, g=args.g)
    path = deliver(text, args.output, text.split('\nname = "', 1)[1].split('"', 1)[0] + ".toml", args.force, args.description)
    if path is not None:
        print("\n".join(lines + [f"wrote {path}: `{_prog()} generate {path}` derives its model"]))
    return 0


def cmd_export(args) -> int:
    """The spec as a robot description: URDF or MJCF."""
    from . import exchange

    spec = load_spec(args.spec)
    text, lines = exchange.export_text(spec, args.spec, args.to, run_values(spec, cliargs.params_of(args.param)))
    path = deliver(text, args.output, spec.name + exchange.FORMATS[args.to][1], args.force, args.spec)
    if path is not None:
        print("\n".join(lines + [f"wrote {path}"]))
    return 0


def cmd_fmu(args) -> int:
    """The model as a Functional Mock-up Unit."""
    from . import fmu

    spec = load_spec(args.spec)
    asked = fmu.Asked(tuple(k.strip() for k in args.kind.split(",") if k.strip()), args.fmi, args.real,
                      tuple(dict.fromkeys(args.input or ())), tuple(dict.fromkeys(args.add_output or ())))
    fmu.check(spec, asked)  # the options first, then the file, then the build
    if args.output != "-":
        target(args.output, spec.name + ".fmu", args.force, args.spec)
    data, lines = fmu.make(spec, args.spec, run_values(spec, cliargs.params_of(args.param)), asked)
    path = deliver(data, args.output, spec.name + ".fmu", args.force, args.spec)
    print("\n".join(lines + [f"wrote {path}"]))
    return 0


class _Parser(argparse.ArgumentParser):
    """argparse with one line for a mistake: ``error: <what> (see <prog> --help)``, exit 2."""

    def error(self, message):
        print(f"error: {cliargs.plain(message)} (see {self.prog} --help)", file=sys.stderr)
        raise SystemExit(EXIT_BAD_INPUT)


def _prog() -> str:
    """The command as the user typed it: the console script, or python -m gyrochain."""
    from . import DISTRIBUTION

    return DISTRIBUTION if Path(sys.argv[0]).name == DISTRIBUTION else "python -m gyrochain"


def main(argv=None) -> int:
    from . import DISTRIBUTION, __version__

    ap = _Parser(prog=_prog(), description=__doc__.splitlines()[0])
    ap.add_argument("--version", action="version", version=f"{DISTRIBUTION} {__version__}")
    ap.add_argument("--debug", action="store_true", help="on an internal error, print the traceback (anywhere on the line)")
    sub = ap.add_subparsers(dest="cmd", required=True)
    g = sub.add_parser("generate", help="derive and emit C, Python and LaTeX for a spec")
    g.add_argument("spec")
    g.add_argument("-o", "--output", help="output folder (default generated/<name>)")
    g.add_argument("--no-build", action="store_true", help="do not compile the cffi extension")
    g.add_argument("--force", action="store_true", help="write into an output folder gyrochain did not write (its "
                   "other files are kept; files of the same names are replaced)")
    g.add_argument("-q", "--quiet", action="store_true", help="no progress lines")
    g.add_argument(
        "--qdd-form", choices=("auto", "composite", "articulated"), default="auto",
        help="how NAME_qdd solves for phi'': auto (fewer operations, the default), composite bodies + LDL^T, or articulated bodies",
    )
    g.add_argument(
        "--derivative-form", choices=("auto", "forward", "world"), default="auto",
        help="how NAME_qdd_derivatives is computed: auto (fewer operations, the default), forward mode over the "
             "articulated recursion, or inverse dynamics differentiated in frame 0 (fixed base, constant rotors, no body loads)",
    )
    g.add_argument("--real", choices=("double", "float"), default="double",
                   help="the floating type of the C: double (the default) or float, for a single-precision FPU "
                        "(the Python mirror stays in double)")
    g.add_argument("--regressor", action="store_true", help="also NAME_regressor (u = Y pi + tau0), the energy's, "
                   "the base parameters and NAME_base_regressor (parameter identification)")
    c = sub.add_parser("check", help="validate a spec without generating")
    c.add_argument("spec")
    s = sub.add_parser("simulate", help="integrate a spec with the emitted C (CSV to stdout: t, phi, phidot, energy)")
    s.add_argument("spec")
    s.add_argument("--t1", type=float, default=1.0, help="end time (s)")
    s.add_argument("--steps", type=int, default=100, help="output intervals over [0, t1]")
    s.add_argument("--phi", default="", help="initial angles (default: the spec's [initial] or 0)")
    s.add_argument("--phidot", default="", help="initial rates")
    s.add_argument("--u", default="", help="constant torques of the controlled joints (default 0)")
    s.add_argument("--param", action="append", help="name=value for a symbolic parameter (default: the spec's [values])")
    s.add_argument("--method", default="dop853", help="dop853 (adaptive, dense output; the default) | rk4 | gauss2 | "
                   "gauss2_symplectic (fixed step --h)")
    s.add_argument("--h", type=float, default=None, help="step of rk4/gauss2 (default: a tenth of an output interval)")
    s.add_argument("--rtol", type=float, default=None, help="relative tolerance of dop853 (default 1e-10)")
    s.add_argument("--atol", type=float, default=None, help="absolute tolerance of dop853 (default 1e-12)")
    s.add_argument("--yes", action="store_true", help="run past the limits (200 MiB of CSV, 1e8 fixed steps, an RK4 "
                   "step beyond stability) instead of stopping")
    s.add_argument("--reference", action="store_true", help="integrate the independent numpy model with scipy's DOP853 "
                   "instead (slow; a cross-check)")
    st = sub.add_parser("steady", help="equilibria and steady rotations, with their stability (of a model driven "
                        "periodically in t: its equilibria for all t, by Floquet multipliers)")
    st.add_argument("spec")
    st.add_argument("--u", default="", help="constant torques of the controlled joints (default 0)")
    st.add_argument("--param", action="append", help="name=value for a symbolic parameter")
    st.add_argument("--omega", default="", help="a:b:N grid of the rotation rate phidot1 (default: from the equilibria)")
    st.add_argument("--start", action="append", help="an extra Newton start phi1,...,phin")
    st.add_argument("--no-rotations", action="store_true", help="equilibria only")
    st.add_argument("--period", type=float, default=None, help="the period of a model that depends on t "
                    "(default: from the spec's sines and cosines of t)")
    st.add_argument("--vary", action="append", help="name=a:b:N: a model that depends on t, its equilibria continued over a "
                    "parameter, where the Floquet verdict changes (one parameter)")
    ob = sub.add_parser("orbits", help="periodic orbits of an autonomous spec (nonlinear normal modes, steady rotations) "
                        "by shooting, with their Floquet multipliers")
    ob.add_argument("spec")
    ob.add_argument("--at", default="", help="the stable equilibrium phi1,...,phin (default: the one of least energy)")
    ob.add_argument("--energy", default="", help="a:b:N energies above the equilibrium's (J; default: 20 up to half the "
                    "lowest barrier)")
    ob.add_argument("--mode", action="append", type=int, help="the linear mode to continue, 1 = the slowest (repeatable; "
                    "default all)")
    ob.add_argument("--vary", action="append", help="name=a:b:N: continue over a parameter at the first energy instead "
                    "(one parameter)")
    ob.add_argument("--omega", default="", help="W or a:b:N: the steady rotations phidot1 = W as periodic orbits "
                    "(phi1 cyclic)")
    ob.add_argument("--u", default="", help="constant torques of the controlled joints (default 0)")
    ob.add_argument("--param", action="append", help="name=value for a symbolic parameter")
    sw = sub.add_parser("sweep", help="integrate a grid or random samples of initial states/parameters into a Zarr store")
    sw.add_argument("spec")
    sw.add_argument("--vary", action="append", help="name=lo:hi:count (grid; name phiK, phidotK or a parameter) or name=lo:hi with --random")
    sw.add_argument("--random", type=int, default=0, help="that many uniform random samples in the box of the --vary ranges")
    sw.add_argument("--seed", type=int, default=0, help="seed of --random")
    sw.add_argument("--t1", type=float, default=10.0, help="end time of every trajectory (s)")
    sw.add_argument("--measure", action="append", help="final | flip_time | energy_error | lyapunov | lyapunov_spectrum | "
                    "floquet (repeatable; default final)")
    sw.add_argument("--method", default="dop853", help="rk4 | dop853 | gauss2")
    sw.add_argument("--h", type=float, default=0.0, help="step of rk4/gauss2 (first step of dop853, 0: automatic)")
    sw.add_argument("--rtol", type=float, default=1e-8, help="relative tolerance of dop853")
    sw.add_argument("--atol", type=float, default=1e-10, help="absolute tolerance of dop853")
    sw.add_argument("--samples", type=int, default=None, help="output intervals over [0, t1] for flip_time and energy_error "
                    "(default 1000)")
    sw.add_argument("--flip", default=None, help="the angle of flip_time (phiK: link or joint K; default: the first of any)")
    sw.add_argument("--angles", default=None, help="flip_time watches the links' absolute angles phi1+..+phiK (absolute; "
                                                     "planar chains), the joint angles (relative), or auto: absolute where "
                                                     "the chain is planar")
    sw.add_argument("--lyap-interval", type=float, default=None, help="renormalisation interval of the Lyapunov exponent "
                    "and of lyapunov_spectrum's QR (s; default 0.1)")
    sw.add_argument("--phi", default="", help="the coordinates that are not varied (default: the spec's initial or 0)")
    sw.add_argument("--phidot", default="", help="the rates that are not varied")
    sw.add_argument("--u", default="", help="constant torques of the controlled joints")
    sw.add_argument("--param", action="append", help="name=value for a symbolic parameter that is not varied")
    sw.add_argument("--chunk", type=int, default=1024, help="points per chunk (whole rows of the grid)")
    sw.add_argument("--threads", type=int, default=None, help="threads on this machine (default: one per core)")
    sw.add_argument("--workers", type=int, default=None, help="start a local Dask cluster of N worker processes")
    sw.add_argument("--scheduler", default="", help="address of an existing Dask scheduler (tcp://host:8786)")
    sw.add_argument("-o", "--output", required=True, help="the Zarr store (created, or resumed if it is this sweep's)")
    sw.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    pl = sub.add_parser("plot", help="a heat map or a curve of a sweep store")
    pl.add_argument("store")
    pl.add_argument("-o", "--output", required=True, help="the image (png, pdf, svg)")
    pl.add_argument("--measure", default="", help="which array (default: the sweep's first measure)")
    pl.add_argument("--component", default="0", help="the state component of 'final': phiK, phidotK or its 0-based index")
    pl.add_argument("--cmap", default="", help="the colour map of a map (default viridis; points without a value are grey)")
    pl.add_argument("--log", action="store_true", help="a logarithmic scale: of the colours of a map, of the values of a curve")
    pl.add_argument("--dpi", type=int, default=150, help="resolution of a PNG (dots per inch)")
    an = sub.add_parser("animate", help="the motion as a GIF, MP4, PNG still (--frame) or an offline HTML viewer")
    an.add_argument("spec", help="a spec file, or a sweep's store (with --at)")
    an.add_argument("-o", "--output", required=True, help="FILE.gif, FILE.mp4 (needs ffmpeg), FILE.html or FILE.png (with --frame)")
    an.add_argument("--phi", default="", help="initial angles (default: the spec's [initial] or 0)")
    an.add_argument("--phidot", default="", help="initial rates")
    an.add_argument("--u", default="", help="constant torques of the controlled joints (default 0)")
    an.add_argument("--param", action="append", help="name=value for a symbolic parameter")
    an.add_argument("--t1", type=float, default=None, help="end time (s; default 10, or the sweep's)")
    an.add_argument("--fps", type=float, default=25.0, help="frames per second of the animation and of its time")
    an.add_argument("--frame", type=float, default=None, help="one still at this time (s)")
    an.add_argument("--at", default="", help="the point of a sweep store: name=value,... (grid) or an index (--random)")
    an.add_argument("--trajectory", default="", help="a saved trajectory (CSV: t, phi1.., [phidot1..]) instead of integrating")
    an.add_argument("--size", default="480x480", help="WIDTHxHEIGHT of a GIF, MP4 or PNG")
    an.add_argument("--view", default="", help="azimuth,elevation of the camera in degrees (default: fitted to the motion)")
    an.add_argument("--trace", type=float, default=2.0, help="seconds of the tip's trace")
    an.add_argument("--follow", action=argparse.BooleanOptionalAction, default=None,
                    help="keep the platform's O1 in the middle of the view (default: where O1 moves farther than the "
                         "chain reaches; --no-follow for the world view)")
    an.add_argument("--rtol", type=float, default=1e-10, help="relative tolerance of DOP853")
    an.add_argument("--force", action="store_true", help="replace an existing file animate did not write")
    an.add_argument("--yes", action="store_true", help=f"draw more than {10_000} frames instead of stopping")
    an.add_argument("-q", "--quiet", action="store_true")
    words = list(sys.argv[1:] if argv is None else argv)
    debug = "--debug" in words or bool(os.environ.get(f"{DISTRIBUTION.upper()}_TRACEBACK"))
    words = [w for w in words if w != "--debug"]  # anywhere on the line: the traceback of an internal error
    ex = sub.add_parser("examples", help="list the example specs that come with the package, print one, or copy them "
                        "into a folder to start from",
                        description="Without an action: list the example specs (name, number of bodies, what it is).")
    exs = ex.add_subparsers(dest="action")
    exc = exs.add_parser("copy", help="copy example specs into a folder (NAME.toml; an existing file only with --force)")
    exc.add_argument("names", nargs="+", metavar="NAME", help="example names (see gyrochain examples), or all")
    exc.add_argument("-o", "--output", default=".", help="the folder (default: this one)")
    exc.add_argument("--force", action="store_true", help="replace files of the same name")
    exw = exs.add_parser("show", help="print an example spec")
    exw.add_argument("name")
    nw = sub.add_parser("new", help="write a new commented spec to start from: a pendulum, a planar or spatial chain, "
                        "with rotors, motors or a vibrating pivot")
    from .starter import KINDS

    nw.add_argument("kind", choices=list(KINDS), help="; ".join(f"{k}: {v[1]}" for k, v in KINDS.items()))
    nw.add_argument("--n", type=int, default=None, help="number of links of a chain")
    nw.add_argument("--name", default="", help="the model's name, a C identifier (default: from the kind)")
    nw.add_argument("--rotor", action="store_true", help="a spinning wheel in the last link (a gyrostat)")
    nw.add_argument("--control", action="store_true", help="a motor torque in every joint (inputs u)")
    nw.add_argument("--driven", action="store_true", help="the pivot vibrates vertically, a cos(w t) (parameters a, w)")
    nw.add_argument("--mass", type=float, default=1.0, help="mass of each rod (kg)")
    nw.add_argument("--length", type=float, default=1.0, help="length of each rod (m)")
    nw.add_argument("-o", "--output", default="", help="the file (default NAME.toml here; - for standard output)")
    nw.add_argument("--force", action="store_true", help="replace an existing file")
    cliargs.add_exchange(sub)
    cliargs.add_identify(sub)
    args, extra = ap.parse_known_args(cliargs.join_negative(words, cliargs.valued_options(ap)))
    if extra:  # said by the command's own parser, with the nearest option it has
        sub.choices[args.cmd].error(cliargs.unrecognized(extra, sub.choices[args.cmd]))
    command = {"generate": cmd_generate, "check": cmd_check, "simulate": cmd_simulate, "steady": cmd_steady,
               "orbits": cmd_orbits, "sweep": cmd_sweep, "plot": cmd_plot, "animate": cmd_animate,
               "examples": cmd_examples, "new": cmd_new, "import": cmd_import,
               "export": cmd_export, "fmu": cmd_fmu, "identify": cmd_identify, "excite": cmd_excite}[args.cmd]
    beat = cliargs.Heartbeat(args.cmd) if args.cmd in ("simulate", "steady", "orbits", "animate", "identify", "excite") else None
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
        where = exc.filename or args.cmd  # a file the user named, else the command that met it
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
    (build.interruptible), which must not run on while the interpreter is torn down."""
    import threading

    if any(t.is_alive() for t in threading.enumerate() if t is not threading.main_thread()):
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(code)


def _interrupted() -> int:
    print("error: interrupted", file=sys.stderr)
    _exit_if_held(130)
    return 130


def _ours(exc: OSError) -> bool:
    """Whether a file-system error is about the package's own files (a template or kernel missing
    from an installation), not a file or folder the user named."""
    if type(exc).__module__.split(".")[0] == "jinja2":  # TemplateNotFound is an OSError
        return True
    if not exc.filename:
        return False
    package = Path(__file__).resolve().parent
    return Path(os.path.abspath(exc.filename)).is_relative_to(package)


def _internal(exc: BaseException, debug: bool) -> int:
    """A bug of ours, or a broken installation: one line that says so, with the version and what
    to do; the traceback with --debug or $GYROCHAIN_TRACEBACK."""
    from . import DISTRIBUTION, __version__

    what = " ".join(str(exc).split()) or "(no message)"
    print(f"error: internal error in {DISTRIBUTION} {__version__}: {type(exc).__name__}: {what} — please report it "
          f"with the command (--debug or {DISTRIBUTION.upper()}_TRACEBACK=1 prints the traceback)", file=sys.stderr)
    if debug:
        raise exc
    return EXIT_INTERNAL
