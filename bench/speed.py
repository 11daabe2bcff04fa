"""`make bench-speed`: the scale benchmark, n = 2 ... 128.  ns per forward-dynamics call of the
generated C against Pinocchio's ABA (C++), CasADi-generated C (our ABA in SX, numbers folded in; up
to n = CASADI_MAX_N) and MuJoCo's mj_forward, and ns per Jacobian ∂φ̈/∂(φ, φ̇) against Pinocchio's
computeABADerivatives, on the same random spatial gyrostat chains, in one run; generation and gcc
time, C size, peak memory and op counts against n, with their log-log slopes; the op count of
reduced scenes (planar, no rotors, zero offsets).

Every implementation's φ̈ is checked against gyrochain.reference before it is timed; the programs
of one n are then timed in turn, ROUNDS times, each figure the least of its rounds' medians.  Peers that
are not installed (pip install '.[bench]', apt libeigen3-dev) are reported as missing.
Results: bench/results/speed.csv (speed_O3_march_native.csv etc. with other BENCH_CFLAGS), scenes.csv,
generation_symbolic.csv; `make plot` draws the charts and tables of docs/benchmarks.md from them.
"""
from __future__ import annotations

import argparse
import dataclasses
import json
import os
import re
import resource
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "bench"))

from gyrochain import reference  # noqa: E402
from provenance import cpu as _cpu, write  # noqa: E402
from gyrochain.randspec import random_spec_text  # noqa: E402
from gyrochain.spec import parse_spec  # noqa: E402

BUILD = ROOT / "bench" / "build"
RESULTS = ROOT / "bench" / "results"
# the same for every C and C++ program of the comparison; BENCH_CFLAGS="-O3 -march=native" for the figures
CFLAGS = os.environ.get("BENCH_CFLAGS", "-O2").split()
K_STATES = 64
HARNESS_REPEATS = 21  # BENCH_REPEATS of harness.h
COUNT_INSTRUCTIONS = False  # --instructions: also callgrind's instructions per call of every program
ROUNDS = 3  # each program's timing, taken in turn with the others of the same n (more_rounds)
TOL = 1e-8  # relative agreement with the reference model required before timing


def chain_text(n: int, **kw) -> str:
    return random_spec_text(np.random.default_rng(1000 + n), n, name=f"chain{n}", **kw)


def symbolic_text(n: int) -> str:
    """A spatial gyrostat chain with every field a parameter."""
    def vec(name):
        return "[" + ", ".join(f'"{name}{i}"' for i in (1, 2, 3)) + "]"

    def mat(name):
        idx = lambda i, j: f"{min(i, j)}{max(i, j)}"  # noqa: E731
        return "[" + ", ".join("[" + ", ".join(f'"{name}{idx(i, j)}"' for j in (1, 2, 3)) + "]" for i in (1, 2, 3)) + "]"

    text = f'name = "sym{n}"\ng = "g"\n'
    for k in range(1, n + 1):
        text += f'[[body]]\ntheta = "th{k}"\nm = "m{k}"\nc = {vec(f"c{k}_")}\nA = {mat(f"A{k}_")}\n'
        if k < n:
            text += f"s = {vec(f's{k}_')}\n"
        text += f"lambda = {vec(f'lam{k}_')}\n"
    return text


def states(n: int) -> np.ndarray:
    rng = np.random.default_rng(7 + n)
    return np.hstack([rng.uniform(-np.pi, np.pi, (K_STATES, n)), rng.normal(size=(K_STATES, n))])


# --------------------------------------------------------------------------- generation
def generate_one(spec_path: str, out: str) -> None:
    """Child process: derive + emit + compile one spec; print seconds and peak RSS as JSON."""
    from gyrochain.pipeline import derive_and_render

    t0 = time.perf_counter()
    spec = parse_spec(Path(spec_path).read_text())
    files, model = derive_and_render(spec, Path(spec_path).name)
    t_emit = time.perf_counter() - t0
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    for name, text in files.items():
        (out / name).write_text(text)
    t1 = time.perf_counter()
    subprocess.run(["gcc", *CFLAGS, "-std=c99", "-c", str(out / f"{spec.name}.c"), "-o", str(out / f"{spec.name}.o")], check=True)
    t_cc = time.perf_counter() - t1
    from gyrochain.assemble import op_counts

    c_file = out / f"{spec.name}.c"
    print(json.dumps(dict(emit=t_emit, cc=t_cc, rss_mb=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, ops=op_counts(model),
                          c_kb=c_file.stat().st_size / 1e3, fn_kb=function_sizes(c_file.read_text(), spec.name))))


def function_sizes(c_text: str, name: str) -> dict[str, float]:
    """KB of each function of a generated C file (from its definition to the next one's); a long
    function's parts (printers/chunks.py) are counted in it."""
    heads = [(m.start(), m.group(1)) for m in re.finditer(
        rf"^(?:static )?(?:int|void|double|long|{re.escape(name.upper())}_PART_) {re.escape(name)}_(\w+)\(", c_text, re.M)]
    ends = [a for a, _ in heads[1:]] + [len(c_text)]
    out: dict[str, float] = {}
    for (a, fn), b in zip(heads, ends):
        fn = re.sub(r"_part\d+_$", "", fn)
        out[fn] = out.get(fn, 0.0) + (b - a) / 1e3
    return out


def generate(text: str, name: str) -> dict:
    d = BUILD / name
    d.mkdir(parents=True, exist_ok=True)
    (d / f"{name}.toml").write_text(text)
    res = subprocess.run(
        [sys.executable, __file__, "--generate-one", str(d / f"{name}.toml"), str(d)],
        check=True, capture_output=True, text=True, env=dict(os.environ, PYTHONHASHSEED="0"),
    )
    return json.loads(res.stdout.strip().splitlines()[-1])


# --------------------------------------------------------------------------- running
def _feed(exe: Path, xs: np.ndarray, d: Path, prefix: tuple = (), **env) -> str:
    """A harness program (harness.h) run on the states xs, under ``prefix`` (valgrind ...); its stdout."""
    inp = "\n".join(" ".join(repr(float(v)) for v in row) for row in xs)
    env = dict(os.environ, BENCH_CHAIN=str(d / "pinocchio_chain.txt"), **env)
    return subprocess.run([*prefix, str(exe)], input=inp, capture_output=True, text=True, check=True, cwd=d, env=env).stdout


def run(exe: Path, xs: np.ndarray, d: Path) -> tuple[np.ndarray, float, float]:
    lines = _feed(exe, xs, d).strip().splitlines()
    qdd = np.array([[float(v) for v in ln.split()] for ln in lines[:-1]])
    _, med, mn = lines[-1].split()
    return qdd, float(med), float(mn)


def check(qdd: np.ndarray, ref: np.ndarray) -> float:
    return float(np.max(np.abs(qdd - ref)) / max(1.0, float(np.max(np.abs(ref)))))


def build_ours(n: int, d: Path) -> Path:
    src = d / "bench_ours.c"
    src.write_text(
        "#define _POSIX_C_SOURCE 199309L  /* clock_gettime in harness.h */\n"
        f'#include "chain{n}.c"  /* one translation unit, as the CasADi peer */\nstatic int bench_setup(void) {{ return {n}; }}\n'
        f"static int bench_qdd(const double *x, double *qdd) {{ return chain{n}_qdd(x, 0, 0, qdd); }}\n"
        '#include "harness.h"\n'
    )
    exe = d / "ours"
    subprocess.run(["gcc", *CFLAGS, "-std=c99", f"-I{ROOT / 'bench'}", f"-I{d}", str(src), "-lm", "-o", str(exe)], check=True)
    return exe


def build_casadi(ch, n: int, d: Path) -> Path | None:
    try:
        from peers import casadi_aba
    except ImportError:
        return None
    try:
        import casadi  # noqa: F401
    except ImportError:
        return None
    f = casadi_aba(ch, f"fd{n}")  # CasADi's own common-subexpression pass is on (Function option cse)
    cwd = os.getcwd()
    os.chdir(d)
    try:
        f.generate(f"casadi{n}.c", {"casadi_real": "double"})
    finally:
        os.chdir(cwd)
    src = d / "bench_casadi.c"
    src.write_text(
        f'#include "casadi{n}.c"\n'
        f"static casadi_real w_[{max(1, f.sz_w())}];\nstatic casadi_int iw_[{max(1, f.sz_iw())}];\n"
        f"static int bench_setup(void) {{ return {n}; }}\n"
        "static int bench_qdd(const double *x, double *qdd) {\n"
        f"    const casadi_real *arg[{max(1, f.sz_arg())}] = {{x}};\n    casadi_real *res[{max(1, f.sz_res())}] = {{qdd}};\n"
        f"    return fd{n}(arg, res, iw_, w_, 0);\n}}\n"
        '#include "harness.h"\n'
    )
    exe = d / "casadi"
    subprocess.run(["gcc", *CFLAGS, f"-I{ROOT / 'bench'}", str(src), "-lm", "-o", str(exe)], check=True)
    return exe


def _pin_prefix() -> Path | None:
    try:
        import cmeel  # noqa: F401
    except ImportError:
        return None
    import site

    for p in site.getsitepackages():
        pre = Path(p) / "cmeel.prefix"
        if (pre / "include" / "pinocchio").exists():
            return pre
    return None


# what pinocchio's CMake config gives its users (boost::variant of 25 joint types)
PIN_DEFINES = [
    "-DBOOST_MPL_LIMIT_LIST_SIZE=30", "-DBOOST_MPL_LIMIT_VECTOR_SIZE=30", "-DBOOST_MPL_CFG_NO_PREPROCESSED_HEADERS",
    "-DBOOST_FUSION_INVOKE_MAX_ARITY=12",
]


def pin_defines(flags: list[str]) -> list[str]:
    """With flags that change the vector unit (-march=native, -mavx2 ...), Eigen's alignment in our
    program differs from the prebuilt library's: its explicitly instantiated ABA then sees a Data
    of another layout and aborts (model.check(data) fails).  So the algorithms are compiled from
    the headers with the program's own flags there (slower to build, and Pinocchio gets the same
    vectors as every other program); with plain -O2/-O3 the library's instances are used."""
    same_abi = not any(f.startswith("-m") for f in flags)
    return PIN_DEFINES + (["-DPINOCCHIO_ENABLE_TEMPLATE_INSTANTIATION"] if same_abi else [])


def build_pinocchio(ch, n: int, d: Path, program: str = "pinocchio") -> Path | None:
    """One executable for every n (Pinocchio's headers take a minute to compile); the chain is
    read at run time from the file in BENCH_CHAIN.  ``program``: bench/<program>.cpp."""
    from peers import pinocchio_data

    pre = _pin_prefix()
    if pre is None or not Path("/usr/include/eigen3").exists() or shutil.which("g++") is None:
        return None
    exe = BUILD / (program + "".join(CFLAGS).replace("=", "_"))  # one per flag set (BENCH_CFLAGS)
    src = ROOT / "bench" / f"{program}.cpp"
    # harness.h too: its BENCH_NMAX is the largest chain the program takes
    newest = max((ROOT / "bench" / f).stat().st_mtime for f in (f"{program}.cpp", "pinocchio_chain.h", "harness.h"))
    if not exe.exists() or exe.stat().st_mtime < newest:
        lib = pre / "lib"
        subprocess.run(
            ["g++", *CFLAGS, "-std=c++17", "-w", *pin_defines(CFLAGS), f"-I{pre / 'include'}", "-I/usr/include/eigen3",
             f"-I{ROOT / 'bench'}", str(src), f"-L{lib}", "-lpinocchio_default", f"-Wl,-rpath,{lib}", "-o", str(exe)],
            check=True,
        )
    (d / "pinocchio_chain.txt").write_text(pinocchio_data(ch))
    return exe


def build_mujoco(ch, n: int, d: Path) -> Path | None:
    try:
        import mujoco
    except ImportError:
        return None
    from peers import mujoco_c, mujoco_xml

    base = Path(mujoco.__file__).parent
    libs = sorted(base.glob("libmujoco.so*"))
    if not libs or not (base / "include").exists():
        return None
    (d / "chain.xml").write_text(mujoco_xml(ch))
    src = d / "bench_mujoco.c"
    src.write_text(mujoco_c(n, str(d / "chain.xml")))
    exe = d / "mujoco"
    subprocess.run(
        ["gcc", *CFLAGS, f"-I{base / 'include'}", f"-I{ROOT / 'bench'}", str(src), str(libs[0]), f"-Wl,-rpath,{base}", "-lm", "-o", str(exe)],
        check=True,
    )
    return exe


# --------------------------------------------------------------------------- main
PEERS = ("pinocchio", "mujoco", "casadi")
CASADI_MAX_N = 32  # CasADi's SX of the ABA is straight-line code: its C grows with n like ours before the loop form


def speed(ns: list[int]) -> list[dict]:
    rows = []
    for n in ns:
        text = chain_text(n)
        spec = parse_spec(text)
        ch = reference.numeric(spec)
        d = BUILD / f"chain{n}"
        gen = generate(text, f"chain{n}")
        xs = states(n)
        ref = np.array([reference.qdd(ch, x) for x in xs])
        row = dict(n=n, qdd_ops=gen["ops"]["qdd"], gen_s=gen["emit"], cc_s=gen["cc"], rss_mb=gen["rss_mb"],
                   c_kb=gen["c_kb"], c_kb_per_link=gen["c_kb"] / n)
        big = sorted(gen["fn_kb"].items(), key=lambda kv: -kv[1])[:6]
        print(f"n={n:>3}  C {gen['c_kb']:.0f} KB ({gen['c_kb'] / n:.0f} KB per link); largest: "
              + ", ".join(f"{fn} {kb:.0f}" for fn, kb in big), flush=True)
        exe = build_ours(n, d)
        qdd, med, _ = run(exe, xs, d)
        err = check(qdd, ref)
        if err > TOL:
            raise SystemExit(f"n = {n}: generated C disagrees with the reference model ({err:.2e})")
        row["ours_ns"], row["ours_err"] = med, err
        timed = {"ours_ns": exe}  # what is timed again in the later rounds (checked programs only)
        # MuJoCo has no rotor momentum: its chain is the same without λ, checked against that
        ch0 = dataclasses.replace(ch, lam=np.zeros_like(ch.lam))
        ref0 = np.array([reference.qdd(ch0, x) for x in xs])
        for peer, builder, chain, r in (
            ("pinocchio", build_pinocchio, ch, ref),
            ("mujoco", build_mujoco, ch0, ref0),
            ("casadi", build_casadi, ch, ref),
        ):
            try:
                exe = None if peer == "casadi" and n > CASADI_MAX_N else builder(chain, n, d)
            except subprocess.CalledProcessError as e:
                print(f"  {peer} n = {n}: build failed ({e})", file=sys.stderr)
                exe = None
            if exe is None:
                row[f"{peer}_ns"], row[f"{peer}_err"] = None, None
                continue
            qdd, med, _ = run(exe, xs, d)
            err = check(qdd, r)
            row[f"{peer}_err"] = err
            row[f"{peer}_ns"] = med if err <= TOL else None
            if err <= TOL:
                timed[f"{peer}_ns"] = exe
            if err > TOL:
                print(f"  {peer} n = {n}: disagrees with the reference ({err:.2e}); not timed", file=sys.stderr)
        jacobian(ch, ch0, n, d, xs, row, timed)
        more_rounds(timed, xs, d, row)
        if COUNT_INSTRUCTIONS:
            for key, exe in timed.items():
                row[key.replace("_ns", "_instructions")] = instructions(exe, xs, d)
            print(_instructions_line(row), flush=True)
        best = min((row[f"{p}_ns"] for p in PEERS if row[f"{p}_ns"]), default=None)
        row["best_peer_over_ours"] = best / row["ours_ns"] if best else None
        row["pinocchio_jac_over_ours"] = row["pinocchio_jac_ns"] / row["ours_jac_ns"] if row["pinocchio_jac_ns"] else None
        rows.append(row)
        print(_speed_line(row), flush=True)
    return rows


def more_rounds(timed: dict, xs: np.ndarray, d: Path, row: dict) -> None:
    """ROUNDS − 1 more timings of every program of one n, taken in turn (ours, the peers, ours
    again ...), each figure the least of its rounds' medians: a slow spell of this shared host
    (one run of the same binary took 7× its usual time) then spoils one round, not the ratio."""
    for _ in range(ROUNDS - 1):
        for key, exe in timed.items():
            row[key] = min(row[key], run(exe, xs, d)[1])


def instructions(exe: Path, xs: np.ndarray, d: Path) -> float:
    """Instructions per call, counted by callgrind: the same on a quiet and a busy host, where the
    times are not.  The program runs with a fixed number of timed sweeps (BENCH_SWEEPS, harness.h),
    once with none and once with one; the difference is K × BENCH_REPEATS calls, libm's included."""
    totals = []
    for sweeps in (0, 1):
        out = (d / f"callgrind.{exe.name}.{sweeps}").resolve()
        _feed(exe, xs, d, ("valgrind", "--tool=callgrind", f"--callgrind-out-file={out}"), BENCH_SWEEPS=str(sweeps))
        totals.append(int(re.search(r"^(?:summary|totals):\s*(\d+)", out.read_text(), re.M).group(1)))
    return (totals[1] - totals[0]) / (len(xs) * HARNESS_REPEATS)


def _instructions_line(row: dict) -> str:
    keys = [k for k in row if k.endswith("_instructions")]
    ours = row.get("ours_instructions")
    peers = [k for k in keys if k != "ours_instructions" and not k.endswith("jac_instructions")]
    best = min((row[k] for k in peers), default=None)
    jac = (f"  | Jacobian ours {row['ours_jac_instructions']:,.0f}"
           + (f", Pinocchio {row['pinocchio_jac_instructions']:,.0f}" if "pinocchio_jac_instructions" in row else "")
           if "ours_jac_instructions" in row else "")
    return (f"n={row['n']:>3}  instructions per call: ours {ours:,.0f}  "
            + "  ".join(f"{k.removesuffix('_instructions')} {row[k]:,.0f}" for k in peers)
            + (f"  fewest of a peer / ours {best / ours:.2f}" if best else "") + jac)


def jacobian(ch, ch0, n: int, d: Path, xs: np.ndarray, row: dict, timed: dict) -> None:
    """ns per ∂φ̈/∂(φ, φ̇): ours (NAME_qdd_derivatives) and Pinocchio's computeABADerivatives
    (on the chain without rotors, which it cannot take), each checked first against Richardson
    differences of the reference model (bench/derivatives.py has the other peers)."""
    import derivatives as dv

    ref = [dv.ref_jacobian(ch, x) for x in xs[:dv.N_CHECK]]
    exe = dv.build_ours(n, d)
    J, med, _ = run(exe, xs, d)
    err = dv.err(J[:dv.N_CHECK], ref)
    if err > dv.TOL:
        raise SystemExit(f"n = {n}: our derivatives disagree with the reference ({err:.2e})")
    row["ours_jac_ns"] = med
    timed["ours_jac_ns"] = exe
    row["pinocchio_jac_ns"] = None
    try:
        exe = build_pinocchio(ch0, n, d, "pinocchio_derivatives")
    except subprocess.CalledProcessError as e:
        print(f"  pinocchio derivatives n = {n}: build failed ({e})", file=sys.stderr)
        exe = None
    if exe is not None:
        J, med, _ = run(exe, xs, d)
        err = dv.err(J[:dv.N_CHECK], [dv.ref_jacobian(ch0, x) for x in xs[:dv.N_CHECK]])
        row["pinocchio_jac_ns"] = med if err <= dv.TOL else None
        if err <= dv.TOL:
            timed["pinocchio_jac_ns"] = exe
        if err > dv.TOL:
            print(f"  pinocchio derivatives n = {n}: disagree with the reference ({err:.2e}); not timed", file=sys.stderr)


SLOPE_MIN_N = 16  # the slopes are fitted from here on: below it the fixed costs dominate


def slopes(rows: list[dict]) -> str:
    """Log-log slopes against n, least squares over n >= SLOPE_MIN_N: 1 is linear growth, 2
    quadratic (the aims: 1 for generation and per φ̈ call, 2 for the Jacobian)."""
    rows = [r for r in rows if r["n"] >= SLOPE_MIN_N]
    if len(rows) < 2:
        return "slopes: need two sizes from n = %d on" % SLOPE_MIN_N

    def k(key):
        pts = [(r["n"], r[key]) for r in rows if r.get(key)]
        return np.polyfit(np.log([p[0] for p in pts]), np.log([p[1] for p in pts]), 1)[0] if len(pts) > 1 else None

    keys = (("gen_s", "derive + emit"), ("cc_s", "gcc"), ("c_kb", "C size"), ("ours_ns", "ns per qdd"),
            ("pinocchio_ns", "Pinocchio qdd"), ("mujoco_ns", "MuJoCo"), ("ours_jac_ns", "ns per Jacobian"),
            ("pinocchio_jac_ns", "Pinocchio Jacobian"))
    parts = [f"{label} {s:.2f}" for key, label in keys if (s := k(key)) is not None]
    return f"slopes d log / d log n over n = {rows[0]['n']}...{rows[-1]['n']}: " + ", ".join(parts)


def _fmt(v, spec=".0f"):
    return "-" if v is None else format(v, spec)


def _speed_line(r: dict) -> str:
    return (
        f"n={r['n']:>3}  ours {_fmt(r['ours_ns']):>7} ns ({r['qdd_ops']} ops)  pinocchio {_fmt(r['pinocchio_ns']):>7}"
        f"  mujoco(λ=0) {_fmt(r['mujoco_ns']):>7}  casadi {_fmt(r['casadi_ns']):>7}"
        f"  best peer / ours {_fmt(r['best_peer_over_ours'], '.2f'):>5}"
        f"  | Jacobian ours {_fmt(r['ours_jac_ns']):>8} ns  Pinocchio (λ=0) {_fmt(r['pinocchio_jac_ns']):>8}"
        f"  Pinocchio / ours {_fmt(r['pinocchio_jac_over_ours'], '.2f'):>5}"
        f"  | generate {r['gen_s']:.1f} s + gcc {r['cc_s']:.1f} s, peak {r['rss_mb']:.0f} MB"
    )


def symbolic(ns: list[int]) -> list[dict]:
    rows = []
    for n in ns:
        gen = generate(symbolic_text(n), f"sym{n}")
        rows.append(dict(n=n, gen_s=gen["emit"], cc_s=gen["cc"], rss_mb=gen["rss_mb"], qdd_ops=gen["ops"]["qdd"]))
        print(f"symbolic n={n:>2}: generate {gen['emit']:.1f} s + gcc {gen['cc']:.1f} s, peak {gen['rss_mb']:.0f} MB, qdd {gen['ops']['qdd']} ops", flush=True)
    return rows


def scenes(n: int) -> list[dict]:
    """The same chain (same random draws) general and reduced: the model shrinks with the scene."""
    from gyrochain import assemble, dynamics, integrals, kinematics

    rows = []
    variants = [
        ("general (spatial, rotors, offsets)", {}),
        ("planar (all axes parallel)", dict(planar=True)),
        ("no rotors (lambda = 0)", dict(gyro=False)),
        ("zero offsets (c = 0)", dict(zero_c=True)),
    ]
    base = None
    for label, kw in variants:
        zero_c = kw.pop("zero_c", False)
        text = chain_text(n, **kw)
        if zero_c:
            text = "\n".join("c = [0.0, 0.0, 0.0]" if ln.startswith("c = ") else ln for ln in text.splitlines())
        spec = parse_spec(text)
        kin = kinematics.derive(spec)
        dyn = dynamics.derive(spec, kin.prog, kin)
        ints = integrals.derive(spec, kin.prog, kin, dyn)
        counts = assemble.op_counts(assemble.build_model(spec, kin.prog, kin, dyn, ints))
        base = base or counts
        rows.append(dict(n=n, scene=label, **{k: counts[k] for k in ("mass_matrix", "forces", "qdd")},
                         qdd_vs_general=counts["qdd"] / base["qdd"]))
        print(f"scene n={n} {label:<36} mass_matrix {counts['mass_matrix']:>6}  forces {counts['forces']:>6}  qdd {counts['qdd']:>6}  ({counts['qdd'] / base['qdd']:.2f} of general)")
    return rows


def write_csv(path: Path, rows: list[dict]) -> None:
    """Write the rows, and note in bench/results/machines.csv which machine measured them, when."""
    write(path, rows, " ".join(CFLAGS))


def flagged(stem: str) -> str:
    """The results' file name: ``stem.csv`` at the product's -O2, ``stem_O3_march_native.csv`` etc. otherwise."""
    return stem + ("" if CFLAGS == ["-O2"] else "_" + "_".join(f.lstrip("-").replace("=", "_") for f in CFLAGS)) + ".csv"


def main() -> int:
    if len(sys.argv) == 4 and sys.argv[1] == "--generate-one":
        generate_one(sys.argv[2], sys.argv[3])
        return 0
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, nargs="*", default=[2, 4, 8, 16, 32, 64, 128])
    ap.add_argument("--symbolic", type=int, nargs="*", default=[1, 2, 3, 4, 5, 6])
    ap.add_argument("--instructions", action="store_true",
                    help="also count each program's instructions per call with callgrind (deterministic; slow)")
    args = ap.parse_args()
    global COUNT_INSTRUCTIONS
    COUNT_INSTRUCTIONS = args.instructions and shutil.which("valgrind") is not None
    if args.instructions and not COUNT_INSTRUCTIONS:
        print("no valgrind: the instructions per call are not counted (apt-get install valgrind)", flush=True)
    BUILD.mkdir(parents=True, exist_ok=True)
    RESULTS.mkdir(parents=True, exist_ok=True)
    print(f"machine: {os.cpu_count()} cores, {_cpu()}; flags {' '.join(CFLAGS)} for every compiled peer", flush=True)
    sp = speed(args.n)
    write_csv(RESULTS / flagged("speed"), sp)
    print(slopes(sp), flush=True)
    sym = symbolic(args.symbolic) if args.symbolic else []
    if sym:
        write_csv(RESULTS / "generation_symbolic.csv", sym)
    sc = scenes(8)
    write_csv(RESULTS / "scenes.csv", sc)
    print(f"wrote {RESULTS.relative_to(ROOT)}/: {flagged('speed')}, scenes.csv, generation_symbolic.csv "
          "(make plot draws the charts and the tables of docs/benchmarks.md from them)")
    return 0




if __name__ == "__main__":
    sys.exit(main())
