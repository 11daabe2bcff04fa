"""Does evaluating the rhs of several trajectories in lock-step pay?  (issue 15, make bench)

The emitted φ̈ of the double pendulum (NAME_qdd's straight-line body) is rewritten with a lane
dimension: every temporary becomes an array of L lanes and every statement a loop over them, so
that gcc can vectorise across trajectories; RK4 then advances L trajectories at once.  Timed
against the same body one trajectory at a time (without the emitted code's input and pivot
checks, so that only the lanes differ) and against the product's NAME_integrate_batch, all at the
product's flags (-std=c99 -O2) and, for reference, at -O3 -march=native.  Prints ns per RK4 step
per trajectory and writes bench/results/lanes.csv.
"""
from __future__ import annotations

import csv
import re
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
RESULTS = ROOT / "bench" / "results"
NAME = "double_pendulum"


def qdd_body(c_text: str) -> tuple[list[tuple[str, str]], list[str]]:
    """The temporaries (name, expression) of NAME_qdd and the expressions of acc[0..n-1]."""
    body = c_text.split(f"int {NAME}_qdd(")[1].split("piv[0]")[0]
    temps = re.findall(r"const double (\w+) = (.*);", body)
    acc = re.findall(r"acc\[\d+\] = (.*);", body)
    return temps, acc


def lane_expr(expr: str, temps: set) -> str:
    expr = re.sub(r"\bx\[(\d+)\]", lambda m: f"x[{m.group(1)}*L + l]", expr)
    return re.sub(r"\b([A-Za-z_]\w*)\b(?!\s*\()", lambda m: f"{m.group(1)}[l]" if m.group(1) in temps else m.group(1), expr)


def c_program(temps, acc) -> str:
    names = {t for t, _ in temps}
    scalar = "\n".join(f"    const double {t} = {e};" for t, e in temps)
    scalar += "\n" + "\n".join(f"    qdd[{i}] = {e};" for i, e in enumerate(acc))
    lanes = "\n".join(f"    double {t}[L];\n    for (l = 0; l < L; ++l) {t}[l] = {lane_expr(e, names)};" for t, e in temps)
    lanes += "\n" + "\n".join(f"    for (l = 0; l < L; ++l) qdd[{i}*L + l] = {lane_expr(e, names)};" for i, e in enumerate(acc))
    return f"""
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#define N 2
#define D 4
#ifndef L
#define L 4
#endif
static void qdd1(const double *x, double *qdd) {{
{scalar}
}}
static void qddL(const double *x, double *qdd) {{
    int l;
{lanes}
}}
static void rhs1(const double *x, double *f) {{ f[0] = x[2]; f[1] = x[3]; qdd1(x, f + 2); }}
static void rhsL(const double *x, double *f) {{
    int i;
    for (i = 0; i < N * L; ++i) f[i] = x[N * L + i];
    qddL(x, f + N * L);
}}
static void rk4_1(double *x, double h, long steps) {{
    double k1[D], k2[D], k3[D], k4[D], y[D];
    long s; int i;
    for (s = 0; s < steps; ++s) {{
        rhs1(x, k1); for (i = 0; i < D; ++i) y[i] = x[i] + 0.5 * h * k1[i];
        rhs1(y, k2); for (i = 0; i < D; ++i) y[i] = x[i] + 0.5 * h * k2[i];
        rhs1(y, k3); for (i = 0; i < D; ++i) y[i] = x[i] + h * k3[i];
        rhs1(y, k4);
        for (i = 0; i < D; ++i) x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
    }}
}}
static void rk4_L(double *x, double h, long steps) {{  /* x[i*L + l] */
    double k1[D * L], k2[D * L], k3[D * L], k4[D * L], y[D * L];
    long s; int i;
    for (s = 0; s < steps; ++s) {{
        rhsL(x, k1); for (i = 0; i < D * L; ++i) y[i] = x[i] + 0.5 * h * k1[i];
        rhsL(y, k2); for (i = 0; i < D * L; ++i) y[i] = x[i] + 0.5 * h * k2[i];
        rhsL(y, k3); for (i = 0; i < D * L; ++i) y[i] = x[i] + h * k3[i];
        rhsL(y, k4);
        for (i = 0; i < D * L; ++i) x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
    }}
}}
static double now(void) {{ struct timespec t; clock_gettime(CLOCK_MONOTONIC, &t); return t.tv_sec + 1e-9 * t.tv_nsec; }}
int main(void) {{
    const int nb = 256; const long steps = 2000; const double h = 1e-3;
    double *X = malloc(sizeof(double) * nb * D), *Y = malloc(sizeof(double) * nb * D), g[D * L];
    int b, i, l, rep; double best1 = 1e30, bestL = 1e30, diff = 0.0;
    for (rep = 0; rep < 5; ++rep) {{
        double t0;
        for (b = 0; b < nb; ++b) {{ X[b * D] = -3.0 + 6.0 * b / nb; X[b * D + 1] = 3.0 - 5.0 * b / nb; X[b * D + 2] = X[b * D + 3] = 0.0; }}
        for (i = 0; i < nb * D; ++i) Y[i] = X[i];
        t0 = now();
        for (b = 0; b < nb; ++b) rk4_1(X + b * D, h, steps);
        if (now() - t0 < best1) best1 = now() - t0;
        t0 = now();
        for (b = 0; b < nb; b += L) {{
            for (l = 0; l < L; ++l) for (i = 0; i < D; ++i) g[i * L + l] = Y[(b + l) * D + i];
            rk4_L(g, h, steps);
            for (l = 0; l < L; ++l) for (i = 0; i < D; ++i) Y[(b + l) * D + i] = g[i * L + l];
        }}
        if (now() - t0 < bestL) bestL = now() - t0;
    }}
    for (i = 0; i < nb * D; ++i) if (fabs(X[i] - Y[i]) > diff) diff = fabs(X[i] - Y[i]);
    printf("%.3f %.3f %.3g\\n", 1e9 * best1 / (nb * steps), 1e9 * bestL / (nb * steps), diff);
    free(X); free(Y);
    return 0;
}}
"""


def main() -> int:
    sys.path.insert(0, str(ROOT))
    import numpy as np

    from gyrochain import pipeline
    from gyrochain.spec import parse_spec

    text = (ROOT / "specs" / f"{NAME}.toml").read_text()
    files, _ = pipeline.derive_and_render(parse_spec(text), targets=("c",))
    temps, acc = qdd_body(files[f"{NAME}.c"])
    model = pipeline.compile(files, NAME)
    X0 = np.array([[-3.0 + 6.0 * b / 256, 3.0 - 5.0 * b / 256, 0.0, 0.0] for b in range(256)])
    import time

    best = np.inf
    for _ in range(5):
        t0 = time.perf_counter()
        model.integrate_batch([0.0, 2.0], X0, method="rk4", h=1e-3)
        best = min(best, time.perf_counter() - t0)
    product = 1e9 * best / (256 * 2000)
    rows = []
    print(f"ns per RK4 step per trajectory (double pendulum, 256 trajectories x 2000 steps); product NAME_integrate_batch: {product:.1f}")
    with tempfile.TemporaryDirectory() as tmp:
        src = Path(tmp) / "lanes.c"
        src.write_text(c_program(temps, acc))
        for flags in (["-std=c99", "-O2"], ["-std=c99", "-O3", "-march=native"]):
            for lanes in (2, 4, 8):
                exe = Path(tmp) / "lanes"
                subprocess.run(["gcc", *flags, f"-DL={lanes}", str(src), "-o", str(exe), "-lm"], check=True)
                one, lane, diff = (float(v) for v in subprocess.run([str(exe)], capture_output=True, text=True, check=True).stdout.split())
                rows.append(dict(flags=" ".join(flags), lanes=lanes, one_at_a_time_ns=one, lanes_ns=lane, gain=round(one / lane, 2),
                                 product_ns=round(product, 1), max_difference=diff))
                print(f"  {' '.join(flags):28s} L = {lanes}: one at a time {one:6.1f}, in lanes {lane:6.1f}  (gain {one / lane:4.2f}x; "
                      f"states differ by {diff:.1g})")
    RESULTS.mkdir(parents=True, exist_ok=True)
    with open(RESULTS / "lanes.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
