"""The GPU beside the CPU (bench/gpu.sh runs it on a machine with an NVIDIA card): for the double
pendulum, UR5, Panda and a random 16-link chain, RK4 (h = 1 ms, 1,000 steps) of N trajectories
by NAME_gpu_rk4 against NAME_integrate_batch on every core of the machine (one thread a core,
each a slice of the batch), after checking that the GPU's trajectories are the CPU's (1 s of RK4
and of DOP853 from 1,000 random states: the largest relative difference and the codes), the
double pendulum in float too; then a 1000 x 1000 Kapitza Floquet chart by `gyrochain sweep --device
cuda` (in a first process, and again), its multipliers against the CPU's at 1,000 of its points.
Prints a table; writes bench/results/gpu.csv.  Usage: python bench/gpu.py [N]"""
from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "bench"))
from gyrochain import gpu  # noqa: E402
from gyrochain.analysis import floquet  # noqa: E402
from gyrochain.chainspec.randspec import random_spec_text  # noqa: E402
from gyrochain.ensembles import sweep as sw  # noqa: E402
from gyrochain.models import pipeline  # noqa: E402
from gyrochain.spec import load_spec, parse_spec  # noqa: E402

STEPS, H = 1000, 1e-3


def models():
    for name in ("double_pendulum", "ur5", "panda"):
        yield name, load_spec(ROOT / "specs" / f"{name}.toml")
    yield "random16", parse_spec(random_spec_text(np.random.default_rng(16), 16, name="random16", planar=False, gyro=True,
                                                  controls=()))


def params_of(spec):
    return {str(p): 1.0 for p in spec.params} or None


def exactness(gm, cm, spec, rng, rtol=1e-8):
    X0 = rng.uniform(-1, 1, (1000, 2 * cm.n))
    prm = params_of(spec)
    worst, same = 0.0, True
    for method, h in (("rk4", H), ("dop853", 0.0)):
        Xg, cg = gm.integrate_batch([0.0, 1.0], X0, method=method, h=h, params=prm)
        Xc, cc = cm.integrate_batch([0.0, 1.0], X0, method=method, h=h, params=prm)
        same &= bool(np.array_equal(cg, cc))
        ok = cc == 0
        rel = np.abs(Xg[ok] - Xc[ok]) / np.maximum(1.0, np.abs(Xc[ok]))
        worst = max(worst, float(rel.max()) if rel.size else 0.0)
    return worst, same


def gpu_rate(gm, n, nb):
    X0 = np.random.default_rng(1).uniform(-1, 1, (nb, 2 * n))
    gm.integrate_batch([0.0, STEPS * H], X0[:1024], method="rk4", h=H)  # warm-up (the module loaded, the stack set)
    t0 = time.perf_counter()
    gm.integrate_batch([0.0, STEPS * H], X0, method="rk4", h=H)
    return nb * STEPS / (time.perf_counter() - t0)


def cpu_rate(cm, n, nb):
    cores = os.cpu_count() or 1
    X0 = np.random.default_rng(1).uniform(-1, 1, (nb, 2 * n))
    parts = np.array_split(X0, cores)
    with ThreadPoolExecutor(cores) as pool:
        list(pool.map(lambda x: cm.integrate_batch([0.0, STEPS * H], x[:8], method="rk4", h=H), parts))
        t0 = time.perf_counter()
        list(pool.map(lambda x: cm.integrate_batch([0.0, STEPS * H], x, method="rk4", h=H), parts))
    return nb * STEPS / (time.perf_counter() - t0), cores


def kapitza(rng, size: int = 1000, device: str = "cuda"):
    """The size x size chart as a user runs it (`gyrochain sweep ... --device cuda`), in a first
    process (the C and the kernels built into the cache) and again; its multipliers against the
    CPU's at 1,000 points."""
    args = ["specs/kapitza.toml", "--phi", "3.141592653589793", "--vary", f"a=0:0.012:{size}", "--vary",
            f"w=200:300:{size}", "--measure", "floquet", "--chunk", "100000", "--device", device, "-q"]
    with tempfile.TemporaryDirectory() as tmp:
        took = []
        for _ in range(2):
            shutil.rmtree(Path(tmp) / "k.zarr", ignore_errors=True)
            t0 = time.perf_counter()
            subprocess.run([sys.executable, "-m", "gyrochain", "sweep", *args, "-o", str(Path(tmp) / "k.zarr")],
                           cwd=ROOT, check=True)
            took.append(time.perf_counter() - t0)
        import zarr

        g = zarr.open_group(str(Path(tmp) / "k.zarr"), mode="r")
        mu = np.asarray(g["floquet"][...])
        a, w = np.asarray(g["a"][...]), np.asarray(g["w"][...])
    spec = load_spec(ROOT / "specs" / "kapitza.toml")
    plan = sw.Plan(sw.Sweep(spec_text=spec.source, vary=[("a", 0.0, 0.012, size), ("w", 200.0, 300.0, size)], t1=1.0,
                            measures=["floquet"], phi=[np.pi], phidot=[0.0]))
    files, model = pipeline.derive_and_render(spec, targets=("c",))
    cm = pipeline.compile(files, spec.name)
    worst = 0.0
    for i, j in zip(rng.integers(0, size, 1000), rng.integers(0, size, 1000)):
        p = {**plan.params, "a": float(a[i]), "w": float(w[j])}
        ref, _ = floquet.sweep_moduli(cm, model, np.array([[np.pi, 0.0]]), [p], None, plan.cyclic)
        if np.isfinite(ref[0]) or np.isfinite(mu[i, j]):
            worst = max(worst, abs(mu[i, j] - ref[0]) / max(1.0, abs(ref[0])))
    return took, worst


def main(nb: int) -> None:
    why = gpu.unavailable()
    if why:
        sys.exit(f"bench/gpu.py: {why}")
    import cupy

    card = cupy.cuda.runtime.getDeviceProperties(0)["name"].decode()
    rng = np.random.default_rng(2026)
    rows = []
    start = time.perf_counter()
    for name, spec in models():
        gm = gpu.gpu_model(spec)
        print(f"{name}: C and kernels built at {time.perf_counter() - start:.0f} s", flush=True)
        cm = gm.cpu
        worst, same = exactness(gm, cm, spec, rng)
        g = gpu_rate(gm, cm.n, nb)
        c, cores = cpu_rate(cm, cm.n, max(16 * cores_of(), nb // 64))
        rows.append(dict(model=name, real="double", n=cm.n, trajectories=nb, gpu_steps_per_s=f"{g:.3g}",
                         cpu_steps_per_s=f"{c:.3g}", ratio=f"{g / c:.0f}", max_rel_diff=f"{worst:.1e}", codes_equal=same,
                         card=card, cores=cores))
        print(rows[-1], flush=True)
    spec = load_spec(ROOT / "specs" / "double_pendulum.toml")
    files, _ = pipeline.derive_and_render(spec, targets=("c",), real="float", gpu=True)
    cm = pipeline.compile({k: v for k, v in files.items() if not k.endswith(".cu")}, spec.name)
    gm = gpu.GpuModel(cm, files)
    worst, same = exactness(gm, cm, spec, rng)
    rows.append(dict(model="double_pendulum", real="float", n=2, trajectories=nb, gpu_steps_per_s=f"{gpu_rate(gm, 2, nb):.3g}",
                     cpu_steps_per_s="", ratio="", max_rel_diff=f"{worst:.1e}", codes_equal=same, card=card, cores=""))
    print(rows[-1], flush=True)
    took, worst = kapitza(rng)
    print(f"Kapitza 1000 x 1000 floquet chart, `gyrochain sweep --device cuda`: {took[0]:.1f} s in a first process, "
          f"{took[1]:.1f} s again; largest |mu| difference from the CPU at 1,000 points: {worst:.1e}")
    from provenance import write

    write(ROOT / "bench" / "results" / "gpu.csv", rows, flags=f"NVRTC {gpu.nvrtc_version()} --fmad=false; {card}")


def cores_of() -> int:
    return os.cpu_count() or 1


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 1 << 20)
