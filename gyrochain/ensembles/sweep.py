"""Ensembles: a grid (or random samples) of initial states and parameters, integrated by the
batched C (NAME_integrate_batch) chunk by chunk, on threads of this machine, a local Dask cluster
or an existing one, each finished chunk written to a Zarr store at once
(``gyrochain sweep SPEC --vary link1=-3.1:3.1:400 --vary link2=-3.1:3.1:400 --t1 10 --measure flip_time -o out.zarr``).
The store holds one array per measure over the grid (dimension names for xarray), the grid's
coordinates, the integrator's return code of every point and a ``done`` flag per chunk; its
attributes are the spec, the sweep's arguments and the gyrochain version.  A chunk's results depend
only on the spec, the arguments and the chunk's points (never on where or when it ran), and the
client is the only writer: a rerun of the same command skips the chunks marked done, so an
interrupted run or one that lost a worker ends with the same store as an undisturbed one.
"""
from __future__ import annotations

import json
import math
import os
import shutil
import sys
import threading
from concurrent.futures import ThreadPoolExecutor, as_completed
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from ..models import pipeline
from ..models.files import writable
from ..models.paramtable import ParamTable
from ..printers.codes import METHODS
from ..analysis import floquet
from .. import gpu
from .measures import (angles_of, energies, flip_times, joint_angles, link_signs, lyapunov, lyapunov_spectrum,
                       lyapunov_spectrum_batch, pairing_summary)
from ..chainspec.physical import check_values, run_values
from ..chainspec.errors import did_you_mean
from ..chainspec.spec import SpecError
# the store's layout and files (store.py); EXTRA_DIM, STORE_KIND, check_store, read and stored_attrs
# are named here too, as the commands and plot know them
from .store import (EXTRA_DIM, STORE_KIND, _attrs, _done_flags, _readable, _write, _zarr, check_store,  # noqa: F401
                    open_store, read, stored_attrs)

MEASURES = ("final", "flip_time", "energy_error", "lyapunov", "lyapunov_spectrum", "floquet")
# the measures on the variational equations (NAME_integrate_variational: DOP853 at --rtol/--atol)
VARIATIONAL_MEASURES = ("lyapunov_spectrum", "floquet")
# the extra dimension of a measure with more than one number per point
ANGLES = ("auto", "absolute", "relative")  # --angles: what flip_time watches
METHOD_NAMES = tuple(m for m in METHODS if m in ("rk4", "dop853", "gauss2", "rk4_lanes"))  # those a sweep offers


# --------------------------------------------------------------------------- the sweep's arguments
@dataclass
class Sweep:
    """Everything a chunk's results depend on (stored as the store's ``args``)."""

    spec_text: str
    vary: list  # [(name, lo, hi, count)]; count 0 in random mode
    t1: float
    measures: list
    random: int = 0  # > 0: that many uniform samples in the box of the --vary ranges
    seed: int = 0
    method: str = "dop853"
    h: float = 0.0
    rtol: float = 1e-8
    atol: float = 1e-10
    samples: int = 1000  # output intervals over [0, t1] for flip_time and energy_error
    flip: str = ""  # the coordinate of flip_time (phiK), "" = the first of any
    angles: str = "auto"  # flip_time on the links' absolute angles, the joint angles, or auto (absolute where planar)
    lyap_interval: float = 0.1  # renormalisation interval of the Lyapunov exponent (and of the spectrum's QR)
    lyap_d0: float = 1e-8  # the initial separation (Euclidean, in state space)
    phi: list = field(default_factory=list)  # the state of what is not varied
    phidot: list = field(default_factory=list)
    u: list = field(default_factory=list)
    params: dict = field(default_factory=dict)  # the symbolic parameters that are not varied
    chunk: int = 1024  # points per chunk (rounded to whole rows of the grid)

    def args(self) -> dict:
        d = asdict(self)
        d.pop("spec_text")
        return d


MAX_POINTS = 10**9  # points in one sweep
MAX_CHUNKS = 10**6  # chunks in one store


LYAPUNOV_MEASURES = ("lyapunov", "lyapunov_spectrum")


def tolerances(measures, rtol: float | None, atol: float | None, d0: float) -> tuple[float, float, str]:
    """DOP853's tolerances of a sweep, and the line that says why when a Lyapunov measure chose them.

    A Lyapunov exponent compares two trajectories d0 apart (or the tangent map): the integrator's
    error over an interval must stay far below d0, or the exponent measures the integrator.  With a
    Lyapunov measure the defaults are rtol 1e-11 and atol 1e-5 d0 (at most 1e-13) instead of 1e-8 and
    1e-10; what the user gives is kept."""
    lyap = any(m in LYAPUNOV_MEASURES for m in measures)
    if not lyap:
        return (1e-8 if rtol is None else rtol), (1e-10 if atol is None else atol), ""
    r = 1e-11 if rtol is None else rtol
    a = min(1e-13, 1e-5 * d0) if atol is None else atol
    if rtol is not None and atol is not None:
        return r, a, ""
    asked = [m for m in LYAPUNOV_MEASURES if m in measures]
    why = (f"far below the separation d0 = {d0:g} (--rtol, --atol, --lyap-d0 change them)" if "lyapunov" in asked
           else "small beside the stretching it measures (--rtol, --atol change them)")
    return r, a, (f"{' and '.join(asked)}: dop853 at rtol {r:g}, atol {a:g}, so that its error stays {why}; over a finite "
                  "--t1 a chaotic motion's exponent still varies by some percent with any change of its trajectory "
                  "(a longer --t1 narrows it)")


def parse_vary(text: str, random_mode: bool) -> tuple:
    """``name=lo:hi:N`` (grid) or ``name=lo:hi`` (random samples)."""
    name, eq, rng = text.partition("=")
    name = name.strip()
    if not eq or not name:
        raise SpecError("--vary", f"{text!r}: expected name=lo:hi:N")
    parts = rng.split(":")
    if len(parts) not in (2, 3) or (not random_mode and len(parts) != 3):
        raise SpecError(f"--vary {name}", f"{rng!r}: expected lo:hi:N" + (" (or lo:hi with --random)" if not random_mode else ""))
    try:
        lo, hi = float(parts[0]), float(parts[1])
        count = int(parts[2]) if len(parts) == 3 else 0
    except ValueError:
        raise SpecError(f"--vary {name}", f"{rng!r}: lo and hi must be numbers, N an integer") from None
    if not (math.isfinite(lo) and math.isfinite(hi)):
        raise SpecError(f"--vary {name}", "the range must be finite")
    if random_mode:
        if len(parts) == 3:
            raise SpecError(f"--vary {name}", "give lo:hi without N with --random (the number is --random's)")
        if not lo < hi:
            raise SpecError(f"--vary {name}", f"empty range {lo:g}:{hi:g} (need lo < hi)")
    elif count < 1 or (count > 1 and lo == hi):
        raise SpecError(f"--vary {name}", f"empty range {rng!r} (need N >= 1 and lo != hi when N > 1)")
    return (name, lo, hi, count)


# --------------------------------------------------------------------------- the plan
class Plan:
    """The grid, its chunks and how a point becomes a state and parameters."""

    def __init__(self, sweep: Sweep):
        from ..chainspec.spec import parse_spec

        self.sweep = sweep
        self.spec = spec = parse_spec(sweep.spec_text)
        n = self.n = spec.n
        self.state_names = [f"phi{k}" for k in range(1, n + 1)] + [f"phidot{k}" for k in range(1, n + 1)]
        self.param_names = [str(p) for p in spec.params]
        names = [v[0] for v in sweep.vary]
        if not names and sweep.random > 0:
            raise SpecError("--random", "samples the box of the --vary ranges; give at least one --vary NAME=lo:hi")
        self.link_signs = link_signs(spec)  # linkK, the absolute angle of link K, exists where the chain is planar
        self.link_names = [f"link{k}" for k in range(1, n + 1)] if self.link_signs else []
        for name in names:
            if name not in self.state_names + self.link_names and name not in self.param_names:
                allowed = (f"phi1..phi{n}, phidot1..phidot{n}" + (f", link1..link{n}" if self.link_names else "")
                           + (f" or a parameter ({', '.join(self.param_names)})" if self.param_names else ""))
                raise SpecError("--vary", f"unknown name {name!r} (expected {allowed})")
        if any(nm in self.link_names for nm in names) and any(nm in self.state_names[:n] for nm in names):
            raise SpecError("--vary", "give the links' absolute angles (linkK) or the joint angles (phiK), not both")
        if len(set(names)) != len(names):
            raise SpecError("--vary", "a name is varied twice")
        clash = [nm for nm in names if nm in MEASURES + ("code", "done")]
        if clash:
            raise SpecError("--vary", f"{clash[0]!r} is the name of a stored array; rename the parameter")
        self._check_options()
        fixed = [p for p in self.param_names if p not in names]
        # the values of the parameters that are not varied: --param over the spec's [values]
        self.params = {k: v for k, v in run_values(spec, sweep.params, needed=fixed).items() if k not in names}
        if sweep.u and len(sweep.u) != len(spec.controls):
            raise SpecError("--u", f"the spec has {len(spec.controls)} control torques; give that many values (default 0)")
        init = spec.initial or {}
        self.base = np.array((sweep.phi or list(init.get("phi", [0.0] * n))) + (sweep.phidot or list(init.get("phidot", [0.0] * n))), float)
        if self.base.shape != (2 * n,):
            raise SpecError("--phi", f"expected {n} values for --phi and for --phidot")
        self._check_size()
        # the points
        if not names:  # one trajectory: a sample of one point, nothing varied
            self.points = np.zeros((1, 0))
            self.shape, self.dims, self.coords = (1,), ["sample"], {}
        elif sweep.random > 0:
            rng = np.random.default_rng(sweep.seed)
            lo = np.array([v[1] for v in sweep.vary])
            hi = np.array([v[2] for v in sweep.vary])
            self.points = lo + (hi - lo) * rng.random((sweep.random, len(names)))
            self.shape = (sweep.random,)
            self.dims = ["sample"]
            self.coords = {name: (["sample"], self.points[:, i]) for i, name in enumerate(names)}
        else:
            axes = [np.linspace(lo, hi, count) for _, lo, hi, count in sweep.vary]
            self.shape = tuple(len(a) for a in axes)
            self.dims = list(names)
            self.coords = {name: ([name], axes[i]) for i, name in enumerate(names)}
            self.axes = axes
            self.points = None
        self.names = names
        row = int(np.prod(self.shape[1:])) if len(self.shape) > 1 else 1
        self.rows = max(1, sweep.chunk // row)
        self.n_chunks = -(-self.shape[0] // self.rows)
        self._check_varied_values()
        if "energy_error" in sweep.measures and not self._has_energy():
            raise SpecError("--measure", "energy_error: the energy (23) is not an integral of this spec")
        if "floquet" in sweep.measures:
            self._check_floquet()

    def _check_floquet(self) -> None:
        """floquet: a time-periodic model, the state an equilibrium for all t (floquet.sweep_setup)."""
        self.model = pipeline.derive(self.spec, latex=False)
        first = dict(self.params, **{nm: float(self.chunk_points(0)[0, j]) for j, nm in enumerate(self.names)})
        self.cyclic = floquet.sweep_setup(lambda: pipeline.compiled(self.spec)[0], self.model, self.base, first,
                                          np.array(self.sweep.u, float) if self.sweep.u else None,
                                          [nm for nm in self.names if nm not in self.param_names])

    def _check_options(self) -> None:
        """The measures, the integrator and the flip angles asked for."""
        sweep, n = self.sweep, self.n
        for m in sweep.measures:
            if m not in MEASURES:
                raise SpecError("--measure", f"unknown measure {m!r} ({did_you_mean(m, MEASURES)}one of {', '.join(MEASURES)})")
        if not sweep.measures:
            raise SpecError("--measure", "no measure asked for")
        if len(set(sweep.measures)) != len(sweep.measures):
            raise SpecError("--measure", "a measure is asked for twice")
        if sweep.method not in METHOD_NAMES:
            raise SpecError("--method", f"one of {', '.join(METHOD_NAMES)}")
        if sweep.method != "dop853" and not sweep.h > 0:
            raise SpecError("--h", f"{sweep.method} needs a step --h > 0")
        if not (sweep.t1 > 0 and math.isfinite(sweep.t1)):
            raise SpecError("--t1", "must be a positive number")
        if sweep.samples < 1:
            raise SpecError("--samples", "must be at least 1")
        if sweep.flip and sweep.flip not in self.state_names[:n]:
            raise SpecError("--flip", f"expected one of phi1..phi{n}")
        if sweep.angles not in ANGLES:
            raise SpecError("--angles", f"one of {', '.join(ANGLES)}, got {sweep.angles!r}")
        self.signs = self.link_signs if sweep.angles != "relative" else None
        if sweep.angles == "absolute" and self.signs is None:
            raise SpecError("--angles", "absolute: the axes are not all parallel, so a link has no one angle "
                                        "(use relative, the joint angles)")
        self.angles = "relative" if self.signs is None else "absolute"  # what flip_time measures
        if ("lyapunov" in sweep.measures or "lyapunov_spectrum" in sweep.measures) and not (0 < sweep.lyap_interval <= sweep.t1):
            raise SpecError("--lyap-interval", "must be in (0, t1]")
        asked = [m for m in VARIATIONAL_MEASURES if m in sweep.measures]
        if asked and sweep.method != "dop853":
            raise SpecError("--method", f"{asked[0]} integrates the variational equations with dop853 at --rtol/--atol; "
                                        "give --method dop853 (the default)")
        if asked and n > 16:
            raise SpecError("--measure", f"{asked[0]}: needs NAME_integrate_variational, emitted up to n = 16 (n = {n})")

    def _check_size(self) -> None:
        """Refuse, before anything is allocated, more than MAX_POINTS points (held in memory, stored
        per measure) or MAX_CHUNKS chunks (each a task and a stored file)."""
        sweep = self.sweep
        points = sweep.random if sweep.random > 0 else math.prod(v[3] for v in sweep.vary)
        if points > MAX_POINTS:
            raise SpecError("--random" if sweep.random > 0 else "--vary",
                            f"{points:.3g} points; one sweep holds at most {MAX_POINTS:.0e} (split the range)")
        shape = (sweep.random,) if sweep.random > 0 else (tuple(v[3] for v in sweep.vary) or (1,))
        row = math.prod(shape[1:])
        chunks = -(-shape[0] // max(1, sweep.chunk // row))
        if chunks > MAX_CHUNKS:
            raise SpecError("--chunk", f"{chunks} chunks of {max(1, sweep.chunk // row) * row} points; at most "
                                       f"{MAX_CHUNKS} (give a bigger --chunk)")

    def _check_varied_values(self, most: int = 4096) -> None:
        """The varied parameters' values checked like --param: every combination of a grid's
        parameter axes (or every random sample) up to ``most``, else the corners of their box."""
        varied = [(j, nm) for j, nm in enumerate(self.names) if nm in self.param_names]
        if not varied:
            return
        if self.points is not None:
            combos = self.points[:, [j for j, _ in varied]]
        else:
            combos = np.array(np.meshgrid(*[self.axes[j] for j, _ in varied], indexing="ij")).reshape(len(varied), -1).T
        if len(combos) > most:
            combos = np.array(np.meshgrid(*[[self.sweep.vary[j][1], self.sweep.vary[j][2]] for j, _ in varied],
                                          indexing="ij")).reshape(len(varied), -1).T
        for row in combos:
            values = dict(self.params, **{nm: float(v) for (_, nm), v in zip(varied, row)})
            check_values(self.spec, values, " with " + ", ".join(f"{k} = {v:g}" for k, v in values.items())
                         + " (a point of --vary)")

    def _has_energy(self) -> bool:
        ints = pipeline.derive(self.spec, latex=False).integrals  # derived once: run() compiles this model
        return bool(ints.has_energy_integral) and not any(self.sweep.u)

    def chunk_rows(self, i: int) -> tuple[int, int]:
        return i * self.rows, min(self.shape[0], (i + 1) * self.rows)

    def chunk_points(self, i: int) -> np.ndarray:
        """The varied values of chunk i's points, shape (count, number of varied names)."""
        r0, r1 = self.chunk_rows(i)
        if self.points is not None:
            return self.points[r0:r1]
        grids = np.meshgrid(self.axes[0][r0:r1], *self.axes[1:], indexing="ij")
        return np.stack([g.ravel() for g in grids], axis=1)

    def chunk_shape(self, i: int) -> tuple:
        r0, r1 = self.chunk_rows(i)
        return (r1 - r0,) + tuple(self.shape[1:])


# --------------------------------------------------------------------------- one chunk
def start_states(plan: Plan, pts: np.ndarray) -> np.ndarray:
    """The initial states (nb, 2n) of points (nb, number of varied names): the base state with the
    varied coordinates set; varied absolute link angles θ_k = s_1 φ¹ + … + s_k φᵏ (linkK) set the
    joint angles φᵏ = s_k (θ_k − θ_{k−1})."""
    n = plan.n
    X0 = np.tile(plan.base, (len(pts), 1))
    links = [(j, plan.link_names.index(nm)) for j, nm in enumerate(plan.names) if nm in plan.link_names]
    if links:
        theta = np.cumsum(X0[:, :n] * plan.link_signs, axis=1)
        theta[:, [k for _, k in links]] = pts[:, [j for j, _ in links]]
        X0[:, :n] = joint_angles(theta, plan.link_signs)
    for j, name in enumerate(plan.names):
        if name in plan.state_names:
            X0[:, plan.state_names.index(name)] = pts[:, j]
    return X0


def compute_chunk(model, plan: Plan, i: int) -> dict[str, np.ndarray]:
    """The measures of chunk i (arrays over the chunk's part of the grid) and the return codes."""
    sw = plan.sweep
    pts = plan.chunk_points(i)
    nb, n = len(pts), plan.n
    X0 = start_states(plan, pts)
    params = dict(plan.params)
    per_point = None
    varied_params = [(j, name) for j, name in enumerate(plan.names) if name in plan.param_names]
    if varied_params:
        per_point = ParamTable(params, [name for _, name in varied_params], pts[:, [j for j, _ in varied_params]])
    prm = per_point if per_point is not None else (params or None)
    u = np.array(sw.u, float) if sw.u else None
    kw = dict(method=sw.method, h=sw.h, rtol=sw.rtol, atol=sw.atol, u=u, params=prm)
    out: dict = {}
    codes = np.zeros(nb, dtype=np.int32)
    series = [m for m in sw.measures if m in ("flip_time", "energy_error")]
    if series or "final" in sw.measures:
        t = np.linspace(0.0, sw.t1, (sw.samples if series else 1) + 1)
        X, c = model.integrate_batch(t, X0, **kw)
        codes = np.maximum(codes, c)
        if "final" in sw.measures:
            out["final"] = X[:, -1, :].copy()
        if "flip_time" in sw.measures:
            out["flip_time"] = flip_times(t, angles_of(X[:, :, :n], plan.signs),
                                          plan.state_names.index(sw.flip) if sw.flip else None)
        if "energy_error" in sw.measures:
            E = energies(model, X, per_point if per_point is not None else params or None)
            out["energy_error"] = np.max(np.abs(E - E[:, :1]), axis=1)
            out["energy_error"][c != 0] = np.nan
    if "lyapunov" in sw.measures:
        lam, c = lyapunov(model, X0, sw, kw, prm)
        out["lyapunov"] = lam
        codes = np.maximum(codes, c)
    batched = hasattr(model, "floquet_batch")  # the GPU's model: the floquet and lyapunov kernels
    if "lyapunov_spectrum" in sw.measures:
        spectrum = lyapunov_spectrum_batch if batched else lyapunov_spectrum
        lam, c = spectrum(model, X0, sw.t1, sw.lyap_interval, prm, u, sw.rtol, sw.atol)
        out["lyapunov_spectrum"] = lam
        codes = np.maximum(codes, c)
    if "floquet" in sw.measures:
        every = per_point or [params or None] * nb
        if batched:
            out["floquet"], c = floquet.sweep_moduli_batch(model, plan.model, X0, every, u, plan.cyclic)
        else:
            out["floquet"], c = floquet.sweep_moduli(model, plan.model, X0, every, u, plan.cyclic)
        codes = np.maximum(codes, c)
    shape = plan.chunk_shape(i)
    res = {k: v.reshape(shape + v.shape[1:]) for k, v in out.items()}
    res["code"] = codes.reshape(shape)
    return res


# --------------------------------------------------------------------------- the model
def _payload(payload: dict) -> dict:
    """What every chunk task of a Dask run reads (a task of its own: see _dask_results)."""
    return payload


def run_chunk_task(payload: dict, i: int) -> dict:
    """What a Dask worker runs: load (build once) the model from the shipped sources, compute."""
    key = json.dumps(payload["sweep"], sort_keys=True)
    with _PLANS_LOCK:
        plan = _PLANS.get(key)
        if plan is None:
            plan = _PLANS[key] = Plan(Sweep(**payload["sweep"]))
    model = pipeline.checked(plan.spec, pipeline.compile(payload["files"], payload["name"]))
    return compute_chunk(model, plan, i)


_PLANS: dict = {}
_PLANS_LOCK = threading.Lock()


# --------------------------------------------------------------------------- the store
# --------------------------------------------------------------------------- running
def resolve_device(device: str, method: str, cpu_option: bool = False) -> str:
    """``device`` "auto": "cuda" where a GPU can run the sweep (CuPy and a CUDA device, a kernel for
    ``method``, no option of the CPU's given: ``cpu_option``), else "cpu"; any other as it is."""
    if device != "auto":
        return device
    return "cpu" if cpu_option or method not in gpu.device.GPU_METHODS or gpu.unavailable() else "cuda"


def run(sweep: Sweep, store: str | Path, threads: int | None = None, workers: int = 0, scheduler: str = "",
        progress: bool = True, plan: Plan | None = None, stop_after: int | None = None, on_written=None,
        note=None, device: str = "cpu") -> dict:
    """Run (or resume) a sweep into ``store``; returns counts.  ``stop_after``: stop once that many
    chunks were written; ``on_written(i)`` is called after chunk i is in the store; ``note(line)``
    is told what happened on the way (a Dask worker lost; default: a line on stderr).  ``device``
    "cuda": the chunks' trajectories on the GPU (gyrochain.gpu; a chunk is one launch); "host": the
    kernels' host form, every GPU thread in turn on this CPU (how the tests check the GPU's path);
    "auto": "cuda" where a GPU can run it, else "cpu" (resolve_device)."""
    device = resolve_device(device, sweep.method, bool(threads or workers or scheduler))
    plan = plan or Plan(sweep)
    store = Path(store)
    created = not store.exists()
    writable(store / "x" if store.is_dir() else store)  # the folder the store is (or is made in)
    g = open_store(store, plan)
    written = 0
    try:
        done = _done_flags(g, plan, note)
        todo = [i for i in range(plan.n_chunks) if not done[i]]
        if not todo:  # nothing to do: no derivation, no cluster
            return dict(chunks=plan.n_chunks, skipped=int(done.sum()), written=0)
        files, _ = pipeline.derive_and_render(plan.spec, targets=("c",), gpu=device != "cpu")
        bar = _bar(plan.n_chunks, int(done.sum()), progress)
        if device != "cpu":
            cpu = pipeline.checked(plan.spec, pipeline.compile({k: v for k, v in files.items() if not k.endswith(".cu")},
                                                               plan.spec.name))
            results = _thread_results(gpu.GpuModel(cpu, files, host=device == "host"), plan, todo, 1)
        elif workers or scheduler:
            results = _dask_results(plan, sweep, files, todo, workers, scheduler, note or _stderr)
        else:
            results = _thread_results(pipeline.checked(plan.spec, pipeline.compile(files, plan.spec.name)), plan, todo,
                                      threads or os.cpu_count() or 1)
        try:
            for i, res in results:  # as chunks finish, wherever they ran; the client alone writes
                _write(g, plan, i, res, on_written)
                written += 1
                bar.update(1)
                if stop_after and written >= stop_after:
                    break
        finally:
            results.close()  # cancels what is pending, shuts a started cluster down
            bar.close()
    except BaseException:
        if created and written == 0:  # a store this run made and filled with nothing: not left behind
            shutil.rmtree(store, ignore_errors=True)
        elif written or not created:
            kept = int(np.sum(np.asarray(g["done"][:]))) if _readable(g) else 0
            (note or _stderr)(f"{store}: {kept} of {plan.n_chunks} chunks are in the store; the same command finishes it")
        raise
    return dict(chunks=plan.n_chunks, skipped=int(done.sum()), written=written)


def _thread_results(model, plan: Plan, todo: list, nthreads: int):
    """(chunk, results) from threads of this process (the batched C runs without the GIL)."""
    if nthreads == 1:
        for i in todo:
            yield i, compute_chunk(model, plan, i)
        return
    pool = ThreadPoolExecutor(max_workers=nthreads)
    futures = {pool.submit(compute_chunk, model, plan, i): i for i in todo}
    ended = False
    try:
        for fut in as_completed(futures):
            yield futures[fut], fut.result()
        ended = True
    finally:
        # at the end, wait for the threads; on an error or Ctrl-C, do not wait for the chunks still
        # running (the command ends the process once its clean-ups are done: cli._exit_if_held)
        pool.shutdown(wait=ended, cancel_futures=True)


def reachable(address: str) -> None:
    """A one-line error, within two seconds, unless a server answers at ``address``
    (tcp://host:port, the form Dask's scheduler prints)."""
    import socket
    from urllib.parse import urlsplit

    parts = urlsplit(address if "://" in address else f"tcp://{address}")
    try:
        host, port = parts.hostname, parts.port
    except ValueError:
        host = port = None
    if parts.scheme not in ("tcp", "tls") or not host or not port:
        raise SpecError("--scheduler", f"{address!r}: expected tcp://host:port (the address the Dask scheduler prints)")
    try:
        with socket.create_connection((host, port), timeout=2.0):
            pass
    except OSError as exc:
        raise SpecError("--scheduler", f"nothing answers at {address} ({exc.strerror or exc})") from None


def _dask_results(plan: Plan, sweep: Sweep, files: dict, todo: list, workers: int, scheduler: str, note):
    """(chunk, results) from a local Dask cluster of ``workers`` processes or the one at ``scheduler``."""
    try:
        from distributed import Client, LocalCluster, as_completed as dask_completed
    except ImportError:
        raise SpecError("--workers", "needs the sweep extra: pip install 'gyrochain[sweep]'") from None
    cluster = None
    if scheduler:
        try:
            client = Client(scheduler, timeout="10s")
        except (OSError, TimeoutError) as exc:
            raise SpecError("--scheduler", f"cannot connect to {scheduler}: {exc}") from None
    else:
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, host="127.0.0.1",
                               dashboard_address=None, silence_logs=40)
        client = Client(cluster)
    futures: list = []
    payload = None
    try:
        # the payload is a task, not scattered data: the scheduler holds its inputs and recomputes it
        # if the worker holding it dies (scattered data would be lost with it), and its key is this
        # sweep's own (a scattered dict's keys are its literal keys, which two sweeps on one
        # scheduler would share)
        token = _token(plan)
        payload = client.submit(_payload, {"sweep": asdict(sweep), "files": files, "name": plan.spec.name},
                                key=f"gyrochain-payload-{token}", retries=2)
        futures = [client.submit(run_chunk_task, payload, i, key=f"gyrochain-chunk-{i}-{token}", retries=2)
                   for i in todo]
        index = {f.key: i for f, i in zip(futures, todo)}
        workers_seen = _workers(client)
        for fut in dask_completed(futures):
            workers_seen = _report_lost(client, workers_seen, note)
            try:
                res = fut.result()
            except Exception as exc:  # noqa: BLE001  (a chunk that killed its workers or failed on them)
                raise SpecError("--workers", f"chunk {index[fut.key]} failed on the Dask workers: "
                                             f"{type(exc).__name__}: {exc}") from None
            yield index[fut.key], res
        _report_lost(client, workers_seen, note)
    finally:
        for f in [*futures, payload]:
            if f is not None:
                f.cancel()
        client.close()
        if cluster is not None:
            cluster.close()


def _stderr(line: str) -> None:
    print(line, file=sys.stderr, flush=True)


def _workers(client) -> set:
    try:
        return set(client.scheduler_info()["workers"])
    except Exception:  # noqa: BLE001  (the scheduler is going away: nothing more to learn)
        return set()


def _report_lost(client, seen: set, note) -> set:
    """Tell ``note`` of every worker that left since ``seen``; the workers now."""
    now = _workers(client)
    for addr in sorted(seen - now):
        note(f"sweep: worker {addr} lost; its chunk will be recomputed")
    return now | (seen & now)


def _token(plan: Plan) -> str:
    import hashlib

    return hashlib.sha256(json.dumps(_attrs(plan), sort_keys=True).encode()).hexdigest()[:16]


class _NoBar:
    def update(self, k):
        pass

    def close(self):
        pass


def _bar(total: int, initial: int, show: bool):
    if not show:
        return _NoBar()
    try:
        from tqdm import tqdm
    except ImportError:
        return _NoBar()
    return tqdm(total=total, initial=initial, unit="chunk", desc="sweep", file=sys.stderr, smoothing=0.1)


# --------------------------------------------------------------------------- reading
def spectrum_summary(store: str | Path, plan: Plan) -> str:
    """What the stored spectra say of their pairing (measures.pairing_summary)."""
    lam = np.asarray(read(store)["lyapunov_spectrum"]).reshape(-1, 2 * plan.n)
    return pairing_summary(lam, pipeline.derive(plan.spec, latex=False).integrals.energy_reasons, plan._has_energy())
