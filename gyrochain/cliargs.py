"""The command line's small parsers, shared by the commands in cli.py: comma-separated numbers,
name=value options, an option given once, sizes, and argparse's words turned into the form of every
other error (``<what>: <why>``); the heartbeat of a long command on a terminal."""
from __future__ import annotations

import argparse
import math
import re
import sys
import time

from .errors import did_you_mean
from .spec import SpecError


def floats(text: str, what: str, count: int) -> list[float]:
    try:
        vals = [float(v) for v in text.split(",")] if text else [0.0] * count
    except ValueError:
        raise SpecError(what, f"expected {count} comma-separated numbers") from None
    if len(vals) != count:
        raise SpecError(what, f"expected {count} comma-separated numbers, got {len(vals)}")
    return finite(vals, what)


def float_list(text: str, what: str) -> list[float] | None:
    """Comma-separated numbers, or None when the option was not given (its count is checked
    where the spec is known)."""
    if not text:
        return None
    try:
        vals = [float(v) for v in text.split(",")]
    except ValueError:
        raise SpecError(what, "expected comma-separated numbers") from None
    return finite(vals, what)


def finite(vals: list[float], what: str) -> list[float]:
    if not all(math.isfinite(v) for v in vals):
        raise SpecError(what, "expected finite numbers, got " + ",".join(f"{v:g}" for v in vals))
    return vals


def one(what: str, given: list | None, why: str) -> None:
    """An option that may be given once: a second one is refused, not silently taken for the first."""
    if given and len(given) > 1:
        raise SpecError(what, f"given {len(given)} times ({', '.join(given)}); {why}")


def params_of(items, what: str = "--param") -> dict:
    """name=number options (--param) as a dict (the names and values are checked against the
    spec by physical.run_values)."""
    params = {}
    for item in items or []:
        key, eq, val = item.partition("=")
        key = key.strip()
        if key in params:
            raise SpecError(f"{what} {key}", "given twice")
        try:
            if not (eq and key):
                raise ValueError
            params[key] = float(val)
        except ValueError:
            raise SpecError(f"{what} {item}", "expected name=number") from None
    return params


def size(text: str) -> tuple[int, int]:
    w, x, h = text.lower().partition("x")
    try:
        size = (int(w), int(h)) if x else (0, 0)
    except ValueError:
        size = (0, 0)
    if not (64 <= size[0] <= 4096 and 64 <= size[1] <= 4096) or size[0] % 2 or size[1] % 2:
        raise SpecError("--size", f"{text!r}: expected WIDTHxHEIGHT, even numbers of pixels from 64 to 4096")
    return size


def unrecognized(extra: list[str], parser: argparse.ArgumentParser) -> str:
    """The first word a command does not know, and the option of the command nearest to it."""
    word = extra[0].split("=", 1)[0]
    if not word.startswith("-"):
        return f"{word}: unexpected argument"
    hint = did_you_mean(word, [o for a in parser._actions for o in a.option_strings])
    return f"{word}: no such option of {parser.prog}" + (f"; {hint.strip()}" if hint else "")


_CHOICE = re.compile(r"^argument (?P<what>[^:]+): invalid choice: '(?P<got>[^']*)' \(choose from (?P<among>.*)\)$")


def plain(message: str) -> str:
    """argparse's words in the form of every other error, ``<what>: <why>``: "argument --t1:
    invalid float value: 'x'" → "--t1: invalid float value: 'x'", and a mistyped choice answered
    with the nearest one ("command: no such command 'chek'; did you mean check? ...")."""
    m = _CHOICE.match(message)
    if m:
        among = [c.strip(" '") for c in m["among"].split(",")]
        what = "command" if m["what"] == "cmd" else m["what"]
        hint = did_you_mean(m["got"], among)
        return f"{what}: no such {'command' if what == 'command' else 'choice'} '{m['got']}'; {hint}one of {', '.join(among)}"
    return message.removeprefix("argument ")


_NEGATIVE = re.compile(r"^-(\.?\d|inf|nan)", re.IGNORECASE)


def join_negative(argv: list[str], valued: set) -> list[str]:
    """``--phi -1,0`` → ``--phi=-1,0`` for every option that takes a value (argparse takes "-1,0",
    "-1e3" or "-inf" for an option)."""
    out, i = [], 0
    while i < len(argv):
        a = argv[i]
        if a in valued and i + 1 < len(argv) and _NEGATIVE.match(argv[i + 1]):
            out.append(f"{a}={argv[i + 1]}")
            i += 2
            continue
        out.append(a)
        i += 1
    return out


def valued_options(parser: argparse.ArgumentParser) -> set:
    """The option strings of ``parser`` and its subcommands that take a value."""
    out = set()
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for sub in action.choices.values():
                out |= valued_options(sub)
        elif action.option_strings and action.nargs != 0:
            out |= {o for o in action.option_strings if o.startswith("--")}
    return out


class ClearsFirst:
    """stdout that stops the heartbeat (and clears its line) before the command's first output."""

    def __init__(self, stream, beat):
        self._stream, self._beat = stream, beat

    def write(self, text):
        self._beat.stop()
        return self._stream.write(text)

    def __getattr__(self, name):
        return getattr(self._stream, name)


class Heartbeat:
    """On a terminal, a command that runs longer than two seconds says so on stderr, once a second,
    on one line it rewrites ("steady: working, 12 s; Ctrl-C stops it"), and clears the line when
    it ends: a long run is never silent.  Not on a pipe or a file (scripts and tests see nothing)."""

    def __init__(self, name: str, after: float = 2.0):
        import threading

        self.name, self.after, self.t0 = name, after, time.perf_counter()
        self.done, self.shown, self.lock = threading.Event(), False, threading.Lock()
        self.running = sys.stderr.isatty()
        if self.running:
            threading.Thread(target=self._run, name="gyrochain-heartbeat", daemon=True).start()

    def _run(self) -> None:
        if self.done.wait(self.after):
            return
        while True:
            with self.lock:
                if self.done.is_set():
                    return
                sys.stderr.write(f"\r{self.name}: working, {time.perf_counter() - self.t0:.0f} s; Ctrl-C stops it ")
                sys.stderr.flush()
                self.shown = True
            self.done.wait(1.0)

    def stop(self) -> None:
        with self.lock:
            self.done.set()
            if self.shown:
                sys.stderr.write("\r\033[K")
                sys.stderr.flush()
                self.shown = False


def add_exchange(sub) -> None:
    """The parsers of the commands that exchange a model with other tools: import, export, fmu."""
    im = sub.add_parser("import", help="a robot description (URDF) as a spec: the revolute chain from the base to the tip",
                        description="The spec's joint angles are the description's joint positions; fixed joints "
                        "merge their links, and a joint the paper's chain cannot have must be locked.")
    im.add_argument("description", help="the URDF file")
    im.add_argument("-o", "--output", default="", help="the spec file (default NAME.toml here; - for standard output)")
    im.add_argument("--base", default=None, help="the link the chain starts from (default: the root)")
    im.add_argument("--tip", default=None, help="the link it ends at (needed where the movable joints branch)")
    im.add_argument("--lock", action="append", metavar="JOINT=VALUE", help="fix a joint at a value (repeatable)")
    im.add_argument("--name", default="", help="the model's name, a C identifier (default: from the robot's name)")
    im.add_argument("--g", type=float, default=9.81, help="gravity along the description's -z (default 9.81)")
    im.add_argument("--no-control", action="store_true", help="no torque inputs (default: one in every joint)")
    im.add_argument("--force", action="store_true", help="replace an existing file")
    xp = sub.add_parser("export", help="the spec as a robot description (URDF for Pinocchio and ROS, MJCF for MuJoCo)",
                        description="A chain on a fixed base, without rotors or loads; joint k is the spec's phi k.")
    xp.add_argument("spec")
    xp.add_argument("--to", required=True, choices=["urdf", "mjcf"], help="the format")
    xp.add_argument("-o", "--output", default="", help="the file (default NAME.urdf or NAME.xml here; - for standard output)")
    xp.add_argument("--param", action="append", metavar="NAME=VALUE", help="a parameter's value (repeatable)")
    xp.add_argument("--force", action="store_true", help="replace an existing file")
    fm = sub.add_parser("fmu", help="the model as an FMU (FMI 3.0 or 2.0, model exchange and co-simulation) for Modelica "
                        "tools, Simulink and FMPy")
    fm.add_argument("spec")
    fm.add_argument("-o", "--output", default="", help="the file (default NAME.fmu here)")
    fm.add_argument("--fmi", default="3", choices=["3", "2"], help="the FMI version: 3 (default) or 2")
    fm.add_argument("--kind", default="me,cs", help="me, cs or me,cs (default): model exchange, co-simulation")
    fm.add_argument("--real", default="double", choices=["double", "float"], help="float is refused: FMI is double")
    fm.add_argument("--param", action="append", metavar="NAME=VALUE", help="a parameter's start value (repeatable)")
    fm.add_argument("--input", action="append", metavar="NAME", help="a parameter as a piecewise-constant input (repeatable)")
    fm.add_argument("--add-output", action="append", choices=["tip"], help="an output more: tip (Gⁿ in frame 0; repeatable)")
    fm.add_argument("--force", action="store_true", help="replace an existing file")


def add_identify(sub) -> None:
    """The parsers of identify and excite (parameter identification, identify.py)."""
    idf = sub.add_parser("identify", help="estimate the base parameters from a measured motion (CSV: t, phi1.., u1..) "
                         "and write the spec with them", description="The torques u1.. are those of the controlled joints, "
                         "in chain order, each the torque at its row's t; a joint without a control has u = 0.  phi is "
                         "filtered and differentiated, u filtered alike (--filter; phidot1.. are used when the file has them).")
    idf.add_argument("spec")
    idf.add_argument("data", help="the measured motion: CSV with columns t, phi1..phiN[, phidot1..phidotN], u1..u_nu")
    idf.add_argument("-o", "--output", default="", help="the identified spec (default NAME_identified.toml here)")
    idf.add_argument("--validate", default=None, metavar="HELD.csv", help="held-out data: predicted torques and a "
                     "simulated motion against it")
    idf.add_argument("--plot", default=None, metavar="FILE.png", help="with --validate: the comparison as a picture")
    idf.add_argument("--filter", default="butter", choices=["butter", "savgol"], help="how phi is smoothed and "
                     "differentiated (u alike): a zero-phase Butterworth low-pass and central differences (default), or "
                     "a Savitzky-Golay filter")
    idf.add_argument("--cutoff", type=float, default=5.0, help="the Butterworth's cutoff in Hz (default 5)")
    idf.add_argument("--window", type=float, default=0.2, help="the Savitzky-Golay window in seconds (default 0.2)")
    idf.add_argument("--order", type=int, default=4, help="the Butterworth's order or the polynomial's (default 4)")
    idf.add_argument("--physical", action="store_true", help="constrain the estimates to physically possible bodies "
                     "(positive masses, realisable inertias)")
    idf.add_argument("--param", action="append", metavar="NAME=VALUE", help="a parameter's value (repeatable)")
    idf.add_argument("--force", action="store_true", help="replace existing output files")
    exc = sub.add_parser("excite", help="a periodic excitation that makes the base parameters well determined (CSV "
                         "for the controller to track)", description="Every joint controlled: the joints' trajectories "
                         "(Fourier series, Swevers et al. 1997) with the torques the spec's parameters need; otherwise "
                         "the controlled joints' torques, with the motion they give.  Minimises cond of the base regressor.")
    exc.add_argument("spec")
    exc.add_argument("-o", "--output", default="", help="the CSV (default NAME_excite.csv here; - for standard output)")
    exc.add_argument("--period", type=float, default=10.0, help="the period (s; default 10)")
    exc.add_argument("--harmonics", type=int, default=5, help="harmonics per joint (default 5)")
    exc.add_argument("--phi-max", default="", help="|phi - centre| limits (rad): one number or one per joint (default 1)")
    exc.add_argument("--phidot-max", default="", help="|phidot| limits (rad/s; default 2)")
    exc.add_argument("--u-max", default="", help="|u| limits of a chain with passive joints (N m; default 1)")
    exc.add_argument("--center", default="", help="the centre of the motion (rad; default 0)")
    exc.add_argument("--samples", type=int, default=200, help="samples per period (default 200)")
    exc.add_argument("--evaluations", type=int, default=2000, help="the optimiser's budget (default 2000)")
    exc.add_argument("--seed", type=int, default=0, help="the start's seed")
    exc.add_argument("--param", action="append", metavar="NAME=VALUE", help="a parameter's value (repeatable)")
    exc.add_argument("--force", action="store_true", help="replace an existing file")
    exc.add_argument("--experiment", type=float, default=None, metavar="SECONDS", help="write instead a simulated "
                     "measurement of the design on the spec's own model, that long (t, phi, u: what identify reads)")
    exc.add_argument("--rate", type=float, default=1000.0, help="--experiment: samples per second (default 1000)")
    exc.add_argument("--noise", type=float, default=0.01, help="--experiment: the torques' noise, a fraction of their RMS "
                     "(default 0.01)")
    exc.add_argument("--encoder", type=int, default=4096, help="--experiment: counts per turn of the angles (default "
                     "4096; 0: exact)")
