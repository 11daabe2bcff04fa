"""Ensembles: trajectories per second of the double pendulum over 10 s (make bench).

In one run, on the same random initial angles:
- scipy's solve_ivp (DOP853, rtol 1e-8) on the generated Python rhs, one trajectory after another
  (what a user without this tool writes);
- MuJoCo's rollout with its RK4 at the same fixed step, one MjData per thread (1 and 2 threads);
- ours, NAME_integrate_batch with RK4 and RK4_LANES at that step and with DOP853 at rtol 1e-8: one
  thread, both cores (two threads, each half of the batch; cffi releases the GIL) and (RK4, DOP853)
  a local Dask cluster of two worker processes (started before the clock, the model built in each
  worker before it); RK4 and RK4_LANES also with the same C compiled at -O3 -march=native.
Each is first checked against ours (the final state after 1 s of a few trajectories).  Prints a
table and writes bench/results/ensemble.csv; the README's 4000 x 4000 estimate comes from it.
"""
from __future__ import annotations

import argparse
import csv
import os
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from gyrochain import build, pipeline  # noqa: E402
from gyrochain.spec import parse_spec  # noqa: E402
sys.path.insert(0, str(Path(__file__).resolve().parent))  # bench/, when loaded from elsewhere
from provenance import record  # noqa: E402

RESULTS = ROOT / "bench" / "results"
SPEC = ROOT / "specs" / "double_pendulum.toml"
T1 = 10.0
H = 1e-3

# The same chain for MuJoCo: two 1 m rods of 1 kg on parallel horizontal hinges, the centre of
# mass 0.5 m down the rod; the spec's A about O^k = diag(0.3335, 0.3335, 0.001) is, about the
# centre of mass, diag(0.0835, 0.0835, 0.001).  Gravity -z; no contacts, no damping.
MJCF = """
<mujoco>
  <option timestep="{h}" integrator="RK4" gravity="0 0 -9.81">
    <flag contact="disable" constraint="disable" energy="enable"/>
  </option>
  <worldbody>
    <body name="b1" pos="0 0 0">
      <joint name="j1" type="hinge" axis="1 0 0" damping="0" armature="0"/>
      <inertial pos="0 0 -0.5" mass="1" diaginertia="0.0835 0.0835 0.001"/>
      <body name="b2" pos="0 0 -1">
        <joint name="j2" type="hinge" axis="1 0 0" damping="0" armature="0"/>
        <inertial pos="0 0 -0.5" mass="1" diaginertia="0.0835 0.0835 0.001"/>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def initial_states(count: int, seed: int = 1) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return np.hstack([rng.uniform(-3.0, 3.0, (count, 2)), np.zeros((count, 2))])


def rate(fn, count: int, repeats: int = 3) -> float:
    """Trajectories per second: the best of ``repeats`` runs of fn() over ``count`` trajectories."""
    best = np.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return count / best


def ours_threads(model, X0, nthreads: int, **kw):
    parts = np.array_split(X0, nthreads)
    t = np.array([0.0, T1])
    if nthreads == 1:
        return model.integrate_batch(t, X0, **kw)
    with ThreadPoolExecutor(max_workers=nthreads) as pool:
        return list(pool.map(lambda part: model.integrate_batch(t, part, **kw), parts))


def native_model(files: dict):
    """The model's C compiled at -O3 -march=native (a bench-only build beside the product's)."""
    import tempfile

    folder = Path(tempfile.mkdtemp(prefix="ensemble_native_"))
    for name, text in files.items():
        if name.startswith("double_pendulum."):
            (folder / name).write_text(text)
    so = build.compile_model(folder, "double_pendulum", extra_cflags=["-O3", "-march=native"])
    return build.CModel(so, "double_pendulum")


def _dask_part(files, part, kw):
    model = pipeline.compile(files, "double_pendulum")
    X, codes = model.integrate_batch(np.array([0.0, T1]), part, **kw)
    return X[:, -1], codes


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--count", type=int, default=2000, help="trajectories per timing of ours and MuJoCo")
    ap.add_argument("--scipy-count", type=int, default=20, help="trajectories timed with scipy (slow)")
    ap.add_argument("--mujoco-count", type=int, default=200, help="trajectories timed with MuJoCo (it stores every step)")
    ap.add_argument("--no-dask", action="store_true")
    args = ap.parse_args()
    text = SPEC.read_text()
    files, _ = pipeline.derive_and_render(parse_spec(text), targets=("c",))
    model = pipeline.compile(files, "double_pendulum")
    X0 = initial_states(args.count)
    rows = []

    def add(who, integrator, where, r, note=""):
        rows.append(dict(implementation=who, integrator=integrator, where=where, traj_per_s=round(r, 1), note=note))
        print(f"{who:28s} {integrator:22s} {where:28s} {r:12.1f} traj/s  {note}", flush=True)

    # ---- scipy on the generated Python rhs
    from scipy.integrate import solve_ivp

    gen = ROOT / "generated" / "double_pendulum"
    py = build.load_python(gen)
    Xs = X0[: args.scipy_count]
    ref = model.integrate_batch([0.0, 1.0], Xs[:3], rtol=1e-12, atol=1e-12)[0][:, -1]
    sol = solve_ivp(py.rhs, (0.0, 1.0), Xs[0], method="DOP853", rtol=1e-10, atol=1e-12)
    assert np.allclose(sol.y[:, -1], ref[0], atol=1e-6), "scipy on the generated Python disagrees"
    add("scipy solve_ivp + gen. Python", "DOP853 rtol 1e-8", "1 thread (a loop)",
        rate(lambda: [solve_ivp(py.rhs, (0.0, T1), x, method="DOP853", rtol=1e-8, atol=1e-10) for x in Xs], len(Xs), 1))

    # ---- MuJoCo rollout
    try:
        import mujoco
        from mujoco import rollout
    except ImportError:
        mujoco = None
        print("mujoco not installed: pip install 'gyrochain[rollout]'", file=sys.stderr)
    nstep = int(round(T1 / H))
    mj_rate = {}
    if mujoco is not None:
        m = mujoco.MjModel.from_xml_string(MJCF.format(h=H))
        nstate = mujoco.mj_stateSize(m, mujoco.mjtState.mjSTATE_FULLPHYSICS)
        d = mujoco.MjData(m)

        def mj_states(X):
            S = np.zeros((len(X), nstate))
            for i, x in enumerate(X):
                mujoco.mj_resetData(m, d)
                d.qpos[:] = x[:2]
                d.qvel[:] = x[2:]
                mujoco.mj_getState(m, d, S[i], mujoco.mjtState.mjSTATE_FULLPHYSICS)
            return S

        S0 = mj_states(X0[: args.mujoco_count])
        # same motion: MuJoCo's hinge angle from the downward vertical, in the same or opposite sense
        st, _ = rollout.rollout(m, d, S0[:3], nstep=int(round(1.0 / H)))
        q_mj = st[:, -1, 1:3]
        q_us = model.integrate_batch([0.0, 1.0], X0[:3], method="rk4", h=H)[0][:, -1, :2]
        err = min(np.abs(q_mj - q_us).max(), np.abs(q_mj + q_us).max())
        assert err < 1e-6, f"MuJoCo's double pendulum does not move as ours (differs by {err:.2g} rad after 1 s)"
        for nthreads in (1, 2):
            datas = [mujoco.MjData(m) for _ in range(nthreads)]
            out = np.empty((len(S0), nstep, nstate))
            r = rate(lambda: rollout.rollout(m, datas if nthreads > 1 else datas[0], S0, nstep=nstep, state=out), len(S0))
            mj_rate[nthreads] = r
            add(f"MuJoCo {mujoco.__version__} rollout", f"RK4 h = {H:g}", f"{nthreads} thread(s), one MjData each", r,
                f"(agrees with ours to {err:.1e} rad at 1 s)" if nthreads == 1 else "")

    # ---- ours
    ours = {}
    every = np.linspace(0.0, T1, nstep + 1)
    Xm = X0[: args.mujoco_count]
    rk, rkl = f"RK4 h = {H:g}", f"RK4_LANES h = {H:g}"
    for integ, method in ((rk, "rk4"), (rkl, "rk4_lanes")):
        add("ours, NAME_integrate_batch", integ, "1 thread, every step stored",
            rate(lambda: model.integrate_batch(every, Xm, method=method, h=H), len(Xm)), "(as rollout stores them)")
    for integ, kw in ((rk, dict(method="rk4", h=H)), (rkl, dict(method="rk4_lanes", h=H)),
                      ("DOP853 rtol 1e-8", dict(method="dop853", rtol=1e-8, atol=1e-10))):
        for nthreads in (1, 2):
            r = rate(lambda: ours_threads(model, X0, nthreads, **kw), len(X0))
            ours[(integ, nthreads)] = r
            add("ours, NAME_integrate_batch", integ, f"{nthreads} thread(s)", r)
        if not args.no_dask and integ != rkl:
            from distributed import Client, LocalCluster

            with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1", dashboard_address=None,
                              silence_logs=40) as cluster, Client(cluster) as client:
                client.run(lambda: pipeline.compile(files, "double_pendulum") and None)  # build and load first
                fut_files = client.scatter(files, broadcast=True)
                parts = np.array_split(X0, 8)

                def go():
                    return client.gather(client.map(_dask_part, [fut_files] * len(parts), parts, [kw] * len(parts), pure=False))
                r = rate(go, len(X0))
                ours[(integ, "dask")] = r
                add("ours, NAME_integrate_batch", integ, "local Dask cluster, 2 workers", r)
    # the same C at -O3 -march=native (the vector width of this machine: 256 or 512 bits)
    native = native_model(files)
    for integ, method in ((rk, "rk4"), (rkl, "rk4_lanes")):
        for nthreads in (1, 2):
            r = rate(lambda: ours_threads(native, X0, nthreads, method=method, h=H), len(X0))
            ours[(integ + " native", nthreads)] = r
            add("ours, -O3 -march=native", integ, f"{nthreads} thread(s)", r)
    # a batch's trajectory is the single call's (the same lanes, one at a time)
    for method in ("rk4", "rk4_lanes"):
        Xb = model.integrate_batch([0.0, T1], X0[:9], method=method, h=H)[0][:, -1]
        single = np.array([model.integrate([0.0, T1], x, method, h=H)[-1] for x in X0[:9]])
        print(f"{method}: batch against single calls, 9 trajectories over {T1:g} s: largest difference "
              f"{np.max(np.abs(Xb - single)):.1e}")
    eff = ours[(rk, 2)] / (2 * ours[(rk, 1)])
    eff_d = ours[("DOP853 rtol 1e-8", 2)] / (2 * ours[("DOP853 rtol 1e-8", 1)])
    print(f"\nparallel efficiency on 2 cores (threads): RK4 {eff:.0%}, DOP853 {eff_d:.0%}")
    if mj_rate:
        for integ in (rk, rkl):
            print(f"ours {integ.split()[0]} / MuJoCo rollout RK4 at h = {H:g}: 1 thread {ours[(integ, 1)] / mj_rate[1]:.1f}x, "
                  f"both cores {ours[(integ, 2)] / mj_rate[2]:.1f}x; at -O3 -march=native "
                  f"{ours[(integ + ' native', 1)] / mj_rate[1]:.1f}x, {ours[(integ + ' native', 2)] / mj_rate[2]:.1f}x")
    per = 1.0 / ours[("DOP853 rtol 1e-8", 1)]
    print("a 4000 x 4000 flip map (DOP853 1e-8, 10 s each, final state only), from the one-thread cost and the 2-core efficiency:")
    for cores in (1, 64, 1024):
        e = 1.0 if cores == 1 else eff_d
        secs = 16e6 * per / (cores * e)
        print(f"  {cores:5d} cores: {secs / 3600:8.2f} h" if secs > 3600 else f"  {cores:5d} cores: {secs / 60:8.1f} min")
    RESULTS.mkdir(parents=True, exist_ok=True)
    with open(RESULTS / "ensemble.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    record(RESULTS / "ensemble.csv", "-O2 unless the row says otherwise")
    print(f"wrote {RESULTS / 'ensemble.csv'}  (cores: {os.cpu_count()})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
