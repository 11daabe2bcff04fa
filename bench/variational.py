"""`make bench`: the variational equations of a 3-body chain over one period, the emitted C
(NAME_integrate_variational: x and Φ by DOP853 in one call) against scipy's solve_ivp (DOP853) on
the same variational system y = (x, Φ), ẏ = (f(x), A(x) Φ), with f and A from the generated Python
(rhs, linearize) and, to separate the integrator from the model, from the compiled C through cffi
(CModel.rhs, CModel.linearize); side by side in one run, every result checked against ours.

The chain is specs/spatial3.toml (tilted axes, offsets, full inertia tensors, rotors) started 0.2 rad
from its stable equilibrium; one period is that of its slowest linear mode there (2.0 s).  The
tolerances are rtol = atol = 1e-10 for all.  Results: bench/results/variational.csv."""
from __future__ import annotations

import csv
import sys
import time
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from gyrochain import build, orbits  # noqa: E402
sys.path.insert(0, str(Path(__file__).resolve().parent))  # bench/, when loaded from elsewhere
from provenance import record  # noqa: E402

RESULTS = ROOT / "bench" / "results"
EQUILIBRIUM = [1.33227005, 1.25831554, -1.64484794]  # spatial3's stable equilibrium (`gyrochain steady`)
TOL = 1e-10


def best_of(fn, repeats: int):
    times, out = [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return min(times), float(np.median(times)), out


def scipy_variational(f, lin, x0, T):
    dim = len(x0)

    def rhs(t, y):
        x = y[:dim]
        A = lin(t, x)
        return np.concatenate([f(t, x), (A @ y[dim:].reshape(dim, dim)).ravel()])

    sol = solve_ivp(rhs, (0.0, T), np.concatenate([x0, np.eye(dim).ravel()]), method="DOP853", rtol=TOL, atol=TOL)
    return sol.y[:dim, -1], sol.y[dim:, -1].reshape(dim, dim), sol.nfev


def main() -> int:
    folder = ROOT / "generated" / "spatial3"
    c = build.load(folder)
    py = build.load_python(folder)
    phi = np.array(EQUILIBRIUM)
    omega = orbits.linear_modes(c, phi)[0][0]
    T = 2 * np.pi / omega
    x0 = np.concatenate([phi + 0.2, np.zeros(3)])
    u = [0.0]  # spatial3's one control torque, held at 0
    rows = []
    best, med, (x1, Phi, st) = best_of(lambda: c.integrate_variational(0.0, T, x0, u=u, rtol=TOL, atol=TOL, full_output=True), 21)
    rows.append(dict(implementation="ours: NAME_integrate_variational (C, DOP853)", seconds=best, median=med,
                     rhs_evaluations=st["n_rhs"], phi_difference=0.0))
    for label, f, lin, repeats in (
        ("scipy solve_ivp DOP853, f and A from the generated Python", lambda t, x: py.rhs(t, x, u),
         lambda t, x: py.linearize(t, x, u)[0], 3),
        ("scipy solve_ivp DOP853, f and A from the C through cffi", lambda t, x: c.rhs(t, x, u),
         lambda t, x: c.linearize(x, u, t=t)[0], 5),
    ):
        b, m, (xs, Ps, nfev) = best_of(lambda f=f, lin=lin: scipy_variational(f, lin, x0, T), repeats)
        diff = float(np.max(np.abs(Ps - Phi)) / np.max(np.abs(Phi)))
        assert diff < 1e-7 and np.max(np.abs(xs - x1)) < 1e-7, (label, diff)
        rows.append(dict(implementation=label, seconds=b, median=m, rhs_evaluations=nfev, phi_difference=diff))
    print(f"variational equations of spatial3 (n = 3, 6 + 36 components) over one period T = {T:.6g} s, "
          f"rtol = atol = {TOL:g}, best of repeated runs:")
    for r in rows:
        print(f"  {r['implementation']:<62} {r['seconds'] * 1e3:9.3f} ms  ({r['rhs_evaluations']} evaluations; "
              f"{r['seconds'] / rows[0]['seconds']:7.1f}x ours; |Phi - ours| / |Phi| = {r['phi_difference']:.1e})")
    RESULTS.mkdir(parents=True, exist_ok=True)
    with (RESULTS / "variational.csv").open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    record(RESULTS / "variational.csv", "-O2")
    print("wrote bench/results/variational.csv")
    return 0


if __name__ == "__main__":
    sys.exit(main())
