"""Fuzzing the commands as users meet them: every example spec mutated (fields dropped,
renamed, duplicated; wrong types; NaN, ±inf, huge and tiny numbers; empty, unicode and very long
strings; expression bombs; wrong vector shapes; n = 0 and n = 40), and command lines for every
command built from valid and invalid options.  The property: exit 0, or exit 2 with one line
``error: …`` on stderr — never a traceback, never exit 1 (an internal error) — nothing written
unless the command succeeded, and within a time bound.

`make test` runs a fixed-seed, bounded search (derandomized: the same inputs every run); `make fuzz`
searches with fresh seeds for FUZZ_SECONDS (default 600) and prints how many inputs it tried.
What a search found is kept below as regular tests (test_found_*)."""
from __future__ import annotations

import contextlib
import copy
import io
import math
import os
import signal
import time
import tomllib
from pathlib import Path

import pytest

hypothesis = pytest.importorskip("hypothesis", reason="the test extra (hypothesis) is not installed")
tomli_w = pytest.importorskip("tomli_w", reason="the test extra (tomli-w) is not installed")
from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from gyrochain.cli import main  # noqa: E402
from conftest import ROOT  # noqa: E402

SPECS = ROOT / "specs"
EXAMPLES = sorted(SPECS.glob("*.toml"))
LONG = float(os.environ.get("FUZZ_SECONDS", "0"))  # > 0: `make fuzz`
TRIED = {"spec": 0, "command": 0}


class TimeBound(Exception):
    pass


@contextlib.contextmanager
def time_bound(seconds: float):
    def alarm(signum, frame):
        raise TimeBound(f"no answer within {seconds} s")
    old = signal.signal(signal.SIGALRM, alarm)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)


def run(args, seconds: float):
    out, err = io.StringIO(), io.StringIO()
    t0 = time.perf_counter()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err), time_bound(seconds):
        try:
            code = main([str(a) for a in args])
        except SystemExit as exc:
            code = exc.code
    return code, out.getvalue(), err.getvalue(), time.perf_counter() - t0


def holds(args, folder: Path, seconds: float, written=()):
    """The property, for one command line run in ``folder`` (its outputs go there)."""
    before = set(folder.iterdir())
    code, out, err, dt = run(args, seconds)
    assert "Traceback" not in err, (args, err)
    if code == 0:
        return code, out, err
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert code == 2, (args, code, err)
    assert len(lines) == 1 and lines[0].startswith("error: "), (args, err)
    assert set(folder.iterdir()) == before, (args, "wrote something on a failure")
    return code, out, err


# --------------------------------------------------------------------------- specs
def _leaves(obj, path=()):
    """Every (path, value) of a parsed spec, tables and lists included."""
    yield path, obj
    if isinstance(obj, dict):
        for k, v in obj.items():
            yield from _leaves(v, path + (k,))
    elif isinstance(obj, list):
        for i, v in enumerate(obj):
            yield from _leaves(v, path + (i,))


def _get(obj, path):
    for p in path:
        obj = obj[p]
    return obj


BOMBS = ["9**9**9", "(" * 60 + "1" + ")" * 60, "1e308*1e308", "sqrt(-1)", "1/0", "0**-1", "x" * 300, "a" * 10_000,
         "-" * 150 + "1", "2**16**2", "sin(" * 30 + "1" + ")" * 30, "__import__('os')", "pi**pi**pi", "1e-400",
         "open('x')", "lambda: 1", "[1, 2]", "m1.real", "phi1", "phidot9", "t", "nan", "inf", "E", "I", "φ", "m₁", ""]
NUMBERS = [math.nan, math.inf, -math.inf, 1e308, -1e308, 1e-308, 5e-324, 0.0, -0.0, -1.0, 1e20, 0, -1, 2**70, 1e-12]
STRINGS = ["", " ", "ünïcödé", "日本", "\x00", "a" * 100_000, "1,2", "true", "pi/2", "-pi"]
VALUES = st.one_of(st.sampled_from(NUMBERS), st.sampled_from(BOMBS), st.sampled_from(STRINGS),
                   st.booleans(), st.integers(-10**20, 10**20), st.floats(allow_nan=True, allow_infinity=True),
                   st.lists(st.floats(-10, 10), max_size=5), st.builds(dict), st.builds(lambda: {"x": 1}), st.text(max_size=40))
# (fresh dicts: a shared st.just({...}) mutated by a later step made the generation depend on earlier cases)


@st.composite
def mutated_spec(draw):
    """One example spec, mutated one to four times."""
    data = tomllib.loads(draw(st.sampled_from(EXAMPLES)).read_text())
    for _ in range(draw(st.integers(1, 4))):
        kind = draw(st.sampled_from(["drop", "rename", "duplicate", "value", "shape", "n0", "n40", "values", "unknown",
                                     "armature", "limits"]))
        paths = [p for p, _ in _leaves(data) if p]
        if kind == "n0":
            data["body"] = []
            continue
        if kind == "n40" and isinstance(data.get("body"), list) and data["body"] and isinstance(data["body"][0], dict):
            one = copy.deepcopy(data["body"][0])
            one.setdefault("s", [0.0, 0.0, 0.1])
            last = copy.deepcopy(data["body"][-1])
            data["body"] = [copy.deepcopy(one) for _ in range(39)] + [last]
            continue
        if kind == "values":
            data["values"] = draw(st.dictionaries(st.sampled_from(["a", "w", "m2", "Omega", "nan", "x", ""]), VALUES, max_size=3))
            continue
        if kind == "unknown":
            data[draw(st.sampled_from(["colour", "Body", "bodies", "n"]))] = 1
            continue
        if kind in ("armature", "limits") and isinstance(data.get("body"), list) and data["body"]:
            body = data["body"][draw(st.integers(0, len(data["body"]) - 1))]
            if isinstance(body, dict):  # a motor's inertia, or a joint's limits (any keys, any values)
                body[kind] = draw(VALUES) if kind == "armature" or draw(st.booleans()) else draw(st.dictionaries(
                    st.sampled_from(["lower", "upper", "velocity", "effort", "uper", ""]), VALUES, max_size=4))
            continue
        if not paths:
            continue
        path = draw(st.sampled_from(paths))
        parent, key = _get(data, path[:-1]), path[-1]
        if kind == "drop":
            del parent[key]
        elif kind == "rename" and isinstance(parent, dict):
            parent[draw(st.sampled_from(["mass", "A ", "Theta", "lambda_", "I", "c2", ""]))] = parent.pop(key)
        elif kind == "duplicate" and isinstance(parent, list):
            parent.insert(key, copy.deepcopy(parent[key]))
        elif kind == "shape":
            v = parent[key]
            parent[key] = (v + v[:1] if draw(st.booleans()) else v[:-1]) if isinstance(v, list) and v else [v, v]
        else:
            parent[key] = draw(VALUES)
    return data


def _toml(data) -> str | None:
    try:
        return tomli_w.dumps(data)
    except (TypeError, ValueError):  # a value TOML cannot hold (\x00 in a key, ...): not a file a user can write
        return None


def spec_property(data, folder: Path):
    text = _toml(data)
    if text is None:
        return
    TRIED["spec"] += 1
    path = folder / "spec.toml"
    path.write_text(text, encoding="utf-8")
    code, out, err = holds(["check", path], folder, 20)
    if code == 0:
        assert out.startswith(f"{path}: ok ("), out
        n = len(data["body"])
        if n <= 3:  # a spec that passes check derives (generate without the compiler), within seconds
            holds(["generate", path, "--no-build", "-q", "-o", folder / "out"], folder, 120)


# --------------------------------------------------------------------------- command lines
NUM = st.sampled_from(["0", "1", "-1", "0.05", "nan", "inf", "-inf", "1e300", "x", "", "1,2", "-0.5"])
LIST = st.sampled_from(["0,0", "-1,0", "0.1,-0.2", "1", "1,2,3", "nan,0", "a,b", "", ",", "1e400,0", "-.5,.5"])
PARAM = st.sampled_from(["m=2", "a=0.01", "w=260", "a=-1", "w=nan", "m2=-0.1", "m2=0.2", "Omega=3", "=1", "a", "a==1", "P=4"])
VARY = st.sampled_from(["phi1=0:1:3", "phi1=-1:1:2", "phi2=0:1:0", "phi1=1:0:3", "phi9=0:1:2", "a=0:0.02:2", "m2=-1:1:3",
                        "phi1=0:1", "phi1=nan:1:2", "phidot1=0:1:2", "x", "phi1=0:1:10000000000"])
# (a grid of 1e8 points is a legitimate hours-long job: the searches offer sizes that must be refused)
SPEC_ARG = st.sampled_from([SPECS / "gimbal.toml", SPECS / "furuta_sym.toml", SPECS / "kapitza.toml", SPECS / "furuta.toml",
                            SPECS / "nope.toml", SPECS, ROOT / "README.md"])
OPTIONS = {
    "check": {},
    "simulate": {"--t1": st.sampled_from(["0.05", "0", "-1", "nan", "x", "0.2"]), "--steps": st.sampled_from(["1", "5", "0", "-5", "x"]),
                 "--phi": LIST, "--phidot": LIST, "--u": LIST, "--param": PARAM, "--method": st.sampled_from(["rk4", "dop853", "euler", "gauss2"]),
                 "--h": st.sampled_from(["0.01", "0", "-1", "nan"]), "--rtol": NUM, "--atol": NUM, "--reference": None},
    "steady": {"--u": LIST, "--param": PARAM, "--omega": st.sampled_from(["-5:5:3", "5:1:3", "x", "0:1:1"]),
               "--start": LIST, "--no-rotations": None},
    "sweep": {"--vary": VARY, "--random": st.sampled_from(["0", "3", "-1"]), "--t1": st.sampled_from(["0.05", "0", "nan"]),
              "--measure": st.sampled_from(["final", "flip_time", "energy_error", "lyapunov", "bogus"]),
              "--method": st.sampled_from(["rk4", "dop853", "x"]), "--h": st.sampled_from(["0.01", "0", "-1"]),
              "--phi": LIST, "--u": LIST, "--param": PARAM, "--chunk": st.sampled_from(["1", "0", "-3", "100"]),
              "--threads": st.sampled_from(["1", "0", "-1"]), "--samples": st.sampled_from(["10", "0"]),
              "--lyap-interval": st.sampled_from(["0.01", "0", "10"]), "-q": None},
    "animate": {"--t1": st.sampled_from(["0.2", "0", "-1", "nan"]), "--fps": st.sampled_from(["10", "0", "-5", "nan"]),
                "--frame": st.sampled_from(["0", "0.1", "-1", "2", "nan"]), "--phi": LIST, "--phidot": LIST, "--u": LIST,
                "--param": PARAM, "--size": st.sampled_from(["64x64", "65x64", "0x0", "x", "64"]),
                "--view": LIST, "--trace": st.sampled_from(["0", "-1", "nan", "0.1"]), "--follow": None,
                "--at": st.sampled_from(["", "phi1=0", "0"]), "-q": None},
    "plot": {"--measure": st.sampled_from(["final", "bogus", "flip_time"]), "--component": st.sampled_from(["0", "-1", "99"]),
             "--cmap": st.sampled_from(["viridis", "magam"]), "--log": None, "--dpi": st.sampled_from(["50", "0", "100000"])},
}
RANGE = st.sampled_from(["0.1:1:3", "1:0:3", "0:1:1", "x", "0:1:1000000000", "nan:1:2", "1e6:1e7:2", "0.5:1:2"])
OPTIONS.update({
    "simulate": {**OPTIONS["simulate"], "--t1": st.sampled_from(["0.05", "0", "-1", "nan", "x", "0.2", "1e4", "1e300"]),
                 "--steps": st.sampled_from(["1", "5", "0", "-5", "x", "100000000"]),
                 "--method": st.sampled_from(["rk4", "dop853", "euler", "gauss2", "gauss2_symplectic"]),
                 "--h": st.sampled_from(["0.01", "0", "-1", "nan", "5", "1e-12"])},
    "steady": {**OPTIONS["steady"], "--vary": st.sampled_from(["w=100:300:3", "a=-1:1:3", "m2=-1:1:3", "w=1:2:100000000", "x=1:2:3", "w"]),
               "--period": st.sampled_from(["1e-9", "0", "-1", "nan", "0.02416609734", "0.1", "x"])},
    "orbits": {"--at": LIST, "--energy": RANGE, "--mode": st.sampled_from(["1", "0", "-1", "9", "x"]),
               "--vary": st.sampled_from(["m2=0.1:0.2:2", "m2=-1:1:3", "x"]), "--omega": st.sampled_from(["1", "0:1:2", "x", "nan"]),
               "--u": LIST, "--param": PARAM},
    "sweep": {**OPTIONS["sweep"], "--workers": st.sampled_from(["0", "-1"]), "--scheduler": st.sampled_from(["tcp://127.0.0.1:1", "x", ""]),
              "--flip": st.sampled_from(["phi1", "phi9", ""]), "--angles": st.sampled_from(["auto", "relative", "bogus"]),
              "--seed": st.sampled_from(["0", "-1", "x"]), "--samples": st.sampled_from(["10", "0", "1000000000"]),
              "--lyap-interval": st.sampled_from(["0.01", "0", "10", "1e-9"])},
    "generate": {"--no-build": None, "-q": None, "--force": None, "--qdd-form": st.sampled_from(["auto", "composite", "bogus"]),
                 "--derivative-form": st.sampled_from(["auto", "world", "forward"]), "--real": st.sampled_from(["double", "float", "half"])},
    "new": {"--n": st.sampled_from(["1", "3", "0", "65", "x"]), "--name": st.sampled_from(["x1", "math", "int", "a b", ""]),
            "--rotor": None, "--control": None, "--driven": None, "--mass": NUM, "--length": NUM, "--force": None},
})
ROBOTS = SPECS / "robots"
CORPUS = sorted((ROOT / "tests" / "robots").glob("*/*.urdf")) + sorted((ROOT / "tests" / "mjcf" / "dm_control").glob("*.xml"))
URDF_ARG = st.sampled_from([ROBOTS / "ur5_robot.urdf", ROBOTS / "panda.urdf", ROBOTS / "double_pendulum.urdf", ROBOTS / "xarm7.urdf",
                            ROBOTS / "missing.urdf", ROBOTS, SPECS / "gimbal.toml", ROBOTS / "README.md", *CORPUS,
                            *sorted((ROOT / "tests" / "mjcf" / "styled").glob("*.xml"))])  # MJCF written with armature and ref
OPTIONS.update({
    "import": {"--tip": st.sampled_from(["wrist_3_link", "panda_link7", "panda_lnk7", "link1", "base_link", "", "FL_FOOT",
                                         "FL_foot", "LF_FOOT", "left_hand_link", "arm_left_7_link", "l_sole", "lower_arm",
                                         "bfoot", "foot", "distal", "fingertip", "wrist3", "left_foot", "pole"]),
               "--base": st.sampled_from(["world", "shoulder_link", "nowhere", "panda_link0", "", "torso", "base", "cart"]),
               "--lock": st.sampled_from(["panda_finger_joint1=0.02", "panda_finger_joint2=0.02", "joint1=0.3", "elbow_joint=x",
                                          "nope=1", "=1", "panda_finger_joint1=nan", "shoulder_pan_joint=1e300",
                                          "panda_finger_joint1=5", "FR_HAA=0.3", "torso_1_joint=-9", "slider=0.5"]),
               "--list": None,
               "--name": st.sampled_from(["arm", "int", "1x", "a b", ""]), "--g": NUM, "--no-control": None, "--force": None},
    "export": {"--to": st.sampled_from(["urdf", "mjcf", "sdf", ""]), "--param": PARAM, "--force": None},
})
CSV_ARG = st.sampled_from(["@DATA@/data.csv", "@DATA@/held.csv", "@DATA@/missing.csv", "@DATA@/furuta.toml", "@DATA@"])
OPTIONS.update({
    "excite": {"--period": st.sampled_from(["5", "0", "-1", "nan", "1e9", "x"]), "--harmonics": st.sampled_from(["1", "3", "0", "-2"]),
               "--phi-max": st.sampled_from(["1", "0", "-1", "0.5,0.5", "1,2,3", "nan"]),
               "--phidot-max": st.sampled_from(["2", "0", "x", "1,1"]), "--u-max": st.sampled_from(["0.05", "0", "-1", "1,2"]),
               "--center": st.sampled_from(["0", "0,0", "1,2,3", "nan,0"]), "--samples": st.sampled_from(["50", "1", "0", "10000000"]),
               "--evaluations": st.sampled_from(["5", "0", "-1"]), "--seed": st.sampled_from(["0", "-1", "x"]),
               "--experiment": st.sampled_from(["1", "0", "-1", "1e9", "nan"]), "--rate": st.sampled_from(["200", "0", "-1", "1e9"]),
               "--noise": st.sampled_from(["0.01", "-1", "nan"]), "--encoder": st.sampled_from(["4096", "0", "-1"]),
               "--param": PARAM, "--force": None},
    "identify": {"--validate": CSV_ARG, "--plot": st.sampled_from(["fit.png", "fit.svg", "fit.toml", "@DATA@/data.csv.png", ""]),
                 "--filter": st.sampled_from(["butter", "savgol", "kalman"]), "--cutoff": NUM, "--window": NUM,
                 "--order": st.sampled_from(["4", "1", "9", "x"]), "--physical": None, "--param": PARAM, "--force": None},
})
OUTPUTS = {"sweep": ["s.zarr", "sub/s.zarr", ""], "animate": ["a.gif", "a.png", "a.html", "a.avi", "sub/a.gif", ""],
           "plot": ["p.png", "p.jpgg", "sub/p.svg", ""], "generate": ["g", "sub/g", ""], "new": ["n.toml", "-", "sub/n.toml"],
           "import": ["i.toml", "-", "sub/i.toml", ""], "export": ["e.urdf", "e.xml", "-", "sub/e.urdf", ""],
           "excite": ["x.csv", "-", "sub/x.csv", ""], "identify": ["id.toml", "sub/id.toml", ""]}
# (never into the recordings' folder: a --force there would change the inputs of the cases after it)
NEW_KINDS = st.sampled_from(["pendulum", "double-pendulum", "chain", "spatial-chain", "chian", ""])


@st.composite
def command_line(draw):
    cmd = draw(st.sampled_from(sorted(OPTIONS)))
    args = [cmd, draw(NEW_KINDS) if cmd == "new" else draw(URDF_ARG) if cmd == "import" else draw(SPEC_ARG)]
    if cmd == "identify":
        args.append(draw(CSV_ARG))
    opts = OPTIONS[cmd]
    for name in draw(st.lists(st.sampled_from(sorted(opts)), max_size=4)) if opts else []:
        args.append(name)
        if opts[name] is not None:
            args.append(draw(opts[name]))
    if cmd in OUTPUTS:
        out = draw(st.sampled_from(OUTPUTS[cmd]))
        if out:
            args += ["-o", f"@OUT@/{out}"]
    if cmd == "sweep" and "--vary" not in args and draw(st.booleans()):
        args += ["--vary", "phi1=0:0.5:2"]
    if cmd == "animate" and draw(st.booleans()):
        args += ["--frame", "0.05", "--size", "64x64"]
    return args


COVERED: dict = {}  # command → how many lines of it a search ran


def command_property(args, folder: Path, store: Path, bench: Path):
    TRIED["command"] += 1
    COVERED[args[0]] = COVERED.get(args[0], 0) + 1
    args = [str(a).replace("@OUT@", str(folder)).replace("@DATA@", str(bench)) for a in args]
    if args[0] == "excite" and "--evaluations" not in args:  # its default (2000 designs) is minutes of legitimate work
        args += ["--evaluations", "5", "--samples", "40"]
    if args[0] == "plot":
        args[1] = str(store)
    if args[0] == "generate" and "-o" not in args:  # never into the repository's generated/
        args += ["-o", str(folder / "g")]
    with contextlib.chdir(folder):  # a default output (NAME.toml, NAME_excite.csv) lands in the case's folder
        holds(args, folder, 120)


@st.composite
def damage(draw):
    """A sweep store hurt as disks and interruptions hurt it: a chunk file cut short, flipped bits,
    a chunk file gone, the done flags gone."""
    return draw(st.sampled_from(["truncate", "flip", "remove", "done"])), draw(st.integers(0, 5)), draw(st.integers(0, 10**6))


def damaged_store_property(how, store: Path, folder: Path):
    """plot and the sweep's rerun on a damaged copy of the store: a picture with the missing points
    said, or one line; the rerun repairs it (every chunk done and readable afterwards)."""
    import shutil

    from gyrochain import sweep

    TRIED["command"] += 1
    kind, which, seed = how
    copy_ = folder / "hurt.zarr"
    shutil.copytree(store, copy_)
    files = sorted(p for p in copy_.rglob("c/*") if p.is_file()) + sorted(p for p in copy_.rglob("c/*/*") if p.is_file())
    if kind == "done":
        shutil.rmtree(copy_ / "done" / "c", ignore_errors=True)
    elif files:
        f = files[which % len(files)]
        data = bytearray(f.read_bytes())
        if kind == "truncate":
            f.write_bytes(data[: len(data) // 2])
        elif kind == "flip" and data:
            data[seed % len(data)] ^= 0xFF
            f.write_bytes(bytes(data))
        else:
            f.unlink()
    holds(["plot", copy_, "-o", folder / "p.png"], folder, 120)
    a = sweep.stored_attrs(copy_)["args"]
    rerun = ["sweep", SPECS / "double_pendulum.toml", "-q", "-o", copy_, "--t1", str(a["t1"]),
             *[x for v in a["vary"] for x in ("--vary", f"{v[0]}={v[1]}:{v[2]}:{v[3]}")],
             *[x for m in a["measures"] for x in ("--measure", m)]]
    code, _, err = holds(rerun, folder, 120)
    assert code == 0, err
    data = sweep.read(copy_)
    assert data["done"].all() and not len(data["damaged"]), (how, data["done"])


@st.composite
def damaged_csv(draw):
    """A measured motion as real files come hurt or mis-scaled: cut short, a cell not a number, a
    column gone or renamed or added, time in ms, angles in degrees, a torque's sign, rows out of
    order or repeated, a byte-order mark, an empty file, bytes that are not text."""
    how = draw(st.sampled_from(["cut", "cell", "drop", "rename", "add", "ms", "degrees", "sign", "shuffle", "repeat", "bom",
                                "empty", "binary", "few", "uneven"]))
    return how, draw(st.integers(0, 10**6))


def csv_property(how, bench: Path, folder: Path):
    """identify on a damaged recording: estimates and a spec, or one line naming the file, and the
    recording itself untouched."""
    import numpy as np

    TRIED["command"] += 1
    kind, seed = how
    rng = np.random.default_rng(seed)
    lines = (bench / "data.csv").read_text().splitlines()
    head, rows = lines[0], lines[1:]
    if kind == "cut":
        rows = rows[: int(rng.integers(0, len(rows)))]
    elif kind == "cell":
        i = int(rng.integers(0, len(rows)))
        cells = rows[i].split(",")
        cells[int(rng.integers(0, len(cells)))] = str(rng.choice(["nan", "x", "", "inf", "1e400"]))
        rows[i] = ",".join(cells)
    elif kind in ("drop", "rename", "add"):
        names = head.split(",")
        j = int(rng.integers(0, len(names)))
        table = [r.split(",") for r in rows]
        if kind == "drop":
            names.pop(j)
            table = [r[:j] + r[j + 1:] for r in table]
        elif kind == "rename":
            names[j] = str(rng.choice(["T", "phi3", "u2", "phidd1", "Phi1", "phi1 ", "time"]))
        else:
            names.append(str(rng.choice(["u2", "phi9", "phidot1", "current", "phidd2"])))
            table = [r + [r[1]] for r in table]
        head, rows = ",".join(names), [",".join(r) for r in table]
    elif kind in ("ms", "degrees", "sign"):
        col, factor = {"ms": (0, 1000.0), "degrees": (1, 57.29577951308232), "sign": (-1, -1.0)}[kind]
        table = [[float(x) for x in r.split(",")] for r in rows]
        for r in table:
            r[col] *= factor
        rows = [",".join(repr(x) for x in r) for r in table]
    elif kind == "shuffle":
        i, j = sorted(int(x) for x in rng.integers(0, len(rows), 2))
        rows[i], rows[j] = rows[j], rows[i]
    elif kind == "repeat":
        i = int(rng.integers(0, len(rows)))
        rows.insert(i, rows[i])
    elif kind == "few":
        rows = rows[:5]
    elif kind == "uneven":
        rows = rows[::2] + rows[1::2][:10]
    path = folder / "d.csv"
    if kind == "empty":
        path.write_bytes(b"")
    elif kind == "binary":
        path.write_bytes(bytes(rng.integers(0, 256, 4096, dtype=np.uint8)))
    else:
        path.write_text("\n".join([head] + rows) + "\n", encoding="utf-8-sig" if kind == "bom" else "utf-8")
    before = path.read_bytes()
    holds(["identify", bench / "furuta.toml", path, "-o", folder / "id.toml"], folder, 120)
    assert path.read_bytes() == before


# --------------------------------------------------------------------------- robot descriptions
@st.composite
def mutated_urdf(draw):
    """A shipped URDF hurt as files are hurt and written wrong: a number replaced, an attribute or
    an element removed, an element doubled, the file cut short, a joint's type changed."""
    import re

    text = draw(st.sampled_from(sorted(ROBOTS.glob("*.urdf")))).read_text()
    how = draw(st.sampled_from(["number", "attribute", "element", "double", "cut", "type"]))
    if how == "number":
        spots = [m.span() for m in re.finditer(r"-?\d+\.?\d*(e-?\d+)?", text)]
        a, b = spots[draw(st.integers(0, len(spots) - 1))]
        text = text[:a] + draw(st.sampled_from(["nan", "-1", "0", "1e400", "x", "", "1 2", "-0.0", "1e-300"])) + text[b:]
    elif how == "attribute":
        spots = [m.span() for m in re.finditer(r'\s\w+="[^"]*"', text)]
        a, b = spots[draw(st.integers(0, len(spots) - 1))]
        text = text[:a] + text[b:]
    elif how in ("element", "double"):
        spots = [m.span() for m in re.finditer(r"<(inertial|origin|axis|mass|inertia|parent|child|limit|dynamics)\b[^>]*/>", text)]
        a, b = spots[draw(st.integers(0, len(spots) - 1))]
        text = text[:a] + (text[a:b] * 2 if how == "double" else "") + text[b:]
    elif how == "cut":
        text = text[:draw(st.integers(0, len(text)))]
    else:
        spots = [m.span(1) for m in re.finditer(r'type="(revolute|continuous|fixed)"', text)]
        a, b = spots[draw(st.integers(0, len(spots) - 1))]
        text = text[:a] + draw(st.sampled_from(["prismatic", "floating", "planar", "fixed", "revolute", "screw"])) + text[b:]
    return text, draw(st.sampled_from([[], ["panda_finger_joint1=0.02", "panda_finger_joint2=0.02"]]))


def urdf_property(data, folder: Path):
    """import of a damaged description: a spec the other commands accept, or one line naming what."""
    from gyrochain import exchange
    from gyrochain.errors import SpecError
    from gyrochain.spec import parse_spec

    TRIED["spec"] += 1
    text, locks = data
    (folder / "r.urdf").write_text(text)
    try:
        with time_bound(30):
            spec_text, _ = exchange.import_text(folder / "r.urdf", locks=locks)
    except SpecError as exc:
        assert "\n" not in str(exc) and str(exc), str(exc)
        return
    parse_spec(spec_text)


# --------------------------------------------------------------------------- the searches
def fixed(examples: int):
    """A fixed-seed (derandomized) search of ``examples`` inputs: the same inputs on every run."""
    return settings(max_examples=examples, derandomize=True, deadline=None, database=None, suppress_health_check=list(HealthCheck))


@pytest.fixture(scope="module")
def store(tmp_path_factory):
    pytest.importorskip("zarr")
    path = tmp_path_factory.mktemp("fuzzstore") / "s.zarr"
    code, _, err, _ = run(["sweep", SPECS / "double_pendulum.toml", "--vary", "phi1=-1:1:3", "--vary", "phi2=0:1:2",
                           "--t1", "0.2", "--measure", "final", "--measure", "flip_time", "-q", "-o", path], 120)
    assert code == 0, err
    return path


@pytest.fixture(scope="module")
def bench(tmp_path_factory):
    """A Furuta pendulum's simulated recordings for identify (and excite's files to collide with)."""
    import shutil

    d = tmp_path_factory.mktemp("fuzzbench")
    shutil.copy(SPECS / "furuta.toml", d / "furuta.toml")
    base = ["excite", d / "furuta.toml", "--u-max", "0.05", "--period", "5", "--harmonics", "3", "--evaluations", "30"]
    for extra in (["--experiment", "20", "-o", d / "data.csv"], ["--experiment", "8", "--seed", "1", "-o", d / "held.csv"]):
        code, _, err, _ = run([*base, *extra], 300)
        assert code == 0, err
    return d


def _fresh(tmp_path: Path, i: int) -> Path:
    d = tmp_path / f"case{i}"
    d.mkdir()
    return d


def test_mutated_specs(tmp_path):
    count = iter(range(10**9))

    @fixed(200)
    @given(mutated_spec())
    def prop(data):
        spec_property(data, _fresh(tmp_path, next(count)))
    prop()
    assert TRIED["spec"] > 100  # the search ran (most mutations are valid TOML)


def test_mutated_robot_descriptions(tmp_path):
    count = iter(range(10**9))

    @fixed(150)
    @given(mutated_urdf())
    def prop(data):
        urdf_property(data, _fresh(tmp_path, next(count)))
    prop()


def test_command_lines(tmp_path, store, bench):
    count = iter(range(10**9))

    @fixed(150)
    @given(command_line())
    def prop(args):
        command_property(args, _fresh(tmp_path, next(count)), store, bench)
    prop()
    assert TRIED["command"] >= 100
    assert set(COVERED) == set(OPTIONS), sorted(set(OPTIONS) - set(COVERED))  # every command, every run


def test_damaged_recordings(tmp_path, bench):
    count = iter(range(10**9))

    @fixed(25)
    @given(damaged_csv())
    def prop(how):
        csv_property(how, bench, _fresh(tmp_path, next(count)))
    prop()


def test_the_corpus_and_its_trees(tmp_path):
    """Every description of the corpus: --list, and the first leaf it names as --tip, answer."""
    for path in CORPUS:
        code, out, _ = holds(["import", path, "--list"], tmp_path, 30)
        leaves = out.split("leaves a chain can end at", 1)[1].splitlines()[1:] if code == 0 and "leaves a chain" in out else []
        if leaves:
            holds(["import", path, "--tip", leaves[0].split()[0], "-o", "-"], tmp_path, 30)


def test_damaged_stores(tmp_path, store):
    count = iter(range(10**9))

    @fixed(12)
    @given(damage())
    def prop(how):
        damaged_store_property(how, store, _fresh(tmp_path, next(count)))
    prop()


@pytest.mark.skipif(LONG <= 0, reason="make fuzz (FUZZ_SECONDS) searches longer with fresh seeds")
def test_fuzz_for_a_while(tmp_path, store, bench, sigint_from_a_terminal):
    """Rounds of fresh random searches until FUZZ_SECONDS have passed; prints the inputs tried."""
    t_end = time.monotonic() + LONG
    count = iter(range(10**9))
    rounds = settings(max_examples=50, derandomize=False, deadline=None, database=None, suppress_health_check=list(HealthCheck))
    start = dict(TRIED)
    while time.monotonic() < t_end:
        given(mutated_spec())(rounds(lambda data: spec_property(data, _fresh(tmp_path, next(count)))))()
        given(mutated_urdf())(rounds(lambda data: urdf_property(data, _fresh(tmp_path, next(count)))))()
        given(command_line())(rounds(lambda args: command_property(args, _fresh(tmp_path, next(count)), store, bench)))()
        given(damaged_csv())(settings(rounds, max_examples=10)(lambda how: csv_property(how, bench, _fresh(tmp_path, next(count)))))()
        given(damage())(settings(rounds, max_examples=5)(lambda how: damaged_store_property(how, store, _fresh(tmp_path, next(count)))))()
        given(command_line(), st.floats(0.2, 3.0))(settings(rounds, max_examples=3)(
            lambda args, delay: interrupt_property(args, delay, _fresh(tmp_path, next(count)), store, bench)))()
        print(f"fuzz: {TRIED['spec'] - start['spec']} specs and {TRIED['command'] - start['command']} command lines "
              f"so far", flush=True)
    print(f"\nfuzz: {TRIED['spec'] - start['spec']} specs and {TRIED['command'] - start['command']} command lines "
          f"in {LONG:.0f} s, no failure")


def interrupt_property(args, delay: float, folder: Path, store: Path, bench: Path):
    """The command line in its own process, SIGINT after ``delay`` seconds: it has ended by itself
    (0 or 2), or it ends within a second with exit 130 and one line, nothing half-written."""
    import subprocess
    import sys

    TRIED["command"] += 1
    args = [str(a).replace("@OUT@", str(folder)).replace("@DATA@", str(bench)) for a in args]
    if args[0] == "plot":
        args[1] = str(store)
    if args[0] == "generate" and "-o" not in args:
        args += ["-o", str(folder / "g")]
    proc = subprocess.Popen([sys.executable, "-m", "gyrochain", *args], cwd=folder, stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, text=True)
    time.sleep(delay)
    t0 = time.perf_counter()
    proc.send_signal(signal.SIGINT)
    try:
        code = proc.wait(timeout=10)
    finally:
        proc.kill()
    err = proc.stderr.read()
    assert "Traceback" not in err, (args, err)
    if code == -signal.SIGINT:  # the signal came before Python's handler was in place, or after the command had
        # ended, while the interpreter shut down (then its one line is out): nothing half-written either way
        assert err.count("\n") <= 1, (args, err)
        assert not [p for p in folder.rglob("*") if ".tmp" in p.name], (args, list(folder.rglob("*")))
        return
    assert code in (0, 2, 130), (args, code, err)
    if code == 130:
        assert time.perf_counter() - t0 < 1.0 and err.rstrip().endswith("error: interrupted"), (args, err)
        assert not [p for p in folder.rglob("*") if ".tmp" in p.name], (args, list(folder.rglob("*")))


# --------------------------------------------------------------------------- what the searches found
def test_found_fps_zero_with_a_still(tmp_path):
    """--fps 0 with --frame: was a ZeroDivisionError (exit 1); --fps is checked first now."""
    code, _, err = holds(["animate", SPECS / "gimbal.toml", "--fps", "0", "--frame", "0.05", "--size", "64x64",
                          "-o", tmp_path / "a.png"], tmp_path, 60)
    assert code == 2 and err.startswith("error: --fps:"), err


def test_found_log_scale_of_nothing_positive(tmp_path, store):
    """plot --log of a measure with no positive value (no flip within t1: all NaN): was matplotlib's
    "Invalid vmin or vmax" (exit 1)."""
    pytest.importorskip("matplotlib")
    code, _, err = holds(["plot", store, "--measure", "flip_time", "--log", "-o", tmp_path / "p.png"], tmp_path, 60)
    assert code == 2 and err.startswith("error: --log:"), err


def test_found_negative_values_that_argparse_took_for_options():
    """--atol -inf, --t1 -1e3: argparse's "expected one argument"; now the value reaches the check."""
    for args, field in ((["--atol", "-inf"], "--atol"), (["--t1", "-1e3"], "--t1"), (["--rtol", "-nan"], "--rtol")):
        code, _, err, _ = run(["simulate", SPECS / "gimbal.toml", *args], 30)
        assert code == 2 and err.startswith(f"error: {field}:"), err


def test_found_nan_in_a_list_option(tmp_path):
    """animate --view nan,0: was "cannot convert float NaN to integer" (exit 1); every list option
    refuses non-finite numbers now."""
    for args, field in ((["animate", "--view", "nan,0", "-o", tmp_path / "a.gif"], "--view"),
                        (["simulate", "--phi", "-inf,0"], "--phi"), (["simulate", "--u", "inf"], "--u")):
        code, _, err, _ = run([args[0], SPECS / "gimbal.toml", *args[1:]], 30)
        assert code == 2 and err.startswith(f"error: {field}:"), err
    assert not (tmp_path / "a.gif").exists()


def test_found_a_sweep_of_a_hundred_million_chunks(tmp_path):
    """--vary phi1=0:1:100000000 --chunk 1: was an internal error after 120 s spent laying out 1e8
    chunks; a sweep too large for one store is refused before anything is allocated."""
    for args, field in ((["--vary", "phi1=0:1:100000000", "--chunk", "1"], "--chunk"),
                        (["--vary", "phi1=0:1:100000", "--vary", "phi2=0:1:100000"], "--vary"),
                        (["--random", "10000000000", "--vary", "phi1=0:1"], "--random")):
        code, _, err, dt = run(["sweep", SPECS / "gimbal.toml", *args, "-o", tmp_path / "s.zarr"], 30)
        assert code == 2 and err.startswith(f"error: {field}:") and dt < 10, (err, dt)
    assert not any(tmp_path.iterdir())


def test_found_a_purely_relative_tolerance(tmp_path):
    """simulate --reference --atol 0 --phidot 0,0: scipy's DOP853 asked for steps without end (no
    answer in 120 s, with numpy's warnings on stderr); the C said STEP_UNDERFLOW.  --atol must be
    positive now, on both paths."""
    for extra in ([], ["--reference"]):
        code, _, err, dt = run(["simulate", SPECS / "gimbal.toml", "--atol", "0", "--phidot", "0,0", *extra], 30)
        assert code == 2 and err.startswith("error: --atol:") and dt < 10, (err, dt)


def test_found_an_inertia_that_overflows(tmp_path):
    """m = 1e300 with |c| = 1e200: the central inertia A − m(|c|²1 − c cᵀ) overflowed to inf − inf,
    numpy printed three RuntimeWarnings and eigvalsh failed ("Eigenvalues did not converge", exit 1).
    Refused now, naming the field, on every path that checks an inertia."""
    text = (SPECS / "gimbal.toml").read_text().replace("m = 0.5", "m = 1e300", 1).replace("c = [0.0, 0.0, 0.0]", "c = [1e200, 0.0, 0.0]", 1)
    spec = tmp_path / "big.toml"
    spec.write_text(text)
    code, _, err = holds(["check", spec], tmp_path, 30)
    assert code == 2 and err.startswith("error: body[1].") and "overflows double precision" in err, err


def test_found_a_forced_form_refused_after_the_progress_lines(tmp_path):
    """generate --derivative-form world on a moving platform (or body loads): the refusal came after
    four progress lines (the derivation ran first); it is said before the first line now."""
    for spec in ("kapitza", "ziegler"):
        code, _, err = holds(["generate", SPECS / f"{spec}.toml", "--derivative-form", "world", "-o", tmp_path / "g"],
                             tmp_path, 60)
        assert code == 2 and err.startswith("error: --derivative-form: the world form needs"), err
