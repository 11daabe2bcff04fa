"""This release against the previous, function by function (make bench-speed; issue: "never slower
than ourselves").

The same random spatial gyrostat chains as the scale benchmark (bench/speed.py, n = 2 ... 128) are
emitted twice: by the package at the previous release's commit (its source taken with git archive
into bench/build/, run in a child process with that source first on the path) and by this working
tree.  Each C is compiled with the same flags into one timing program that calls every public
function both releases have (mass_matrix, forces, qdd, energy, qdd_derivatives; momenta,
velocities and pdot where the model has Hamilton's variables; one RK4 step of NAME_integrate) on
the same K states.  The programs run alternately, several rounds; a function's figure is the least
of its rounds' medians (ns per call).  Before timing, both releases' outputs are compared (the
largest relative difference is printed: the releases must compute the same model).

Prints one table per flag set (-O2, the product's own build, and -O3 -march=native), writes
bench/results/releases.csv.  Usage: bench/releases.py [--previous COMMIT] [--n 2 4 8 ...]
"""
from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path[:0] = [str(ROOT), str(ROOT / "bench")]

from speed import chain_text, write_csv  # noqa: E402

BUILD = ROOT / "bench" / "build" / "releases"
RESULTS = ROOT / "bench" / "results"
# the last release before the speed work of issue 50 (the one the table measured)
PREVIOUS = "b3877bb"
FLAGS = {"-O2": ["-O2"], "-O3 -march=native": ["-O3", "-march=native"]}
K = 32  # states per timing
COUNT = False  # --instructions

EMIT = r'''
import importlib, sys
from pathlib import Path
spec_path, out = Path(sys.argv[1]), Path(sys.argv[2])
pipeline = importlib.import_module("gyrochain.pipeline")
src = Path(sys.path[0]).resolve()
assert Path(pipeline.__file__).resolve().is_relative_to(src), ("not the release's package", pipeline.__file__)
spec = importlib.import_module("gyrochain.spec").parse_spec(spec_path.read_text())
files, _ = pipeline.derive_and_render(spec, spec_path.name, targets=("c",))
out.mkdir(parents=True, exist_ok=True)
for name, text in files.items():
    if name.endswith((".c", ".h")):
        (out / name).write_text(text)
'''

# the timing program: every function on K states, median of R repeats of K calls, ns per call
PROGRAM = r'''#define _POSIX_C_SOURCE 199309L
#include "{name}.c"
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include <stdlib.h>
#define N {n}
#define K {k}
#define R 15
static double now_(void) {{ struct timespec ts; clock_gettime(CLOCK_MONOTONIC, &ts); return ts.tv_sec + 1e-9 * ts.tv_nsec; }}
static int cmp_(const void *a, const void *b) {{ double d = *(const double *)a - *(const double *)b; return (d > 0) - (d < 0); }}
static double X[K][2 * N], out[K][2 * N * N + N];
static volatile double sink;
#define TIME(label, call, reps) do {{ double t_[R]; int r_, k_, i_; \
    for (r_ = 0; r_ < R; ++r_) {{ double a_ = now_(); for (i_ = 0; i_ < (reps); ++i_) for (k_ = 0; k_ < K; ++k_) {{ call; }} \
        t_[r_] = (now_() - a_) / ((double)(reps) * K); }} \
    qsort(t_, R, sizeof t_[0], cmp_); printf("time %s %.6g\n", label, 1e9 * t_[R / 2]); }} while (0)
int main(void)
{{
    static double M[N * N], f[N], dq[N * N], dv[N * N], pm[N], x1[2 * N];
    int k, i, reps;
    for (k = 0; k < K; ++k) for (i = 0; i < 2 * N; ++i) if (scanf("%lf", &X[k][i]) != 1) return 2;
    /* the outputs, for the comparison of the releases */
    for (k = 0; k < K; ++k) {{
        double *o = out[k];
        {name}_mass_matrix(X[k], 0, M); for (i = 0; i < N * N; ++i) printf("%.17g ", M[i]);
        {name}_forces(X[k], 0, 0, f); for (i = 0; i < N; ++i) printf("%.17g ", f[i]);
        {name}_qdd(X[k], 0, 0, o); for (i = 0; i < N; ++i) printf("%.17g ", o[i]);
        printf("%.17g ", {name}_energy(X[k], 0));
        {name}_qdd_derivatives(X[k], 0, 0, f, dq, dv, 0);
        for (i = 0; i < N * N; ++i) printf("%.17g %.17g ", dq[i], dv[i]);
#if {NAME}_HAS_CANONICAL
        {name}_momenta(X[k], 0, pm); for (i = 0; i < N; ++i) printf("%.17g ", pm[i]);
#endif
        {name}_integrate({NAME}_RK4, 0.0, 1e-3, 1e-3, 0.0, 0.0, X[k], 0, 0, x1, 0); for (i = 0; i < 2 * N; ++i) printf("%.17g ", x1[i]);
        printf("\n");
    }}
    reps = getenv("RELEASES_COUNT") != NULL ? 1 : N >= 64 ? 1 : N >= 16 ? 4 : 40; /* callgrind: fewest */
    TIME("mass_matrix", {name}_mass_matrix(X[k_], 0, M), reps);
    TIME("forces", {name}_forces(X[k_], 0, 0, f), reps);
    TIME("qdd", {name}_qdd(X[k_], 0, 0, f), reps);
    TIME("energy", sink = {name}_energy(X[k_], 0), reps);
    TIME("qdd_derivatives", {name}_qdd_derivatives(X[k_], 0, 0, f, dq, dv, 0), reps);
#if {NAME}_HAS_CANONICAL
    TIME("momenta", {name}_momenta(X[k_], 0, pm), reps);
    TIME("velocities", {name}_velocities(X[k_], pm, 0, f), reps);
    TIME("pdot", {name}_pdot(X[k_], 0, 0, f), reps);
#endif
    TIME("rk4_step", {name}_integrate({NAME}_RK4, 0.0, 1e-3, 1e-3, 0.0, 0.0, X[k_], 0, 0, x1, 0), reps);
    (void)out;
    return 0;
}}
'''


def source_of(commit: str) -> Path:
    """The package's source at ``commit`` (git archive), once."""
    sha = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", commit], capture_output=True, text=True,
                         check=True).stdout.strip()
    src = BUILD / f"src-{sha}"
    if not (src / "gyrochain").is_dir():
        src.mkdir(parents=True, exist_ok=True)
        subprocess.run(f"git -C '{ROOT}' archive {sha} | tar -x -C '{src}'", shell=True, check=True)
    return src


def emit(src: Path, n: int, out: Path) -> None:
    if (out / f"chain{n}.c").exists() and src != ROOT:
        return
    spec = BUILD / f"chain{n}.toml"
    spec.write_text(chain_text(n))
    env = dict(os.environ, PYTHONPATH=str(src), PYTHONHASHSEED="0")
    subprocess.run([sys.executable, "-c", EMIT, str(spec), str(out)], cwd=src, env=env, check=True)


def program(out: Path, n: int, flags: list[str], apart: bool = False) -> Path:
    """The timing program, the model's C included in it (one translation unit, as timed); with
    ``apart``, the model compiled on its own and linked, as a user's program links it: every public
    function is then a call of its own, which callgrind can count (gcc -O3 inlines some into the
    program otherwise)."""
    name = f"chain{n}"
    text = PROGRAM.format(name=name, NAME=name.upper(), n=n, k=K)
    tag = "".join(flags).replace("=", "")
    if not apart:
        (out / "time_all.c").write_text(text)
        exe = out / ("time_all" + tag)
        subprocess.run(["gcc", "-std=c99", *flags, f"-I{out}", str(out / "time_all.c"), "-lm", "-o", str(exe)], check=True)
        return exe
    (out / "count_all.c").write_text(text.replace(f'#include "{name}.c"', f'#include "{name}.h"'))
    obj, exe = out / f"{name}{tag}.o", out / ("count_all" + tag)
    subprocess.run(["gcc", "-std=c99", *flags, "-c", str(out / f"{name}.c"), "-o", str(obj)], check=True)
    subprocess.run(["gcc", "-std=c99", *flags, f"-I{out}", str(out / "count_all.c"), str(obj), "-lm", "-o", str(exe)], check=True)
    return exe


def run(exe: Path, states: str) -> tuple[np.ndarray, dict]:
    lines = subprocess.run([str(exe)], input=states, capture_output=True, text=True, check=True).stdout.splitlines()
    outs = np.array([[float(v) for v in ln.split()] for ln in lines if not ln.startswith("time ")])
    times = {ln.split()[1]: float(ln.split()[2]) for ln in lines if ln.startswith("time ")}
    return outs, times


# each timed label and the public function it calls
CALLS = {"mass_matrix": "mass_matrix", "forces": "forces", "qdd": "qdd", "energy": "energy", "qdd_derivatives": "qdd_derivatives",
         "momenta": "momenta", "velocities": "velocities", "pdot": "pdot", "rk4_step": "integrate"}


def instructions(exe: Path, states: str, name: str) -> dict:
    """Instructions per call of every timed function, counted by callgrind (the same on a busy host
    as on a quiet one, where the times are not): its inclusive count over its calls, from every
    call site of the program (the model linked apart: program(apart=True)).  Each is called through
    its public name; RK4's step is NAME_integrate's."""
    out = exe.with_name(exe.name + ".callgrind")
    subprocess.run(["valgrind", "--tool=callgrind", "--compress-strings=no", "--compress-pos=no", f"--callgrind-out-file={out}",
                    str(exe)], input=states, capture_output=True, text=True, check=True, env=dict(os.environ, RELEASES_COUNT="1"))
    calls: dict = {}
    cost: dict = {}
    target, pending = None, None
    for line in out.read_text().splitlines():
        if line.startswith("cfn="):
            target = line[4:].split(".")[0].split("'")[0]  # a clone (.constprop.0) is the function
        elif line.startswith("calls="):
            pending = int(line[6:].split()[0])
        elif pending is not None:
            calls[target] = calls.get(target, 0) + pending
            cost[target] = cost.get(target, 0) + int(line.split()[1])
            pending = None
    return {label: cost[f"{name}_{fn}"] / calls[f"{name}_{fn}"] for label, fn in CALLS.items() if calls.get(f"{name}_{fn}")}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--previous", default=PREVIOUS, help=f"the previous release's commit (default {PREVIOUS})")
    ap.add_argument("--n", type=int, nargs="+", default=[2, 4, 8, 16, 32, 64, 128])
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--instructions", action="store_true",
                    help="also count every function's instructions per call with callgrind (deterministic)")
    args = ap.parse_args()
    global COUNT
    COUNT = args.instructions and shutil.which("valgrind") is not None
    if args.instructions and not COUNT:
        print("no valgrind: the instructions per call are not counted (apt-get install valgrind)", flush=True)
    prev = source_of(args.previous)
    rng = np.random.default_rng(7)
    rows = []
    for n in args.n:
        states = "\n".join(" ".join(repr(float(v)) for v in np.concatenate([rng.uniform(-np.pi, np.pi, n), rng.normal(size=n)]))
                           for _ in range(K))
        dirs = {"previous": BUILD / f"prev-{prev.name[4:]}-{n}", "this": BUILD / f"this-{n}"}
        emit(prev, n, dirs["previous"])
        emit(ROOT, n, dirs["this"])
        for label, flags in FLAGS.items():
            exes = {who: program(d, n, flags) for who, d in dirs.items()}
            best: dict = {who: {} for who in exes}
            outs = {}
            for _ in range(args.rounds):
                for who, exe in exes.items():
                    outs[who], times = run(exe, states)
                    for fn, t in times.items():
                        best[who][fn] = min(best[who].get(fn, np.inf), t)
            counted = {who: instructions(program(d, n, flags, apart=True), states, f"chain{n}") for who, d in dirs.items()} if COUNT else None
            a, b = outs["previous"], outs["this"]
            diff = float(np.max(np.abs(a - b) / (1.0 + np.abs(a)))) if a.shape == b.shape else float("nan")
            print(f"n = {n:3d}, {label}: outputs differ by {diff:.1e} (relative)")
            for fn in best["this"]:
                p, t = best["previous"].get(fn, np.nan), best["this"][fn]
                row = dict(n=n, flags=label, function=fn, previous_ns=round(p, 1), this_ns=round(t, 1),
                           previous_over_this=round(p / t, 3), outputs_differ=f"{diff:.1e}")
                flag = "  <- slower" if p / t < 0.95 else ""
                line = f"    {fn:16s} previous {p:12.1f}  this {t:12.1f}  previous/this {p / t:5.2f}{flag}"
                if counted is not None:
                    ip, it = counted["previous"].get(fn, np.nan), counted["this"].get(fn, np.nan)
                    row.update(previous_instructions=round(ip, 1), this_instructions=round(it, 1),
                               previous_over_this_instructions=round(ip / it, 3))
                    line += f"  | instructions {ip:12,.0f} {it:12,.0f}  previous/this {ip / it:5.2f}" + ("  <- more" if ip / it < 0.995 else "")
                rows.append(row)
                print(line)
    RESULTS.mkdir(parents=True, exist_ok=True)
    write_csv(RESULTS / "releases.csv", rows)
    print(f"wrote {RESULTS / 'releases.csv'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
