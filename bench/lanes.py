"""RK4's lanes (issue 50, make bench): NAME_integrate_batch with RK4 against the previous release's.

This release advances a batch LANES trajectories at a time in lock-step (the model's right side
printed for lanes, its sines and cosines from kernels/trig.c, gcc vectorising across the lanes);
the previous release integrated one trajectory after another with libm's sin and cos.  For a few
example models, the generated C of both (this tree's generated/ and the previous release's, from
git) is compiled into one C program per flag set, which times RK4 over 256 trajectories of 2000
steps: the previous release's batch, this release's batch, and this release one trajectory at a
time (NAME_integrate_grid, the one-lane instance).  Prints ns per RK4 step per trajectory and
writes bench/results/lanes.csv.  Usage: bench/lanes.py [--previous COMMIT] [--models ...]
"""
from __future__ import annotations

import argparse
import csv
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
RESULTS = ROOT / "bench" / "results"
PREVIOUS = "b3877bb"
MODELS = ["double_pendulum", "furuta", "spatial3", "ur5"]
FLAGS = (["-std=c99", "-O2", "-fno-tree-slp-vectorize"], ["-std=c99", "-O3", "-march=native"])

PROGRAM = r"""
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include "{name}.h"
#define NB 256
#define STEPS 2000
#define D (2 * {NAME}_N)
static double now(void)
{{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}}
int main(int argc, char **argv)
{{
    static double x0[NB * D], X[NB * 2 * D], u[{NAME}_NU + 1];
    {params}
    const double t[2] = {{0.0, STEPS * 1e-3}};
    int codes[NB], b, i, rep;
    const int single = argc > 1 && argv[1][0] == 's', method = argc > 2 ? atoi(argv[2]) : {NAME}_RK4;
    double best = 1e30;
    srand(7);
    for (b = 0; b < NB * D; ++b) {{
        x0[b] = (b % D < {NAME}_N ? 3.0 : 0.5) * (2.0 * rand() / RAND_MAX - 1.0);
    }}
    for (i = 0; i <= {NAME}_NU; ++i) {{
        u[i] = 0.0;
    }}
    for (rep = 0; rep < 7; ++rep) {{
        const double t0 = now();
        if (single) {{
            for (b = 0; b < NB; ++b) {{
                codes[b] = {name}_integrate_grid(method, 2, t, 1e-3, 0.0, 0.0, 0, x0 + b * D, u, p, X + 2 * b * D, 0);
            }}
        }} else {{
            {name}_integrate_batch(method, NB, 2, t, 1e-3, 0.0, 0.0, 0, x0, u, 0, p, 0, X, codes);
        }}
        if (now() - t0 < best) {{
            best = now() - t0;
        }}
    }}
    for (b = 0; b < NB; ++b) {{
        if (codes[b] != 0) {{
            fprintf(stderr, "trajectory %d failed with %d\n", b, codes[b]);
            return 1;
        }}
    }}
    printf("%.2f %.17g\n", 1e9 * best / ((double)NB * STEPS), X[D]);
    return 0;
}}
"""


def _params(name: str) -> str:
    sys.path.insert(0, str(ROOT / "tests"))
    from conftest import example_params  # the parameter values the examples are tested with

    from gyrochain.spec import load_spec

    values = example_params(name)
    if not values:
        return f"const {name}_params *p = 0;"
    spec = load_spec(ROOT / "specs" / f"{name}.toml")
    return f"const {name}_params prm = {{{', '.join(repr(values[str(q)]) for q in spec.params)}}}, *p = &prm;"


def _time(folder: Path, name: str, flags: list[str], params: str, *args: str) -> tuple[float, float]:
    (folder / "main.c").write_text(PROGRAM.format(name=name, NAME=name.upper(), params=params))
    exe = folder / "main"
    subprocess.run(["gcc", *flags, f"-I{folder}", str(folder / "main.c"), str(folder / f"{name}.c"), "-o", str(exe), "-lm"],
                   check=True)
    ns, x = subprocess.run([str(exe), *args], capture_output=True, text=True, check=True).stdout.split()
    return float(ns), float(x)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--previous", default=PREVIOUS, help=f"the previous release's commit (default {PREVIOUS})")
    ap.add_argument("--models", nargs="+", default=MODELS)
    args = ap.parse_args()
    sys.path.insert(0, str(ROOT))
    rows = []
    print("ns per RK4 step per trajectory (256 trajectories x 2000 steps of 1 ms, u = 0)")
    with tempfile.TemporaryDirectory() as tmp:
        for name in args.models:
            params = _params(name)
            dirs = {"previous": Path(tmp) / f"prev-{name}", "this": Path(tmp) / f"this-{name}"}
            for d in dirs.values():
                d.mkdir()
            for suffix in (".c", ".h"):
                old = subprocess.run(["git", "show", f"{args.previous}:generated/{name}/{name}{suffix}"], cwd=ROOT,
                                     capture_output=True, text=True, check=True).stdout
                (dirs["previous"] / f"{name}{suffix}").write_text(old)
                (dirs["this"] / f"{name}{suffix}").write_text((ROOT / "generated" / name / f"{name}{suffix}").read_text())
            for flags in FLAGS:
                prev, x_prev = _time(dirs["previous"], name, flags, params)
                this, x_this = _time(dirs["this"], name, flags, params)
                one, x_one = _time(dirs["this"], name, flags, params, "single")
                assert x_one == x_this, f"{name}: a batch's trajectory is not the single call's"
                rows.append(dict(model=name, flags=" ".join(flags), previous_ns=prev, batch_ns=this, one_at_a_time_ns=one,
                                 gain=round(prev / this, 2), lanes_gain=round(one / this, 2)))
                print(f"  {name:16s} {' '.join(flags):36s} previous {prev:7.1f}  this batch {this:7.1f}  "
                      f"this one at a time {one:7.1f}   {prev / this:4.2f}x the previous  (state after 2 s: "
                      f"{abs(x_this - x_prev):.1e} apart)")
    RESULTS.mkdir(parents=True, exist_ok=True)
    with open(RESULTS / "lanes.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print(f"wrote {RESULTS / 'lanes.csv'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
