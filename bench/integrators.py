"""`make bench`: speed against accuracy of the emitted C integrators (RK4, DOP853, GAUSS2) and of
scipy's solve_ivp (RK45, DOP853, Radau) driving the generated Python rhs and the cffi C rhs.

1. Work-precision: error at the final time against wall time and against rhs evaluations on the
   gimbal gyroscope (10 periods, exact reference from the two-body quadratures), a chaotic 3-link
   spatial chain (2 s, reference: our DOP853 at rtol 1e-14, checked against scipy's DOP853 on the
   independent reference model) and the fast-spinning gyrostat fast_gyro (1 s = 45 nutations,
   exact reference from the quadratures).  Error = max |x - x_ref| / max |x_ref|.
2. The speed target: at 1e-8 on the gimbal, C DOP853 against scipy DOP853 on the generated Python
   rhs (the cheapest run of each that reaches 1e-8), side by side.
3. Long-time drift: energy and momentum error over 1e5 gimbal periods for each C method; then
   GAUSS2 against GAUSS2_SYMPLECTIC (and DOP853) where no reversing symmetry bounds GAUSS2's error:
   the gyrostat gyrostat2 over 1e5 periods and the chaotic chain spatial3 over 5e4 s.
4. rhs cost: ns per call of the generated C (every example), its op count, and the Python-level
   costs (generated Python rhs, cffi call through CModel.rhs).
Results: bench/results/work_precision.csv, drift.csv, drift_symplectic.csv, rhs_cost.csv,
and bench/report.py draws work_precision.png, drift.png, drift_symplectic.png from them.
"""
from __future__ import annotations

import csv
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "bench"))
sys.path.insert(0, str(ROOT / "tests"))

from gyrochain import build, reference  # noqa: E402
from gyrochain.build import IntegrationError  # noqa: E402
from gyrochain.spec import load_spec  # noqa: E402
from conftest import example_params  # noqa: E402  (the values of furuta_sym's parameters)
from provenance import record  # noqa: E402

RESULTS = ROOT / "bench" / "results"
GEN = ROOT / "generated"


def timed(fn, budget=0.2, max_repeats=5):
    """The fastest of a few runs (at least one, more while they are short), and the result."""
    best, out, spent, k = np.inf, None, 0.0, 0
    while k < max_repeats and (k == 0 or spent < budget):
        t0 = time.perf_counter()
        out = fn()
        dt = time.perf_counter() - t0
        best, spent, k = min(best, dt), spent + dt, k + 1
    return best, out


def relerr(x, ref):
    return float(np.max(np.abs(x - ref)) / np.max(np.abs(ref)))


class Counted:
    """f(t, x) for solve_ivp that counts its calls."""

    def __init__(self, f):
        self.f, self.n = f, 0

    def __call__(self, t, x):
        self.n += 1
        return self.f(t, x)


def problems():
    gim, fast = build.load(GEN / "gimbal"), build.load(GEN / "fast_gyro")
    x_g = np.array([0.0, 0.3, 2.0, 0.5])
    T = gim.quad_period(x_g)
    x_f = np.array([0.0, 2.6, 1.0, 0.0])
    Tn = fast.quad_period(x_f)
    sp = build.load(GEN / "spatial3")
    x_s = np.array([0.3, -0.2, 0.5, 1.0, -0.5, 2.0])
    ref_s = sp.integrate([0.0, 2.0], x_s, "dop853", rtol=1e-14, atol=1e-14)[1]
    ch = reference.numeric(load_spec(ROOT / "specs" / "spatial3.toml"))
    check = reference.simulate(ch, x_s, [0.0, 2.0], None, 1e-13, 1e-13)[-1]
    print(f"spatial3 reference: C DOP853 at 1e-14 vs scipy DOP853 on the independent model at 1e-13: "
          f"{relerr(check, ref_s):.1e}", flush=True)
    return [
        dict(name="gimbal", t1=10 * T, x0=x_g, ref=gim.quad_state(10 * T, x_g), c=gim, tchar=T),
        dict(name="spatial3", t1=2.0, x0=x_s, ref=ref_s, c=sp, tchar=0.5),
        dict(name="fast_gyro", t1=1.0, x0=x_f, ref=fast.quad_state(1.0, x_f), c=fast, tchar=Tn),
    ]


def work_precision(pb, rows):
    c, x0, t1, ref = pb["c"], pb["x0"], pb["t1"], pb["ref"]
    py = build.load_python(GEN / pb["name"])
    name = pb["name"]

    def add(method, driver, param, x, sec, nfev):
        e = relerr(x, ref)
        rows.append(dict(problem=name, method=method, driver=driver, param=param, error=e, seconds=sec, n_rhs=nfev))
        print(f"  {name:10s} {method:7s} {driver:9s} {param:>9.3g}  err {e:8.1e}  {sec * 1e3:9.3f} ms  {nfev:8d} rhs",
              flush=True)

    tols = [10.0 ** (-k / 2) for k in range(6, 27)]  # 1e-3 .. 1e-13
    for tol in tols:
        sec, (X, st) = timed(lambda: c.integrate([0.0, t1], x0, "dop853", rtol=tol, atol=tol, full_output=True))
        add("DOP853", "C", tol, X[1], sec, st["n_rhs"])
    for k in np.unique(np.round(np.logspace(1, 3.5, 11)).astype(int)):
        h = pb["tchar"] / k
        for m in ("rk4", "gauss2"):
            try:
                sec, (X, st) = timed(lambda: c.integrate([0.0, t1], x0, m, h=h, full_output=True))
            except IntegrationError as e:  # e.g. GAUSS2's fixed-point iteration at a too-long step
                print(f"  {name} {m} h={h:.3g}: {e}")
                continue
            add(m.upper(), "C", h, X[1], sec, st["n_rhs"])
    drivers = {"Python": lambda t, x: py.rhs(t, x), "cffi C": lambda t, x: c.rhs(t, x)}
    limits = {"RK45": 1e-10, "DOP853": 1e-12, "Radau": 1e-9}
    for method, lim in limits.items():
        for driver, f in drivers.items():
            for tol in tols:
                if tol < lim * 0.99:
                    break
                def once():
                    fc = Counted(f)
                    return solve_ivp(fc, (0.0, t1), x0, method=method, rtol=tol, atol=tol), fc.n

                sec, (sol, nfev) = timed(once, max_repeats=2)
                add(method, driver, tol, sol.y[:, -1], sec, nfev)


def speed_target(rows):
    def cheapest(method, driver):
        ok = [r for r in rows if r["problem"] == "gimbal" and r["method"] == method and r["driver"] == driver
              and r["error"] <= 1e-8]
        return min(ok, key=lambda r: r["seconds"]) if ok else None

    ours, theirs = cheapest("DOP853", "C"), cheapest("DOP853", "Python")
    print("\nAt 1e-8 relative error on the gimbal (10 periods), the cheapest run of each:")
    for label, r in (("C DOP853 (emitted)", ours), ("scipy DOP853, generated Python rhs", theirs)):
        print(f"  {label:36s} tol {r['param']:.0e}  err {r['error']:.1e}  {r['seconds'] * 1e3:9.3f} ms  {r['n_rhs']} rhs")
    ratio = theirs["seconds"] / ours["seconds"]
    print(f"  speed-up: {ratio:.0f}x (target >= 50x)", flush=True)
    return ratio


def drift(rows):
    """Energy and momentum error against time over 1e5 gimbal periods."""
    c = build.load(GEN / "gimbal")
    x0 = np.array([0.0, 0.3, 2.0, 0.5])
    T = c.quad_period(x0)
    E0, p0 = c.energy(x0), c.momentum(x0)
    per = 20  # steps per period of the fixed-step methods
    h = T / per
    n_end = 100_000 * per
    ks = np.unique(np.r_[np.arange(1, per + 1), np.round(np.logspace(np.log10(per), np.log10(n_end), 400)).astype(int)])
    t = np.r_[0.0, ks * h]
    out = {}
    for m, kw in (("rk4", dict(h=h)), ("gauss2", dict(h=h)), ("dop853", dict(rtol=1e-10, atol=1e-10))):
        t0 = time.perf_counter()
        X, st = c.integrate(t, x0, m, full_output=True, **kw)
        sec = time.perf_counter() - t0
        dE = np.abs([c.energy(x) - E0 for x in X[1:]]) / abs(E0)
        dp = np.abs([c.momentum(x) - p0 for x in X[1:]]) / abs(p0)
        first = ks <= per
        out[m] = (t[1:] / T, dE, dp)
        for tk, e, q in zip(t[1:] / T, dE, dp):
            rows.append(dict(method=m.upper(), periods=tk, energy_error=e, momentum_error=q))
        print(f"  {m.upper():7s} {sec:6.2f} s {st['n_rhs']:>11d} rhs  energy: first period {dE[first].max():.1e}, "
              f"max over 1e5 periods {dE.max():.1e} (x{dE.max() / dE[first].max():.1f}), at the end {dE[-1]:.1e};  "
              f"momentum: {dp[first].max():.1e} -> max {dp.max():.1e}", flush=True)
    return out


def symplectic_drift(rows):
    """GAUSS2 on (φ, φ̇) against GAUSS2_SYMPLECTIC on Hamilton's (φ, p), with DOP853 beside them, on
    two systems without a reversing symmetry: the gyrostat gyrostat2 (C ≠ 0, λ ≠ 0; 1e5 periods
    of its nutation, h = T/20) and the chaotic 3-link chain spatial3 without control (u = 0;
    5e4 s, h = 0.01 s)."""
    out = {}
    gy = build.load(GEN / "gyrostat2")
    x_gy = np.array([0.0, 0.8, 1.5, 0.0])
    T = gy.quad_period(x_gy)
    sp3 = build.load(GEN / "spatial3")
    x_sp = np.array([0.5, 0.5, 0.5, 0.0, 0.0, 0.0])
    for name, c, x0, h, t_end, unit, u in (("gyrostat2", gy, x_gy, T / 20, 1e5 * T, T, None),
                                           ("spatial3", sp3, x_sp, 0.01, 5e4, 1.0, np.zeros(1))):
        n_end = int(round(t_end / h))
        ks = np.unique(np.round(np.logspace(0, np.log10(n_end), 400)).astype(int))
        t = np.r_[0.0, ks * h]
        E0 = c.energy(x0)
        K0 = c.momentum(x0) if c.has_momentum and name == "gyrostat2" else None
        out[name] = {}
        for m, kw in (("gauss2", dict(h=h)), ("gauss2_symplectic", dict(h=h)), ("dop853", dict(rtol=1e-10, atol=1e-10))):
            t0 = time.perf_counter()
            X, st = c.integrate(t, x0, m, u=u, full_output=True, **kw)
            sec = time.perf_counter() - t0
            dE = np.abs([c.energy(x) / E0 - 1 for x in X[1:]])
            dK = np.abs([c.momentum(x) / K0 - 1 for x in X[1:]]) if K0 is not None else None
            out[name][m] = (t[1:] / unit, dE, dK)
            for i, tk in enumerate(t[1:] / unit):
                rows.append(dict(system=name, method=m.upper(), time=tk, energy_error=dE[i],
                                 momentum_error=dK[i] if dK is not None else ""))
            tenth = t[1:] <= t_end / 10
            mom = f";  momentum (27): max {dK.max():.1e}" if dK is not None else ""
            print(f"  {name:9s} {m.upper():17s} {sec:6.1f} s {st['n_rhs'] / st['n_steps']:5.1f} rhs/step  energy: "
                  f"max over the first tenth {dE[tenth].max():.1e}, over all {dE.max():.1e}, at the end {dE[-1]:.1e}{mom}",
                  flush=True)
    return out


def gauss2_solver(rows):
    """GAUSS2's stage solver: the sweeps alone (GAUSS2_FIXED) against the automatic choice (sweeps,
    or simplified Newton with the exact Jacobian where it pays), per step: rhs calls, iterations,
    share of Newton steps, wall time (best of 5 runs of 1 s of motion)."""
    cases = [("gimbal", GIMBAL_X0_), ("double_pendulum", None), ("furuta", None), ("spatial3", None), ("fast_gyro", None)]
    for name, x0 in cases:
        spec = load_spec(ROOT / "specs" / f"{name}.toml")
        c = build.load(GEN / name)
        n = spec.n
        if x0 is None:
            x0 = (np.array([*spec.initial["phi"], *spec.initial["phidot"]]) if spec.initial
                  else np.concatenate([np.full(n, 0.5), np.zeros(n)]))
        u = np.zeros(len(spec.controls)) if spec.controls else None
        params = example_params(name)
        for h in (0.001, 0.01, 0.03, 0.1):
            row = dict(example=name, h=h)
            for m in ("gauss2_fixed", "gauss2"):
                try:
                    sec, (X, st) = timed(lambda: c.integrate([0.0, 1.0], x0, m, h=h, u=u, params=params, full_output=True))
                    row[f"{m}_rhs_per_step"] = st["n_rhs"] / st["n_steps"]
                    row[f"{m}_iter_per_step"] = st["n_iter"] / st["n_steps"]
                    row[f"{m}_newton_share"] = st["n_newton"] / st["n_steps"]
                    row[f"{m}_us_per_step"] = sec / st["n_steps"] * 1e6
                except IntegrationError as e:
                    row[f"{m}_rhs_per_step"] = row[f"{m}_iter_per_step"] = row[f"{m}_newton_share"] = None
                    row[f"{m}_us_per_step"] = None
                    row[f"{m}_code"] = e.code
            rows.append(row)

            def fmt(key, f=".1f"):
                v = row.get(key)
                return "fails (NO_CONVERGENCE)" if v is None else format(v, f)
            def show(m):
                if row.get(f"{m}_rhs_per_step") is None:
                    return "fails (NO_CONVERGENCE)"
                out = f"{fmt(m + '_rhs_per_step')} rhs/step, {fmt(m + '_us_per_step', '.2f')} us/step"
                return out + (f", Newton on {fmt(m + '_newton_share', '.0%')} of steps" if m == "gauss2" else "")
            print(f"  {name:16s} h = {h:<6} sweeps only: {show('gauss2_fixed')}  | auto: {show('gauss2')}", flush=True)


GIMBAL_X0_ = np.array([0.0, 0.3, 2.0, 0.5])


def rhs_cost(rows):
    """ns per call of the generated C rhs (the timing harness of bench/speed.py), and the Python costs."""
    from speed import run

    for spec in sorted((ROOT / "specs").glob("*.toml")):
        name = spec.stem
        d = GEN / name
        py = build.load_python(d)
        c = build.load(d)
        params = example_params(name)
        n = py.N
        init = ", ".join(repr(params[k]) for k in py.PARAMS) if params else "0"
        with tempfile.TemporaryDirectory() as tmp:
            src = Path(tmp) / "b.c"
            src.write_text(
                "#define _POSIX_C_SOURCE 199309L\n"
                f'#include "{name}.c"\n'
                f"static int bench_setup(void) {{ return {n}; }}\n"
                f"static int bench_qdd(const double *x, double *out) {{\n"
                f"    {name}_params p = {{ {init} }}; double xd[{2 * n}]; int i, rc = {name}_rhs(0.0, x, 0, &p, xd);\n"
                f"    for (i = 0; i < {n}; ++i) out[i] = xd[{n} + i];\n    return rc;\n}}\n"
                '#include "harness.h"\n')
            exe = Path(tmp) / "b"
            subprocess.run(["gcc", "-O2", "-std=c99", f"-I{ROOT / 'bench'}", f"-I{d}", str(src), "-lm", "-o", str(exe)],
                           check=True)
            rng = np.random.default_rng(3)
            xs = np.hstack([rng.uniform(-np.pi, np.pi, (64, n)), rng.normal(size=(64, n))])
            _, med, _mn = run(exe, xs, Path(tmp))
        x = xs[0]
        k = 2000
        t_py = timed(lambda: [py.rhs(0.0, x, None, params) for _ in range(k)])[0] / k
        t_cffi = timed(lambda: [c.rhs(0.0, x, None, params) for _ in range(k)])[0] / k
        ops = py.OP_COUNTS["rhs"]
        rows.append(dict(spec=name, n=n, c_ns=med, ops=ops, python_us=t_py * 1e6, cffi_us=t_cffi * 1e6))
        print(f"  {name:16s} n={n}  C {med:7.1f} ns  {ops:5d} ops   generated Python {t_py * 1e6:7.1f} us   "
              f"cffi CModel.rhs {t_cffi * 1e6:5.2f} us", flush=True)


def write_csv(path, rows):
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    record(path, "-O2")


def main():
    RESULTS.mkdir(parents=True, exist_ok=True)
    t_start = time.perf_counter()
    cpu = next((ln.split(":", 1)[1].strip() for ln in Path("/proc/cpuinfo").read_text().splitlines()
                if ln.startswith("model name")), platform.processor())
    machine = f"{cpu} ({os.cpu_count()} cores), {platform.system()} {platform.machine()}, Python {platform.python_version()}, gcc -O2"
    print(machine)
    print("\n1. Work-precision", flush=True)
    wp = []
    for pb in problems():
        work_precision(pb, wp)
    write_csv(RESULTS / "work_precision.csv", wp)
    speed_target(wp)
    print("\n3. Long-time drift, gimbal, 1e5 periods", flush=True)
    dr_rows = []
    drift(dr_rows)
    write_csv(RESULTS / "drift.csv", dr_rows)
    print("\n3b. Symplectic or not, systems without a reversing symmetry", flush=True)
    sy_rows = []
    symplectic_drift(sy_rows)
    write_csv(RESULTS / "drift_symplectic.csv", sy_rows)
    print("\n4. GAUSS2's stage solver: sweeps only against sweeps or Newton (1 s of motion)", flush=True)
    gs = []
    gauss2_solver(gs)
    write_csv(RESULTS / "gauss2_solver.csv", [dict((k, r.get(k)) for k in sorted(set().union(*gs))) for r in gs])
    print("\n5. rhs cost", flush=True)
    rc = []
    rhs_cost(rc)
    write_csv(RESULTS / "rhs_cost.csv", rc)
    print(f"\nwrote the CSVs in {RESULTS} (make plot draws work_precision.png, drift.png and drift_symplectic.png from them); total {time.perf_counter() - t_start:.0f} s")


if __name__ == "__main__":
    main()
