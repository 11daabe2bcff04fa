"""NAME_gpu.cu on a GPU: compiled to PTX by NVRTC (the ``nvidia-cuda-nvrtc-cu12`` wheel, or the
CUDA toolkit's library), kept in the private model cache by the hash of its sources and the
card's architecture, loaded and launched through CuPy.  ``GpuModel.integrate_batch`` takes and
returns what the compiled C model's does (NumPy arrays), so a sweep's chunk is computed by the
same code on either.  Without CuPy, a CUDA device or NVRTC, ``unavailable()`` says why in one
line; ``compile_ptx`` and ``ptxas_report`` need no GPU (the tests compile every example's kernels
for sm_90 on a machine without one)."""
from __future__ import annotations

import ctypes
import ctypes.util
import hashlib
import importlib.util
import operator
import os
import re
import shutil
import subprocess
import tempfile
from pathlib import Path

import numpy as np

from ..models import pipeline
from ..models.paramtable import ParamTable

# NVRTC has no C library: NAME.c's #include <math.h> and <float.h> read these (its math functions
# are NVRTC's own; the macros are the IEEE values C99 gives them)
NVRTC_HEADERS = {
    "math.h": "#define NAN __longlong_as_double(0x7ff8000000000000LL)\n"
              "#define HUGE_VAL __longlong_as_double(0x7ff0000000000000LL)\n"
              "#define HUGE_VALF __int_as_float(0x7f800000)\n",
    "float.h": "#define FLT_EVAL_METHOD 0\n",
}
ARCH = "90"  # the architecture compile checks use without a card (H100, H200)
BLOCK = 128  # threads per block
GPU_METHODS = ("rk4", "dop853")  # the kernels of NAME_gpu.cu (RK4_LANES is the CPU's vector form of RK4)
VARIATIONAL_KERNELS = ("variational", "floquet", "lyapunov")  # where NAME_integrate_variational is (n <= 16)


class GpuUnavailable(RuntimeError):
    """No CuPy, no CUDA device or no NVRTC here: the message says which, in one line."""


def _package_file(package: str, *parts: str) -> Path | None:
    spec = importlib.util.find_spec(package) if importlib.util.find_spec("nvidia") else None
    if spec is None or not spec.submodule_search_locations:
        return None
    path = Path(list(spec.submodule_search_locations)[0], *parts)
    return path if path.exists() else None


def nvrtc_library() -> Path | None:
    """libnvrtc: the nvidia-cuda-nvrtc-cu12 wheel's, else CUDA 13's wheel (nvidia/cu13, beside
    cupy-cuda13x), else a CUDA toolkit's (CUDA_HOME, CUDA_PATH, /usr/local/cuda), else the one the
    system's loader knows; None where there is none."""
    for found in (_package_file("nvidia.cuda_nvrtc", "lib", "libnvrtc.so.12"),
                  _package_file("nvidia.cu13", "lib", "libnvrtc.so.13")):
        if found:
            return found
    homes = [os.environ.get(v) for v in ("CUDA_HOME", "CUDA_PATH")] + ["/usr/local/cuda"]
    for home in filter(None, homes):
        for lib in sorted(Path(home).glob("lib*/libnvrtc.so.1[2-9]")):
            return lib
    name = ctypes.util.find_library("nvrtc")
    return Path(name) if name else None


def nvrtc_version() -> str | None:
    """NVRTC's version ("12.4"), or None without NVRTC."""
    lib = nvrtc_library()
    if lib is None:
        return None
    major, minor = ctypes.c_int(), ctypes.c_int()
    ctypes.CDLL(str(lib)).nvrtcVersion(ctypes.byref(major), ctypes.byref(minor))
    return f"{major.value}.{minor.value}"


def ptxas_path() -> Path | None:
    """ptxas: the nvidia-cuda-nvcc-cu12 wheel's, else one on PATH."""
    found = _package_file("nvidia.cuda_nvcc", "bin", "ptxas")
    if found:
        return found
    which = shutil.which("ptxas")
    return Path(which) if which else None


def compile_ptx(source: str, headers: dict[str, str], arch: str = ARCH, name: str = "model_gpu.cu",
                debug: bool = False) -> str:
    """The PTX of ``source`` (a NAME_gpu.cu) for compute_``arch``, ``headers`` the files it includes
    (NAME.c, NAME.h) besides NVRTC_HEADERS.  ``debug``: NVRTC's -G, device code unoptimised (the
    same front end and code generation in a second where the optimiser takes half a minute to
    minutes: a check that a model's kernels compile, not code to run).  Raises GpuUnavailable
    without NVRTC, RuntimeError with NVRTC's log when the source does not compile, or when NVRTC
    warns."""
    lib = nvrtc_library()
    if lib is None:
        raise GpuUnavailable("NVRTC is not installed (pip install 'gyrochain[gpu]', or a CUDA toolkit)")
    nv = ctypes.CDLL(str(lib))
    allh = {**NVRTC_HEADERS, **headers}
    names = (ctypes.c_char_p * len(allh))(*[k.encode() for k in allh])
    texts = (ctypes.c_char_p * len(allh))(*[v.encode() for v in allh.values()])
    prog = ctypes.c_void_p()
    if nv.nvrtcCreateProgram(ctypes.byref(prog), source.encode(), name.encode(), len(allh), texts, names) != 0:
        raise RuntimeError("nvrtcCreateProgram failed")
    try:
        # --fmad=false: a*b+c rounded twice, as the host's C (no FMA) rounds it, so that a GPU trajectory
        # follows the CPU's to the libm's last bits.  -diag-suppress=550: "set but never used", which
        # EDG says of the few variables a model's facts leave unread (an empty array of the world
        # form's terms, GAUSS2's Newton flag where Newton is not emitted) despite their (void) casts
        opts = [f"--gpu-architecture=compute_{arch}", "-std=c++17", "--fmad=false", "-diag-suppress=550"]
        if debug:
            opts.append("-G")
        arr = (ctypes.c_char_p * len(opts))(*[o.encode() for o in opts])
        rc = nv.nvrtcCompileProgram(prog, len(opts), arr)
        size = ctypes.c_size_t()
        nv.nvrtcGetProgramLogSize(prog, ctypes.byref(size))
        log = ctypes.create_string_buffer(size.value)
        nv.nvrtcGetProgramLog(prog, log)
        text = log.value.decode(errors="replace").strip()
        if rc != 0 or text:
            raise RuntimeError(f"NVRTC: {name} does not compile cleanly:\n{text}")
        nv.nvrtcGetPTXSize(prog, ctypes.byref(size))
        ptx = ctypes.create_string_buffer(size.value)
        nv.nvrtcGetPTX(prog, ptx)
        return ptx.value.decode()
    finally:
        nv.nvrtcDestroyProgram(ctypes.byref(prog))


_ENTRY = re.compile(r"Compiling entry function '(\w+)'")
_USE = re.compile(r"Used (\d+) registers")
_FRAME = re.compile(r"(\d+) bytes stack frame, (\d+) bytes spill stores, (\d+) bytes spill loads")


def ptxas_report(ptx: str, arch: str = ARCH) -> dict[str, dict]:
    """ptxas -v on ``ptx`` for sm_``arch``: per kernel its registers, stack frame and spills (bytes).
    Raises GpuUnavailable without ptxas, RuntimeError when it fails or warns."""
    exe = ptxas_path()
    if exe is None:
        raise GpuUnavailable("ptxas is not installed (pip install nvidia-cuda-nvcc-cu12, or a CUDA toolkit)")
    run = subprocess.run([str(exe), f"-arch=sm_{arch}", "-v", "-", "-o", "/dev/null"], input=ptx,
                         capture_output=True, text=True, timeout=600)
    if run.returncode != 0 or "warning" in run.stderr:
        raise RuntimeError(f"ptxas: {run.stderr.strip()}")
    out: dict[str, dict] = {}
    kernel = None
    for line in run.stderr.splitlines():
        if m := _ENTRY.search(line):
            kernel = out.setdefault(m.group(1), {})
        elif kernel is not None and (m := _FRAME.search(line)) and "stack" not in kernel:
            kernel.update(stack=int(m.group(1)), spill_stores=int(m.group(2)), spill_loads=int(m.group(3)))
        elif kernel is not None and (m := _USE.search(line)):
            kernel["registers"] = int(m.group(1))
    return out


def unavailable() -> str | None:
    """Why no kernel can run here (one line), or None: CuPy importable, a CUDA device, NVRTC."""
    try:
        import cupy
    except ImportError:
        return "CuPy is not installed (pip install 'gyrochain[gpu]')"
    try:
        count = cupy.cuda.runtime.getDeviceCount()
    except Exception as exc:  # CUDARuntimeError: no driver, or one too old
        return f"no CUDA device ({str(exc).splitlines()[0]})"
    if count < 1:
        return "no CUDA device"
    if nvrtc_library() is None:
        return "NVRTC is not installed (pip install 'gyrochain[gpu]', or a CUDA toolkit)"
    return None


def _host_kernels(files: dict[str, str], name: str):
    """NAME_gpu.cu compiled by the host's C++ compiler (g++ -x c++, the C model's -O2 arithmetic):
    each kernel a function that runs its threads in turn; kept in the model cache by its sources."""
    key = hashlib.sha256("\0".join(files[k] for k in (f"{name}_gpu.cu", f"{name}.c", f"{name}.h")).encode()).hexdigest()[:24]
    folder = pipeline.cache_root() / "gpu" / f"{name}-{key}"
    lib = folder / f"lib{name}_gpu.so"
    if not lib.exists():
        cxx = shutil.which("g++") or shutil.which("c++")
        if cxx is None:
            raise GpuUnavailable("the kernels' host form needs a C++ compiler (g++)")
        folder.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryDirectory(dir=folder) as work:  # (processes building the same kernels at once
            work = Path(work)                                    # each compile in their own folder)
            for k in (f"{name}_gpu.cu", f"{name}.c", f"{name}.h"):
                (work / k).write_text(files[k])
            run = subprocess.run([cxx, "-x", "c++", "-std=c++11", "-O2", "-fno-tree-slp-vectorize", "-fPIC", "-shared",
                                  str(work / f"{name}_gpu.cu"), "-o", str(work / lib.name), "-lm"],
                                 capture_output=True, text=True)
            if run.returncode != 0:
                raise RuntimeError(f"{cxx}: {name}_gpu.cu does not compile:\n{run.stderr}")
            (work / lib.name).replace(lib)
    return ctypes.CDLL(str(lib))


def _c_arg(a):
    """A kernel argument for ctypes: an array's address, a NumPy scalar by its type (uint64 0: NULL)."""
    if isinstance(a, np.ndarray):
        return a.ctypes.data_as(ctypes.c_void_p)
    if isinstance(a, np.uint64):
        return None
    return {np.int64: ctypes.c_long, np.int32: ctypes.c_int, np.float64: ctypes.c_double,
            np.float32: ctypes.c_float}[type(a)](a)


class GpuModel:
    """The kernels of one model on the current CUDA device, with the compiled C model ``cpu``'s
    calls (everything but the integrators is the C model's, on the host).  ``host``: the kernels'
    host form instead (every thread in turn on this CPU, NumPy arrays): the same arguments, the
    same results, where there is no GPU (the tests, and a check of a card's results)."""

    def __init__(self, cpu, files: dict[str, str], host: bool = False):
        self.cpu, self.name, self.host = cpu, cpu.name, host
        self.fields = [f for f, _ in cpu.ffi.typeof(f"{self.name}_params").fields]
        if host:
            self.cp = np
            lib = _host_kernels(files, self.name)
            self.kernels = {m: lib[f"{self.name}_gpu_{m}"] for m in self._kernel_names()}
            return
        why = unavailable()
        if why:
            raise GpuUnavailable(why)
        import cupy

        self.cp = cupy
        arch = str(cupy.cuda.Device().compute_capability)  # "90" on an H100 or H200
        source = files[f"{self.name}_gpu.cu"]
        headers = {f"{self.name}.c": files[f"{self.name}.c"], f"{self.name}.h": files[f"{self.name}.h"]}
        key = hashlib.sha256("\0".join([arch, source, *headers.values()]).encode()).hexdigest()[:24]
        folder = pipeline.cache_root() / "gpu"
        folder.mkdir(parents=True, exist_ok=True)
        path = folder / f"{self.name}-{key}.ptx"
        if not path.exists():
            tmp = path.with_suffix(f".{os.getpid()}.tmp")
            tmp.write_text(compile_ptx(source, headers, arch, f"{self.name}_gpu.cu"))
            tmp.replace(path)
        self.module = cupy.RawModule(path=str(path))
        self.kernels = {m: self.module.get_function(f"{self.name}_gpu_{m}") for m in self._kernel_names()}
        stack = max(k.local_size_bytes for k in self.kernels.values())
        limit = cupy.cuda.runtime.cudaLimitStackSize
        if cupy.cuda.runtime.deviceGetLimit(limit) < stack + 1024:
            cupy.cuda.runtime.deviceSetLimit(limit, stack + 1024)

    def _kernel_names(self) -> tuple:
        return (*GPU_METHODS, *(VARIATIONAL_KERNELS if self.cpu.has_variational else ()))

    def __getattr__(self, attr):  # n, nu, dtype, energy, qdd_derivatives, ...: the C model's
        return getattr(self.cpu, attr)

    # ------------------------------------------------------------------ arguments
    def _params(self, params, nb):
        """(device array, p_stride in structs): NULL (0) for None, one struct for a dict, nb for a list."""
        if params is None:
            return np.uint64(0), 0
        rows = [params] if isinstance(params, dict) else params if isinstance(params, ParamTable) else list(params)
        if not isinstance(params, dict) and len(rows) != nb:
            raise ValueError(f"params: {len(rows)} parameter sets for {nb} trajectories")
        P = np.zeros((len(rows), len(self.fields)), self.dtype)
        if isinstance(params, ParamTable) and set(params.keys()) <= set(self.fields):
            params.fill(P, self.fields)
            return self.cp.asarray(P), 1
        names = list(rows[0]) if rows else []
        table = []
        if names and set(names) <= set(self.fields) and all(len(d) == len(names) for d in rows):
            try:  # a sweep's points: every row has the same names (one array operation)
                get = operator.itemgetter(*names)
                table = [get(d) for d in rows]
            except KeyError:
                table = []
        if len(table) == len(rows):
            P[:, [self.fields.index(k) for k in names]] = np.array(table, dtype=self.dtype).reshape(len(rows), len(names))
        else:
            for i, d in enumerate(rows):
                for k, v in d.items():
                    P[i, self.fields.index(k)] = float(v)
        return self.cp.asarray(P), 0 if isinstance(params, dict) else 1

    def _inputs(self, u, nb):
        if u is None:
            return np.uint64(0), 0
        U = np.ascontiguousarray(u, dtype=self.dtype)
        if U.shape == (self.nu,):
            return self.cp.asarray(U), 0
        if U.shape == (nb, self.nu):
            return self.cp.asarray(U), self.nu
        raise ValueError(f"u must have shape ({self.nu},) or ({nb}, {self.nu}), not {U.shape}")

    def _launch(self, kernel, nb, args):
        if not nb:
            return
        if self.host:
            self.kernels[kernel](*map(_c_arg, args))
        else:
            self.kernels[kernel](((nb + BLOCK - 1) // BLOCK,), (BLOCK,), args)
            self.cp.cuda.Device().synchronize()

    def _out(self, a):
        return np.asarray(a) if self.host else self.cp.asnumpy(a)

    # ------------------------------------------------------------------ the integrators
    def integrate_batch(self, t, X0, method="dop853", h=0.0, rtol=1e-8, atol=1e-10, u=None, params=None, max_steps=0):
        """NAME_integrate_batch's results from the kernel of ``method`` (rk4 or dop853): X of shape
        (nb, len(t), 2N), NaN rows past a failure, and each trajectory's code."""
        if method not in GPU_METHODS:
            raise ValueError(f"method {method!r} has no GPU kernel (one of {', '.join(GPU_METHODS)})")
        cp, real = self.cp, np.dtype(self.dtype).type
        ts = np.ascontiguousarray(np.atleast_1d(np.asarray(t, dtype=self.dtype)))
        X0 = np.ascontiguousarray(X0, dtype=self.dtype)
        if X0.ndim != 2 or X0.shape[1] != 2 * self.n:
            raise ValueError(f"X0 must have shape (nb, {2 * self.n}), not {X0.shape}")
        nb = X0.shape[0]
        U, u_stride = self._inputs(u, nb)
        P, p_stride = self._params(params, nb)
        X = cp.empty((nb, len(ts), 2 * self.n), self.dtype)
        codes = cp.zeros(nb, dtype=np.int32)
        head = (np.int64(nb), np.int32(len(ts)), cp.asarray(ts), real(h))
        tol = (real(rtol), real(atol)) if method == "dop853" else ()
        self._launch(method, nb, (*head, *tol, np.int64(max_steps), cp.asarray(X0), U, np.int64(u_stride), P,
                                  np.int64(p_stride), X, codes))
        return self._out(X), self._out(codes)

    def integrate_variational_batch(self, t0, t1, X0, Phi0=None, u=None, params=None, rtol=1e-10, atol=1e-12, h=0.0):
        """NAME_integrate_variational of each trajectory b from t0 to t1[b] (an array, or one end for
        all): x1 (nb, 2N), Phi (nb, 2N, 2N) (Phi0: the identity by default) and the codes."""
        nb, X0d, U, us, P, ps = self._variational_args(X0, u, params)
        cp, real, dim = self.cp, np.dtype(self.dtype).type, 2 * self.n
        T1 = cp.asarray(np.ascontiguousarray(np.broadcast_to(np.asarray(t1, self.dtype), (nb,))))
        Phi = np.array(np.broadcast_to(np.eye(dim) if Phi0 is None else Phi0, (nb, dim, dim)), dtype=self.dtype, order="C")
        x1, Pd, codes = cp.empty((nb, dim), self.dtype), cp.asarray(Phi), cp.zeros(nb, dtype=np.int32)
        self._launch("variational", nb, (np.int64(nb), real(t0), T1, real(h), real(rtol), real(atol), X0d, U, us, P, ps,
                                         x1, Pd, codes))
        return self._out(x1), self._out(Pd), self._out(codes)

    def _variational_args(self, X0, u, params):
        if "variational" not in self.kernels:
            raise ValueError(f"{self.name}: no NAME_integrate_variational (emitted up to n = 16; n = {self.n})")
        X0 = np.ascontiguousarray(X0, dtype=self.dtype)
        nb = X0.shape[0]
        U, u_stride = self._inputs(u, nb)
        P, p_stride = self._params(params, nb)
        return nb, self.cp.asarray(X0), U, np.int64(u_stride), P, np.int64(p_stride)

    def floquet_batch(self, T, X0, samples: int, tol: float, u=None, params=None, rtol=1e-12, atol=1e-12, h=0.0):
        """sweep --measure floquet's kernel: for each point b whether X0[b] is an equilibrium for all t
        (|φ̈| ≤ tol · max(1, |∂φ̈/∂φ|) at ``samples`` times of the period T[b]) and, where it is, the
        monodromy matrix over T[b]; T[b] NaN: no period there (not an equilibrium, nothing
        integrated).  Returns Phi (nb, 2N, 2N), the equilibrium flags (nb,) and the codes."""
        nb, X0d, U, us, P, ps = self._variational_args(X0, u, params)
        cp, real, dim = self.cp, np.dtype(self.dtype).type, 2 * self.n
        Td = cp.asarray(np.ascontiguousarray(np.broadcast_to(np.asarray(T, self.dtype), (nb,))))
        x1, Phi = cp.empty((nb, dim), self.dtype), cp.full((nb, dim, dim), np.nan, self.dtype)
        eq, codes = cp.zeros(nb, dtype=np.int32), cp.zeros(nb, dtype=np.int32)
        self._launch("floquet", nb, (np.int64(nb), Td, np.int32(samples), real(tol), real(h), real(rtol), real(atol),
                                     X0d, U, us, P, ps, x1, Phi, eq, codes))
        return self._out(Phi), self._out(eq), self._out(codes)

    def lyapunov_batch(self, X0, dt: float, steps: int, u=None, params=None, rtol=1e-8, atol=1e-10):
        """The Lyapunov spectrum's QR steps in the kernel (every dt, ``steps`` times, from t = 0):
        the sums of log Rᵢᵢ (nb, 2N), in the order of Gram-Schmidt's columns, and the codes."""
        nb, X0d, U, us, P, ps = self._variational_args(X0, u, params)
        cp, real, dim = self.cp, np.dtype(self.dtype).type, 2 * self.n
        x1, sums, codes = cp.empty((nb, dim), self.dtype), cp.empty((nb, dim), self.dtype), cp.zeros(nb, dtype=np.int32)
        self._launch("lyapunov", nb, (np.int64(nb), real(dt), np.int64(steps), real(rtol), real(atol), X0d, U, us, P, ps,
                                      x1, sums, codes))
        return self._out(sums), self._out(codes)


def gpu_model(spec, cpu=None) -> GpuModel:
    """The GPU model of ``spec``: its C and kernels rendered (the derivation cached), the C model
    compiled for the host's part (``cpu``, if not given)."""
    why = unavailable()
    if why:
        raise GpuUnavailable(why)
    files, _ = pipeline.derive_and_render(spec, targets=("c", "cuda"))
    cpu = cpu or pipeline.checked(spec, pipeline.compile({k: v for k, v in files.items() if not k.endswith(".cu")}, spec.name))
    return GpuModel(cpu, files)


__all__ = ["GpuModel", "GpuUnavailable", "NVRTC_HEADERS", "compile_ptx", "gpu_model", "nvrtc_library", "nvrtc_version",
           "ptxas_path", "ptxas_report", "unavailable"]
