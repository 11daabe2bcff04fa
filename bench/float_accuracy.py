"""What single precision costs (`generate --real float`), measured against the double model:

1. φ̈ and the Jacobian ∂φ̈/∂(φ, φ̇) at 1000 random states of every short example and of random
   spatial gyrostat chains (n = 4, 8): the relative error (to the largest entry), its median, 99th
   percentile and worst, and cond(M) where it is worst against its median (error ~ cond(M) · eps);
   a scatter of error against cond(M) (docs/img/float_error.png).
2. RK4 at a control rate (1 kHz) over 10 s from each example's [initial] state: the drift of the
   energy where it is an integral, float against double.
3. The Furuta LQR loop of examples/furuta_lqr.py closed on the float model: the pendulum's angle
   after 4 s from 0.2 rad off upright, float against double.

Prints the tables of docs/embedding.md; writes bench/results/float_accuracy.csv.  About 2 minutes
(it builds the float models)."""
from __future__ import annotations

import csv
import importlib.util
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))

from gyrochain import pipeline  # noqa: E402
from gyrochain.randspec import random_spec_text  # noqa: E402
from gyrochain.spec import load_spec, parse_spec  # noqa: E402
from conftest import SHORT_EXAMPLES, example_params  # noqa: E402
sys.path.insert(0, str(Path(__file__).resolve().parent))  # bench/, when loaded from elsewhere
from provenance import record  # noqa: E402

RESULTS = ROOT / "bench" / "results"
STATES = 1000


def models(spec, params):
    files, _ = pipeline.derive_and_render(spec, f"{spec.name}.toml", targets=("c",), real="float")
    return pipeline.compiled(spec)[0], pipeline.compile(files, spec.name), params


def errors(d, f, params, rng):
    rows = []
    for _ in range(STATES):
        x = np.concatenate([rng.uniform(-np.pi, np.pi, d.n), rng.normal(size=d.n)]).astype(np.float32)
        u = rng.normal(size=d.nu).astype(np.float32) if d.nu else None
        t = float(np.float32(rng.uniform(0, 2))) if d.time_dependent else 0.0
        try:
            q, dq, dv, _ = d.qdd_derivatives(x.astype(float), u, params, t=t)
            qf, dqf, dvf, _ = f.qdd_derivatives(x, u, params, t=t)
        except ArithmeticError:
            continue
        J, Jf = np.hstack([dq, dv]), np.hstack([dqf, dvf])
        cond = np.linalg.cond(d.mass_matrix(x[:d.n].astype(float), params))
        rows.append((np.max(np.abs(qf - q)) / np.max(np.abs(q)), np.max(np.abs(Jf - J)) / np.max(np.abs(J)), cond))
    return np.array(rows)


def drift(d, f, spec, params):
    init = spec.initial or {}
    x0 = np.array(list(init.get("phi", [0.1] * spec.n)) + list(init.get("phidot", [0.0] * spec.n)))
    t = np.linspace(0.0, 10.0, 10001)
    out = []
    for m in (d, f):
        X = m.integrate(t, x0, "rk4", h=1e-3, params=params, u=np.zeros(m.nu) if m.nu else None)
        E = np.array([m.energy(x, params) for x in X[::100]], float)
        out.append(float(np.max(np.abs(E - E[0]))))
    return out


def lqr(d, f):
    spec = importlib.util.spec_from_file_location("furuta_lqr", ROOT / "examples" / "furuta_lqr.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    K = mod.gain(d)
    return [float(abs(mod.run(m, K)[1][-1, 1] - np.pi)) for m in (d, f)]


def main() -> int:
    rng = np.random.default_rng(11)
    cases = [(n, load_spec(ROOT / "specs" / f"{n}.toml"), example_params(n)) for n in SHORT_EXAMPLES]
    cases += [(f"random chain n = {n}", parse_spec(random_spec_text(np.random.default_rng(500 + n), n, name=f"fchain{n}")), None)
              for n in (4, 8)]
    rows, allerr = [], []
    print("| model | φ̈: median | 99 % | worst | Jacobian: median | 99 % | worst | cond(M): median | at the worst φ̈ | energy drift, 10 s of RK4 at 1 kHz: double | float |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for label, spec, params in cases:
        d, f, params = models(spec, params)
        e = errors(d, f, params, rng)
        allerr.append(e)
        worst = int(np.argmax(e[:, 0]))
        conservative = pipeline.derive(spec, latex=False).integrals.has_energy_integral and not spec.controls
        dd, df = drift(d, f, spec, params) if conservative else (None, None)
        row = dict(model=label, qdd_median=np.median(e[:, 0]), qdd_p99=np.percentile(e[:, 0], 99), qdd_max=e[:, 0].max(),
                   jac_median=np.median(e[:, 1]), jac_p99=np.percentile(e[:, 1], 99), jac_max=e[:, 1].max(),
                   cond_median=np.median(e[:, 2]), cond_at_worst=e[worst, 2], drift_double=dd, drift_float=df)
        rows.append(row)
        fmt = lambda v: "—" if v is None else f"{v:.1e}"  # noqa: E731
        print(f"| {label} | {fmt(row['qdd_median'])} | {fmt(row['qdd_p99'])} | {fmt(row['qdd_max'])} | {fmt(row['jac_median'])} | "
              f"{fmt(row['jac_p99'])} | {fmt(row['jac_max'])} | {row['cond_median']:.0f} | {row['cond_at_worst']:.2g} | "
              f"{fmt(dd)} | {fmt(df)} |", flush=True)
    e = np.vstack(allerr)
    print(f"\nall: phi'' median {np.median(e[:, 0]):.1e}, 99 % {np.percentile(e[:, 0], 99):.1e}; Jacobian median "
          f"{np.median(e[:, 1]):.1e}, 99 % {np.percentile(e[:, 1], 99):.1e}; correlation of log error and log cond(M): "
          f"{np.corrcoef(np.log(e[:, 0] + 1e-16), np.log(e[:, 2]))[0, 1]:.2f}")
    d, f, _ = models(load_spec(ROOT / "specs" / "furuta.toml"), None)
    ld, lf = lqr(d, f)
    print(f"Furuta LQR at 1 kHz from 0.2 rad off upright, |phi2 - pi| after 4 s: double {ld:.1e} rad, float {lf:.1e} rad")
    RESULTS.mkdir(parents=True, exist_ok=True)
    with (RESULTS / "float_accuracy.csv").open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    record(RESULTS / "float_accuracy.csv", "-O2")
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(6.4, 4.2), dpi=120)
        ax.loglog(e[:, 2], np.maximum(e[:, 0], 1e-10), ".", ms=2, alpha=0.5, label="φ̈, one random state")
        c = np.logspace(0, np.log10(e[:, 2].max()), 50)
        ax.loglog(c, c * 1.19e-7, "k--", lw=1, label="cond(M) · FLT_EPSILON")
        ax.set_xlabel("cond(M) at the state")
        ax.set_ylabel("relative error of φ̈, float against double")
        ax.set_title(f"single precision: {len(e)} states of {len(cases)} models", fontsize=9)
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(ROOT / "docs" / "img" / "float_error.png")
        print("wrote docs/img/float_error.png")
    except ImportError:
        pass
    return 0


if __name__ == "__main__":
    sys.exit(main())
