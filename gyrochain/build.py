"""cffi (API mode, out of line) build of an emitted model, and a numpy-friendly wrapper."""
from __future__ import annotations

import functools
import importlib.util
import shutil
import sys
import tempfile
from pathlib import Path

import numpy as np

from .codes import METHODS, MOTIONS, status_text

# after Python's own flags, which carry -g and -O3: -O2 as everywhere in this project, and no debug
# information (for a 128-link chain's 12 MB of C it cost a gigabyte and a fifth of gcc's time).
# No SLP vectoriser (gcc and clang spell it so): on the emitted straight-line code it took a
# sixth of gcc's time and won nothing (n = 32: gcc 10.0 -> 8.2 s; qdd and the Jacobian as fast;
# docs/benchmarks.md, "Long chains").  The loops' vectoriser stays on.
CFLAGS = ["-std=c99", "-O2", "-fno-tree-slp-vectorize", "-g0", "-Wall", "-Wextra"]


@functools.cache
def lto_flags() -> tuple[list[str], list[str]]:
    """(compile, link) flags that spread gcc's work over every core: the C is compiled to GIMPLE
    (-flto, quick) and the link step optimises and generates code in parallel partitions
    (-flto=auto).  gcc's time is all in that second half, so a long chain builds in about half the
    time on two cores (n = 32: gcc 21 s on one core, 11 s on two; docs/benchmarks.md, "Long
    chains").  Empty with a compiler that is not gcc."""
    import subprocess
    import sysconfig

    cc = (sysconfig.get_config_var("CC") or "cc").split()
    try:
        banner = subprocess.run([*cc, "--version"], capture_output=True, text=True, timeout=30).stdout
    except (OSError, subprocess.SubprocessError):
        return [], []
    if "Free Software Foundation" not in banner or "clang" in banner.lower():
        return [], []
    return ["-flto"], ["-flto=auto", *CFLAGS]


def module_name(name: str) -> str:
    return f"_{name}_cffi"


def build_key(src_dir: str | Path, name: str, extra_cflags=()) -> str:
    """What an extension depends on: the C, header and cdef texts (they carry the spec and the
    generator's output), the compiler flags, the compiler and the Python ABI.  ``generate``
    reuses an extension whose key is unchanged instead of compiling it again."""
    src_dir = Path(src_dir)
    return key_of([(src_dir / f"{name}{suffix}").read_bytes() for suffix in (".c", ".h", ".cdef")], extra_cflags)


def key_of(sources: list[bytes], extra_cflags=()) -> str:
    """``build_key`` of the C, header and cdef given as bytes, in that order."""
    import hashlib
    import sysconfig

    import cffi

    h = hashlib.sha256()
    for text in sources:
        h.update(text)
        h.update(b"\0")
    lto_compile, lto_link = lto_flags()
    parts = [*CFLAGS, *extra_cflags, *lto_compile, *lto_link, str(sysconfig.get_config_var("CC")), str(sysconfig.get_config_var("EXT_SUFFIX")),
             cffi.__version__, sys.version]
    h.update("\0".join(parts).encode("utf-8"))
    return h.hexdigest()


def key_path(directory: str | Path, name: str) -> Path:
    """Where the build key of a folder's extension is kept (beside it, ignored by git)."""
    return Path(directory) / f"{module_name(name)}.key"


def extensions(directory: str | Path, name: str) -> list[Path]:
    """The compiled extensions of a model in a folder (one, normally)."""
    directory = Path(directory)
    return sorted(directory.glob(f"{module_name(name)}.*.so")) + sorted(directory.glob(f"{module_name(name)}.so"))


def is_current(directory: str | Path, name: str, sources: list[bytes]) -> bool:
    """Whether the folder's extension was built from these C, header and cdef bytes with the
    flags and compiler of now (its key file says so)."""
    key_file = key_path(directory, name)
    return (len(extensions(directory, name)) == 1 and key_file.is_file()
            and key_file.read_text().strip() == key_of(sources))


def reuse_extension(old_dir: str | Path, new_dir: str | Path, name: str) -> bool:
    """Copy the extension of ``old_dir`` into ``new_dir`` when it was built from exactly the
    sources now in ``new_dir`` with the same flags; False (nothing copied) otherwise."""
    old_dir, new_dir = Path(old_dir), Path(new_dir)
    key_file = key_path(old_dir, name)
    found = extensions(old_dir, name)
    if not key_file.is_file() or len(found) != 1:
        return False
    key = build_key(new_dir, name)
    if key_file.read_text().strip() != key:
        return False
    shutil.copy2(found[0], new_dir / found[0].name)
    key_path(new_dir, name).write_text(key + "\n")
    return True


def compile_model(src_dir: str | Path, name: str, out_dir: str | Path | None = None, extra_cflags=()) -> Path:
    """Build the extension from ``<name>.c``/``.h``/``.cdef`` in src_dir; returns the .so path
    (placed in out_dir, default src_dir).  The cffi wrapper source stays in a temporary folder."""
    import cffi

    src_dir = Path(src_dir).resolve()
    out_dir = Path(out_dir or src_dir).resolve()
    ffi = cffi.FFI()
    ffi.cdef((src_dir / f"{name}.cdef").read_text())
    lto_compile, lto_link = lto_flags()
    ffi.set_source(
        module_name(name),
        f'#include "{name}.h"',
        sources=[str(src_dir / f"{name}.c")],
        include_dirs=[str(src_dir)],
        extra_compile_args=list(CFLAGS) + list(extra_cflags) + lto_compile,
        extra_link_args=lto_link + list(extra_cflags),
        libraries=["m"],
    )
    with tempfile.TemporaryDirectory(prefix="gyrochain-build-") as tmp:
        so = Path(ffi.compile(tmpdir=tmp, verbose=False))
        target = out_dir / so.name
        shutil.copy2(so, target)
    if out_dir == src_dir:
        key_path(out_dir, name).write_text(build_key(src_dir, name, extra_cflags) + "\n")
    return target


def load_module(so_path: str | Path):
    so_path = Path(so_path)
    modname = so_path.name.split(".")[0]
    # an extension module must be loaded under its own name (PyInit_<name>); the path tells
    # apart two builds of the same model
    spec = importlib.util.spec_from_file_location(modname, so_path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


class ModelError(ArithmeticError):
    def __init__(self, func: str, code: int):
        super().__init__(f"{func} returned {code}: {status_text(code)}")
        self.code = code


class IntegrationError(ModelError):
    """An integrator stopped early; ``t``, ``x`` are where (the last accepted step), ``X`` the
    trajectory with NaN rows past it, ``stats`` the counts."""

    def __init__(self, func: str, code: int, X, stats: dict):
        super().__init__(func, code)
        self.X, self.stats, self.t, self.x = X, stats, stats["t"], stats["x"]
        self.args = (f"{self.args[0]} at t = {self.t!r}",)




class CModel:
    """The compiled C model called through cffi, with numpy arrays in and out."""

    def __init__(self, so_path: str | Path, name: str):
        self.mod = load_module(so_path)
        self.ffi, self.lib = self.mod.ffi, self.mod.lib
        self.name = name
        self.n = getattr(self.lib, f"{name.upper()}_N")
        self.nu = getattr(self.lib, f"{name.upper()}_NU")
        self.has_momentum = hasattr(self.lib, f"{name}_momentum")
        self.has_jacobi = hasattr(self.lib, f"{name}_jacobi")
        self.has_canonical = bool(getattr(self.lib, f"{name.upper()}_HAS_CANONICAL", 0))
        self.has_variational = bool(getattr(self.lib, f"{name.upper()}_HAS_VARIATIONAL", 0))
        # NAME_TIME_DEPENDENT (general models only): forces, qdd, energy, momentum take t first
        self.time_dependent = bool(getattr(self.lib, f"{name.upper()}_TIME_DEPENDENT", 0))
        # NAME_REAL: double, or float (generate --real float): the arrays in and out follow it
        self.real = self.ffi.typeof(self._fn("mass_matrix")).args[0].item.cname
        self.dtype = np.float32 if self.real == "float" else np.float64
        self._ptr = f"{self.real} *"

    def _t(self, t) -> tuple:
        return (float(t),) if self.time_dependent else ()

    def _fn(self, what):
        return getattr(self.lib, f"{self.name}_{what}")

    def _p(self, params):
        if params is None:
            return self.ffi.NULL
        p = self.ffi.new(f"{self.name}_params *")
        for k, v in params.items():
            setattr(p, k, float(v))
        return p

    def _arr(self, v, n):
        v = np.ascontiguousarray(v, dtype=self.dtype)
        assert v.shape == (n,), (v.shape, n)
        return self.ffi.cast(self._ptr, self.ffi.from_buffer(v)), v

    def _u(self, u):
        if u is None:
            return self.ffi.NULL, None
        return self._arr(u, self.nu)

    def _call(self, what, *args, out_len):
        out = np.empty(out_len, self.dtype)
        code = self._fn(what)(*args, self.ffi.cast(self._ptr, self.ffi.from_buffer(out)))
        if code != 0:
            raise ModelError(f"{self.name}_{what}", code)
        return out

    def mass_matrix(self, q, params=None):
        qp, _k = self._arr(q, self.n)
        return self._call("mass_matrix", qp, self._p(params), out_len=self.n * self.n).reshape(self.n, self.n)

    def forces(self, x, u=None, params=None, t=0.0):
        xp, _k = self._arr(x, 2 * self.n)
        up, _ku = self._u(u)
        return self._call("forces", *self._t(t), xp, up, self._p(params), out_len=self.n)

    def qdd(self, x, u=None, params=None, t=0.0):
        """φ̈ at the state x (and the time t, for a time-dependent model)."""
        xp, _k = self._arr(x, 2 * self.n)
        up, _ku = self._u(u)
        return self._call("qdd", *self._t(t), xp, up, self._p(params), out_len=self.n)

    def rhs(self, t, x, u=None, params=None):
        xp, _k = self._arr(x, 2 * self.n)
        up, _ku = self._u(u)
        return self._call("rhs", float(t), xp, up, self._p(params), out_len=2 * self.n)

    def qdd_derivatives(self, x, u=None, params=None, t=0.0):
        """(φ̈, ∂φ̈/∂φ, ∂φ̈/∂φ̇, ∂φ̈/∂u) from NAME_qdd_derivatives (arrays n, n×n, n×n, n×nu)."""
        xp, _k = self._arr(x, 2 * self.n)
        up, _ku = self._u(u)
        n, nu = self.n, self.nu
        out = [np.empty(shape, self.dtype) for shape in (n, (n, n), (n, n), (n, nu))]
        ptrs = [self.ffi.cast(self._ptr, self.ffi.from_buffer(a)) if a.size else self.ffi.NULL for a in out]
        code = self._fn("qdd_derivatives")(*self._t(t), xp, up, self._p(params), *ptrs)
        if code != 0:
            raise ModelError(f"{self.name}_qdd_derivatives", code)
        return tuple(out)

    def linearize(self, x, u=None, params=None, t=0.0):
        """(A, B) of ẋ ≈ A δx + B δu about (x, u), from NAME_linearize."""
        xp, _k = self._arr(x, 2 * self.n)
        up, _ku = self._u(u)
        A, B = np.empty((2 * self.n, 2 * self.n), self.dtype), np.empty((2 * self.n, self.nu), self.dtype)
        bp = self.ffi.cast(self._ptr, self.ffi.from_buffer(B)) if B.size else self.ffi.NULL
        code = self._fn("linearize")(float(t), xp, up, self._p(params), self.ffi.cast(self._ptr, self.ffi.from_buffer(A)), bp)
        if code != 0:
            raise ModelError(f"{self.name}_linearize", code)
        return A, B

    def energy(self, x, params=None, t=0.0):
        xp, _k = self._arr(x, 2 * self.n)
        return self._fn("energy")(*self._t(t), xp, self._p(params))

    def momentum(self, x, params=None, t=0.0):
        xp, _k = self._arr(x, 2 * self.n)
        return self._fn("momentum")(*self._t(t), xp, self._p(params))

    def jacobi(self, x, params=None):
        xp, _k = self._arr(x, 2 * self.n)
        return self._fn("jacobi")(xp, self._p(params))

    # ---- Hamilton's variables (models with NAME_HAS_CANONICAL: fixed base, autonomous)
    def momenta(self, x, params=None):
        """p = ∂ℒ/∂φ̇ = M φ̇ + k(φ) at the state x."""
        xp, _k = self._arr(x, 2 * self.n)
        return self._call("momenta", xp, self._p(params), out_len=self.n)

    def velocities(self, q, pm, params=None):
        """φ̇ from the coordinates q and the momenta pm (M φ̇ = p − k)."""
        qp, _k = self._arr(q, self.n)
        pp, _kp = self._arr(pm, self.n)
        return self._call("velocities", qp, pp, self._p(params), out_len=self.n)

    def pdot(self, x, u=None, params=None):
        """ṗ = ∂ℒ/∂φ + the torques without a force function, at the state x."""
        xp, _k = self._arr(x, 2 * self.n)
        up, _ku = self._u(u)
        return self._call("pdot", xp, up, self._p(params), out_len=self.n)

    # ---- the integrators (NAME_integrate_grid)
    def integrate(self, t, x0, method="dop853", h=0.0, rtol=1e-8, atol=1e-10, u=None, params=None,
                  max_steps=0, full_output=False):
        """The trajectory at the times t (monotone; t[0] is the start, x0 the state there), as an
        array (len(t), 2N), by the C integrator `method` (rk4, gauss2: fixed step h; dop853:
        adaptive, h the first step or 0; gauss2_fixed: GAUSS2 by fixed-point sweeps only;
        gauss2_symplectic: GAUSS2 on Hamilton's variables (φ, p), symplectic, fixed step h).  Raises
        IntegrationError when it stops early.  With full_output, also a dict of counts (n_rhs,
        n_steps, n_rejected, n_iter, n_newton: GAUSS2 steps solved by Newton)."""
        if method == "gauss2_symplectic" and not self.has_canonical:
            raise ValueError(f"{self.name}: gauss2_symplectic needs Hamilton's variables, which a model with a moving "
                             "platform, a lambda(t) or a load of t does not have")
        ts = np.ascontiguousarray(np.atleast_1d(np.asarray(t, dtype=self.dtype)))
        xp, _k = self._arr(x0, 2 * self.n)
        up, _ku = self._u(u)
        X = np.empty((len(ts), 2 * self.n), self.dtype)
        st = self.ffi.new(f"{self.name}_integrate_stats *")
        code = self._fn("integrate_grid")(
            METHODS[method], len(ts), self.ffi.cast(self._ptr, self.ffi.from_buffer(ts)), float(h), float(rtol),
            float(atol), int(max_steps), xp, up, self._p(params), self.ffi.cast(self._ptr, self.ffi.from_buffer(X)), st)
        stats = dict(t=st.t, x=np.array(list(st.x)), n_rhs=st.n_rhs, n_steps=st.n_steps,
                     n_rejected=st.n_rejected, n_iter=st.n_iter, n_newton=st.n_newton)
        if code != 0:
            raise IntegrationError(f"{self.name}_integrate_grid({method})", code, X, stats)
        return (X, stats) if full_output else X

    def integrate_batch(self, t, X0, method="dop853", h=0.0, rtol=1e-8, atol=1e-10, u=None, params=None, max_steps=0):
        """Many trajectories at the same output times t in one C call (NAME_integrate_batch, which
        runs without the GIL): X0 of shape (nb, 2N); u None, one (NU,) for all or (nb, NU); params
        None, one dict for all or a list of nb dicts.  Returns X of shape (nb, len(t), 2N) (rows
        past a failure NaN) and the return code of each trajectory (0: OK)."""
        ts = np.ascontiguousarray(np.atleast_1d(np.asarray(t, dtype=self.dtype)))
        X0 = np.ascontiguousarray(X0, dtype=self.dtype)
        if X0.ndim != 2 or X0.shape[1] != 2 * self.n:
            raise ValueError(f"X0 must have shape (nb, {2 * self.n}), not {X0.shape}")
        nb = X0.shape[0]
        U, u_stride = None, 0
        if u is not None:
            U = np.ascontiguousarray(u, dtype=self.dtype)
            if U.shape == (self.nu,):
                u_stride = 0
            elif U.shape == (nb, self.nu):
                u_stride = self.nu
            else:
                raise ValueError(f"u must have shape ({self.nu},) or ({nb}, {self.nu}), not {U.shape}")
        if params is None:
            pp, p_stride = self.ffi.NULL, 0
        elif isinstance(params, dict):
            pp, p_stride = self._p(params), 0
        else:
            if len(params) != nb:
                raise ValueError(f"params: {len(params)} parameter sets for {nb} trajectories")
            pp, p_stride = self.ffi.new(f"{self.name}_params[]", nb), 1
            for i, d in enumerate(params):
                for k, v in d.items():
                    setattr(pp[i], k, float(v))
        X = np.empty((nb, len(ts), 2 * self.n), self.dtype)
        codes = np.zeros(nb, dtype=np.intc)
        dp = lambda a: self.ffi.cast(self._ptr, self.ffi.from_buffer(a))  # noqa: E731
        failed = self._fn("integrate_batch")(
            METHODS[method], nb, len(ts), dp(ts), float(h), float(rtol), float(atol), int(max_steps), dp(X0),
            dp(U) if U is not None else self.ffi.NULL, u_stride, pp, p_stride, dp(X),
            self.ffi.cast("int *", self.ffi.from_buffer(codes)))
        if failed < 0:
            raise ModelError(f"{self.name}_integrate_batch", -failed)
        return X, codes

    def integrate_variational(self, t0, t1, x0, Phi0=None, u=None, params=None, rtol=1e-10, atol=1e-12, h=0.0,
                              full_output=False):
        """(x(t1), Φ(t1)) from x(t0) = x0 by NAME_integrate_variational: the state with its
        fundamental matrix, Φ' = A(t, x) Φ with A the exact Jacobian of the emitted φ̈, by DOP853
        at rtol/atol over both.  Φ(t0) = Phi0 (2N × 2N; the identity by default, when Φ(t1) is
        ∂x(t1)/∂x(t0), the monodromy matrix over a period).  Raises IntegrationError when it stops
        early; with full_output also the counts (n_rhs, n_steps, n_rejected)."""
        if not self.has_variational:
            raise ValueError(f"{self.name}: no NAME_integrate_variational (emitted up to n = 16; n = {self.n})")
        dim = 2 * self.n
        xp, _k = self._arr(x0, dim)
        up, _ku = self._u(u)
        Phi = np.array(np.eye(dim) if Phi0 is None else Phi0, dtype=self.dtype, order="C")
        if Phi.shape != (dim, dim):
            raise ValueError(f"Phi0 must have shape ({dim}, {dim}), not {Phi.shape}")
        x1 = np.empty(dim, self.dtype)
        st = self.ffi.new(f"{self.name}_integrate_stats *")
        dp = lambda a: self.ffi.cast(self._ptr, self.ffi.from_buffer(a))  # noqa: E731
        code = self._fn("integrate_variational")(float(t0), float(t1), float(h), float(rtol), float(atol), xp, up,
                                                 self._p(params), dp(x1), dp(Phi), st)
        stats = dict(t=st.t, x=np.array(list(st.x)), n_rhs=st.n_rhs, n_steps=st.n_steps, n_rejected=st.n_rejected)
        if code != 0:
            raise IntegrationError(f"{self.name}_integrate_variational", code, x1[None, :], stats)
        return (x1, Phi, stats) if full_output else (x1, Phi)

    # ---- the two-body quadratures (models with NAME_HAS_QUADRATURES)
    def quad_motion(self, x0, params=None) -> dict:
        xp, _k = self._arr(x0, 4)
        info = self.ffi.new(f"{self.name}_quad_info *")
        code = self._fn("quad_motion")(xp, self._p(params), info)
        if code != 0:
            raise ModelError(f"{self.name}_quad_motion", code)
        kinds = {v: k for k, v in MOTIONS.items()}
        fields = ("E", "k", "phi_min", "phi_max", "period", "psi_advance", "separatrix_distance")
        return dict(kind=kinds[info.kind], **{f: getattr(info, f) for f in fields})

    def quad_period(self, x0, params=None) -> float:
        xp, _k = self._arr(x0, 4)
        out = self.ffi.new(self._ptr)
        code = self._fn("quad_period")(xp, self._p(params), out)
        if code != 0:
            raise ModelError(f"{self.name}_quad_period", code)
        return out[0]

    def quad_state(self, t, x0, params=None) -> np.ndarray:
        xp, _k = self._arr(x0, 4)
        ts = np.atleast_1d(np.asarray(t, dtype=float))
        out = np.empty((len(ts), 4), self.dtype)
        p = self._p(params)
        for i, ti in enumerate(ts):
            code = self._fn("quad_state")(float(ti), xp, p, self.ffi.cast(self._ptr, self.ffi.from_buffer(out[i])))
            if code != 0:
                raise ModelError(f"{self.name}_quad_state", code)
        return out if np.ndim(t) else out[0]

    def quad_functions(self, phi, x0, params=None) -> np.ndarray:
        xp, _k = self._arr(x0, 4)
        return self._call("quad_functions", float(phi), xp, self._p(params), out_len=6)


def load(directory: str | Path, name: str | None = None) -> CModel:
    """The compiled model in a generated folder (built there if missing)."""
    directory = Path(directory)
    name = name or directory.name
    found = extensions(directory, name)
    so = found[0] if found else compile_model(directory, name)
    return CModel(so, name)


def load_python(directory: str | Path, name: str | None = None):
    """The generated pure-Python module of a generated folder."""
    directory = Path(directory)
    name = name or directory.name
    path = directory / f"{name}.py"
    spec = importlib.util.spec_from_file_location(f"generated_{name}_{abs(hash(str(path)))}", path)
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod
    spec.loader.exec_module(mod)
    return mod
