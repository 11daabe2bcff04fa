"""Command line: ``python -m codegen {generate,check,simulate,steady,sweep,animate} SPEC`` and ``plot STORE``.

Only this module touches the disk.  A bad spec gets one line on stderr naming the field, exit
status 2, and nothing written: outputs go to a temporary folder beside the target and replace it
in one rename at the end.
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from .spec import SpecError, load_spec

EXIT_BAD_INPUT = 2


class _Progress:
    def __init__(self, quiet: bool):
        self.t0 = time.perf_counter()
        self.quiet = quiet

    def __call__(self, msg: str) -> None:
        if not self.quiet:
            print(f"  [{time.perf_counter() - self.t0:6.2f} s] {msg}", file=sys.stderr, flush=True)


def derive_and_render(spec, spec_label: str, progress=None, qdd_form: str = "auto",
                      der_form: str = "auto", tex: bool = True) -> tuple[dict[str, str], object]:
    from . import dynamics, emit, integrals, kinematics

    say = progress or (lambda msg: None)
    say(f"kinematics: direction cosines and angular velocities of {spec.n} bodies")
    kin = kinematics.derive(spec)
    say("dynamics: mass matrix and forces (recursions over the sub-chains p >= k)")
    dyn = dynamics.derive(spec, kin)
    say("integrals: energy (23) and, where l1 may be vertical, momentum (27)")
    ints = integrals.derive(spec, kin, dyn)
    model = emit.build_model(spec, kin, dyn, ints, progress=say, qdd_form=qdd_form, der_form=der_form)
    say("printing C, Python and LaTeX" if tex else "printing C and Python")
    return emit.render(model, spec_label, tex=tex), model


def _is_ours(directory: Path) -> bool:
    """A folder we may replace: missing, empty, or written by codegen (it has our MANIFEST.json)."""
    if not directory.exists():
        return True
    if not directory.is_dir():
        return False
    entries = list(directory.iterdir())
    if not entries:
        return True
    manifest = directory / "MANIFEST.json"
    try:
        return "spec_sha256" in json.loads(manifest.read_text())
    except (OSError, ValueError):
        return False


def write_tree(files: dict[str, str], target: Path, build: bool, name: str) -> str | None:
    """Write every file into a fresh temporary folder, build there, then swap it in.  The build
    is skipped when the folder's extension was built from the same C, header and cdef with the
    same flags (build.build_key): returns "compiled", "reused" or None (no build)."""
    target.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{target.name}.tmp-", dir=target.parent))
    how = None
    try:
        for rel, text in sorted(files.items()):
            with open(tmp / rel, "w", encoding="utf-8", newline="\n") as fh:
                fh.write(text)
        if build:
            from .build import compile_model, reuse_extension

            if target.is_dir() and reuse_extension(target, tmp, name):
                how = "reused"
            else:
                compile_model(tmp, name)
                how = "compiled"
        old = None
        if target.exists():
            old = target.parent / f".{target.name}.old-{os.getpid()}"
            target.rename(old)
        tmp.rename(target)
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return how


def cmd_generate(args) -> int:
    t0 = time.perf_counter()
    spec = load_spec(args.spec)
    target = Path(args.output) if args.output else Path("generated") / spec.name
    if not _is_ours(target) and not args.force:
        raise SpecError(
            "-o", f"{target} exists and was not written by codegen; choose another folder or pass --force"
        )
    label = Path(args.spec).name
    progress = _Progress(args.quiet)
    print(f"generating {spec.name} (n = {spec.n}) from {args.spec}", file=sys.stderr)
    from .emit import FormNotApplicable

    try:
        files, model = derive_and_render(spec, label, progress, qdd_form=args.qdd_form, der_form=args.derivative_form)
    except FormNotApplicable as exc:
        raise SpecError("--derivative-form", str(exc)) from None
    if not args.no_build:
        progress("compiling the cffi extension (unless the one there was built from the same C and flags)")
    how = write_tree(files, target, build=not args.no_build, name=spec.name)
    from .emit import op_counts

    counts = op_counts(model)
    print(f"{spec.name}: n = {spec.n}, {len(spec.params)} symbolic parameters, {len(spec.controls)} control torques"
          + (", moving platform" if spec.base is not None and spec.base.moves else ""))
    print("op counts: " + ", ".join(f"{spec.name}_{k} {v}" for k, v in counts.items()))
    print(f"qdd form: {model.qdd_form}" + (" (composite bodies + LDL^T)" if model.qdd_form == "composite" else " (articulated bodies, O(n))"))
    print(f"derivative form: {model.der_form} (" + DERIVATIVE_FORMS[model.der_form] + ")")
    for line in _integral_lines(spec, model):
        print(line)
    if model.quad is not None and spec.initial is not None:
        print(_motion_line(spec, target))
    built = {None: "", "compiled": " + cffi extension",
             "reused": " + cffi extension (not recompiled: the C, the header and the compiler flags are those it was built from)"}[how]
    print(f"wrote {target}/: " + ", ".join(sorted(files)) + built)
    print(f"done in {time.perf_counter() - t0:.2f} s")
    return 0


DERIVATIVE_FORMS = {
    "specialised": "forward mode over the articulated recursion, one function per column",
    "generic": "forward mode over the articulated recursion, one tangent called per column",
    "world": "inverse dynamics differentiated in frame 0, M^-1 by LDL^T, O(n^2) pairs",
}


def _integral_lines(spec, model) -> list[str]:
    """What `generate` says about the integrals and the quadratures of a spec."""
    from .quadratures import why_not

    ints = model.integrals
    if spec.general:
        energy = "energy T - U (23): " + ("conserved (" + ("U includes " + ", ".join(w for w, _ in ints.U_extra) if ints.U_extra
                                                         else "no load but gravity does work") + ")"
                                          if ints.has_energy_integral else "not conserved: " + "; ".join(ints.energy_reasons)
                                          + (" removed it" if len(ints.energy_reasons) == 1 else " removed it"))
    else:
        energy = "energy T - U (23): " + ("conserved (fixed base, no control torque)" if ints.has_energy_integral
                                          else "not conserved (control torques act)")
    if ints.momentum_condition:
        momentum = f"momentum (27): conserved only if {ints.momentum_condition}"
    elif ints.momentum is None:
        momentum = "momentum (27): not an integral (theta1 is not 0 or pi: the axis l1 is not vertical)"
    elif ints.has_momentum_integral:
        momentum = "momentum (27): conserved (axis l1 vertical, no torque in joint 1)"
    elif ints.momentum_reasons:
        momentum = "momentum (27): not conserved: " + "; ".join(ints.momentum_reasons)
    else:
        momentum = "momentum (27): not conserved (a control torque acts in joint 1)"
    reason = why_not(spec)
    quad = ("quadratures (30): emitted (" + ("Nikolai's balanced gyroscope, " if model.quad.nikolai else "")
            + "NAME_quad_period, NAME_quad_state)" if reason is None else f"quadratures (30): not emitted: {reason}")
    out = ["integrals: " + energy, "           " + momentum]
    if spec.general and spec.base is not None and spec.base.moves:
        out.append("           Jacobi integral T2 - T0 - U - sum lambda.omega0: " + (
            "conserved (the platform turns uniformly, gravity fixed in it; NAME_jacobi)" if ints.jacobi is not None
            else "none (the platform's motion or a load makes the Lagrangian depend on t)"))
    if spec.general:
        from .emit import time_dependent

        out.append("time: " + ("the equations depend on t (NAME_TIME_DEPENDENT 1: forces, qdd, energy, momentum take t)"
                               if time_dependent(model) else "autonomous (NAME_TIME_DEPENDENT 0)"))
    return [line.replace("NAME_T", f"{spec.name.upper()}_T").replace("NAME", spec.name) for line in out] + [quad.replace("NAME", spec.name)]


def _motion_line(spec, target: Path) -> str:
    """The kind of motion of the spec's [initial] state, by the generated Python module itself."""
    from .build import load_python

    if spec.params:
        return "motion of [initial]: needs values of the parameters (" + ", ".join(map(str, spec.params)) + ")"
    mod = load_python(target, spec.name)
    x0 = [*spec.initial["phi"], *spec.initial["phidot"]]
    try:
        m = mod.quad_motion(x0)
    except ArithmeticError as exc:
        return f"motion of [initial]: {exc}"
    if m["kind"] == "libration":
        return (f"motion of [initial]: libration of phi2 between {m['phi_min']:.9g} and {m['phi_max']:.9g} rad, "
                f"period {m['period']:.12g} s, psi gains {m['psi_advance']:.9g} rad per period")
    if m["kind"] == "rotation":
        return (f"motion of [initial]: rotation (phi2 runs round), period {m['period']:.12g} s per turn, "
                f"psi gains {m['psi_advance']:.9g} rad per turn")
    return "motion of [initial]: steady (phi2 stays constant, psi turns uniformly)"


def cmd_check(args) -> int:
    spec = load_spec(args.spec)
    params = ", ".join(str(p) for p in spec.params) or "none"
    print(f"{args.spec}: ok ({spec.name}, n = {spec.n}, symbolic parameters: {params})")
    return 0


def _floats(text: str, what: str, count: int) -> list[float]:
    try:
        vals = [float(v) for v in text.split(",")] if text else [0.0] * count
    except ValueError:
        raise SpecError(what, f"expected {count} comma-separated numbers") from None
    if len(vals) != count:
        raise SpecError(what, f"expected {count} comma-separated numbers, got {len(vals)}")
    return vals


def _params_of(items, what: str = "--param") -> dict:
    """name=number options (--param) as a dict."""
    params = {}
    for item in items or []:
        key, _, val = item.partition("=")
        try:
            params[key.strip()] = float(val)
        except ValueError:
            raise SpecError(f"{what} {key}", "expected name=number") from None
    return params


def _initial_state(spec, args) -> tuple[list, list]:
    """φ and φ̇ at t = 0: --phi/--phidot, else the spec's [initial], else zero."""
    n, init = spec.n, spec.initial or {}
    phi = _floats(args.phi, "--phi", n) if args.phi else list(init.get("phi", [0.0] * n))
    phidot = _floats(args.phidot, "--phidot", n) if args.phidot else list(init.get("phidot", [0.0] * n))
    return phi, phidot


def cmd_simulate(args) -> int:
    """Integrate a spec with the independent reference model; CSV on stdout."""
    import numpy as np

    from . import reference

    spec = load_spec(args.spec)
    params = _params_of(args.param)
    try:
        ch = reference.numeric(spec, params)
    except ValueError as exc:
        raise SpecError("--param", str(exc)) from None
    n = spec.n
    phi, phidot = _initial_state(spec, args)
    u = _floats(args.u, "--u", len(spec.controls)) if spec.controls else None
    t = np.linspace(0.0, args.t1, args.steps + 1)
    X = reference.simulate(ch, phi + phidot, t, u=u)
    cols = [f"phi{k}" for k in range(1, n + 1)] + [f"phidot{k}" for k in range(1, n + 1)]
    print(",".join(["t", *cols, "energy"]))
    for ti, xi in zip(t, X):
        print(",".join(f"{v:.17g}" for v in [ti, *xi, reference.energy(ch, xi, ti)]))
    return 0


def cmd_steady(args) -> int:
    """Equilibria and steady rotations of a spec, with their stability."""
    from . import steady

    spec = load_spec(args.spec)
    params = _params_of(args.param)
    unknown = sorted(set(params) - {str(p) for p in spec.params})
    if unknown:
        raise SpecError("--param", f"unknown parameter {unknown[0]} (the spec's are: {', '.join(map(str, spec.params)) or 'none'})")
    u = _floats(args.u, "--u", len(spec.controls)) if args.u else None
    starts = [_floats(s, "--start", spec.n) for s in args.start or []]
    try:
        omegas = steady.parse_range(args.omega) if args.omega else None
        an, eqs, branches, omegas = steady.analyze_spec(spec, params or None, u, omegas, starts, rotations=not args.no_rotations)
    except steady.SteadyError as exc:
        what, _, why = str(exc).partition(": ")
        raise SpecError(what, why) from None
    print(f"{spec.name}: n = {spec.n}" + (f", u = {u}" if u else "") + (f", {params}" if params else ""))
    print(steady.report(an, eqs, branches, omegas))
    return 0


def cmd_sweep(args) -> int:
    """A grid (or random samples) of initial states and parameters, integrated in chunks into a Zarr store."""
    from . import sweep as sw

    spec = load_spec(args.spec)  # the spec's own errors first, naming its fields
    vary = [sw.parse_vary(v, args.random > 0) for v in args.vary or []]
    sweep = sw.Sweep(
        spec_text=spec.source, vary=vary, t1=args.t1, measures=args.measure or ["final"], random=args.random, seed=args.seed,
        method=args.method, h=args.h, rtol=args.rtol, atol=args.atol, samples=args.samples, flip=args.flip,
        lyap_interval=args.lyap_interval, phi=_floats(args.phi, "--phi", spec.n) if args.phi else [],
        phidot=_floats(args.phidot, "--phidot", spec.n) if args.phidot else [],
        u=_floats(args.u, "--u", len(spec.controls)) if args.u else [], params=_params_of(args.param), chunk=args.chunk,
    )
    plan = sw.Plan(sweep)
    if args.threads is not None and args.threads < 1:
        raise SpecError("--threads", "must be at least 1")
    if args.workers and args.scheduler:
        raise SpecError("--workers", "give --workers (a local Dask cluster) or --scheduler (an existing one), not both")
    sw.check_store(Path(args.output), plan)
    t0 = time.perf_counter()
    where = (f"the Dask scheduler {args.scheduler}" if args.scheduler else f"a local Dask cluster of {args.workers} worker processes"
             if args.workers else f"{args.threads or os.cpu_count()} thread(s)")
    print(f"sweep of {plan.spec.name}: {int(np.prod(plan.shape))} points in {plan.n_chunks} chunks on {where} -> {args.output}",
          file=sys.stderr)
    counts = sw.run(sweep, args.output, threads=args.threads, workers=args.workers, scheduler=args.scheduler,
                    progress=not args.quiet, plan=plan)
    print(f"{counts['written']} chunks computed, {counts['skipped']} already done, in {time.perf_counter() - t0:.1f} s",
          file=sys.stderr)
    return 0


def cmd_plot(args) -> int:
    """A heat map (two varied quantities) or a curve (one) of a sweep store."""
    from . import sweep as sw

    if not Path(args.store).exists():
        raise SpecError("store", f"{args.store}: no such store")
    data = sw.read(args.store)
    a = data["attrs"]["args"]
    measure = args.measure or a["measures"][0]
    if measure not in data:
        raise SpecError("--measure", f"{measure!r} is not in the store (it has {', '.join(a['measures'])})")
    values = data[measure]
    if measure == "final":
        values = values[..., args.component]
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        raise SpecError("plot", "needs matplotlib: pip install 'gyrochain[plot]'") from None
    names = [v[0] for v in a["vary"]]
    label = _measure_label(measure, args.component, data["attrs"])
    fig, ax = plt.subplots(figsize=(6.4, 5.2) if len(names) == 2 else (6.4, 4.0), dpi=args.dpi)
    if len(names) == 2 and not a["random"]:
        x, y = data["coords"][names[0]], data["coords"][names[1]]
        norm = None
        if args.log:
            from matplotlib.colors import LogNorm
            norm = LogNorm()
        im = ax.pcolormesh(x, y, values.T, shading="nearest", cmap=args.cmap, norm=norm)
        fig.colorbar(im, ax=ax, label=label)
        ax.set_xlabel(_axis_label(names[0]))
        ax.set_ylabel(_axis_label(names[1]))
    elif len(names) == 2:
        sc = ax.scatter(data["coords"][names[0]], data["coords"][names[1]], c=values, s=4, cmap=args.cmap)
        fig.colorbar(sc, ax=ax, label=label)
        ax.set_xlabel(_axis_label(names[0]))
        ax.set_ylabel(_axis_label(names[1]))
    elif len(names) == 1:
        x = data["coords"][names[0]]
        order = np.argsort(x)
        ax.plot(x[order], values[order], ".-" if len(x) < 200 else "-")
        ax.set_xlabel(_axis_label(names[0]))
        ax.set_ylabel(label)
    else:
        raise SpecError("store", f"plot shows one or two varied quantities; this sweep varies {len(names)}")
    ax.set_title(f"{data['attrs']['spec_name']}: {label}")
    fig.tight_layout()
    fig.savefig(args.output)
    print(f"wrote {args.output}", file=sys.stderr)
    return 0


def _axis_label(name: str) -> str:
    import re

    m = re.fullmatch(r"(phi|phidot)(\d+)", name)
    if not m:
        return name
    return f"$\\varphi^{{{m.group(2)}}}$ (rad)" if m.group(1) == "phi" else f"$\\dot\\varphi^{{{m.group(2)}}}$ (rad/s)"


def _measure_label(measure: str, component: int, attrs: dict) -> str:
    t1 = attrs["args"]["t1"]
    return {"flip_time": f"flip time (s; blank: none within {t1:g} s)", "energy_error": "largest |E(t) - E(0)|",
            "lyapunov": "largest Lyapunov exponent (1/s)", "code": "integrator return code"}.get(
        measure, f"final state component {component}")


def cmd_animate(args) -> int:
    """The motion of a spec (or of a sweep's point) as a GIF, MP4, PNG still or an offline HTML viewer."""
    import math

    from . import animate, reference, scene
    from . import sweep as sw
    from .spec import parse_spec

    t_start = time.perf_counter()
    out = animate.Output(args.output, force=args.force)  # the extension and an existing file first
    if out.ext == ".png" and args.frame is None:
        raise SpecError("--frame", "a .png is one still: give --frame T (seconds)")
    size = _size(args.size)
    view = _floats(args.view, "--view", 2) if args.view else None
    source = Path(args.spec)
    if source.is_dir():  # a sweep store: its spec, and the state and parameters of one point
        if args.phi or args.phidot or args.param or args.u:
            raise SpecError("--at", "the state, parameters and torques come from the sweep's point; drop --phi/--phidot/--param/--u")
        pt = sw.point(source, args.at)
        spec = parse_spec(pt["spec_text"])
        x0, params, u = list(pt["x0"]), pt["params"], pt["u"] or None
        t1 = args.t1 if args.t1 is not None else pt["t1"]
        description = f"{spec.description} (sweep {source.name}: {pt['label']})"
    else:
        if args.at:
            raise SpecError("--at", "a point of a sweep: give the sweep's store as SPEC")
        spec = load_spec(args.spec)
        params = _params_of(args.param)
        phi, phidot = _initial_state(spec, args)
        x0 = phi + phidot
        u = _floats(args.u, "--u", len(spec.controls)) if spec.controls else None
        t1 = args.t1 if args.t1 is not None else 10.0
        description = spec.description
    try:
        ch = reference.numeric(spec, params)
    except ValueError as exc:
        raise SpecError("--param", str(exc)) from None
    if not (args.trace >= 0 and math.isfinite(args.trace)):
        raise SpecError("--trace", "must be a number of seconds >= 0")
    sub = 4  # the trace is sampled 4 times per frame: smooth where the tip moves fast
    if args.trajectory:
        times, X, has_rate, fine, fine_X = animate.read_csv(args.trajectory, spec.n, args.fps, args.frame)
    elif args.frame is not None:
        times, has_rate = animate.frame_times(t1, args.fps, args.frame), True
        fine = np.unique(np.concatenate([np.linspace(max(0.0, args.frame - args.trace), args.frame, 100), times]))
    else:
        fine, has_rate = animate.frame_times(t1, args.fps, None, sub), True
        times = fine[::sub]
    model, derived = sw.compiled(spec)
    if not args.trajectory:
        fine_X = animate.motion(model, fine, x0, u=u, params=params or None, rtol=args.rtol, atol=args.rtol * 1e-2)
        X = fine_X[np.searchsorted(fine, times)]
    integral = animate.integral_curve(model, derived, X, times, u, params or None) if has_rate else None
    if args.follow and spec.base is None:
        raise SpecError("--follow", "the spec has no [base]: there is no platform to follow")
    sc = scene.build(spec, ch, times, X, trace=args.trace, integral=integral, tip_times=fine, tip_X=fine_X,
                     rates=has_rate, follow=args.follow)
    camera = scene.Camera(math.radians(view[0]), math.radians(view[1])) if view else scene.default_camera(sc.points)
    with out:
        if out.ext == ".html":
            animate.write_html(sc, camera, out.tmp, description)
        else:
            raster = animate.Raster(sc, size[0], size[1], camera)
            {".gif": lambda: animate.write_gif(raster, out.tmp, args.fps), ".png": lambda: animate.write_png(raster, out.tmp),
             ".mp4": lambda: animate.write_mp4(raster, out.tmp, args.fps)}[out.ext]()
    if not args.quiet:
        span = f"t = {times[0]:g} s" if len(times) == 1 else f"{len(times)} frames over [{times[0]:g}, {times[-1]:g}] s"
        print(f"wrote {out.path}: {span}, {out.path.stat().st_size // 1024} KiB, in {time.perf_counter() - t_start:.1f} s",
              file=sys.stderr)
    return 0


def _size(text: str) -> tuple[int, int]:
    w, x, h = text.lower().partition("x")
    try:
        size = (int(w), int(h)) if x else (0, 0)
    except ValueError:
        size = (0, 0)
    if not (64 <= size[0] <= 4096 and 64 <= size[1] <= 4096) or size[0] % 2 or size[1] % 2:
        raise SpecError("--size", f"{text!r}: expected WIDTHxHEIGHT, even numbers of pixels from 64 to 4096")
    return size


def _prog() -> str:
    """The command as the user typed it: the console script, or python -m codegen."""
    from . import DISTRIBUTION

    return DISTRIBUTION if Path(sys.argv[0]).name == DISTRIBUTION else "python -m codegen"


def main(argv=None) -> int:
    from . import DISTRIBUTION, __version__

    ap = argparse.ArgumentParser(prog=_prog(), description=__doc__.splitlines()[0])
    ap.add_argument("--version", action="version", version=f"{DISTRIBUTION} {__version__}")
    sub = ap.add_subparsers(dest="cmd", required=True)
    g = sub.add_parser("generate", help="derive and emit C, Python and LaTeX for a spec")
    g.add_argument("spec")
    g.add_argument("-o", "--output", help="output folder (default generated/<name>)")
    g.add_argument("--no-build", action="store_true", help="do not compile the cffi extension")
    g.add_argument("--force", action="store_true", help="replace an output folder codegen did not write")
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
    c = sub.add_parser("check", help="validate a spec without generating")
    c.add_argument("spec")
    s = sub.add_parser("simulate", help="integrate a spec with the reference model (CSV to stdout)")
    s.add_argument("spec")
    s.add_argument("--t1", type=float, default=1.0)
    s.add_argument("--steps", type=int, default=100)
    s.add_argument("--phi", default="")
    s.add_argument("--phidot", default="")
    s.add_argument("--u", default="", help="constant torques of the controlled joints")
    s.add_argument("--param", action="append", help="name=value for a symbolic parameter")
    st = sub.add_parser("steady", help="equilibria and steady rotations, with their stability")
    st.add_argument("spec")
    st.add_argument("--u", default="", help="constant torques of the controlled joints (required if the spec has any)")
    st.add_argument("--param", action="append", help="name=value for a symbolic parameter")
    st.add_argument("--omega", default="", help="a:b:N grid of the rotation rate phidot1 (default: from the equilibria)")
    st.add_argument("--start", action="append", help="an extra Newton start phi1,...,phin")
    st.add_argument("--no-rotations", action="store_true", help="equilibria only")
    sw = sub.add_parser("sweep", help="integrate a grid or random samples of initial states/parameters into a Zarr store")
    sw.add_argument("spec")
    sw.add_argument("--vary", action="append", help="name=lo:hi:count (grid; name phiK, phidotK or a parameter) or name=lo:hi with --random")
    sw.add_argument("--random", type=int, default=0, help="that many uniform random samples in the box of the --vary ranges")
    sw.add_argument("--seed", type=int, default=0, help="seed of --random")
    sw.add_argument("--t1", type=float, default=10.0, help="end time of every trajectory (s)")
    sw.add_argument("--measure", action="append", help="final | flip_time | energy_error | lyapunov (repeatable; default final)")
    sw.add_argument("--method", default="dop853", help="rk4 | dop853 | gauss2")
    sw.add_argument("--h", type=float, default=0.0, help="step of rk4/gauss2 (first step of dop853, 0: automatic)")
    sw.add_argument("--rtol", type=float, default=1e-8)
    sw.add_argument("--atol", type=float, default=1e-10)
    sw.add_argument("--samples", type=int, default=1000, help="output intervals over [0, t1] for flip_time and energy_error")
    sw.add_argument("--flip", default="", help="the coordinate of flip_time (phiK; default: the first of any)")
    sw.add_argument("--lyap-interval", type=float, default=0.1, help="renormalisation interval of the Lyapunov exponent (s)")
    sw.add_argument("--phi", default="", help="the coordinates that are not varied (default: the spec's initial or 0)")
    sw.add_argument("--phidot", default="", help="the rates that are not varied")
    sw.add_argument("--u", default="", help="constant torques of the controlled joints")
    sw.add_argument("--param", action="append", help="name=value for a symbolic parameter that is not varied")
    sw.add_argument("--chunk", type=int, default=1024, help="points per chunk (whole rows of the grid)")
    sw.add_argument("--threads", type=int, default=None, help="threads on this machine (default: one per core)")
    sw.add_argument("--workers", type=int, default=0, help="start a local Dask cluster of N worker processes")
    sw.add_argument("--scheduler", default="", help="address of an existing Dask scheduler (tcp://host:8786)")
    sw.add_argument("-o", "--output", required=True, help="the Zarr store (created, or resumed if it is this sweep's)")
    sw.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    pl = sub.add_parser("plot", help="a heat map or a curve of a sweep store")
    pl.add_argument("store")
    pl.add_argument("-o", "--output", required=True, help="the image (png, pdf, svg)")
    pl.add_argument("--measure", default="", help="which array (default: the sweep's first measure)")
    pl.add_argument("--component", type=int, default=0, help="the state component of 'final'")
    pl.add_argument("--cmap", default="viridis")
    pl.add_argument("--log", action="store_true", help="a logarithmic colour scale (maps)")
    pl.add_argument("--dpi", type=int, default=150)
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
    an.add_argument("--follow", action="store_true", help="keep the platform's O1 in the middle of the view (a heaving base)")
    an.add_argument("--rtol", type=float, default=1e-10, help="relative tolerance of DOP853")
    an.add_argument("--force", action="store_true", help="replace an existing file animate did not write")
    an.add_argument("-q", "--quiet", action="store_true")
    args = ap.parse_args(argv)
    try:
        return {"generate": cmd_generate, "check": cmd_check, "simulate": cmd_simulate, "steady": cmd_steady,
                "sweep": cmd_sweep, "plot": cmd_plot, "animate": cmd_animate}[args.cmd](args)
    except SpecError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
