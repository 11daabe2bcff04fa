"""``functions(spec_or_folder)``: CasADi functions of a model's NAME_casadi.c, compiled with its
NAME.c into one shared library kept in the private model cache (by the sources' hash), loaded by
``casadi.external``; and the parameter values p0 that go with them."""
from __future__ import annotations

import hashlib
import re
import shutil
import subprocess
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..chainspec.errors import SpecError
from ..chainspec.spec import load_spec
from ..chainspec.tables import spec_limits
from ..models import pipeline
from ..printers import casadi as target

CFLAGS = ["-O2", "-fPIC", "-shared"]
# f's and F's second derivatives (IPOPT's exact Hessian asks for them) are the library's own,
# jac_adj1_NAME_f and jac_adj1_NAME_F (NAME_rhs_hessian, NAME_step_hessian); a chain whose Hessian
# is too long to emit has none, and CasADi differences the exact Jacobians instead (forward differences)
SECOND_ORDER_BY_DIFFERENCES = {"der_options": {"enable_fd": True, "fd_method": "forward"}}


class CasadiUnavailable(RuntimeError):
    """CasADi is not installed (the optional extra gyrochain[casadi])."""


def _casadi():
    try:
        import casadi
    except ImportError:
        raise CasadiUnavailable("CasADi is not installed: pip install 'gyrochain[casadi]'") from None
    return casadi


@dataclass(frozen=True)
class Bounds:
    r"""Box bounds from the spec's joint limits, for Opti (``opti.subject_to(opti.bounded(lbx, X[:, k],
    ubx))``) or rockit: the state $x = (\varphi, \dot\varphi)$ (2n) between ``lbx`` and ``ubx`` (the range, ± the speed),
    the controls u (nu) between ``lbu`` and ``ubu`` (± the effort of each controlled joint); ±inf where
    the spec gives none.  The model itself does not enforce them."""

    lbx: np.ndarray
    ubx: np.ndarray
    lbu: np.ndarray
    ubu: np.ndarray


def bounds_of(limits: dict, n: int, controls) -> Bounds:
    """``limits`` as tables.spec_limits gives them; ``controls`` the 1-based controlled joints."""
    def row(key, sign):
        return np.array([sign * np.inf if v is None else float(v) for v in limits.get(key, [None] * n)])
    speed = row("velocity", 1)
    effort = row("effort", 1)[[k - 1 for k in controls]]
    return Bounds(np.concatenate([row("lower", -1), -speed]), np.concatenate([row("upper", 1), speed]), -effort, effort)


@dataclass
class CasadiModel:
    """The CasADi functions of one model: ``f`` (x, u, p) -> xdot, ``F`` (x, u, p, h) -> xnext (one
    RK4 step), ``M`` (q, p) -> M, ``E`` (x, p) -> E; ``p0`` the parameter values (the spec's
    [values], overridden by those given), ``library`` the shared library they are loaded from,
    ``bounds`` the spec's joint limits as box bounds on x and u (Bounds).  A model that reads t
    (``time_dependent``) takes t as an input of f and F after p (and h): (x, u, p, t) and
    (x, u, p, h, t); one with disturbance torques (``ndist`` of them) takes them last, as u_dist."""

    name: str
    n: int
    nu: int
    params: list
    p0: np.ndarray
    library: Path
    f: object = field(repr=False)
    F: object = field(repr=False)
    M: object = field(repr=False)
    E: object = field(repr=False)
    bounds: Bounds = field(default=None, repr=False)
    time_dependent: bool = False
    ndist: int = 0


def build_library(files: dict[str, str], name: str) -> Path:
    """lib NAME_casadi.so from NAME_casadi.c, NAME.c and NAME.h (cc -O2), kept in the model cache."""
    sources = (f"{name}_casadi.c", f"{name}.c", f"{name}.h")
    key = hashlib.sha256("\0".join([*CFLAGS, *(files[k] for k in sources)]).encode()).hexdigest()[:24]
    folder = pipeline.cache_root() / "casadi" / f"{name}-{key}"
    lib = folder / f"lib{name}_casadi.so"
    if lib.exists():
        return lib
    cc = shutil.which("cc") or shutil.which("gcc")
    if cc is None:
        raise SpecError("--casadi", "needs a C compiler (cc) to build the library")
    folder.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=folder) as work:  # (two processes at once: each its own folder)
        work = Path(work)
        for k in sources:
            (work / k).write_text(files[k])
        run = subprocess.run([cc, *CFLAGS, str(work / sources[0]), str(work / sources[1]), "-o", str(work / lib.name),
                              "-lm"], capture_output=True, text=True)
        if run.returncode != 0:
            raise RuntimeError(f"{cc}: {name}_casadi.c does not compile:\n{run.stderr}")
        (work / lib.name).replace(lib)
    return lib


@dataclass(frozen=True)
class _Source:
    files: dict
    name: str
    n: int
    nu: int  # CasADi's u: the controls (not the disturbances)
    ndist: int
    params: list  # the parameters' names, in NAME_params' order
    values: dict  # their values where known (a spec's [values]; a folder holds none)
    bounds: Bounds


def _folder(folder: Path) -> _Source:
    """What `generate --casadi` wrote into ``folder``: the sources, and the sizes and parameter
    names its header declares."""
    found = sorted(folder.glob("*_casadi.c"))
    if not found:
        raise SpecError(str(folder), "holds no NAME_casadi.c (write one with gyrochain generate SPEC --casadi)")
    name = found[0].name[: -len("_casadi.c")]
    missing = [k for k in (f"{name}.c", f"{name}.h") if not (folder / k).exists()]
    if missing:
        raise SpecError(str(folder), f"lacks {missing[0]} beside {name}_casadi.c")
    files = {k: (folder / k).read_text() for k in (f"{name}_casadi.c", f"{name}.c", f"{name}.h")}
    header = files[f"{name}.h"]
    sizes = {k: int(v) for k, v in re.findall(rf"#define {name.upper()}_(N|NU) (\d+)\n", header)}
    struct = re.search(rf"typedef struct {name}_params {{\n(.*?)\n}} {name}_params;", header, re.S)
    if len(sizes) != 2 or struct is None:
        raise SpecError(str(folder), f"{name}.h is not a header gyrochain wrote")
    params = [f for f in re.findall(r"double (\w+);", struct.group(1)) if f != "unused_"]
    py = (folder / f"{name}.py").read_text() if (folder / f"{name}.py").exists() else ""
    ndist = len(_joints(py, "DISTURBANCES") or ())
    return _Source(files, name, sizes["N"], sizes["NU"] - ndist, ndist, params, {},
                   _header_bounds(header, name, sizes["N"], sizes["NU"] - ndist, py))


def _joints(py: str, key: str) -> list | None:
    """A generated NAME.py's tuple of joints ``key`` (CONTROLS, DISTURBANCES), None without it."""
    found = re.search(rf"^{key} = \(([\d, ]*)\)", py, re.M)
    return None if found is None else [int(k) for k in found.group(1).replace(" ", "").split(",") if k]


def _header_bounds(header: str, name: str, n: int, nu: int, py: str) -> Bounds:
    """The limits' initializers of a generated header (NAME_PHI_LOWER, …) as Bounds; the
    controlled joints from the folder's NAME.py ``py`` (CONTROLS but DISTURBANCES), else none
    bounded in u."""
    from ..printers.c import LIMIT_MACROS

    limits = {}
    for key, (macro, _) in LIMIT_MACROS.items():
        found = re.search(rf"#define {name.upper()}_{macro} \{{(.*?)\}}\n", header)
        if found:
            limits[key] = [None if "HUGE_VAL" in v else float(v) for v in found.group(1).split(",")]
    controls = _joints(py, "CONTROLS")
    if controls is None:  # which joints u drives is not known here: no bound on u
        limits.pop("effort", None)
        return bounds_of(limits, n, range(1, nu + 1))
    dist = set(_joints(py, "DISTURBANCES") or ())
    return bounds_of(limits, n, [k for k in controls if k not in dist])


def _source(spec_or_folder) -> _Source:
    """The sources of a spec (object or file: derived and printed here) or of a generated folder."""
    if isinstance(spec_or_folder, (str, Path)) and Path(spec_or_folder).is_dir():
        return _folder(Path(spec_or_folder))
    spec = load_spec(spec_or_folder) if isinstance(spec_or_folder, (str, Path)) else spec_or_folder
    target.check(spec)
    files, _ = pipeline.derive_and_render(spec, targets=("c", "casadi"))
    ctrl = [k for k in spec.controls if k not in spec.disturbances]
    return _Source(files, spec.name, spec.n, len(ctrl), len(spec.disturbances), [str(p) for p in spec.params],
                   dict(getattr(spec, "values", None) or {}), bounds_of(spec_limits(spec), spec.n, ctrl))


def functions(spec_or_folder, params: dict | None = None) -> CasadiModel:
    """The CasADi functions of a spec (a ChainSpec or a spec file: derived, printed and built here)
    or of a folder ``generate --casadi`` wrote; ``params`` override the spec's [values] in ``p0``."""
    casadi = _casadi()
    src = _source(spec_or_folder)
    given = dict(params or {})
    unknown = [k for k in given if k not in src.params]
    if unknown:
        raise SpecError(f"--param {unknown[0]}", "unknown parameter (the model's are: " + (", ".join(src.params) or "none") + ")")
    values = {**src.values, **given}
    missing = [k for k in src.params if k not in values]
    if missing:
        raise SpecError("--param", "no value for " + ", ".join(missing) + " (give params={...}, or a [values] table in "
                                   "the spec: a generated folder holds no values)")
    bad = [k for k in src.params if not np.isfinite(float(values[k]))]
    if bad:
        raise SpecError(f"--param {bad[0]}", f"{values[bad[0]]} is not a finite number")
    lib = build_library(src.files, src.name)
    exact = f"int jac_adj1_{src.name}_f(" in src.files[f"{src.name}_casadi.c"]
    made = {k: casadi.external(f"{src.name}_{k}", str(lib), {} if exact or k not in "fF" else SECOND_ORDER_BY_DIFFERENCES)
            for k in ("f", "F", "M", "E")}
    timed = f"#define {src.name.upper()}_TIME_DEPENDENT 1\n" in src.files[f"{src.name}.h"]
    return CasadiModel(src.name, src.n, src.nu, list(src.params), np.array([float(values[k]) for k in src.params]), lib,
                       **made, bounds=src.bounds, time_dependent=timed, ndist=src.ndist)
