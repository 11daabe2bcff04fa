"""A sweep's Zarr store: its layout (one array per measure, the exit codes, the chunks done), the
CRC-32C of every chunk, the chunks found damaged, and reading it back with what is missing said.
sweep.py computes the chunks; this module is all that touches the files."""
from __future__ import annotations

import json
import os
import shutil
import sys
from pathlib import Path

import numpy as np

from .. import __version__
from ..chainspec.errors import SpecError
from ..models.files import folders_for, writable

STORE_KIND = "gyrochain-sweep"
EXTRA_DIM = {"final": "state", "lyapunov_spectrum": "exponent"}  # measures with a trailing dimension


def _stderr(line: str) -> None:
    print(line, file=sys.stderr, flush=True)


def _zarr():
    try:
        import zarr
    except ImportError:
        raise SpecError("sweep", "needs the sweep extra: pip install 'gyrochain[sweep]' (dask, distributed, zarr, tqdm)") from None
    return zarr


def _attrs(plan) -> dict:
    return {"kind": STORE_KIND, "gyrochain": __version__, "spec_name": plan.spec.name, "spec": plan.sweep.spec_text,
            "args": json.loads(json.dumps(plan.sweep.args())), "shape": list(plan.shape), "dims": plan.dims,
            "flip_angles": plan.angles, "link_signs": plan.signs}


def stored_attrs(path: str | Path) -> dict | None:
    """The sweep attributes of the store at ``path``, or None if it is not a sweep store."""
    try:
        return dict(_zarr().open_group(str(path), mode="r").attrs).get("gyrochain_sweep")
    except Exception:
        return None


def check_store(path: Path, plan) -> None:
    """A one-line error unless ``path`` is free or a store of this spec and sweep (reads only), in
    a folder this user may write in."""
    want = _attrs(plan)
    if path.exists():
        have = stored_attrs(path)
        if have is None:
            raise SpecError("-o", f"{path} exists and is not a sweep store; choose another path")
        for key in ("spec", "args", "gyrochain"):
            if have.get(key) != want[key]:
                what = {"spec": "a different spec", "args": "a different sweep (other arguments)", "gyrochain": f"gyrochain {have.get('gyrochain')}"}[key]
                raise SpecError("-o", f"{path} belongs to {what}; choose another path or delete it")
    writable(path / "x" if path.is_dir() else path)


def open_store(path: Path, plan):
    """Create the store, or open an existing one of the same spec and sweep (else a one-line
    error, the store untouched)."""
    zarr = _zarr()
    check_store(path, plan)
    want = _attrs(plan)
    if path.exists():
        for junk in path.rglob("*.partial"):  # a write an interruption cut short
            junk.unlink(missing_ok=True)
        g = zarr.open_group(str(path), mode="r+")
        for name, (_dims, values) in plan.coords.items():  # the coordinates follow from the plan: rewritten, so repaired
            g[name][...] = values
        return g
    # built beside its place and renamed into it: a run killed now leaves no half-made store
    tmp = path.parent / f".{path.name}.tmp-{os.getpid()}"
    shutil.rmtree(tmp, ignore_errors=True)
    with folders_for(path):
        try:
            _make(zarr, tmp, plan, want)
            tmp.rename(path)
        finally:  # Ctrl-C or an error while it is made: nothing half-made stays beside it
            shutil.rmtree(tmp, ignore_errors=True)
    return zarr.open_group(str(path), mode="r+")


def _make(zarr, folder: Path, plan, attrs: dict) -> None:
    """A new, empty store of ``plan`` in ``folder``: the coordinates written, every measure's array
    and the codes at their fill values, no chunk done."""
    g = zarr.open_group(str(folder), mode="w")
    chunks = (plan.rows,) + tuple(plan.shape[1:])
    checked = _checksummed(zarr)  # every chunk carries its CRC-32C: a damaged one is found when read
    for name, (dims, values) in plan.coords.items():
        a = g.create_array(name, shape=values.shape, dtype="f8", dimension_names=dims, chunks=values.shape,
                           compressors=checked)
        a[...] = values
    for m in plan.sweep.measures:
        extra = (2 * plan.n,) if m in EXTRA_DIM else ()
        g.create_array(m, shape=plan.shape + extra, chunks=chunks + extra, dtype="f8", fill_value=np.nan,
                       dimension_names=plan.dims + ([EXTRA_DIM[m]] if extra else []), compressors=checked)
    g.create_array("code", shape=plan.shape, chunks=chunks, dtype="i4", fill_value=-1, dimension_names=plan.dims,
                   compressors=checked)
    g.create_array("done", shape=(plan.n_chunks,), chunks=(1,), dtype="bool", fill_value=False, dimension_names=["chunk"],
                   compressors=checked)
    g.attrs["gyrochain_sweep"] = attrs


def _checksummed(zarr) -> list:
    """The byte codecs of every stored array: Zarr's default compression, then a CRC-32C of the
    chunk (Zarr v3's crc32c codec), so that a chunk cut short or changed on disk fails to read."""
    from zarr.codecs import Crc32cCodec, ZstdCodec

    return [ZstdCodec(), Crc32cCodec()]


def files_present(g, keys, i: int) -> bool:
    """Whether every array in ``keys`` has its chunk ``i`` on disk (a folder store: the file
    c/i/0/…, Zarr v3's default key encoding); True for a store that is not a folder."""
    root = getattr(g.store, "root", None)
    if root is None:
        return True
    return all((Path(root) / g.path / k / "c" / str(i) / "/".join("0" * (g[k].ndim - 1))).is_file() for k in keys)


def chunk_intact(g, keys, i: int, rows: int) -> bool:
    """Whether chunk ``i`` (rows i·rows …) of every array in ``keys`` and its done flag are there and
    read back: a chunk file gone (it would read as the fill value, a "no flip"), a checksum that
    does not match, or a file cut short is a damaged chunk."""
    if not files_present(g, keys, i):
        return False
    try:
        for k in keys:
            np.asarray(g[k][i * rows:(i + 1) * rows])
        np.asarray(g["done"][i])
        return True
    except Exception:  # noqa: BLE001  (the codecs' errors for a damaged chunk: ValueError, RuntimeError, ...)
        return False


def _done_flags(g, plan, note) -> np.ndarray:
    """The chunks finished and intact; a damaged one is said and computed again (its flag cleared)."""
    keys = [*plan.sweep.measures, "code"]
    done = np.zeros(plan.n_chunks, bool)
    for i in range(plan.n_chunks):
        try:
            flag = bool(g["done"][i])
        except Exception:  # noqa: BLE001  (its flag itself damaged)
            flag = True
        if flag and not chunk_intact(g, keys, i, plan.rows):
            (note or _stderr)(f"chunk {i} of the store is damaged (a file missing, cut short or not matching its "
                              "checksum): computing it again")
            for k in keys:
                _rewrite_missing(g, k, i, plan.rows)
            g["done"][i] = False
            flag = False
        done[i] = flag
    return done


def _rewrite_missing(g, key: str, i: int, rows: int) -> None:
    """Chunk ``i`` of array ``key`` back to its fill value (its damaged file replaced)."""
    a = g[key]
    r1 = min((i + 1) * rows, a.shape[0])
    a[i * rows:r1] = np.full((r1 - i * rows,) + a.shape[1:], a.fill_value, dtype=a.dtype)


def _write(g, plan, i: int, res: dict, on_written=None) -> None:
    """Chunk i's results, then its done flag; every chunk a file even when it is all NaN (Zarr
    leaves out a chunk equal to the fill value unless told), so a missing file is a lost chunk."""
    zarr = _zarr()
    r0, r1 = plan.chunk_rows(i)
    with zarr.config.set({"array.write_empty_chunks": True}):
        for k, v in res.items():
            g[k][r0:r1] = v
        g["done"][i] = True  # after the data: a chunk cut short is computed again
    if on_written is not None:
        on_written(i)


def _readable(g) -> bool:
    try:
        np.asarray(g["done"][:])
        return True
    except Exception:  # noqa: BLE001
        return False


def _flag(g, i: int) -> bool:
    """Chunk i's done flag; a flag that does not read back counts as set (its chunk is then checked)."""
    try:
        return bool(g["done"][i])
    except Exception:  # noqa: BLE001
        return True


def read(store: str | Path) -> dict:
    """The store as numpy arrays: {"attrs", "coords": {name: values}, measure: array, "code", "done"}."""
    zarr = _zarr()
    g = zarr.open_group(str(store), mode="r")
    attrs = dict(g.attrs).get("gyrochain_sweep")
    if attrs is None:
        raise SpecError("store", f"{store} is not a sweep store")
    out = {"attrs": attrs, "coords": {}}
    varied = [v[0] for v in attrs["args"]["vary"]]
    shape = tuple(attrs["shape"])
    rows = g["code"].chunks[0]
    n_chunks = -(-shape[0] // rows)
    keys = [k for k in sorted(g.array_keys()) if k not in varied and k != "done"]
    try:  # the whole arrays at once; a chunk that fails its checksum, or is gone, sends us chunk by chunk
        for k in [*keys, "done"]:
            np.asarray(g[k][...])
        flags = np.asarray(g["done"][...])
        if not all(files_present(g, keys, i) for i in range(n_chunks) if flags[i]):
            raise ValueError("a chunk marked done is not on disk")
        damaged = []
    except Exception:  # noqa: BLE001
        damaged = [i for i in range(n_chunks) if _flag(g, i) and not chunk_intact(g, keys, i, rows)]
    for key in sorted(g.array_keys()):
        if key in varied:
            try:
                out["coords"][key] = np.asarray(g[key][...])
            except Exception:  # noqa: BLE001  (the codecs' errors for a damaged chunk)
                raise SpecError("store", f"{store}: the coordinates {key} are damaged; run the same sweep again, "
                                         "which writes them anew") from None
        elif key == "done":
            out[key] = (np.asarray(g[key][...]) if not damaged else
                        np.array([bool(g[key][i]) if i not in damaged else False for i in range(n_chunks)]))
        elif not damaged:
            out[key] = np.asarray(g[key][...])
        else:
            a = g[key]
            arr = np.full(a.shape, a.fill_value, dtype=a.dtype)
            for i in range(n_chunks):
                if i not in damaged:
                    arr[i * rows:(i + 1) * rows] = g[key][i * rows:(i + 1) * rows]
            out[key] = arr
    computed = np.repeat(out["done"], rows)[: shape[0]]
    out["computed"] = np.broadcast_to(computed.reshape((shape[0],) + (1,) * (len(shape) - 1)), shape).copy()
    out["damaged"] = np.array(damaged, dtype=np.int64)  # the chunks whose checksum did not match
    return out
