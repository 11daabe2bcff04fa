"""Where the loop form of long chains (gyrochain/derive/loopform.py) starts to pay: the same random spatial
gyrostat chains emitted in the straight-line form and in the loop form, side by side in one run —
C size, gcc -O2 time, and ns per call of every function the loop form changes.

    python bench/loops.py [n ...]      (default 8 12 16 24)

Writes bench/results/loops.csv: per n, the loop form's figure over the straight-line form's.
"""
from __future__ import annotations

import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from provenance import RESULTS, write  # noqa: E402

from gyrochain import pipeline
from gyrochain.randspec import random_spec_text
from gyrochain.spec import parse_spec

DRIVER = r"""
#include <stdio.h>
#include <time.h>
#include "{name}.h"
static double now(void) {{ struct timespec t; clock_gettime(CLOCK_MONOTONIC, &t); return t.tv_sec + 1e-9 * t.tv_nsec; }}
int main(void)
{{
    static double x[2 * {N}], M[{N} * {N}], out[{N}], pm[{N}];
    double s = 0.0, t0;
    int i, k, reps = {reps};
    for (i = 0; i < 2 * {N}; ++i) x[i] = 0.1 * i - 0.7;
#define TIME(label, call, use) t0 = now(); for (k = 0; k < reps; ++k) {{ x[0] = 1e-7 * k; call; s += use; }} \
    printf("%s %.1f\n", label, (now() - t0) / reps * 1e9);
    TIME("mass_matrix", {name}_mass_matrix(x, 0, M), M[1])
    TIME("energy", s += {name}_energy(x, 0), 0.0)
    TIME("momenta", {name}_momenta(x, 0, pm), pm[0])
    TIME("velocities", {name}_velocities(x, pm, 0, out), out[0])
    TIME("pdot", {name}_pdot(x, 0, 0, out), out[0])
    fprintf(stderr, "%g\n", s);
    return 0;
}}
"""


def measure(n: int, form: str, work: Path) -> dict:
    name = f"c{n}{form[0]}"
    spec = parse_spec(random_spec_text(np.random.default_rng(1000 + n), n, name=name))
    files, _ = pipeline.derive_and_render(spec, targets=("c",), loops=form)
    d = work / name
    d.mkdir()
    for f, text in files.items():
        (d / f).write_text(text)
    t0 = time.perf_counter()
    subprocess.run(["gcc", "-std=c99", "-O2", "-c", str(d / f"{name}.c"), "-o", str(d / "m.o")], check=True)
    gcc = time.perf_counter() - t0
    (d / "drv.c").write_text(DRIVER.format(name=name, N=n, reps=max(2000, 400000 // (n * n))))
    subprocess.run(["gcc", "-O2", "-I", str(d), str(d / "drv.c"), str(d / "m.o"), "-lm", "-o", str(d / "drv")], check=True)
    runs = [dict(line.split() for line in subprocess.run([str(d / "drv")], capture_output=True, text=True,
                                                          check=True).stdout.splitlines()) for _ in range(5)]
    ns = {k: float(np.median([float(r[k]) for r in runs])) for k in runs[0]}
    return dict(kb=len(files[f"{name}.c"]) / 1e3, gcc=gcc, **ns)


def main(ns) -> None:
    fns = ("mass_matrix", "energy", "momenta", "velocities", "pdot")
    print(f"{'n':>3} {'form':>8} {'C KB':>7} {'gcc s':>6} " + " ".join(f"{f:>11}" for f in fns) + "   (ns per call)")
    out = []
    with tempfile.TemporaryDirectory() as tmp:
        for n in ns:
            rows = {form: measure(n, form, Path(tmp)) for form in ("straight", "loops")}
            for form, r in rows.items():
                print(f"{n:>3} {form:>8} {r['kb']:>7.0f} {r['gcc']:>6.1f} " + " ".join(f"{r[f]:>11.0f}" for f in fns))
            s, lo = rows["straight"], rows["loops"]
            print(f"{n:>3} {'ratio':>8} {lo['kb'] / s['kb']:>7.2f} {lo['gcc'] / s['gcc']:>6.2f} "
                  + " ".join(f"{lo[f] / s[f]:>11.2f}" for f in fns) + "   (loops / straight)", flush=True)
            out.append(dict(n=n, c_size=round(lo["kb"] / s["kb"], 3), gcc_time=round(lo["gcc"] / s["gcc"], 3),
                            **{f: round(lo[f] / s[f], 3) for f in fns}))
    path = RESULTS / "loops.csv"
    write(path, out, "-O2")


if __name__ == "__main__":
    if not all(a.isdigit() for a in sys.argv[1:]):
        raise SystemExit(__doc__)
    main([int(a) for a in sys.argv[1:]] or [8, 12, 16, 24])
