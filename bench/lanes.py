"""RK4's lanes (issue 50, make bench): NAME_integrate_batch with RK4 against the previous release's.

This release advances a batch 8 trajectories at a time in lock-step (the model's right side
printed for lanes, gcc vectorising across them): RK4 with libm's sin and cos, RK4_LANES with the
lanes' own (kernels/trig.c); the previous release integrated one trajectory after another.  For a
few example models, the generated C of both (this tree's generated/ and the previous release's,
from git) is compiled into one C program per flag set, which times RK4 over 256 trajectories of
2000 steps, as a batch and one trajectory at a time (NAME_integrate_grid), and checks that a
batch's trajectory is the single call's bit for bit (and RK4's the previous release's).  Prints ns
per RK4 step per trajectory and writes bench/results/lanes.csv.
Usage: bench/lanes.py [--previous COMMIT] [--models ...]
"""
from __future__ import annotations

import argparse
import csv
import subprocess
import sys
import tempfile
from pathlib import Path
sys.path.insert(0, str(Path(__file__).resolve().parent))  # bench/, when loaded from elsewhere
from provenance import record  # noqa: E402

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


_BUILT: dict = {}


def _time(folder: Path, name: str, flags: list[str], params: str, *args: str) -> tuple[float, float]:
    """(ns per step per trajectory, φ¹ of trajectory 1 after 2 s) from the program of this folder
    at these flags, built once."""
    key = (folder, tuple(flags))
    if key not in _BUILT:
        (folder / "main.c").write_text(PROGRAM.format(name=name, NAME=name.upper(), params=params))
        exe = folder / f"main{len(_BUILT)}"
        subprocess.run(["gcc", *flags, f"-I{folder}", str(folder / "main.c"), str(folder / f"{name}.c"), "-o", str(exe), "-lm"],
                       check=True)
        _BUILT[key] = exe
    ns, x = subprocess.run([str(_BUILT[key]), *args], capture_output=True, text=True, check=True).stdout.split()
    return float(ns), float(x)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--previous", default=PREVIOUS, help=f"the previous release's commit (default {PREVIOUS})")
    ap.add_argument("--models", nargs="+", default=MODELS)
    args = ap.parse_args()
    sys.path.insert(0, str(ROOT))
    rows = []
    print("ns per RK4 step per trajectory (256 trajectories x 2000 steps of 1 ms, u = 0); the gains: the "
          "previous release's batch over this one's, RK4 and RK4_LANES")
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
                prev, x_prev = _time(dirs["previous"], name, flags, params, "batch", "1")
                row = dict(model=name, flags=" ".join(flags), previous_batch_ns=prev)
                for method, number in (("rk4", "1"), ("rk4_lanes", "6")):
                    batch, x_batch = _time(dirs["this"], name, flags, params, "batch", number)
                    one, x_one = _time(dirs["this"], name, flags, params, "single", number)
                    assert x_one == x_batch, f"{name} {method}: a batch's trajectory is not the single call's"
                    if method == "rk4":
                        assert x_batch == x_prev, f"{name}: RK4 does not give the previous release's bits"
                    row.update({f"{method}_batch_ns": batch, f"{method}_single_ns": one})
                row["previous_single_ns"] = _time(dirs["previous"], name, flags, params, "single", "1")[0]
                rows.append(row)
                print(f"  {name:16s} {' '.join(flags):38s} previous: batch {prev:6.1f} single {row['previous_single_ns']:6.1f}"
                      f" | rk4: batch {row['rk4_batch_ns']:6.1f} single {row['rk4_single_ns']:6.1f}"
                      f" | rk4_lanes: batch {row['rk4_lanes_batch_ns']:6.1f} single {row['rk4_lanes_single_ns']:6.1f}"
                      f"   batch gain {prev / row['rk4_batch_ns']:4.2f}x, {prev / row['rk4_lanes_batch_ns']:4.2f}x")
    RESULTS.mkdir(parents=True, exist_ok=True)
    with open(RESULTS / "lanes.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    record(RESULTS / "lanes.csv", "")
    print(f"wrote {RESULTS / 'lanes.csv'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
