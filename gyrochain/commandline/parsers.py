"""The command line's grammar: every subcommand, its arguments, their formats and defaults.

One place for what ``--help`` says, so that every argument is described with its default and its
format (a test walks the parsers and checks it).  The formats are the same everywhere: a list is
comma-separated numbers in chain order (``PHI1,..,PHIn``), a grid is ``lo:hi:N`` (N values from lo
to hi), a parameter is ``NAME=VALUE``.  cli.py runs what is parsed here.
"""
from __future__ import annotations

import argparse
import sys

from . import cliargs

EXIT_BAD_INPUT = 2
SPEC = "the spec file (TOML; `gyrochain examples` lists ready ones, `gyrochain new` writes one)"
PARAM = "a symbolic parameter's value, NAME=VALUE (repeatable; default: the spec's [values])"
U = "constant torques of the controlled joints, N m, comma-separated in chain order (default 0)"
PHI = "initial joint angles, rad, comma-separated PHI1,..,PHIn (default: the spec's [initial], else 0)"
PHIDOT = "initial joint rates, rad/s, comma-separated (default: the spec's [initial], else 0)"
FORCE = "replace an existing file (default: refuse)"


class Parser(argparse.ArgumentParser):
    """argparse with one line for a mistake: ``error: <what> (see <prog> --help)``, exit 2; a
    missing subcommand lists the subcommands."""

    def parse_known_args(self, args=None, namespace=None):
        if args is not None and not any(isinstance(a, argparse._SubParsersAction) for a in self._actions):
            self._refuse_repeats(list(args))
        return super().parse_known_args(args, namespace)

    def _refuse_repeats(self, args: list) -> None:
        """An option given twice is refused, whatever it is (a repeatable one, like --param, aside):
        the last value silently winning would hide a typo in a long command line."""
        once = {s: a for a in self._actions if a.option_strings and not isinstance(a, argparse._AppendAction)
                for s in a.option_strings}
        seen: dict = {}
        for tok in args:
            if tok == "--":
                break
            if not tok.startswith("-") or tok == "-" or tok[1:2].isdigit() or tok[1:2] == ".":
                continue
            name = tok.split("=", 1)[0]
            if name not in once and name.startswith("--"):  # argparse's unique prefixes (--out for --output)
                hits = {once[s] for s in once if s.startswith(name)}
                action = hits.pop() if len(hits) == 1 else None
            else:
                action = once.get(name)
            if action is None:
                continue
            if action in seen:
                self.error(f"{seen[action]}: given twice; give it once")
            seen[action] = name

    def error(self, message):
        subs = [a for a in self._actions if isinstance(a, argparse._SubParsersAction)]
        if subs and "required: " in message:
            what = "command" if subs[0].dest == "cmd" else subs[0].dest
            message = f"{what}: missing; one of {', '.join(subs[0].choices)}"
        print(f"error: {cliargs.plain(message)} (see {self.prog} --help)", file=sys.stderr)
        raise SystemExit(EXIT_BAD_INPUT)


def build(prog: str, description: str, version: str, kinds: dict) -> argparse.ArgumentParser:
    """The parser of ``gyrochain`` and all its subcommands; ``kinds`` those of ``new``."""
    ap = Parser(prog=prog, description=description)
    ap.add_argument("--version", action="version", version=version)
    ap.add_argument("--debug", action="store_true", help="on an internal error, print the traceback (anywhere on the line)")
    sub = ap.add_subparsers(dest="cmd", required=True, metavar="COMMAND", parser_class=Parser)
    _derive(sub)
    _analyse(sub)
    _sweep(sub)
    _animate(sub)
    _start(sub, kinds)
    _exchange(sub)
    _identify(sub)
    return ap


def _spec(p) -> None:
    p.add_argument("spec", metavar="SPEC", help=SPEC)


def _derive(sub) -> None:
    g = sub.add_parser("generate", help="derive and emit C, Python and LaTeX for a spec",
                       description="Derive the equations of a spec and write them as C, Python and LaTeX into a folder. "
                                   "Before a file is written, the emitted C (when built) and Python are compared with an "
                                   "independent numeric model of the spec at random states; a difference is an internal "
                                   "error and nothing is written.")
    _spec(g)
    g.add_argument("-o", "--output", metavar="DIR", help="output folder (default generated/NAME)")
    g.add_argument("--no-build", action="store_true", help="do not compile the cffi extension (default: compile it)")
    g.add_argument("--force", action="store_true", help="write into an output folder gyrochain did not write (its "
                   "other files are kept; files of the same names are replaced; default: refuse)")
    g.add_argument("-q", "--quiet", action="store_true", help="no progress lines (default: one per stage, on stderr)")
    g.add_argument("--qdd-form", choices=("auto", "composite", "articulated"), default="auto",
                   help="how NAME_qdd solves for phi'': auto (fewer operations; the default), composite bodies + "
                        "LDL^T, or articulated bodies")
    g.add_argument("--derivative-form", choices=("auto", "forward", "world", "world-solve", "world-inverse"), default="auto",
                   help="how NAME_qdd_derivatives is computed: auto (fewer operations; the default), forward mode over "
                        "the articulated recursion, or inverse dynamics differentiated in frame 0 (fixed base, constant "
                        "rotors, no body loads), its products with M^-1 by fewer operations, by LDL^T solves or by M^-1 "
                        "formed")
    g.add_argument("--real", choices=("double", "float"), default="double",
                   help="the floating type of the C: double (the default) or float, for a single-precision FPU "
                        "(the Python mirror stays in double)")
    g.add_argument("--regressor", action="store_true", help="also NAME_regressor (u = Y pi + tau0), the energy's, "
                   "the base parameters and NAME_base_regressor (parameter identification; default: without)")
    g.add_argument("--hessian", action="store_true", help="also NAME_rhs_hessian and NAME_step_hessian: the exact second "
                   "derivatives of lam . f and of lam . (one RK4 step) that an optimiser's exact Hessian asks for "
                   "(default: without; --casadi includes them)")
    g.add_argument("--paper", choices=("a4", "letter"), default="a4",
                   help="the page of the LaTeX document: a4 (the default) or letter (US)")
    g.add_argument("--pdf", action="store_true", help="also typeset the LaTeX into NAME.pdf with LuaLaTeX, two passes "
                   "(default: the .tex only)")
    g.add_argument("--gpu", action="store_true", help="also NAME_gpu.cu: CUDA kernels of one thread per trajectory that "
                   "run NAME.c's RK4, DOP853 and variational equations (NAME_integrate_batch on a GPU; default: without)")
    g.add_argument("--casadi", action="store_true", help="also NAME_casadi.c: the dynamics, one RK4 step, the mass "
                   "matrix and the energy as CasADi external functions, with the exact Jacobians and Hessians (optimal control; "
                   "a spec with a control; default: without)")
    c = sub.add_parser("check", help="validate a spec without generating")
    _spec(c)
    s = sub.add_parser("simulate", help="integrate a spec with the emitted C (CSV to stdout: t, phi, phidot, energy)")
    _spec(s)
    s.add_argument("--t1", type=float, default=1.0, help="end time, s (default 1)")
    s.add_argument("--steps", type=int, default=100, help="output intervals over [0, t1] (default 100)")
    s.add_argument("--phi", default="", metavar="PHI1,..", help=PHI)
    s.add_argument("--phidot", default="", metavar="RATE1,..", help=PHIDOT)
    s.add_argument("--u", default="", metavar="U1,..", help=U)
    s.add_argument("--param", action="append", metavar="NAME=VALUE", help=PARAM)
    s.add_argument("--method", default="dop853", help="dop853 (adaptive, dense output; the default) | rk4 | gauss2 | "
                   "gauss2_symplectic (fixed step --h)")
    s.add_argument("--h", type=float, default=None, help="step of rk4/gauss2, s (default: a tenth of an output interval)")
    s.add_argument("--rtol", type=float, default=None, help="relative tolerance of dop853 (default 1e-10)")
    s.add_argument("--atol", type=float, default=None, help="absolute tolerance of dop853 (default 1e-12)")
    s.add_argument("--yes", action="store_true", help="run past the limits (200 MiB of CSV, 1e8 fixed steps, an RK4 "
                   "step beyond stability) instead of stopping (default: stop)")
    s.add_argument("--reference", action="store_true", help="integrate the independent numpy model with scipy's DOP853 "
                   "instead (slow; a cross-check; default: the emitted C)")


def _analyse(sub) -> None:
    st = sub.add_parser("steady", help="equilibria and steady rotations, with their stability (of a model driven "
                        "periodically in t: its equilibria for all t, by Floquet multipliers)")
    _spec(st)
    st.add_argument("--u", default="", metavar="U1,..", help=U)
    st.add_argument("--param", action="append", metavar="NAME=VALUE", help=PARAM)
    st.add_argument("--at", default="", metavar="phi=PHI1,..", help="only the equilibrium Newton finds from there: "
                    "phi= one angle for every joint or one per joint, rad (default: search from every start)")
    st.add_argument("--max-equilibria", type=int, default=None, metavar="K", help="print the first K equilibria "
                    "(default: all; the count of all is printed)")
    st.add_argument("--digits", type=int, default=None, help="significant digits of the eigenvalues (default 10) and "
                    "of a driven model's Floquet multipliers (default 4, the accuracy of a period's integration)")
    st.add_argument("--omega", default="", metavar="lo:hi:N", help="grid of the rotation rate phidot1, rad/s "
                    "(default: 161 values over four times the fastest small-oscillation rate)")
    st.add_argument("--start", action="append", metavar="PHI1,..", help="an extra Newton start, rad (repeatable; "
                    "default: only the built-in starts)")
    st.add_argument("--no-rotations", action="store_true", help="equilibria only (default: steady rotations too, "
                    "where phi1 is cyclic)")
    st.add_argument("--period", type=float, default=None, help="the period of a model that depends on t, s "
                    "(default: from the spec's sines and cosines of t)")
    st.add_argument("--vary", action="append", metavar="NAME=lo:hi:N", help="a model that depends on t: its equilibria "
                    "continued over one parameter, where the Floquet verdict changes (default: none)")
    co = sub.add_parser("continue", help="branches of equilibria traced over a parameter's range by continuation, "
                        "with their folds, branch points and changes of stability; with a second --vary, the curves "
                        "those points trace in the two parameters (stability boundaries)")
    _spec(co)
    co.add_argument("--vary", action="append", required=True, metavar="NAME=lo:hi", help="the parameter the branches "
                    "follow over lo:hi, both ways from its value (--param or the spec's; lo when it has none in the "
                    "range), or phidot1, the rate of steady rotations about a cyclic joint 1 (from 0); a second --vary: the other parameter of the curves of their special points, held at its "
                    "value along the branches (required)")
    co.add_argument("--from", dest="start", action="append", metavar="PHI1,..", help="a branch's first point: Newton "
                    "from these angles, rad, where the branch starts (repeatable; default: every equilibrium found there); "
                    "with --orbits of a driven model, the angles or the angles and rates of the orbit's start (default: "
                    "rest at phi = 0); of an autonomous one, the equilibrium of the normal modes (default: the stable "
                    "one of least energy)")
    co.add_argument("--orbits", action="store_true", help="periodic orbits instead of equilibria: of a driven model, "
                    "the orbits of the drive's period over --vary NAME=lo:hi; of an autonomous model whose energy is "
                    "conserved, the nonlinear normal modes of a stable equilibrium over --vary energy=lo:hi, the energy "
                    "above the equilibrium's, J (default: equilibria; --vary energy implies --orbits)")
    co.add_argument("--mode", action="append", type=int, help="with --vary energy: the linear mode whose family is "
                    "traced, 1 = the slowest (repeatable; default all)")
    co.add_argument("--param", action="append", metavar="NAME=VALUE", help=PARAM)
    co.add_argument("--u", default="", metavar="U1,..", help=U)
    co.add_argument("--period", type=float, default=None, help="the period of a model that depends on t, s "
                    "(default: from the spec's sines and cosines of t)")
    co.add_argument("--max-steps", type=int, default=400, metavar="N", help="the most continuation steps of the whole "
                    "run (default 400)")
    co.add_argument("--step", type=float, default=0.02, help="the first step along a branch, in radians and "
                    "ranges (a parameter's whole range counts as 1; default 0.02)")
    co.add_argument("-o", "--output", default="", metavar="FILE.csv", help="the branches, their special points and "
                    "the curves, one row each; NAME.zarr: the same as a Zarr store, a column an array (default: none, "
                    "the report only)")
    co.add_argument("--force", action="store_true", help=FORCE)
    ob = sub.add_parser("orbits", help="periodic orbits of an autonomous spec (nonlinear normal modes, steady rotations) "
                        "by shooting, with their Floquet multipliers")
    _spec(ob)
    ob.add_argument("--at", default="", metavar="PHI1,..", help="the stable equilibrium, rad (default: the one of "
                    "least energy)")
    ob.add_argument("--energy", default="", metavar="lo:hi:N", help="energies above the equilibrium's, J (default: 20 "
                    "values up to half the lowest barrier)")
    ob.add_argument("--mode", action="append", type=int, help="the linear mode to continue, 1 = the slowest "
                    "(repeatable; default all)")
    ob.add_argument("--vary", action="append", metavar="NAME=lo:hi:N", help="continue over a parameter at the first "
                    "energy instead (one parameter; default: over the energy)")
    ob.add_argument("--omega", default="", metavar="W or lo:hi:N", help="the steady rotations phidot1 = W as periodic "
                    "orbits, rad/s (phi1 cyclic; default: the normal modes instead)")
    ob.add_argument("--u", default="", metavar="U1,..", help=U)
    ob.add_argument("--param", action="append", metavar="NAME=VALUE", help=PARAM)


def _sweep(sub) -> None:
    sw = sub.add_parser("sweep", help="integrate one trajectory, a grid or random samples of initial states and "
                        "parameters into a Zarr store")
    _spec(sw)
    sw.add_argument("--vary", action="append", metavar="NAME=lo:hi:N", help="a grid axis: NAME phiK, phidotK, linkK or "
                    "a parameter; NAME=lo:hi with --random (repeatable; default: none, one trajectory)")
    sw.add_argument("--random", type=int, default=0, metavar="N", help="N uniform random samples in the box of the "
                    "--vary ranges (default 0: a grid)")
    sw.add_argument("--seed", type=int, default=0, help="seed of --random (default 0)")
    sw.add_argument("--t1", type=float, default=10.0, help="end time of every trajectory, s (default 10)")
    sw.add_argument("--measure", action="append", help="final | flip_time | energy_error | lyapunov | lyapunov_spectrum "
                    "| floquet (repeatable; default final)")
    sw.add_argument("--method", default="dop853", help="rk4 | dop853 | gauss2 | rk4_lanes (RK4 with the model's own "
                    "vectorised sin/cos: the fastest fixed-step sweep; default dop853)")
    sw.add_argument("--h", type=float, default=0.0, help="step of rk4/rk4_lanes/gauss2, s (first step of dop853; default 0: "
                    "automatic)")
    sw.add_argument("--rtol", type=float, default=None, help="relative tolerance of dop853 (default 1e-8; 1e-11 with a "
                    "Lyapunov measure)")
    sw.add_argument("--atol", type=float, default=None, help="absolute tolerance of dop853 (default 1e-10; with a "
                    "Lyapunov measure 1e-5 of --lyap-d0, at most 1e-13)")
    sw.add_argument("--samples", type=int, default=None, help="output intervals over [0, t1] of flip_time and "
                    "energy_error (default 1000)")
    sw.add_argument("--flip", default=None, metavar="phiK", help="the angle of flip_time (link or joint K; default: "
                    "the first of any)")
    sw.add_argument("--angles", default=None, help="what flip_time watches: absolute (the links' angles phi1+..+phiK, "
                    "planar chains), relative (the joint angles) or auto (default: absolute where the chain is planar)")
    sw.add_argument("--lyap-interval", type=float, default=None, help="renormalisation interval of the Lyapunov exponent "
                    "and of lyapunov_spectrum's QR, s (default 0.1)")
    sw.add_argument("--lyap-d0", type=float, default=None, help="the initial separation of lyapunov's two "
                    "trajectories, in state space (default 1e-8)")
    sw.add_argument("--phi", default="", metavar="PHI1,..", help="the angles that are not varied, rad (default: the "
                    "spec's [initial], else 0)")
    sw.add_argument("--phidot", default="", metavar="RATE1,..", help="the rates that are not varied, rad/s (default: "
                    "the spec's [initial], else 0)")
    sw.add_argument("--u", default="", metavar="U1,..", help=U)
    sw.add_argument("--param", action="append", metavar="NAME=VALUE", help=PARAM)
    sw.add_argument("--chunk", type=int, default=1024, help="points per chunk, whole rows of the grid (default 1024)")
    sw.add_argument("--threads", type=int, default=None, help="threads on this machine (default: one per core)")
    sw.add_argument("--device", choices=("cpu", "cuda", "auto"), default="cpu", help="where the trajectories run: cpu "
                    "(threads or Dask; the default), cuda, one GPU thread per trajectory (--method rk4 or dop853; needs "
                    "CuPy and a CUDA device: pip install 'gyrochain[gpu]'), or auto: cuda where it can run, else cpu")
    sw.add_argument("--workers", type=int, default=None, metavar="N", help="start a local Dask cluster of N worker "
                    "processes (default: threads here)")
    sw.add_argument("--scheduler", default="", metavar="ADDRESS", help="an existing Dask scheduler, tcp://host:8786 "
                    "(default: none)")
    sw.add_argument("-o", "--output", required=True, metavar="STORE.zarr", help="the Zarr store (created, or resumed if "
                    "it is this sweep's; required)")
    sw.add_argument("-q", "--quiet", action="store_true", help="no progress bar (default: one on a terminal)")
    pl = sub.add_parser("plot", help="a heat map or a curve of a sweep store; the bifurcation diagram of continue's file")
    pl.add_argument("store", metavar="STORE", help="a sweep's Zarr store, or the CSV file or store of continue (its branches, "
                    "stable solid and unstable dashed, the special points labelled, and the curves in two parameters)")
    pl.add_argument("-o", "--output", required=True, metavar="FILE", help="the image: .png, .pdf or .svg (required)")
    pl.add_argument("--measure", default="", help="which array (default: the sweep's first measure)")
    pl.add_argument("--component", default="0", help="the state component of 'final': phiK, phidotK or its 0-based "
                    "index; of a diagram, the column drawn: phiK, and of periodic orbits phidotK, period or ampK (default 0: of a "
                    "diagram, the angle that moves most, of periodic orbits the amplitude)")
    pl.add_argument("--cmap", default="", help="the colour map of a map (default viridis; points without a value are "
                    "grey)")
    pl.add_argument("--log", action="store_true", help="a logarithmic scale: of the colours of a map, of the values of "
                    "a curve (default: linear)")
    pl.add_argument("--dpi", type=int, default=150, help="resolution of a PNG, dots per inch (default 150)")


def _animate(sub) -> None:
    an = sub.add_parser("animate", help="the motion as a GIF, MP4, PNG still (--frame) or an offline HTML viewer")
    an.add_argument("spec", metavar="SPEC", help="a spec file, or a sweep's store (with --at)")
    an.add_argument("-o", "--output", required=True, metavar="FILE", help="FILE.gif, FILE.mp4 (needs ffmpeg), "
                    "FILE.html or FILE.png (with --frame; required)")
    an.add_argument("--phi", default="", metavar="PHI1,..", help=PHI)
    an.add_argument("--phidot", default="", metavar="RATE1,..", help=PHIDOT)
    an.add_argument("--u", default="", metavar="U1,..", help=U)
    an.add_argument("--param", action="append", metavar="NAME=VALUE", help=PARAM)
    an.add_argument("--t1", type=float, default=None, help="end time, s (default 10, or the sweep's)")
    an.add_argument("--fps", type=float, default=25.0, help="frames per second of the animation and of its time "
                    "(default 25)")
    an.add_argument("--frame", type=float, default=None, metavar="T", help="one still at this time, s (default: an "
                    "animation)")
    an.add_argument("--at", default="", help="the point of a sweep store: NAME=VALUE,... (grid) or an index (--random); "
                    "needed with a store of more than one point (default: the only one)")
    an.add_argument("--trajectory", default="", metavar="CSV", help="a saved trajectory (t, phi1.., [phidot1..]) "
                    "instead of integrating (default: integrate)")
    an.add_argument("--size", default="480x480", metavar="WxH", help="pixels of a GIF, MP4 or PNG (default 480x480)")
    an.add_argument("--view", default="", metavar="AZIMUTH,ELEVATION", help="the camera, degrees (default: fitted to "
                    "the motion)")
    an.add_argument("--trace", type=float, default=2.0, help="seconds of the tip's trace (default 2)")
    an.add_argument("--follow", action=argparse.BooleanOptionalAction, default=None,
                    help="keep the platform's O1 in the middle of the view (default: where O1 moves farther than the "
                         "chain reaches; --no-follow for the world view)")
    an.add_argument("--rtol", type=float, default=1e-10, help="relative tolerance of DOP853 (default 1e-10)")
    an.add_argument("--force", action="store_true", help="replace an existing file animate did not write (default: "
                    "refuse)")
    an.add_argument("--yes", action="store_true", help="draw more than 10000 frames instead of stopping (default: stop)")
    an.add_argument("-q", "--quiet", action="store_true", help="no closing line (what was written, how long it took)")


def _start(sub, kinds: dict) -> None:
    ex = sub.add_parser("examples", help="list the example specs that come with the package, print one, or copy them "
                        "into a folder to start from",
                        description="Without an action: list the example specs (name, number of bodies, what it is).")
    exs = ex.add_subparsers(dest="action", metavar="ACTION", parser_class=Parser)
    exc = exs.add_parser("copy", help="copy example specs into a folder (NAME.toml; an existing file only with --force)")
    exc.add_argument("names", nargs="+", metavar="NAME", help="example names (see gyrochain examples), or all")
    exc.add_argument("-o", "--output", default=".", metavar="DIR", help="the folder (default: this one)")
    exc.add_argument("--force", action="store_true", help="replace files of the same name (default: refuse)")
    exw = exs.add_parser("show", help="print an example spec")
    exw.add_argument("name", metavar="NAME", help="an example's name (see gyrochain examples)")
    nw = sub.add_parser("new", help="write a new commented spec to start from: a pendulum, a planar or spatial chain, "
                        "with rotors, motors or a vibrating pivot")
    nw.add_argument("kind", choices=list(kinds), metavar="KIND", help="; ".join(f"{k}: {v[1]}" for k, v in kinds.items()))
    nw.add_argument("--n", type=int, default=None, help="number of links of a chain (default: the kind's)")
    nw.add_argument("--name", default="", help="the model's name, a C identifier (default: from the kind)")
    nw.add_argument("--rotor", action="store_true", help="a spinning wheel in the last link, a gyrostat (default: none)")
    nw.add_argument("--control", action="store_true", help="a motor torque in every joint, inputs u (default: none)")
    nw.add_argument("--driven", action="store_true", help="the pivot vibrates vertically, a cos(w t), parameters a, w "
                    "(default: fixed)")
    nw.add_argument("--mass", type=float, default=1.0, help="mass of each rod, kg (default 1)")
    nw.add_argument("--length", type=float, default=1.0, help="length of each rod, m (default 1)")
    nw.add_argument("-o", "--output", default="", metavar="FILE", help="the file (default NAME.toml here; - for "
                    "standard output)")
    nw.add_argument("--force", action="store_true", help=FORCE)


def _exchange(sub) -> None:
    im = sub.add_parser("import", help="a robot description (URDF or MJCF) as a spec: the revolute chain from the base "
                        "to the tip",
                        description="The spec's joint angles are the description's joint positions; fixed joints "
                        "merge their links, and with --tip every joint off the chain is locked at its zero (or "
                        "at its --lock value) and merged too. --list shows the tree to choose from.")
    im.add_argument("description", metavar="FILE", help="the URDF file, or an MJCF model (read by MuJoCo's compiler)")
    im.add_argument("--list", action="store_true", help="print the tree (links, joints, the leaves a chain can end "
                    "at) and write nothing (default: import the chain)")
    im.add_argument("-o", "--output", default="", metavar="FILE", help="the spec file (default NAME.toml here; - for "
                    "standard output)")
    im.add_argument("--base", default=None, metavar="LINK", help="the link the chain starts from (default: the root)")
    im.add_argument("--tip", default=None, metavar="LINK", help="the link it ends at; every joint off the chain is "
                    "locked (needed where the movable joints branch; default: the only leaf)")
    im.add_argument("--lock", action="append", metavar="JOINT=VALUE", help="fix a joint at a value, rad or m "
                    "(repeatable; default: none, or with --tip the joints off the chain at 0)")
    im.add_argument("--name", default="", help="the model's name, a C identifier (default: from the robot's name)")
    im.add_argument("--g", type=float, default=None, help="gravity along the description's -z, m/s^2 (default: the "
                    "MJCF model's, 9.81 for a URDF)")
    im.add_argument("--no-control", action="store_true", help="no torque inputs (default: one in every joint)")
    im.add_argument("--force", action="store_true", help=FORCE)
    xp = sub.add_parser("export", help="the spec as a robot description (URDF for Pinocchio and ROS, MJCF for MuJoCo)",
                        description="A chain on a fixed base, without rotors or loads; joint k is the spec's phi k.")
    _spec(xp)
    xp.add_argument("--to", required=True, choices=["urdf", "mjcf"], help="the format (required)")
    xp.add_argument("-o", "--output", default="", metavar="FILE", help="the file (default NAME.urdf or NAME.xml here; - "
                    "for standard output)")
    xp.add_argument("--param", action="append", metavar="NAME=VALUE", help=PARAM)
    xp.add_argument("--force", action="store_true", help=FORCE)
    fm = sub.add_parser("fmu", help="the model as an FMU (FMI 3.0 or 2.0, model exchange and co-simulation) for Modelica "
                        "tools, Simulink and FMPy")
    _spec(fm)
    fm.add_argument("-o", "--output", default="", metavar="FILE", help="the file (default NAME.fmu here)")
    fm.add_argument("--fmi", default="3", choices=["3", "2"], help="the FMI version: 3 (default) or 2")
    fm.add_argument("--kind", default="me,cs", help="me, cs or me,cs: model exchange, co-simulation (default me,cs)")
    fm.add_argument("--real", default="double", choices=["double", "float"], help="the floating type (default double; "
                    "float is refused: FMI is double)")
    fm.add_argument("--param", action="append", metavar="NAME=VALUE", help="a parameter's start value (repeatable; "
                    "default: the spec's [values])")
    fm.add_argument("--input", action="append", metavar="NAME", help="a parameter as a piecewise-constant input "
                    "(repeatable; default: none)")
    fm.add_argument("--add-output", action="append", choices=["tip"], help="an output more: tip, Gn in frame 0 "
                    "(repeatable; default: none)")
    fm.add_argument("--force", action="store_true", help=FORCE)


def _identify(sub) -> None:
    idf = sub.add_parser("identify", help="estimate the base parameters from a measured motion (CSV: t, phi1.., u1..) "
                         "and write the spec with them", description="The torques u1.. are those of the controlled joints, "
                         "in chain order, each the torque at its row's t; a joint without a control has u = 0.  phi is "
                         "filtered and differentiated, u filtered alike (--filter; phidot1.. are used when the file has them).")
    _spec(idf)
    idf.add_argument("data", metavar="DATA.csv", help="the measured motion: CSV with columns t, phi1..phiN[, "
                     "phidot1..phidotN], u1..u_nu")
    idf.add_argument("-o", "--output", default="", metavar="FILE", help="the identified spec (default "
                     "NAME_identified.toml here)")
    idf.add_argument("--validate", default=None, metavar="HELD.csv", help="held-out data: predicted torques and a "
                     "simulated motion against it (default: none)")
    idf.add_argument("--plot", default=None, metavar="FILE.png", help="with --validate: the comparison as a picture "
                     "(default: none)")
    idf.add_argument("--filter", default="butter", choices=["butter", "savgol"], help="how phi is smoothed and "
                     "differentiated (u alike): a zero-phase Butterworth low-pass and central differences (default), or "
                     "a Savitzky-Golay filter")
    idf.add_argument("--cutoff", type=float, default=None, help="--filter butter: the cutoff, Hz (default 5)")
    idf.add_argument("--window", type=float, default=None, help="--filter savgol: the window, s (default 0.2)")
    idf.add_argument("--order", type=int, default=4, help="the Butterworth's order or the polynomial's (default 4)")
    idf.add_argument("--physical", action="store_true", help="constrain the estimates to physically possible bodies "
                     "(positive masses, realisable inertias; default: unconstrained least squares)")
    idf.add_argument("--param", action="append", metavar="NAME=VALUE", help=PARAM)
    idf.add_argument("--force", action="store_true", help="replace existing output files (default: refuse)")
    exc = sub.add_parser("excite", help="a periodic excitation that makes the base parameters well determined (CSV "
                         "for the controller to track)", description="Every joint controlled: the joints' trajectories "
                         "(Fourier series, Swevers et al. 1997) with the torques the spec's parameters need; otherwise "
                         "the controlled joints' torques, with the motion they give.  Minimises cond of the base regressor.")
    _spec(exc)
    exc.add_argument("-o", "--output", default="", metavar="FILE", help="the CSV (default NAME_excite.csv here; - for "
                     "standard output)")
    exc.add_argument("--period", type=float, default=10.0, help="the period, s (default 10)")
    exc.add_argument("--harmonics", type=int, default=5, help="harmonics per joint (default 5)")
    exc.add_argument("--phi-max", default="", metavar="A or A1,..", help="|phi - centre| limits, rad: one number or one "
                     "per joint (default: 90%% of the way to the spec's range, else 1)")
    exc.add_argument("--phidot-max", default="", metavar="W or W1,..", help="|phidot| limits, rad/s (default: 90%% of the "
                     "spec's velocity limit, else 2)")
    exc.add_argument("--u-max", default="", metavar="U or U1,..", help="|u| limits of a chain with passive joints, N m "
                     "(default: 90%% of the spec's effort limit, else 1)")
    exc.add_argument("--center", default="", metavar="C or C1,..", help="the centre of the motion, rad (default: the "
                     "middle of the spec's range, else 0)")
    exc.add_argument("--samples", type=int, default=200, help="samples per period (default 200)")
    exc.add_argument("--evaluations", type=int, default=2000, help="the optimiser's budget (default 2000)")
    exc.add_argument("--seed", type=int, default=0, help="the start's seed (default 0)")
    exc.add_argument("--param", action="append", metavar="NAME=VALUE", help=PARAM)
    exc.add_argument("--force", action="store_true", help=FORCE)
    exc.add_argument("--experiment", type=float, default=None, metavar="SECONDS", help="write instead a simulated "
                     "measurement of the design on the spec's own model, that long: t, phi, u, what identify reads "
                     "(default: the design)")
    exc.add_argument("--rate", type=float, default=None, help="--experiment: samples per second (default 1000)")
    exc.add_argument("--noise", type=float, default=None, help="--experiment: the torques' noise, a fraction of their RMS "
                     "(default 0.01)")
    exc.add_argument("--encoder", type=int, default=None, help="--experiment: counts per turn of the angles (default "
                     "4096; 0: exact)")
