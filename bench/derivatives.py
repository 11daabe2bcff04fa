"""`make bench-speed`, second part: ns per call of the exact derivatives ∂φ̈/∂(φ, φ̇) against
Pinocchio's analytical computeABADerivatives (C++), CasADi-generated C of the Jacobian of its ABA,
and central differences of our own NAME_qdd (2·2n calls), on the random spatial gyrostat chains of
bench/speed.py, in one run; and the accuracy of the derivatives against Richardson differences of
the independent reference model.

Pinocchio's derivatives do not see state-dependent external forces, so it gets the chain with
λ = 0 (a lighter problem, as MuJoCo in speed.py); its Jacobian is checked against the reference of
that chain.  Results: bench/results/derivatives.csv.
"""
from __future__ import annotations

import argparse
import dataclasses
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "bench"))

from gyrochain import reference  # noqa: E402
from gyrochain.spec import parse_spec  # noqa: E402
from speed import BUILD, CFLAGS, RESULTS, build_pinocchio, chain_text, flagged, generate, run, states, write_csv, _cpu  # noqa: E402

TOL = 1e-6  # relative agreement with the reference differences required before timing
N_CHECK = 3  # states checked against the reference (its differences cost 8n reference calls each)


def ref_jacobian(ch, x, h=1e-3):
    """[∂φ̈/∂φ | ∂φ̈/∂φ̇] of the reference model by Richardson-extrapolated central differences."""
    cols = []
    for e in np.eye(len(x)):
        d1 = (reference.qdd(ch, x + h * e) - reference.qdd(ch, x - h * e)) / (2 * h)
        d2 = (reference.qdd(ch, x + h / 2 * e) - reference.qdd(ch, x - h / 2 * e)) / h
        cols.append((4 * d2 - d1) / 3)
    return np.array(cols).T


def err(J: np.ndarray, ref: list) -> float:
    worst = 0.0
    for Ji, Ri in zip(J, ref):
        worst = max(worst, float(np.max(np.abs(Ji - Ri.ravel())) / max(1.0, float(np.max(np.abs(Ri))))))
    return worst


def _c_program(d: Path, name: str, n: int, body: str) -> Path:
    src = d / f"bench_{name}.c"
    src.write_text(
        "#define _POSIX_C_SOURCE 199309L\n"
        f'#include "chain{n}.c"\n#define BENCH_NOUT(n) ((n) * 2 * (n))\nstatic int bench_setup(void) {{ return {n}; }}\n'
        + body + '#include "harness.h"\n'
    )
    exe = d / name
    subprocess.run(["gcc", *CFLAGS, "-std=c99", f"-I{ROOT / 'bench'}", f"-I{d}", str(src), "-lm", "-o", str(exe)], check=True)
    return exe


def build_ours(n: int, d: Path) -> Path:
    return _c_program(d, "ours_deriv", n, f"""
static int bench_qdd(const double *x, double *out)
{{
    double q[{n}], dq[{n * n}], dv[{n * n}];
    int i, j, code = chain{n}_qdd_derivatives(x, 0, 0, q, dq, dv, 0);
    for (i = 0; i < {n}; ++i) {{
        for (j = 0; j < {n}; ++j) {{
            out[i * {2 * n} + j] = dq[i * {n} + j];
            out[i * {2 * n} + {n} + j] = dv[i * {n} + j];
        }}
    }}
    return code;
}}
""")


def build_fd(n: int, d: Path) -> Path:
    """Central differences of our own chain<n>_qdd: what a user without derivatives writes."""
    return _c_program(d, "fd_deriv", n, f"""
static int bench_qdd(const double *x, double *out)
{{
    double y[{2 * n}], a[{n}], b[{n}], h;
    int i, j, code = 0;
    for (j = 0; j < {2 * n}; ++j) {{
        y[j] = x[j];
    }}
    for (j = 0; j < {2 * n}; ++j) {{
        h = 1e-6 * (1.0 + fabs(x[j]));
        y[j] = x[j] + h;
        code |= chain{n}_qdd(y, 0, 0, a);
        y[j] = x[j] - h;
        code |= chain{n}_qdd(y, 0, 0, b);
        y[j] = x[j];
        for (i = 0; i < {n}; ++i) {{
            out[i * {2 * n} + j] = (a[i] - b[i]) / (2.0 * h);
        }}
    }}
    return code;
}}
""")


def build_casadi(ch, n: int, d: Path) -> Path | None:
    try:
        import casadi as ca
        from peers import casadi_aba
    except ImportError:
        return None
    f = casadi_aba(ch, f"fd{n}")
    x = ca.SX.sym("x", 2 * n)
    J = ca.jacobian(f(x), x)
    g = ca.Function(f"jac{n}", [x], [J.T], {"cse": True})  # column-major out: transpose gives rows
    cwd = os.getcwd()
    os.chdir(d)
    try:
        g.generate(f"casadi_jac{n}.c", {"casadi_real": "double"})
    finally:
        os.chdir(cwd)
    src = d / "bench_casadi_jac.c"
    src.write_text(
        f'#include "casadi_jac{n}.c"\n#define BENCH_NOUT(n) ((n) * 2 * (n))\n'
        f"static casadi_real w_[{max(1, g.sz_w())}];\nstatic casadi_int iw_[{max(1, g.sz_iw())}];\n"
        f"static double dense_[{2 * n * n}];\n"
        f"static int bench_setup(void) {{ return {n}; }}\n"
        "static int bench_qdd(const double *x, double *out) {\n"
        f"    const casadi_real *arg[{max(1, g.sz_arg())}] = {{x}};\n    casadi_real *res[{max(1, g.sz_res())}] = {{dense_}};\n"
        f"    int i, code = jac{n}(arg, res, iw_, w_, 0);\n"
        "    /* the Jacobian's sparsity is dense for a spatial chain: copy */\n"
        f"    for (i = 0; i < {2 * n * n}; ++i) out[i] = dense_[i];\n"
        "    return code;\n}\n"
        '#include "harness.h"\n'
    )
    exe = d / "casadi_jac"
    subprocess.run(["gcc", *CFLAGS, f"-I{ROOT / 'bench'}", str(src), "-lm", "-o", str(exe)], check=True)
    return exe


def symbolic_check(cases) -> list[dict]:
    """Our derivatives against those of the sympy Lagrangian (tests/lagrange.py, built in the fixed
    frame independently of the generator): its Lagrange terms H = ∂²ℒ/∂φ̇² and b symbolically (sympy
    diff), evaluated in double precision; φ̈ = H⁻¹(τ − b), so ∂φ̈/∂x = −H⁻¹(∂b/∂x + (∂H/∂x) φ̈), with
    ∂H/∂x and ∂b/∂x by complex steps of the symbolic H and b (step 1e-30: no truncation error, no
    cancellation; the fully symbolic third derivative of the n = 3 Lagrangian did not finish in a
    working session)."""
    import sympy as sp

    sys.path.insert(0, str(ROOT / "tests"))
    from conftest import generate as gen_model
    from lagrange import lagrangian
    from gyrochain.randspec import random_spec_text

    rows = []
    for n, planar in cases:
        rng = np.random.default_rng(40 + n)
        text = random_spec_text(rng, n, name="lag", planar=planar, gyro=True, controls=(n,), theta1=None)
        spec = parse_spec(text)
        t0 = time.perf_counter()
        phi, v = sp.symbols(f"q1:{n + 1}"), sp.symbols(f"v1:{n + 1}")
        L = lagrangian(spec, phi, v)
        p = [sp.diff(L, vi) for vi in v]
        H = [[sp.diff(p[i], v[j]) for j in range(n)] for i in range(n)]
        b = [sum(sp.diff(p[i], phi[r]) * v[r] for r in range(n)) - sp.diff(L, phi[i]) for i in range(n)]
        hb = sp.lambdify([phi, v], [H, b], modules="numpy", cse=True)
        tc = 1e-30

        def f(q, w):
            Hn, bn = (np.array(a, dtype=float) for a in hb(q, w))
            dH = np.empty((n, n, n))
            db = np.empty((n, 2 * n))
            for j in range(2 * n):
                e = np.zeros(2 * n, complex)
                e[j] = 1j * tc
                Hc, bc = (np.array(a, dtype=complex) for a in hb(q + e[:n], w + e[n:]))
                if j < n:
                    dH[:, :, j] = Hc.imag / tc
                db[:, j] = bc.imag / tc
            return Hn, bn, dH, db
        sym_s = time.perf_counter() - t0
        for form in ("forward", "world"):  # both forms of NAME_qdd_derivatives, on the same states
            name = f"lag{n}{'p' if planar else 's'}{form[0]}"
            model = gen_model(parse_spec(text.replace('name = "lag"', f'name = "{name}"')), BUILD / "lagrange", der_form=form)
            states = np.random.default_rng(50 + n)
            worst = 0.0
            for _ in range(5):
                x = np.concatenate([states.uniform(-3, 3, n), states.normal(size=n)])
                u = states.normal(size=1)
                Hn, bn, dHn, dbn = (np.array(a, dtype=float) for a in f(x[:n], x[n:]))
                tau = np.zeros(n)
                tau[n - 1] = u[0]
                a = np.linalg.solve(Hn, tau - bn)
                J = np.empty((n, 2 * n))
                for j in range(2 * n):
                    dHj = dHn[:, :, j] if j < n else np.zeros((n, n))
                    J[:, j] = -np.linalg.solve(Hn, dbn[:, j] + dHj @ a)
                Ju = np.linalg.solve(Hn, np.eye(n)[:, n - 1])
                _, dq, dv, du = model.c.qdd_derivatives(x, u)
                got = np.hstack([dq, dv, du])
                want = np.hstack([J, Ju[:, None]])
                worst = max(worst, float(np.max(np.abs(got - want)) / np.max(np.abs(want))))
            rows.append(dict(n=n, planar=planar, form=form, max_rel_err=worst, sympy_s=sym_s))
            print(f"symbolic Lagrangian n={n} {'planar' if planar else 'spatial'} (rotors, a control), {form} form: "
                  f"max relative difference {worst:.1e} over 5 states (sympy took {sym_s:.0f} s)", flush=True)
    return rows


PEERS = ("pinocchio", "casadi", "fd")
CASADI_MAX_N = 8  # CasADi's Jacobian of n = 16 is 4.6 MB of C that gcc had not compiled after 5 minutes


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, nargs="*", default=[2, 4, 8, 16, 32], help="chain lengths timed (none: only --symbolic)")
    ap.add_argument("--skip", nargs="*", default=[], choices=PEERS, help="peers not to build (CasADi's Jacobian of n = 16 is 4.6 MB of C)")
    ap.add_argument("--symbolic", action="store_true", help="also the n <= 3 check against the sympy Lagrangian (minutes)")
    args = ap.parse_args()
    BUILD.mkdir(parents=True, exist_ok=True)
    RESULTS.mkdir(parents=True, exist_ok=True)
    print(f"derivatives: {os.cpu_count()} cores, {_cpu()}; flags {' '.join(CFLAGS)}", flush=True)
    rows = []
    for n in args.n:
        text = chain_text(n)
        ch = reference.numeric(parse_spec(text))
        ch0 = dataclasses.replace(ch, lam=np.zeros_like(ch.lam))
        d = BUILD / f"chain{n}"
        gen = generate(text, f"chain{n}")
        xs = states(n)
        ref = [ref_jacobian(ch, x) for x in xs[:N_CHECK]]
        ref0 = [ref_jacobian(ch0, x) for x in xs[:N_CHECK]]
        row = dict(n=n, qdd_ops=gen["ops"]["qdd"], deriv_ops=gen["ops"]["qdd_derivatives"])
        J, med, _ = run(build_ours(n, d), xs, d)
        row["ours_err"], row["ours_ns"] = err(J[:N_CHECK], ref), med
        if row["ours_err"] > TOL:
            raise SystemExit(f"n = {n}: our derivatives disagree with the reference ({row['ours_err']:.2e})")
        for peer, make, r in (("fd", lambda: build_fd(n, d), ref),
                              ("casadi", lambda: build_casadi(ch, n, d), ref),
                              ("pinocchio", lambda: build_pinocchio(ch0, n, d, "pinocchio_derivatives"), ref0)):
            try:
                exe = None if peer in args.skip or (peer == "casadi" and n > CASADI_MAX_N) else make()
            except subprocess.CalledProcessError as e:
                print(f"  {peer} n = {n}: build failed ({e})", file=sys.stderr)
                exe = None
            if exe is None:
                row[f"{peer}_ns"] = row[f"{peer}_err"] = None
                continue
            J, med, _ = run(exe, xs, d)
            row[f"{peer}_err"] = err(J[:N_CHECK], r)
            row[f"{peer}_ns"] = med if row[f"{peer}_err"] <= TOL else None
        best = min((row[f"{p}_ns"] for p in PEERS if row[f"{p}_ns"]), default=None)
        row["best_peer_over_ours"] = best / row["ours_ns"] if best else None
        rows.append(row)
        f = lambda v, s=".0f": "-" if v is None else format(v, s)  # noqa: E731
        print(f"n={n:>3}  ours {f(row['ours_ns']):>8} ns ({row['deriv_ops']} ops, err {row['ours_err']:.1e})"
              f"  FD of our qdd {f(row['fd_ns']):>8} (err {f(row['fd_err'], '.1e')})"
              f"  CasADi jacobian {f(row['casadi_ns']):>8}  Pinocchio (λ=0) {f(row['pinocchio_ns']):>8}"
              f"  best peer / ours {f(row['best_peer_over_ours'], '.2f')}", flush=True)
    if rows:
        # one file per flag set: derivatives.csv at the default -O2, derivatives_O3_march_native.csv ...
        out = RESULTS / flagged("derivatives")
        write_csv(out, rows)
        print(f"wrote {out.relative_to(ROOT)}")
    if args.symbolic:
        write_csv(RESULTS / "derivatives_symbolic.csv", symbolic_check([(2, False), (3, False)]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
