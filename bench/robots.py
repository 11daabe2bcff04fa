"""make bench-speed: the imported arms (specs/ur5.toml, specs/panda.toml, from specs/robots/): the
time to derive and emit each model and its op counts, and φ̈ of the generated C against Pinocchio's
ABA on the model Pinocchio's own URDF parser builds from the same file (compiled with -DNDEBUG,
its checks off), timed in one run by the same C harness (bench/harness.h: the median of 21 repeats of ~20 ms over 64 random states) and
checked to agree before it is timed.  Writes bench/results/robots.csv and prints the table.
"""
from __future__ import annotations

import csv
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "bench"))
sys.path.insert(0, str(ROOT))
from speed import CFLAGS, _pin_prefix, pin_defines, run  # noqa: E402

from gyrochain import exchange, pipeline  # noqa: E402
from gyrochain.assemble import op_counts  # noqa: E402
from gyrochain.spec import load_spec  # noqa: E402
from provenance import record  # noqa: E402

ARMS = {"ur5": ("ur5_robot.urdf", []), "panda": ("panda.urdf", ["panda_finger_joint1=0.02", "panda_finger_joint2=0.02"])}


def build_ours(name: str, n: int, d: Path) -> Path:
    spec = load_spec(ROOT / "specs" / f"{name}.toml")
    files = pipeline.render(pipeline.derive(spec, latex=False), targets=("c",))
    for f, text in files.items():
        (d / f).write_text(text)
    src = d / "bench_ours.c"
    src.write_text("#define _POSIX_C_SOURCE 199309L\n"
                   f'#include "{name}.c"\nstatic int bench_setup(void) {{ return {n}; }}\n'
                   f"static const double u0[{n}];\n"
                   f"static int bench_qdd(const double *x, double *qdd) {{ return {name}_qdd(x, u0, 0, qdd); }}\n"
                   '#include "harness.h"\n')
    exe = d / f"ours_{name}"
    subprocess.run(["gcc", *CFLAGS, "-std=c99", f"-I{ROOT / 'bench'}", f"-I{d}", str(src), "-lm", "-o", str(exe)], check=True)
    return exe


def build_pinocchio(d: Path) -> Path | None:
    pre = _pin_prefix()
    if pre is None or not Path("/usr/include/eigen3").exists():
        print("no Pinocchio (pip install pin) or no Eigen headers (apt-get install libeigen3-dev): ours only", file=sys.stderr)
        return None
    exe, lib = d / "pinocchio_urdf", pre / "lib"
    # Pinocchio's URDF parser includes urdfdom's headers (the bench extra installs cmeel-urdfdom-headers)
    # -DNDEBUG: Eigen's and Pinocchio's run-time checks off, as in the library the Python binding calls
    subprocess.run(["g++", *CFLAGS, "-DNDEBUG", "-std=c++17", "-w", *pin_defines(CFLAGS), f"-I{pre / 'include'}", f"-I{pre / 'include' / 'urdfdom_headers'}",
                    f"-I{pre / 'include' / 'urdfdom'}", "-I/usr/include/eigen3",
                    f"-I{ROOT / 'bench'}", str(ROOT / "bench" / "pinocchio_urdf.cpp"), f"-L{lib}", "-lpinocchio_parsers",
                    "-lpinocchio_default", f"-Wl,-rpath,{lib}", "-o", str(exe)], check=True)
    return exe


def main() -> None:
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        d = Path(tmp)
        peer = build_pinocchio(d)
        for name, (file, locks) in ARMS.items():
            urdf = ROOT / "specs" / "robots" / file
            t0 = time.perf_counter()
            text, _ = exchange.import_text(urdf, locks=locks)
            t_import = time.perf_counter() - t0
            spec = load_spec(ROOT / "specs" / f"{name}.toml")
            assert text == (ROOT / "specs" / f"{name}.toml").read_text(), f"specs/{name}.toml is stale"
            t0 = time.perf_counter()
            model = pipeline.derive(spec, latex=False)
            files = pipeline.render(model, targets=("c", "python"))
            t_derive = time.perf_counter() - t0
            counts = op_counts(model)
            n = spec.n
            rng = np.random.default_rng(5)
            xs = np.concatenate([rng.uniform(-np.pi, np.pi, (64, n)), rng.normal(size=(64, n))], axis=1)
            ours_q, ours_med, _ = run(build_ours(name, n, d), xs, d)
            row = dict(arm=name, n=n, import_s=round(t_import, 3), derive_emit_s=round(t_derive, 2),
                       qdd_ops=counts["qdd"], mass_matrix_ops=counts["mass_matrix"],
                       derivatives_ops=counts["qdd_derivatives"], c_kib=round(len(files[f"{name}.c"]) / 1024),
                       ours_ns=round(ours_med, 1), pinocchio_ns=None, pinocchio_over_ours=None, agree=None)
            if peer is not None:
                (d / "locks.txt").write_text("".join(f"{k} {v}\n" for k, v in exchange.locks_of(locks).items()))
                (d / "damping.txt").write_text(" ".join(repr(float(b.damping or 0)) for b in spec.bodies))
                os.environ.update(BENCH_URDF=str(urdf), BENCH_LOCKS=str(d / "locks.txt"), BENCH_DAMPING=str(d / "damping.txt"))
                pin_q, pin_med, _ = run(peer, xs, d)
                agree = float(np.max(np.abs(pin_q - ours_q)) / np.max(np.abs(pin_q)))
                assert agree <= 1e-10, f"{name}: Pinocchio and ours disagree ({agree:.1e}): not timed"
                row.update(pinocchio_ns=round(pin_med, 1), pinocchio_over_ours=round(pin_med / ours_med, 2), agree=f"{agree:.1e}")
            rows.append(row)
            print(f"{name}: n = {n}, import {t_import:.2f} s, derive + emit {t_derive:.2f} s, ops qdd {row['qdd_ops']} "
                  f"(M {row['mass_matrix_ops']}, Jacobian {row['derivatives_ops']}), C {row['c_kib']} KiB; "
                  f"phi'' ours {ours_med:.0f} ns, Pinocchio {row['pinocchio_ns']} ns (ratio {row['pinocchio_over_ours']}, "
                  f"agree {row['agree']})", flush=True)
    out = ROOT / "bench" / "results" / "robots.csv"
    with open(out, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    record(out, "-O2")
    print(f"wrote {out.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
