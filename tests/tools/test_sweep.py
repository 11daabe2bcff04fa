"""Ensembles (issue 15): the batched C, sweeps into Zarr on threads and Dask, resuming, measures, plots."""
from __future__ import annotations

import hashlib
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("zarr", reason="the sweep extra (zarr, dask, distributed, tqdm) is not installed")

from gyrochain import pipeline, reference, sweep  # noqa: E402
from gyrochain.cli import main  # noqa: E402
from gyrochain.spec import load_spec, parse_spec  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
DP = ROOT / "specs" / "double_pendulum.toml"
FURUTA_SYM = ROOT / "specs" / "furuta_sym.toml"


def small(measures=("flip_time", "final", "lyapunov"), **kw) -> sweep.Sweep:
    args = dict(spec_text=DP.read_text(), vary=[("phi1", -3.0, 3.0, 12), ("phi2", -3.0, 3.0, 10)], t1=3.0,
                measures=list(measures), samples=300, chunk=30)
    args.update(kw)
    return sweep.Sweep(**args)


def same(a: Path, b: Path) -> None:
    da, db = sweep.read(a), sweep.read(b)
    assert da["attrs"] == db["attrs"]
    assert sorted(da) == sorted(db)
    for k in da:
        if k in ("attrs", "coords"):
            continue
        assert da[k].dtype == db[k].dtype and np.array_equal(da[k], db[k], equal_nan=True), k
    for k in da["coords"]:
        assert np.array_equal(da["coords"][k], db["coords"][k])


def tree_digest(path: Path) -> str:
    h = hashlib.sha256()
    for p in sorted(path.rglob("*")):
        h.update(str(p.relative_to(path)).encode())
        if p.is_file():
            h.update(p.read_bytes())
    return h.hexdigest()


# --------------------------------------------------------------------------- the batched C
def test_batch_is_the_single_calls_bit_for_bit(make_model):
    m = make_model(load_spec(DP))
    rng = np.random.default_rng(1)
    X0 = np.hstack([rng.uniform(-3, 3, (5, 2)), rng.normal(size=(5, 2))])
    X0[3, 1] = np.nan  # one trajectory fails alone
    t = np.linspace(0, 1.5, 7)
    for method, h in (("dop853", 0.0), ("rk4", 0.01), ("gauss2", 0.02)):
        X, codes = m.c.integrate_batch(t, X0, method=method, h=h, rtol=1e-9, atol=1e-11)
        assert codes.tolist() == [0, 0, 0, 2, 0]
        for b in (0, 1, 2, 4):
            assert np.array_equal(X[b], m.c.integrate(t, X0[b], method=method, h=h, rtol=1e-9, atol=1e-11))


def test_batch_with_own_controls_and_parameters(make_model):
    from conftest import example_params

    base = example_params("furuta_sym")
    m = make_model(load_spec(FURUTA_SYM), base)
    P = [dict(base, m2=base["m2"] * (1 + 0.1 * b)) for b in range(3)]
    U = np.array([[0.0], [0.05], [-0.1]])
    X0 = np.tile([0.1, 2.9, 0.0, 0.3], (3, 1))
    t = np.linspace(0, 0.5, 4)
    X, codes = m.c.integrate_batch(t, X0, u=U, params=P)
    assert not codes.any()
    for b in range(3):
        assert np.array_equal(X[b], m.c.integrate(t, X0[b], u=U[b], params=P[b]))
    # one u and one parameter set for all
    X2, _ = m.c.integrate_batch(t, X0, u=U[1], params=P[1])
    assert np.array_equal(X2[2], m.c.integrate(t, X0[2], u=U[1], params=P[1]))


# --------------------------------------------------------------------------- where it runs
def test_serial_threads_and_dask_give_identical_stores(tmp_path):
    pytest.importorskip("distributed")
    sw = small()
    sweep.run(sw, tmp_path / "serial.zarr", threads=1, progress=False)
    sweep.run(sw, tmp_path / "threads.zarr", threads=2, progress=False)
    sweep.run(sw, tmp_path / "dask.zarr", workers=2, progress=False)
    same(tmp_path / "serial.zarr", tmp_path / "threads.zarr")
    same(tmp_path / "serial.zarr", tmp_path / "dask.zarr")
    d = sweep.read(tmp_path / "serial.zarr")
    assert d["done"].all() and d["flip_time"].shape == (12, 10) and d["final"].shape == (12, 10, 4)
    assert (d["code"] == 0).all()


def test_interrupted_run_resumes_to_the_same_store(tmp_path):
    sw = small()
    sweep.run(sw, tmp_path / "whole.zarr", threads=1, progress=False)
    first: list = []
    out = sweep.run(sw, tmp_path / "cut.zarr", threads=2, progress=False, stop_after=2, on_written=first.append)
    assert out["written"] == 2 and not sweep.read(tmp_path / "cut.zarr")["done"].all()
    second: list = []
    out = sweep.run(sw, tmp_path / "cut.zarr", threads=2, progress=False, on_written=second.append)
    assert out["skipped"] == len(set(first)) == 2
    assert sorted(first + second) == list(range(sweep.Plan(sw).n_chunks))  # none lost, none twice
    same(tmp_path / "whole.zarr", tmp_path / "cut.zarr")


def test_killed_process_resumes_to_the_same_store(tmp_path):
    """The command killed (SIGKILL) after its first chunks are in the store, then run again."""
    args = [sys.executable, "-m", "gyrochain", "sweep", str(DP), "--vary", "phi1=-3:3:40", "--vary", "phi2=-3:3:4",
            "--t1", "10", "--measure", "flip_time", "--chunk", "4", "--threads", "1", "-q"]
    whole, cut = tmp_path / "whole.zarr", tmp_path / "cut.zarr"
    assert main(args[3:] + ["-o", str(whole)]) == 0
    proc = subprocess.Popen(args + ["-o", str(cut)], cwd=ROOT, env=dict(os.environ, PYTHONPATH=str(ROOT)),
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        # Each done flag is one file (done/c/<chunk>), so a directory listing every 2 ms sees the
        # second chunk land long before the fortieth: reading the store to ask would be too slow.
        # A flag's file is listed before its bytes are written: wait for three, so that two are whole.
        flags = cut / "done" / "c"
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline and proc.poll() is None:
            if flags.is_dir() and len(os.listdir(flags)) >= 3:
                break
            time.sleep(0.002)
        proc.send_signal(signal.SIGKILL)
    finally:
        proc.wait(timeout=30)
    done = sweep.read(cut)["done"]
    assert 2 <= done.sum() < len(done), "the kill came too late to test anything"
    written: list = []
    sweep.run(sweep.Sweep(**{**small().__dict__, **_cli_sweep(args)}), cut, threads=1, progress=False, on_written=written.append)
    assert sorted(written) == sorted(np.nonzero(~done)[0].tolist())
    same(whole, cut)


def _cli_sweep(args) -> dict:
    """The Sweep fields the command line above sets (the rest are its defaults)."""
    return dict(vary=[("phi1", -3.0, 3.0, 40), ("phi2", -3.0, 3.0, 4)], t1=10.0, measures=["flip_time"], samples=1000, chunk=4)


def test_killed_worker_loses_nothing(tmp_path):
    """A local cluster of two worker processes; one is killed after the first chunk is written.
    Dask runs its tasks elsewhere; the store is the undisturbed one."""
    distributed = pytest.importorskip("distributed")
    sw = small(measures=("flip_time", "final"), t1=6.0, chunk=10, vary=[("phi1", -3.0, 3.0, 16), ("phi2", -3.0, 3.0, 10)])
    sweep.run(sw, tmp_path / "whole.zarr", threads=2, progress=False)
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                                       dashboard_address=None, silence_logs=50)
    killed: list = []
    try:
        with distributed.Client(cluster, timeout="30s") as client:
            pids = list(client.run(os.getpid).values())

        def kill_one(i):
            if not killed:
                os.kill(pids[0], signal.SIGKILL)
                killed.append(i)

        written: list = []
        notes: list = []
        sweep.run(sw, tmp_path / "dask.zarr", scheduler=cluster.scheduler_address, progress=False,
                  on_written=lambda i: (written.append(i), kill_one(i)), note=notes.append)
    finally:
        cluster.close(timeout=30)
    assert killed
    assert any(nt.startswith("sweep: worker tcp://127.0.0.1:") and nt.endswith("lost; its chunk will be recomputed")
               for nt in notes), notes  # said, not silently replaced
    assert sorted(written) == list(range(sweep.Plan(sw).n_chunks))  # each chunk written once
    same(tmp_path / "whole.zarr", tmp_path / "dask.zarr")


# one user's sweep, in a process of its own: the Sweep's fields as JSON, the scheduler, the store
ONE_USER = """
import json, sys
from gyrochain import sweep
sweep.run(sweep.Sweep(**json.loads(sys.argv[1])), sys.argv[3], scheduler=sys.argv[2], progress=False)
"""


def test_two_sweeps_at_once_on_one_scheduler_keep_their_own_models(tmp_path):
    """Two different sweeps (two specs) sent at once to the same scheduler by two processes, as two
    users of one cluster would: each store equals its run on threads.  Their shared inputs were once
    scattered under the literal keys 'sweep', 'files' and 'name', which the two runs then shared.
    (Two processes, not two threads of this one: two Dask clients in threads of one process share
    one event loop, and in a full suite one such client once waited past 120 s for results its
    workers had computed.)"""
    import json
    from dataclasses import asdict

    distributed = pytest.importorskip("distributed")
    runs = {"dp": small(measures=("final",), t1=1.0, chunk=10),
            "furuta": small(measures=("final",), t1=1.0, chunk=10, spec_text=FURUTA_SYM.read_text(),
                            vary=[("phi1", -1.0, 1.0, 12), ("phi2", -1.0, 1.0, 10)])}
    for name, sw in runs.items():
        sweep.run(sw, tmp_path / f"{name}_threads.zarr", threads=1, progress=False)
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                                       dashboard_address=None, silence_logs=50)
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])}
    users = []
    try:
        users = [subprocess.Popen([sys.executable, "-c", ONE_USER, json.dumps(asdict(sw)), cluster.scheduler_address,
                                   str(tmp_path / f"{name}_dask.zarr")], cwd=tmp_path, env=env,
                                  stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) for name, sw in runs.items()]
        said = [user.communicate(timeout=180) for user in users]
        assert [user.returncode for user in users] == [0, 0], [err[-2000:] for _, err in said]
    finally:
        for user in users:
            user.kill()
        cluster.close(timeout=30)
    for name in runs:
        same(tmp_path / f"{name}_threads.zarr", tmp_path / f"{name}_dask.zarr")


def test_ctrl_c_while_the_store_is_made_leaves_nothing(tmp_path, monkeypatch):
    """Ctrl-C at each array of a new store's making: neither the store, nor its temporary folder,
    nor the folder made for it stays; then the same sweep makes it whole."""
    import zarr

    from gyrochain.ensembles import store

    plan, path = sweep.Plan(small()), tmp_path / "new" / "s.zarr"
    real, calls = zarr.Group.create_array, {"n": 0, "at": 0}

    def create_array(self, *a, **kw):
        calls["n"] += 1
        if calls["n"] == calls["at"]:
            raise KeyboardInterrupt
        return real(self, *a, **kw)

    monkeypatch.setattr(zarr.Group, "create_array", create_array)
    arrays = len(plan.coords) + len(plan.sweep.measures) + 2
    for at in range(1, arrays + 1):
        calls.update(n=0, at=at)
        with pytest.raises(KeyboardInterrupt):
            store.open_store(path, plan)
        assert not list(tmp_path.iterdir()), (at, list(tmp_path.iterdir()))
    calls.update(n=0, at=0)
    g = store.open_store(path, plan)
    assert calls["n"] == arrays and [p.relative_to(tmp_path).as_posix() for p in tmp_path.iterdir()] == ["new"]
    assert [p.name for p in path.parent.iterdir()] == ["s.zarr"]
    assert g.attrs["gyrochain_sweep"] and not g["done"][...].any()


# --------------------------------------------------------------------------- the measures
def test_measures(tmp_path):
    """final against the independent reference model; flip_time (a link's absolute angle passing
    the upright) against a dense trajectory of the same C (30000 samples); the energy error of DOP853 at 1e-11; the Lyapunov exponent of small
    oscillations against that of the chaotic big swings."""
    sw = small(measures=("final", "flip_time", "energy_error"), t1=3.0, samples=1500, rtol=1e-11, atol=1e-12,
               vary=[("phi1", 0.3, 2.6, 2), ("phi2", 0.2, 2.8, 2)])
    sweep.run(sw, tmp_path / "m.zarr", threads=1, progress=False)
    d = sweep.read(tmp_path / "m.zarr")
    model = pipeline.compiled(parse_spec(DP.read_text()))[0]
    ch = reference.numeric(load_spec(DP))
    tt = np.linspace(0, 3.0, 30001)
    flips = 0
    for i, p1 in enumerate(d["coords"]["phi1"]):
        for j, p2 in enumerate(d["coords"]["phi2"]):
            x0 = [p1, p2, 0.0, 0.0]
            X = model.integrate(tt, x0, rtol=1e-11, atol=1e-12)
            theta = np.cumsum(X[:, :2], axis=1)  # the links' absolute angles, from their start's nearest 2πk
            theta -= 2 * np.pi * np.round(theta[0] / (2 * np.pi))
            over = np.nonzero(np.abs(theta).max(axis=1) >= np.pi)[0]
            if len(over):
                flips += 1
                assert d["flip_time"][i, j] == pytest.approx(tt[over[0]], abs=3.0 / 1500)
            else:
                assert np.isnan(d["flip_time"][i, j])
            if i == 0:
                assert np.allclose(d["final"][i, j], reference.simulate(ch, x0, [0.0, 3.0])[-1], rtol=1e-6, atol=1e-6)
    assert flips >= 1 and np.isnan(d["flip_time"][0, 0])
    assert np.nanmax(d["energy_error"]) < 1e-7
    ly = small(measures=("lyapunov",), t1=20.0, vary=[("phi1", 0.05, 2.6, 2), ("phi2", 0.05, 2.8, 2)], lyap_interval=0.1)
    sweep.run(ly, tmp_path / "l.zarr", threads=2, progress=False)
    lam = sweep.read(tmp_path / "l.zarr")["lyapunov"]
    assert abs(lam[0, 0]) < 0.3 and lam[1, 1] > 1.0, lam


def test_random_samples_and_a_parameter(tmp_path):
    from conftest import example_params

    params = example_params("furuta_sym")
    varied = {k: v for k, v in params.items() if k != "l"}
    sw = sweep.Sweep(spec_text=FURUTA_SYM.read_text(), vary=[("l", 0.1, 0.3, 0), ("phi2", 2.5, 3.1, 0)], t1=1.0,
                     measures=["final"], random=50, seed=3, params=varied, u=[0.0], chunk=16)
    sweep.run(sw, tmp_path / "r.zarr", threads=2, progress=False)
    d = sweep.read(tmp_path / "r.zarr")
    assert d["final"].shape == (50, 4) and d["coords"]["l"].shape == (50,)
    assert 0.1 <= d["coords"]["l"].min() and d["coords"]["l"].max() <= 0.3
    # the same sample integrated alone with its own parameter value
    model = pipeline.compiled(parse_spec(FURUTA_SYM.read_text()))[0]
    k = 7
    x = model.integrate([0, 1.0], [0.0, d["coords"]["phi2"][k], 0.0, 0.0], u=[0.0], params=dict(varied, l=d["coords"]["l"][k]))
    assert np.array_equal(d["final"][k], x[-1])


def test_no_flip_where_the_energy_forbids_it(tmp_path):
    """The double pendulum of equal uniform rods released at rest with link angles θ¹, θ²: a link
    can pass the upright only if its energy reaches that of one link upright and the other
    hanging, so where 3 cos θ¹ + cos θ² > 2 no point of the map may flip (checked on every point),
    while elsewhere most do."""
    sw = small(measures=("flip_time",), vary=[("link1", -3.1, 3.1, 41), ("link2", -3.1, 3.1, 41)], t1=10.0,
               samples=1000, chunk=400)
    sweep.run(sw, tmp_path / "e.zarr", threads=2, progress=False)
    d = sweep.read(tmp_path / "e.zarr")
    assert d["attrs"]["flip_angles"] == "absolute"
    t1, t2 = np.meshgrid(d["coords"]["link1"], d["coords"]["link2"], indexing="ij")
    forbidden = 3 * np.cos(t1) + np.cos(t2) > 2
    assert forbidden.sum() > 100 and (~forbidden).sum() > 100
    assert np.all(np.isnan(d["flip_time"][forbidden])), np.argwhere(~np.isnan(d["flip_time"]) & forbidden)
    assert np.mean(np.isfinite(d["flip_time"][~forbidden])) > 0.5


def test_link_angles_set_the_joint_angles():
    """linkK is φ¹ + … + φᵏ at the start (a planar chain); the joint angles follow, and a spatial
    chain has no link angles (nor --angles absolute)."""
    plan = sweep.Plan(small(vary=[("link1", 0.5, 1.0, 2), ("link2", -1.0, 2.0, 2)], phidot=[0.1, 0.2]))
    x0 = sweep.start_states(plan, np.array([[0.5, 2.0], [1.0, -1.0]]))
    assert np.allclose(x0, [[0.5, 1.5, 0.1, 0.2], [1.0, -2.0, 0.1, 0.2]])
    spatial = dict(spec_text=(ROOT / "specs" / "spatial3.toml").read_text())
    with pytest.raises(sweep.SpecError, match="link1"):
        sweep.Plan(small(**spatial, vary=[("link1", 0, 1, 2)]))
    with pytest.raises(sweep.SpecError, match="not all parallel"):
        sweep.Plan(small(**spatial, vary=[("phi1", 0, 1, 2)], angles="absolute"))
    with pytest.raises(sweep.SpecError, match="not both"):
        sweep.Plan(small(vary=[("link1", 0, 1, 2), ("phi2", 0, 1, 2)]))
    assert sweep.Plan(small(**spatial, vary=[("phi1", 0, 1, 2)])).angles == "relative"


def test_relative_angles_flip_when_a_joint_angle_passes_pi(tmp_path):
    """--angles relative watches the joint angles: from φ = (−1.75, 3) the links fold (φ² passes
    π, at 1.07 s) while neither link passes the upright within 3 s, which absolute does not count."""
    vary = [("phi1", -1.75, -1.75, 1), ("phi2", 3.0, 3.0, 1)]
    rel, ab = small(measures=("flip_time",), vary=vary, angles="relative"), small(measures=("flip_time",), vary=vary)
    sweep.run(rel, tmp_path / "r.zarr", threads=1, progress=False)
    sweep.run(ab, tmp_path / "a.zarr", threads=1, progress=False)
    r, a = sweep.read(tmp_path / "r.zarr"), sweep.read(tmp_path / "a.zarr")
    assert r["attrs"]["flip_angles"] == "relative" and a["attrs"]["flip_angles"] == "absolute"
    assert r["flip_time"][0, 0] == pytest.approx(1.07, abs=0.01) and np.isnan(a["flip_time"][0, 0])


# --------------------------------------------------------------------------- bad input
@pytest.mark.parametrize("extra, field", [
    (["--vary", "theta9=0:1:3"], "--vary"),
    (["--vary", "phi1=1:1:5"], "--vary phi1"),
    (["--vary", "phi1=0:1:0"], "--vary phi1"),
    (["--vary", "phi1=0:1"], "--vary phi1"),
    (["--vary", "phi1=0:1:4", "--measure", "speed"], "--measure"),
    (["--vary", "phi1=0:1:4", "--method", "rk4"], "--h"),
    (["--random", "3"], "--random"),
    (["--measure", "lyapunov", "--lyap-d0", "0"], "--lyap-d0"),
    (["--measure", "final", "--lyap-d0", "1e-6"], "--lyap-d0"),
])
def test_bad_arguments(extra, field, tmp_path, capsys):
    out = tmp_path / "s.zarr"
    assert main(["sweep", str(DP), "--t1", "1", *extra, "-o", str(out), "-q"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and field in err[0], err
    assert not out.exists()


def test_one_trajectory_without_vary_and_lyapunov_tolerances_said(tmp_path, capsys):
    """No --vary: one trajectory, the same as the reference model's; a Lyapunov measure tightens the
    tolerances (stored, and said on stderr), --lyap-d0 sets the separation; given ones are kept."""
    out = tmp_path / "one.zarr"
    assert main(["sweep", str(DP), "--t1", "2", "--phi", "2,0", "--measure", "final", "--measure", "lyapunov",
                 "--lyap-d0", "1e-7", "-o", str(out), "-q"]) == 0
    err = capsys.readouterr().err
    assert "1 point in 1 chunk on" in err and "1 chunk computed" in err
    assert "lyapunov: dop853 at rtol 1e-11, atol 1e-13" in err and err.index("lyapunov:") < err.index("sweep of") and "d0 = 1e-07" in err
    got = sweep.read(out)
    args = got["attrs"]["args"]
    assert (args["rtol"], args["atol"], args["lyap_d0"], args["vary"]) == (1e-11, 1e-13, 1e-7, [])
    ch = reference.numeric(load_spec(DP), {})
    want = reference.simulate(ch, [2.0, 0.0, 0.0, 0.0], np.array([0.0, 2.0]), rtol=1e-12, atol=1e-14)[-1]
    assert got["final"].shape == (1, 4) and np.max(np.abs(got["final"][0] - want)) < 1e-7
    assert np.isfinite(got["lyapunov"][0]) and got["lyapunov"][0] > 0
    assert main(["animate", str(out), "--frame", "1", "-o", str(tmp_path / "one.png"), "-q"]) == 0  # no --at: its point
    assert main(["sweep", str(DP), "--t1", "1", "--measure", "lyapunov", "--rtol", "1e-9", "--atol", "1e-11",
                 "-o", str(tmp_path / "two.zarr"), "-q"]) == 0
    assert "lyapunov: dop853" not in capsys.readouterr().err
    assert sweep.read(tmp_path / "two.zarr")["attrs"]["args"]["rtol"] == 1e-9


def test_a_store_of_another_sweep_is_left_untouched(tmp_path, capsys):
    out = tmp_path / "s.zarr"
    base = ["sweep", str(DP), "--t1", "1", "--vary", "phi1=0:1:4", "--measure", "final", "-o", str(out), "-q"]
    assert main(base) == 0
    before = tree_digest(out)
    capsys.readouterr()
    for change in (["--t1", "2"], ["--vary", "phi2=0:1:4"]):
        args = list(base)
        if change[0] == "--t1":
            args[args.index("--t1") + 1] = change[1]
        else:
            args[args.index("--vary") + 1] = change[1]
        assert main(args) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and "different sweep" in err[0], err
    other = ROOT / "specs" / "gimbal.toml"
    args = list(base)
    args[1] = str(other)
    assert main(args) == 2
    assert "different spec" in capsys.readouterr().err
    (tmp_path / "plain").mkdir()
    assert main(base[:-3] + ["-o", str(tmp_path / "plain"), "-q"]) == 2
    assert "not a sweep store" in capsys.readouterr().err
    assert tree_digest(out) == before
    # the same command again: everything done, nothing rewritten
    assert main(base) == 0
    assert tree_digest(out) == before


# --------------------------------------------------------------------------- pictures
def test_plot_map_and_curve(tmp_path):
    pytest.importorskip("matplotlib")
    sweep.run(small(measures=("flip_time",)), tmp_path / "map.zarr", threads=2, progress=False)
    assert main(["plot", str(tmp_path / "map.zarr"), "-o", str(tmp_path / "map.png")]) == 0
    curve = small(measures=("final",), vary=[("phi1", 0.1, 1.0, 9)])
    sweep.run(curve, tmp_path / "curve.zarr", threads=1, progress=False)
    assert main(["plot", str(tmp_path / "curve.zarr"), "-o", str(tmp_path / "curve.png"), "--component", "2"]) == 0
    for f in ("map.png", "curve.png"):
        assert (tmp_path / f).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_plots_say_what_they_show(tmp_path, capsys):
    """A map's points without a flip are grey and counted in a legend, a logarithmic colour bar
    labels its ticks with plain numbers (1, 2, 5 per decade), the title states what flip_time
    measured, a curve names its coordinate and unit, and options that do not apply are refused."""
    pytest.importorskip("matplotlib")
    import matplotlib.pyplot as plt

    from gyrochain import plot

    sweep.run(small(measures=("flip_time",)), tmp_path / "m.zarr", threads=2, progress=False)
    d = sweep.read(tmp_path / "m.zarr")
    _plt, cmap = plot._matplotlib("viridis")
    assert tuple(cmap.get_bad()[:3]) == pytest.approx((0.82, 0.82, 0.82))
    fig, ax = plt.subplots()
    plot._map(fig, ax, d, ["phi1", "phi2"], d["flip_time"], cmap, True, "flip time")
    fig.canvas.draw()
    ticks = [t.get_text() for t in fig.axes[1].get_yticklabels() if t.get_text()]
    plt.close(fig)
    assert len(ticks) >= 3 and all(float(t) > 0 for t in ticks), ticks
    assert ax.get_legend().get_texts()[0].get_text() == f"no flip ({int(np.isnan(d['flip_time']).sum())} points)"
    assert "absolute angle" in plot._flip_definition(d["attrs"])
    curve = small(measures=("final",), vary=[("phi1", 0.1, 1.0, 9)])
    sweep.run(curve, tmp_path / "c.zarr", threads=1, progress=False)
    c = sweep.read(tmp_path / "c.zarr")
    assert plot._measure_label("final", plot._values(c, "final", "phidot2")[1], c["attrs"]) == \
        "$\\dot\\varphi^{2}$ at t = 3 s (rad/s)"
    assert plot._values(c, "final", 1)[1] == "phi2"
    for args, field in ((["--cmap", "magma"], "--cmap"), (["--component", "psi"], "--component"),
                        (["--component", "9"], "--component")):
        assert main(["plot", str(tmp_path / "c.zarr"), "-o", str(tmp_path / "c.png"), *args]) == 2
        assert capsys.readouterr().err.startswith(f"error: {field}:")
    assert not (tmp_path / "c.png").exists()


def test_model_files_are_the_generated_c():
    """The sweep and animate build from a render without the LaTeX: the same C, header and cdef
    as `generate` writes (generated/ is what the code emits)."""
    for name in ("double_pendulum", "ship_gimbal"):
        files, _ = pipeline.derive_and_render(parse_spec((ROOT / "specs" / f"{name}.toml").read_text()), f"{name}.toml",
                                              targets=("c",))
        assert sorted(files) == sorted([f"{name}.{e}" for e in ("c", "h", "cdef", "pc.in")] + ["CMakeLists.txt"])
        for k, v in files.items():
            assert v == (ROOT / "generated" / name / k).read_text(), k
