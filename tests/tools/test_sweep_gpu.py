"""`sweep --device cuda` without a GPU: the GPU's path (gyrochain.gpu.GpuModel: the arguments
packed for the kernels, one launch a chunk, the batched Floquet and Lyapunov measures) run on the
kernels' host form, every thread in turn, must write the store the CPU's path writes; and the
command without a GPU is one line, exit 2, nothing written."""
from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from gyrochain.ensembles import sweep as sw
from gyrochain.spec import load_spec
from conftest import ROOT


def _stores(tmp_path, spec_name, **kw):
    import zarr

    spec = load_spec(ROOT / "specs" / f"{spec_name}.toml")
    out = {}
    for device in ("cpu", "host"):
        sweep = sw.Sweep(spec_text=spec.source, **kw)
        sw.run(sweep, tmp_path / f"{device}.zarr", threads=1, progress=False, device=device)
        out[device] = zarr.open_group(str(tmp_path / f"{device}.zarr"), mode="r")
    return out


def _same(a, b, measure, rtol=0.0, atol=0.0):
    x, y = np.asarray(a[measure][...]), np.asarray(b[measure][...])
    assert x.shape == y.shape and np.array_equal(np.isnan(x), np.isnan(y)), measure
    assert np.allclose(x, y, rtol=rtol, atol=atol, equal_nan=True), (measure, np.nanmax(np.abs(x - y)))


def test_final_flip_time_energy_and_lyapunov_are_the_cpu_s(tmp_path):
    g = _stores(tmp_path, "double_pendulum", vary=[("phi1", -3.0, 3.0, 5), ("phi2", -3.0, 3.0, 4)], t1=2.0,
                measures=["final", "flip_time", "energy_error", "lyapunov"], method="rk4", h=0.002, samples=50,
                chunk=8)
    for m in ("final", "flip_time", "energy_error", "lyapunov", "code"):
        _same(g["cpu"], g["host"], m)  # bit for bit: the same C, one thread per trajectory
    assert dict(g["cpu"].attrs) == dict(g["host"].attrs)  # the spec, the arguments, the version


def test_floquet_and_the_lyapunov_spectrum_in_batches_are_the_cpu_s(tmp_path):
    g = _stores(tmp_path / "k", "kapitza", vary=[("a", 0.0, 0.012, 4), ("w", 200.0, 300.0, 3)], t1=1.0,
                measures=["floquet"], phi=[3.141592653589793], phidot=[0.0], chunk=6)
    _same(g["cpu"], g["host"], "floquet", rtol=1e-10)
    assert np.isfinite(np.asarray(g["host"]["floquet"][...])).all()
    g = _stores(tmp_path / "d", "double_pendulum", vary=[("phi1", 0.3, 2.5, 3)], t1=2.0, phi=[0.0, -2.0],
                measures=["lyapunov_spectrum"], lyap_interval=0.5, rtol=1e-10, atol=1e-10)
    # (the kernel's QR is Gram-Schmidt, twice; the CPU's NumPy's Householder: seen 2.4e-14 apart)
    _same(g["cpu"], g["host"], "lyapunov_spectrum", atol=1e-12)


def test_without_a_gpu_the_command_is_one_line_and_writes_nothing(tmp_path):
    from gyrochain import gpu

    why = gpu.unavailable()
    if why is None:
        pytest.skip("a CUDA device is here")
    store = tmp_path / "s.zarr"
    for extra, field in (([], "--device"), (["--method", "gauss2"], "--method"), (["--threads", "2"], "--threads")):
        res = subprocess.run([sys.executable, "-m", "gyrochain", "sweep", str(ROOT / "specs" / "double_pendulum.toml"),
                              "--vary", "phi1=-1:1:4", "--device", "cuda", "-q", "-o", str(store), *extra],
                             capture_output=True, text=True, timeout=120)
        assert res.returncode == 2 and res.stderr.count("\n") == 1 and f"error: {field}:" in res.stderr, res.stderr
        assert not store.exists()
    assert why in res.stderr or "--threads" in res.stderr


def test_device_auto_takes_the_gpu_only_where_it_can_run(monkeypatch, tmp_path):
    from gyrochain import gpu

    monkeypatch.setattr(gpu, "unavailable", lambda: None)  # as on a machine with a card
    assert sw.resolve_device("auto", "dop853") == "cuda" and sw.resolve_device("auto", "rk4") == "cuda"
    assert sw.resolve_device("auto", "gauss2") == "cpu"  # no kernel for the method
    assert sw.resolve_device("auto", "rk4", cpu_option=True) == "cpu"  # --threads, --workers or --scheduler given
    assert sw.resolve_device("cpu", "rk4") == "cpu" and sw.resolve_device("cuda", "gauss2") == "cuda"
    monkeypatch.setattr(gpu, "unavailable", lambda: "no CUDA device")
    assert sw.resolve_device("auto", "rk4") == "cpu"
    monkeypatch.undo()
    if gpu.unavailable() is None:
        pytest.skip("a CUDA device is here")
    store = tmp_path / "s.zarr"
    res = subprocess.run([sys.executable, "-m", "gyrochain", "sweep", str(ROOT / "specs" / "double_pendulum.toml"),
                          "--vary", "phi1=-1:1:4", "--t1", "0.1", "--device", "auto", "-q", "-o", str(store)],
                         capture_output=True, text=True, timeout=120)
    assert res.returncode == 0 and "thread(s)" in res.stderr and store.exists(), res.stderr
