"""`generate --gpu`: NAME_gpu.cu, tested where there is no GPU.  Its host form (g++ -x c++, strict
warnings) runs every thread of a kernel in turn; each thread must be NAME_integrate_batch's
trajectory bit for bit (the same C, the same compiler arithmetic), with its own parameters,
inputs and return code, and the variational kernel NAME_integrate_variational's.  NVRTC and ptxas
compile the same file for an sm_90 card (an H100 or H200) without warnings: the CUDA side is
checked without a card, and the kernels' registers and stack are printed."""
from __future__ import annotations

import shutil
import subprocess

import numpy as np
import pytest

from gyrochain import gpu
from gyrochain.models import pipeline
from gyrochain.spec import load_spec
from conftest import EXAMPLES, ROOT, example_params

STRICT = ["-Wall", "-Wextra", "-Wpedantic", "-Werror"]


def _files(name: str, real: str = "double") -> dict:
    files, _ = pipeline.derive_and_render(load_spec(ROOT / "specs" / f"{name}.toml"), f"{name}.toml",
                                          targets=("c",), real=real, gpu=True)
    return files


@pytest.fixture(scope="module")
def hosts(example):
    """(the C model, its kernels' host form: gyrochain.gpu.GpuModel(host=True)) of an example, built once."""
    built = {}

    def get(name):
        if name not in built:
            cm = example(name).c
            built[name] = (cm, gpu.GpuModel(cm, _files(name), host=True))
        return built[name]
    return get


def _case(cm, name, rng, nb=6):
    """nb start states (one NaN), per-trajectory parameters about the example's and inputs."""
    X0 = rng.uniform(-1.0, 1.0, (nb, 2 * cm.n))
    X0[3, 0] = np.nan
    base = example_params(name) or {}
    params = [{k: v * (1.0 + 0.1 * rng.uniform(-1, 1)) for k, v in base.items()} for _ in range(nb)] if base else None
    U = rng.uniform(-0.5, 0.5, (nb, cm.nu)) if cm.nu else None
    return X0, params, U


def test_the_host_form_compiles_without_a_warning(tmp_path):
    """g++ -x c++ with -Wall -Wextra -Wpedantic -Werror on every example's kernels, in one run."""
    for name in EXAMPLES:
        files = _files(name)
        for k in (f"{name}.c", f"{name}.h", f"{name}_gpu.cu"):
            (tmp_path / k).write_text(files[k])
    res = subprocess.run(["g++", "-x", "c++", "-std=c++11", *STRICT, "-O0", "-fsyntax-only",
                          *[str(tmp_path / f"{n}_gpu.cu") for n in EXAMPLES]], capture_output=True, text=True)
    assert res.returncode == 0 and not res.stderr, res.stderr


@pytest.mark.parametrize("name", EXAMPLES)
def test_a_thread_is_the_batch_s_trajectory_bit_for_bit(name, hosts, rng):
    cm, gm = hosts(name)
    X0, params, U = _case(cm, name, rng)
    t = np.linspace(0.0, 0.5 if cm.n < 16 else 0.05, 6)
    ok = np.arange(len(X0)) != 3  # (a start refused writes no row: the batch's X is np.empty there)
    for method, h in (("rk4", 0.01), ("dop853", 0.0)):
        X, codes = gm.integrate_batch(t, X0, method=method, h=h, u=U, params=params)
        Xc, cc = cm.integrate_batch(t, X0, method=method, h=h, u=U, params=params)
        assert list(codes) == list(cc), (method, codes, cc)
        assert codes[3] == getattr(cm.lib, f"{name.upper()}_NONFINITE")  # the NaN start
        assert np.array_equal(X[ok], Xc[ok], equal_nan=True), (method, np.nanmax(np.abs(X[ok] - Xc[ok])))
    # one step budget for all: TOO_MANY_STEPS where the batch says it
    X, codes = gm.integrate_batch(t, X0, method="rk4", h=0.01, u=U, params=params, max_steps=3)
    Xc, cc = cm.integrate_batch(t, X0, method="rk4", h=0.01, u=U, params=params, max_steps=3)
    assert list(codes) == list(cc) and np.array_equal(X[ok], Xc[ok], equal_nan=True)
    assert getattr(cm.lib, f"{name.upper()}_TOO_MANY_STEPS") in codes
    # one u and one parameter set for all (strides 0)
    one = params[0] if params else None
    X, codes = gm.integrate_batch(t, X0, method="rk4", h=0.01, u=None if U is None else U[0], params=one)
    Xc, cc = cm.integrate_batch(t, X0, method="rk4", h=0.01, u=None if U is None else U[0], params=one)
    assert list(codes) == list(cc) and np.array_equal(X[ok], Xc[ok], equal_nan=True)


@pytest.mark.parametrize("name", [e for e in EXAMPLES if e != "cable64"])
def test_a_thread_of_the_variational_kernel_is_integrate_variational(name, hosts, rng):
    cm, gm = hosts(name)
    X0, params, U = _case(cm, name, rng, nb=4)
    t1 = np.array([0.3, 0.2, 0.4, 0.1])
    x1, Phi, codes = gm.integrate_variational_batch(0.0, t1, X0, u=U, params=params)
    assert codes[3] == getattr(cm.lib, f"{name.upper()}_NONFINITE")
    for b in range(3):
        x, F = cm.integrate_variational(0.0, t1[b], X0[b], u=None if U is None else U[b],
                                        params=None if params is None else params[b])
        assert codes[b] == 0 and np.array_equal(x1[b], x) and np.array_equal(Phi[b], F)


def test_the_kernels_exist_only_where_the_c_has_their_functions():
    files = _files("cable64")
    assert "cable64_gpu_variational" not in files["cable64_gpu.cu"]  # no NAME_integrate_variational at n = 64
    assert "double_pendulum_gpu_variational(" in _files("double_pendulum")["double_pendulum_gpu.cu"]


def _nvrtc_or_skip():
    if gpu.nvrtc_library() is None or gpu.device.ptxas_path() is None:
        pytest.skip("NVRTC or ptxas is not installed (the test extra installs nvidia-cuda-nvrtc-cu12 and nvidia-cuda-nvcc-cu12)")


@pytest.mark.parametrize("real", ["double", "float"])
def test_nvrtc_and_ptxas_compile_the_kernels_for_sm_90(real, capsys):
    _nvrtc_or_skip()
    name = "double_pendulum"
    files = _files(name, real)
    ptx = gpu.compile_ptx(files[f"{name}_gpu.cu"], {f"{name}.c": files[f"{name}.c"], f"{name}.h": files[f"{name}.h"]})
    report = gpu.ptxas_report(ptx)
    assert set(report) == {f"{name}_gpu_rk4", f"{name}_gpu_dop853", f"{name}_gpu_variational"}
    # RK4 keeps its state in registers: no spills (the figure of the throughput)
    assert report[f"{name}_gpu_rk4"]["spill_stores"] == 0, report
    with capsys.disabled():
        print(f"\n{name} ({real}) on sm_90:", {k.split("_gpu_")[1]: v for k, v in report.items()})


def test_a_source_that_does_not_compile_is_nvrtc_s_log():
    _nvrtc_or_skip()
    with pytest.raises(RuntimeError, match="undefined"):
        gpu.compile_ptx('extern "C" __global__ void k(double *x) { x[0] = nope; }', {})


def test_without_a_gpu_the_reason_is_one_line():
    why = gpu.unavailable()
    if why is None:
        pytest.skip("a CUDA device is here: tests/models/test_gpu_device.py runs the kernels on it")
    assert "\n" not in why and len(why) < 200
    with pytest.raises(gpu.GpuUnavailable) as err:
        gpu.gpu_model(load_spec(ROOT / "specs" / "double_pendulum.toml"))
    assert str(err.value) == why


@pytest.mark.extended
def test_every_example_s_kernels_compile_as_cuda():
    """NVRTC and ptxas on every example's kernels (double): the extended tier (minutes of ptxas)."""
    _nvrtc_or_skip()
    for name in EXAMPLES:
        files = _files(name)
        ptx = gpu.compile_ptx(files[f"{name}_gpu.cu"], {f"{name}.c": files[f"{name}.c"], f"{name}.h": files[f"{name}.h"]})
        assert f"{name}_gpu_rk4" in gpu.ptxas_report(ptx)


if shutil.which("g++") is None:
    pytestmark = pytest.mark.skip(reason="g++ is not installed")
