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
from conftest import EXAMPLES, ONE_ARM, QUICK_EXAMPLES, ROOT, SHORT_EXAMPLES, example_params, tiered

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


@pytest.mark.parametrize("name", tiered(EXAMPLES, QUICK_EXAMPLES))
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


@pytest.mark.parametrize("real", ["double", "float"])
def test_a_table_of_parameters_is_its_list_of_dicts(real, rng):
    """A sweep's points as columns (ParamTable) pack into NAME_integrate_batch's structs and the
    kernels' array as the list of dicts they stand for: the same trajectories, bit for bit."""
    from gyrochain.models.paramtable import ParamTable

    files = _files("kapitza", real)
    cm = pipeline.compile({k: v for k, v in files.items() if not k.endswith(".cu")}, "kapitza")
    gm = gpu.GpuModel(cm, files, host=True)
    base = dict(example_params("kapitza"))
    table = ParamTable(base, ["w", "a"], np.column_stack([rng.uniform(200, 300, 5), rng.uniform(0, 0.012, 5)]))
    X0 = np.tile([np.pi - 0.1, 0.0], (5, 1))
    t = np.linspace(0.0, 0.2, 3)
    for model in (cm, gm):
        X, codes = model.integrate_batch(t, X0, method="rk4", h=1e-3, params=table)
        Xd, cd = model.integrate_batch(t, X0, method="rk4", h=1e-3, params=list(table))
        assert np.array_equal(X, Xd) and np.array_equal(codes, cd)
        assert len({float(x) for x in X[:, -1, 0]}) == 5  # (each trajectory its own parameters)


def _float_thread_is_the_float_batch(name, rng):
    files = _files(name, "float")
    cm = pipeline.compile({k: v for k, v in files.items() if not k.endswith(".cu")}, name)
    gm = gpu.GpuModel(cm, files, host=True)
    assert cm.dtype == np.float32
    X0, params, U = _case(cm, name, rng)
    t = np.linspace(0.0, 0.5, 6)
    ok = np.arange(len(X0)) != 3
    for method, kw in (("rk4", dict(h=0.01)), ("dop853", dict(rtol=1e-5, atol=1e-6))):
        X, codes = gm.integrate_batch(t, X0, method=method, u=U, params=params, **kw)
        Xc, cc = cm.integrate_batch(t, X0, method=method, u=U, params=params, **kw)
        assert X.dtype == np.float32 and list(codes) == list(cc), (method, codes, cc)
        assert np.array_equal(X[ok], Xc[ok], equal_nan=True), (method, np.nanmax(np.abs(X[ok] - Xc[ok])))


def test_a_float_thread_is_the_float_batch_s_trajectory_bit_for_bit(rng):
    """--real float: the kernels are written in NAME_REAL, so a float build's threads are its
    float NAME_integrate_batch's trajectories bit for bit (every short example: the extended tier)."""
    _float_thread_is_the_float_batch("double_pendulum", rng)


@pytest.mark.extended
@pytest.mark.parametrize("name", [e for e in SHORT_EXAMPLES if e in ONE_ARM and e != "double_pendulum"])
def test_every_float_build_s_threads_are_its_batch_s(name, rng):
    _float_thread_is_the_float_batch(name, rng)


@pytest.mark.parametrize("name", tiered([e for e in EXAMPLES if e != "cable64"], QUICK_EXAMPLES))
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


def test_the_floquet_kernel_asks_what_the_cpu_asks(hosts):
    """Per point: the equilibrium test at the same times with the same tolerance as
    floquet.held_for_all_t, and there NAME_integrate_variational's monodromy matrix bit for bit;
    a point with no period (T NaN) or off its equilibrium integrates nothing."""
    from gyrochain.analysis import floquet

    cm, gm = hosts("kapitza")
    base = example_params("kapitza")
    params = [dict(base, a=a, w=w) for a, w in ((0.01, 250.0), (0.002, 200.0), (0.01, 250.0), (0.0, 250.0))]
    X0 = np.array([[np.pi, 0.0], [np.pi, 0.0], [1.0, 0.0], [0.0, 0.0]])
    T = np.array([2 * np.pi / 250.0, 2 * np.pi / 200.0, 2 * np.pi / 250.0, np.nan])
    Phi, held, codes = gm.floquet_batch(T, X0, floquet.SAMPLES, floquet.EQUILIBRIUM_TOL, params=params,
                                        rtol=floquet.RTOL, atol=floquet.ATOL)
    assert list(codes) == [0, 0, 0, 0] and list(held) == [1, 1, 0, 0]
    for b in range(3):
        assert bool(held[b]) == floquet.held_for_all_t(cm, X0[b], T[b], params[b], None)
    for b in range(2):
        assert np.array_equal(Phi[b], floquet.monodromy(cm, X0[b], T[b], params[b]))
    assert np.isnan(Phi[2:]).all()


def test_the_periods_of_many_points_are_time_period_s():
    from gyrochain.analysis import floquet
    from gyrochain.chainspec.errors import SpecError
    from gyrochain.models import pipeline as pl

    model = pl.derive(load_spec(ROOT / "specs" / "kapitza.toml"))
    rng = np.random.default_rng(5)
    params = [dict(example_params("kapitza"), w=w) for w in rng.uniform(-300.0, 300.0, 50)] + \
             [dict(example_params("kapitza"), w=0.0), dict(example_params("kapitza"), w=np.inf)]
    T = floquet.time_periods(model, params)
    for p, t in zip(params, T):
        try:
            assert t == floquet.time_period(model, p, "floquet")[0]
        except SpecError:
            assert np.isnan(t)
    assert np.isnan(T[-2:]).all() and np.isfinite(T[:-2]).all()


@pytest.mark.parametrize("name", ["double_pendulum", "kapitza"])
def test_the_lyapunov_kernel_is_the_qr_method_s(name, hosts, rng):
    """The QR steps in each thread (Gram-Schmidt, twice) give lyapunov_spectrum's exponents (NumPy's
    Householder QR on the host) to 1e-10; a NaN start its code and NaN exponents."""
    from gyrochain.ensembles.measures import lyapunov_spectrum, lyapunov_spectrum_batch

    cm, gm = hosts(name)
    X0 = rng.uniform(-1.0, 1.0, (3, 2 * cm.n))
    X0[1, 0] = np.nan
    prm = example_params(name)
    lam, codes = lyapunov_spectrum_batch(gm, X0, 2.0, 0.25, prm, rtol=1e-10, atol=1e-10)
    ref, rc = lyapunov_spectrum(cm, X0, 2.0, 0.25, prm, rtol=1e-10, atol=1e-10)
    assert list(codes) == list(rc) and codes[1] == getattr(cm.lib, f"{name.upper()}_NONFINITE")
    assert np.isnan(lam[1]).all() and np.isnan(ref[1]).all()
    assert np.max(np.abs(lam[[0, 2]] - ref[[0, 2]])) < 1e-10, np.max(np.abs(lam[[0, 2]] - ref[[0, 2]]))
    assert np.max(np.abs(lam[[0, 2]])) > 0.1  # (a spectrum, not zeros)


def test_the_kernels_exist_only_where_the_c_has_their_functions():
    files = _files("cable64")
    assert "cable64_gpu_variational" not in files["cable64_gpu.cu"]  # no NAME_integrate_variational at n = 64
    assert "double_pendulum_gpu_variational(" in _files("double_pendulum")["double_pendulum_gpu.cu"]


def _nvrtc_or_skip():
    if gpu.nvrtc_library() is None or gpu.device.ptxas_path() is None:
        pytest.skip("NVRTC or ptxas is not installed (the test extra installs nvidia-cuda-nvrtc-cu12 and nvidia-cuda-nvcc-cu12)")


@pytest.mark.extended  # (ptxas on the spilling variational kernels: 13 s each)
@pytest.mark.parametrize("real", ["double", "float"])
def test_nvrtc_and_ptxas_compile_the_kernels_for_sm_90(real, capsys):
    _nvrtc_or_skip()
    name = "double_pendulum"
    files = _files(name, real)
    ptx = gpu.compile_ptx(files[f"{name}_gpu.cu"], {f"{name}.c": files[f"{name}.c"], f"{name}.h": files[f"{name}.h"]})
    report = gpu.ptxas_report(ptx)
    assert set(report) == {f"{name}_gpu_{k}" for k in (*gpu.device.GPU_METHODS, *gpu.device.VARIATIONAL_KERNELS)}
    # RK4 keeps its state in registers: no spills (the figure of the throughput)
    assert report[f"{name}_gpu_rk4"]["spill_stores"] == 0, report
    with capsys.disabled():
        print(f"\n{name} ({real}) on sm_90:", {k.split("_gpu_")[1]: v for k, v in report.items()})


def test_nvrtc_is_found_from_cuda_12_or_13(monkeypatch, tmp_path):
    """The cu12 wheel's NVRTC first, then CUDA 13's wheel (beside cupy-cuda13x), then a toolkit's."""
    wheels = {"nvidia.cuda_nvrtc": tmp_path / "cu12.so", "nvidia.cu13": tmp_path / "cu13.so"}
    monkeypatch.setattr(gpu.device, "_package_file", lambda package, *parts: wheels.get(package))
    assert gpu.nvrtc_library() == tmp_path / "cu12.so"
    wheels.pop("nvidia.cuda_nvrtc")
    assert gpu.nvrtc_library() == tmp_path / "cu13.so"
    wheels.clear()
    (tmp_path / "cuda" / "lib64").mkdir(parents=True)
    (tmp_path / "cuda" / "lib64" / "libnvrtc.so.13").write_text("")
    monkeypatch.setenv("CUDA_HOME", str(tmp_path / "cuda"))
    assert gpu.nvrtc_library() == tmp_path / "cuda" / "lib64" / "libnvrtc.so.13"


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
    """NVRTC's front end and code generation and ptxas on every example's kernels (double), with
    NVRTC's -G: its optimiser took 24-41 s a model and 740 s for all the examples, where -G takes
    under 3 s.  The optimised build is the sm_90 test's above (both reals) and the card's
    (tests/models/test_gpu_device.py)."""
    _nvrtc_or_skip()
    for name in EXAMPLES:
        files = _files(name)
        ptx = gpu.compile_ptx(files[f"{name}_gpu.cu"], {f"{name}.c": files[f"{name}.c"], f"{name}.h": files[f"{name}.h"]},
                              debug=True)
        assert f".target sm_{gpu.device.ARCH}, debug" in ptx.splitlines()
        assert {f"{name}_gpu_{m}" for m in gpu.device.GPU_METHODS} <= set(gpu.ptxas_report(ptx))


if shutil.which("g++") is None:
    pytestmark = pytest.mark.skip(reason="g++ is not installed")
