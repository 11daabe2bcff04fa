"""The kernels on a CUDA card (skipped, saying why, where there is none: CI and most machines).
On a card, NAME_gpu.cu is compiled by NVRTC and run through CuPy; its trajectories must follow the
CPU's NAME_integrate_batch: RK4 to the last bits (the same arithmetic, --fmad=false, CUDA's sin and
cos within an ulp of glibc's), DOP853 to far below its own tolerance (its step control may accept
a step differently when an error estimate differs in its last bit), the same codes for every
trajectory, a float model within float's precision, and a Floquet chart's multipliers to 1e-10."""
from __future__ import annotations

import numpy as np
import pytest

from gyrochain import gpu
from gyrochain.ensembles import sweep as sw
from gyrochain.models import pipeline
from gyrochain.spec import load_spec
from conftest import ROOT

pytestmark = pytest.mark.skipif(gpu.unavailable() is not None, reason=f"no GPU here: {gpu.unavailable()}")


def _relative(a, b):
    return float(np.max(np.abs(a - b) / np.maximum(1.0, np.abs(b))))


@pytest.fixture(scope="module")
def double_pendulum():
    return gpu.gpu_model(load_spec(ROOT / "specs" / "double_pendulum.toml"))


def test_rk4_and_dop853_on_the_card_follow_the_cpu(double_pendulum, rng):
    gm = double_pendulum
    X0 = rng.uniform(-1.0, 1.0, (1000, 4))
    X0[7, 1] = np.nan
    t = np.linspace(0.0, 1.0, 11)
    ok = np.arange(len(X0)) != 7
    for method, h, tol in (("rk4", 1e-3, 1e-13), ("dop853", 0.0, 1e-10)):
        X, codes = gm.integrate_batch(t, X0, method=method, h=h)
        Xc, cc = gm.cpu.integrate_batch(t, X0, method=method, h=h)
        assert np.array_equal(codes, cc) and codes[7] == gm.cpu.lib.DOUBLE_PENDULUM_NONFINITE
        assert _relative(X[ok], Xc[ok]) < tol, (method, _relative(X[ok], Xc[ok]))


def test_a_float_model_on_the_card_follows_its_float_c(rng):
    spec = load_spec(ROOT / "specs" / "double_pendulum.toml")
    files, _ = pipeline.derive_and_render(spec, targets=("c",), real="float", gpu=True)
    cm = pipeline.compile({k: v for k, v in files.items() if not k.endswith(".cu")}, spec.name)
    gm = gpu.GpuModel(cm, files)
    X0 = rng.uniform(-1.0, 1.0, (1000, 4))
    X, codes = gm.integrate_batch([0.0, 1.0], X0, method="rk4", h=1e-3)
    Xc, cc = cm.integrate_batch([0.0, 1.0], X0, method="rk4", h=1e-3)
    assert np.array_equal(codes, cc)
    assert _relative(X, Xc) < 1e-4, _relative(X, Xc)  # (seen: 1.7e-5 on an H200)


@pytest.mark.parametrize("case", ["antiparallel", "moving_base", "planar_flipped", "long_chain"])
def test_the_geometry_users_write_on_the_card(case, rng):
    """Chains of tests/models/test_geometry.py's fixed set on the card: flipped axes (θ = ±π), point
    masses, massless frames, a moving platform with loads and λ(t), the loop form of a long chain.
    RK4 and DOP853 from 1,000 states follow the CPU's batch, codes and all; the variational kernel
    follows NAME_integrate_variational."""
    from test_geometry import FIXED, _der_form, _spec

    plan, qdd_form, der_form, _ = FIXED[case]
    spec = _spec(plan, f"card_{case}")
    files, _ = pipeline.derive_and_render(spec, targets=("c",), qdd_form=qdd_form, der_form=_der_form(spec, der_form), gpu=True)
    cm = pipeline.compile({k: v for k, v in files.items() if not k.endswith(".cu")}, spec.name)
    gm = gpu.GpuModel(cm, files)
    X0 = rng.uniform(-1.0, 1.0, (1000, 2 * spec.n))
    U = rng.normal(size=(1000, len(spec.controls))) if spec.controls else None
    t = np.linspace(0.0, 0.5, 6)
    for method, h, tol in (("rk4", 1e-3, 1e-12), ("dop853", 0.0, 1e-9)):
        X, codes = gm.integrate_batch(t, X0, method=method, h=h, u=U)
        Xc, cc = cm.integrate_batch(t, X0, method=method, h=h, u=U)
        ok = cc == 0
        assert np.array_equal(codes, cc) and ok.sum() > 900, (method, np.unique(codes, return_counts=True))
        print(f"{case} {method}: {_relative(X[ok], Xc[ok]):.1e} from the CPU")
        assert _relative(X[ok], Xc[ok]) < tol, (method, _relative(X[ok], Xc[ok]))
    if cm.has_variational:
        x1, Phi, codes = gm.integrate_variational_batch(0.0, 0.3, X0[:50], u=None if U is None else U[:50])
        for i in range(0, 50, 7):
            xc, Pc = cm.integrate_variational(0.0, 0.3, X0[i], u=None if U is None else U[i])
            assert codes[i] == 0 and _relative(x1[i], xc) < 1e-9 and _relative(Phi[i], Pc) < 1e-8, i


def test_a_floquet_chart_on_the_card_is_the_cpu_s(tmp_path):
    import zarr

    spec = load_spec(ROOT / "specs" / "kapitza.toml")
    out = {}
    for device in ("cpu", "cuda"):
        sweep = sw.Sweep(spec_text=spec.source, vary=[("a", 0.0, 0.012, 5), ("w", 200.0, 300.0, 4)], t1=1.0,
                         measures=["floquet"], phi=[np.pi], phidot=[0.0])
        sw.run(sweep, tmp_path / f"{device}.zarr", progress=False, device=device, threads=1 if device == "cpu" else None)
        out[device] = np.asarray(zarr.open_group(str(tmp_path / f"{device}.zarr"), mode="r")["floquet"][...])
    assert np.isfinite(out["cpu"]).all()
    assert np.allclose(out["cuda"], out["cpu"], rtol=1e-10, atol=0.0), np.max(np.abs(out["cuda"] - out["cpu"]))
