"""The one route from a spec to a compiled model: ``derive`` → ``render`` → ``compile``.

Every command that needs the model (generate, steady, sweep and its Dask workers, animate) and
the tests take this route, so a spec is derived (and its files printed) once per process and a
model's C is compiled once per user: ``compile`` keeps the extension in the user's private cache
folder (``cache_root``) under the build key (the C, header and cdef texts, the flags, the compiler
and the Python ABI; build.build_key), and a file lock lets one process build while the others wait
for it and load its build.

    model = pipeline.derive(spec)                      # assemble.Model: everything derived once
    files = pipeline.render(model, targets=("c",))    # {file name: text}, only what was asked
    cm = pipeline.compile(files, spec.name)            # build.CModel, built once per user
"""
from __future__ import annotations

import fcntl
import hashlib
import os
import shutil
import tempfile
import threading
from collections import OrderedDict
from pathlib import Path

from .. import DISTRIBUTION, printers
from ..derive import assemble, dynamics, integrals, kinematics, loopform
from . import build, selfcheck
from .files import folders_for
from ..chainspec.errors import SpecError
from ..derive.assemble import FormNotApplicable, Model, Stages  # noqa: F401  (the pipeline's vocabulary)
from ..derive.program import Program

C_FILES = (".c", ".h", ".cdef")  # what an extension is built from

_DERIVED: OrderedDict = OrderedDict()  # (spec text, forms) → Model, the last few derived
_DERIVED_MAX = 8
_RENDERED: OrderedDict = OrderedDict()  # (model, label, targets, real, options, paper) → its files, the last few
_LOCK = threading.Lock()
_REGULAR: set = set()  # the (spec text, values) whose mass matrix was found regular
_LOADED: dict = {}  # content hash of the sources → CModel (an extension loads once per process)


def derive(spec, qdd_form: str = "auto", der_form: str = "auto", latex: bool = True, progress=None,
           loops: str = "auto", regressor: bool = False, hessian: bool = False) -> Model:
    r"""Everything the printers need, derived once: kinematics (15)/(1)–(3), dynamics (17)–(19) or
    (8)–(10), the integrals (23), (27) and Jacobi's, the forms of $\ddot\varphi$ and of its derivatives chosen
    by op count, the quadratures (30) and Hamilton's variables where they exist, and (``latex``,
    general case only) the stages again with the platform's motion as symbols for the LaTeX.
    The same spec text and options give the same Model object within a process.  ``loops``: the
    loop form of long chains (loopform.py) by the number of joints ("auto"), or forced
    ("straight", "loops"; tests and benchmarks compare the two).  ``regressor``: also the
    regressor, the energy's and the base parameters (regressor.py, baseparams.py); ``hessian``: also
    the weighted second derivatives of $\ddot\varphi$ (hessian.py)."""
    key = (spec.source, qdd_form, der_form) + (() if loops == "auto" else (loops,)) + (("regressor",) if regressor else ())
    key += ("hessian",) if hessian else ()
    use_loops = loopform.uses_loops(spec.n, loops, armature=any(b.armature != 0 for b in spec.bodies))
    with _LOCK:
        found = _DERIVED.get(key)
    if found is not None:
        if latex and spec.general and found.symbolic is None:
            found = _remember(key, _with_symbolic(found))
        return found
    check_mass_matrix(spec)
    say = progress or (lambda msg: None)
    say(f"kinematics: direction cosines and angular velocities of {spec.n} bodies")
    prog = Program()  # the straight-line program every stage appends its named quantities to, in turn
    kin = kinematics.derive(spec, prog)
    say("dynamics: mass matrix and forces (recursions over the sub-chains p >= k)")
    dyn = dynamics.derive(spec, prog, kin, loops=use_loops)
    say("integrals: energy (23) and, where l1 may be vertical, momentum (27)")
    ints = integrals.derive(spec, prog, kin, dyn)
    model = assemble.build_model(spec, prog, kin, dyn, ints, progress=say, qdd_form=qdd_form, der_form=der_form,
                                 with_regressor=regressor, with_hessian=hessian)
    if latex and spec.general:
        say("the general case again with the platform's motion as symbols (for the LaTeX)")
        model = _with_symbolic(model)
    return _remember(key, model)


def check_mass_matrix(spec, tries: int = 3) -> None:
    """Refuse a chain whose mass matrix is singular in every configuration (a joint whose turning
    moves no mass: a point mass on its own joint axis, a rod along it); decided numerically at a
    few random configurations when the spec's numbers (or its [values]) are all known."""
    import numpy as np

    from ..derive import reference

    if len(spec.values) < len(spec.params):
        return
    key = (spec.source, tuple(sorted((str(k), str(v)) for k, v in spec.values.items())), tries)
    with _LOCK:
        if key in _REGULAR:  # generate checks before it derives, derive checks again: once is enough
            return
    ch = reference.numeric(spec, spec.values)
    rng = np.random.default_rng(0)
    for _ in range(tries):
        M = reference.mass_matrix(ch, rng.uniform(-np.pi, np.pi, spec.n))
        ev, vec = np.linalg.eigh((M + M.T) / 2)
        if ev[0] > 1e-12 * max(abs(ev[-1]), 1e-300):
            with _LOCK:
                _REGULAR.add(key)
            return
    k = int(np.argmax(np.abs(vec[:, 0]))) + 1
    raise SpecError(f"body[{k}]", f"the mass matrix is singular in every configuration: turning joint {k} moves no mass "
                                  f"(bodies {k}..{spec.n} have no inertia about its axis, e.g. a point mass on the axis)")


def forget() -> None:
    """Drop the derived models and the renderings this process keeps (the next derive derives
    anew, the next render prints anew)."""
    with _LOCK:
        _DERIVED.clear()
        _RENDERED.clear()


def _keep(table: OrderedDict, key, value):
    """``value`` kept under ``key`` as the newest of ``table``'s last few (_DERIVED_MAX)."""
    with _LOCK:
        table[key] = value
        table.move_to_end(key)
        while len(table) > _DERIVED_MAX:
            table.popitem(last=False)
    return value


def _remember(key, model: Model) -> Model:
    return _keep(_DERIVED, key, model)


def _with_symbolic(model: Model) -> Model:
    from dataclasses import replace

    prog = Program()
    kin = kinematics.derive(model.spec, prog, symbolic_platform=True)
    kin_defs = len(prog.defs)
    dyn = dynamics.derive(model.spec, prog, kin, loops=model.dyn.loops is not None)
    return replace(model, symbolic=Stages(kin, dyn, integrals.derive(model.spec, prog, kin, dyn), kin_defs))


def render(model: Model, spec_label: str | None = None, targets=printers.ALL, on_c=None, real: str = "double",
           options=(), paper: str = "a4") -> dict[str, str]:
    """The emitted files of the asked targets ("c", "python", "latex"), by file name; with all
    three also MANIFEST.json.  ``spec_label``: how the header names the spec (default NAME.toml);
    ``on_c``: called with the C files as soon as they are printed (``BuildAhead``); ``real``: the
    floating type of the C ("double", or "float": single precision); ``options``: the generate
    options besides ``real`` that made them (the headers' regenerate command); ``paper``: the LaTeX's
    page ("a4" or "letter").  The last few
    renderings are kept: the same model asked again with the same arguments gets a copy of its files."""
    if "latex" in targets and model.spec.general and model.symbolic is None:
        model = _with_symbolic(model)
    label = spec_label or f"{model.spec.name}.toml"
    # the model is kept with its files, so its id stays its own while they are kept
    key = (id(model), label, tuple(targets), real, tuple(options), paper)
    with _LOCK:
        found = _RENDERED.get(key)
    if found is not None:  # printing is a function of the model and these arguments
        _, files, c_files = found
        if on_c is not None and c_files:
            on_c(dict(c_files))
        return dict(files)
    c_files = {}

    def printed_c(printed: dict) -> None:  # kept, and handed on as soon as printed (BuildAhead)
        c_files.update(printed)
        if on_c is not None:
            on_c(printed)

    files = printers.render(model, label, targets, printed_c, real, options, compiled_templates(), paper)
    _keep(_RENDERED, key, (model, dict(files), c_files))
    return files


def derive_and_render(spec, spec_label: str | None = None, progress=None, qdd_form: str = "auto",
                      der_form: str = "auto", targets=printers.ALL, loops: str = "auto", on_c=None,
                      real: str = "double", regressor: bool = False, paper: str = "a4",
                      gpu: bool = False, casadi: bool = False, hessian: bool = False) -> tuple[dict[str, str], Model]:
    """``derive`` then ``render``: the files and the model (``gpu``: NAME_gpu.cu too; ``casadi``:
    NAME_casadi.c too, and the second derivatives it hands on; ``hessian``: those in NAME.c)."""
    targets = (*targets, "cuda") if gpu and "cuda" not in targets else targets
    targets = (*targets, "casadi") if casadi and "casadi" not in targets else targets
    hessian = hessian or "casadi" in targets
    model = derive(spec, qdd_form, der_form, latex="latex" in targets, progress=progress, loops=loops,
                   regressor=regressor, hessian=hessian)
    say = progress or (lambda msg: None)
    say("printing " + ", ".join({"c": "C", "cuda": "CUDA", "casadi": "CasADi", "python": "Python", "latex": "LaTeX"}[t]
                                for t in printers.TARGETS if t in targets))
    options = [*(("--qdd-form", qdd_form) if qdd_form != "auto" else ()),
               *(("--derivative-form", der_form) if der_form != "auto" else ()),
               *(("--regressor",) if regressor else ()),
               *(("--hessian",) if hessian and "casadi" not in targets else ()),
               *(("--gpu",) if "cuda" in targets else ()),
               *(("--casadi",) if "casadi" in targets else ()),
               *(("--paper", paper) if paper != "a4" else ())]
    return render(model, spec_label, targets, on_c, real, options, paper), model


# --------------------------------------------------------------------------- compile
def cache_root() -> Path:
    """Where compiled models are kept, private to the user: $GYROCHAIN_CACHE, else the user's own
    cache folder (platformdirs: $XDG_CACHE_HOME/gyrochain or ~/.cache/gyrochain on Linux,
    ~/Library/Caches/gyrochain on macOS), created with mode 0700.  An extension in it is loaded
    into this process, so a folder another user could have written is refused (``private``)."""
    given = os.environ.get("GYROCHAIN_CACHE")
    if given is not None and not given.strip():
        raise SpecError("$GYROCHAIN_CACHE", "is empty; unset it for the default cache folder, or name a folder")
    if given:
        root = Path(given).expanduser()
    else:
        import platformdirs

        root = Path(platformdirs.user_cache_dir(DISTRIBUTION, appauthor=False))
    what = f"$GYROCHAIN_CACHE {given}" if given else f"build cache {root}"
    try:
        root.mkdir(mode=0o700, parents=True, exist_ok=True)
        return private(root.resolve(strict=True), what)
    except OSError as exc:
        raise SpecError(what, f"cannot be used ({exc.strerror or exc})") from None


def compiled_templates() -> Path | None:
    """Where the printers keep their compiled templates for the next command (compiling
    model.c.jinja took half a second of every ``generate``): a folder in the build cache, private
    as the cache is.  None (each process compiles its own) when the cache cannot be used; a
    command that builds says why."""
    try:
        folder = cache_root() / "templates"
        folder.mkdir(mode=0o700, exist_ok=True)
        return private(folder, f"build cache {folder}")
    except (SpecError, OSError):
        return None


def private(folder: Path, what: str) -> Path:
    """``folder`` (resolved) if no other user can have written into it: it is a directory, owned
    by this user and writable only by them, and each folder above it is owned by this user or
    root and, if others may write there, sticky (as /tmp: nobody can rename another's entries).
    Otherwise one line: what and why (docs/testing.md, "The build cache")."""
    import stat

    if not hasattr(os, "getuid"):  # no POSIX owners to check (not a supported platform for builds)
        return folder
    me = os.getuid()
    st = os.stat(folder)
    if not stat.S_ISDIR(st.st_mode):
        raise SpecError(what, "is not a folder")
    if st.st_uid != me:
        raise SpecError(what, f"is owned by another user (uid {st.st_uid}); a compiled model loaded from it "
                              "could run their code: name a folder of yours in $GYROCHAIN_CACHE")
    if st.st_mode & 0o022:
        raise SpecError(what, f"is writable by {'group and others' if st.st_mode & 0o022 == 0o022 else 'group' if st.st_mode & 0o020 else 'others'} "
                              f"(mode {stat.S_IMODE(st.st_mode):04o}); a compiled model loaded from it could be anyone's: "
                              f"chmod 700 it, or name another folder in $GYROCHAIN_CACHE")
    for above in folder.parents:
        st = os.stat(above)
        if st.st_uid not in (0, me) or (st.st_mode & 0o022 and not st.st_mode & stat.S_ISVTX):
            raise SpecError(what, f"lies in {above}, which another user can change (owner uid {st.st_uid}, mode "
                                  f"{stat.S_IMODE(st.st_mode):04o}); name a folder of yours in $GYROCHAIN_CACHE")
    return folder


def _sources(files: dict[str, str]) -> dict[str, str]:
    return {k: v for k, v in files.items() if k.endswith(C_FILES)}


def extension(files: dict[str, str], name: str) -> tuple[Path, bool]:
    """The cached extension of these sources: (its path, whether it was built by this call).
    Built once per user: the first caller builds under the file lock, the others wait and
    find its build."""
    root = cache_root()
    staging = Path(tempfile.mkdtemp(prefix="stage-", dir=root))
    built = False
    try:
        for k, v in _sources(files).items():
            (staging / k).write_text(v, encoding="utf-8")
        key = build.build_key(staging, name)
        home = root / f"{name}-{key[:20]}"
        with open(root / f"{name}-{key[:20]}.lock", "w") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX)  # one builder; the others wait here and load its build
            found = build.extensions(home, name) if home.is_dir() else []
            if not found:
                build.compile_model(staging, name)
                shutil.rmtree(home, ignore_errors=True)
                staging.rename(home)
                staging, built = None, True
                found = build.extensions(home, name)
        return found[0], built
    finally:
        if staging is not None:
            shutil.rmtree(staging, ignore_errors=True)


class BuildAhead:
    """``render``'s ``on_c`` for ``generate``: compiles the model's extension into the cache in a
    child process while the Python and the LaTeX are printed (gcc runs beside them on the other
    core; n = 32: 0.7 s of the command, n = 128: 3 s).  A child process, not a thread: cffi's
    build changes the working folder of its process; forked, and so only from a process with no
    other thread (a fork copies no other thread and none of the locks they hold).  Nothing
    starts when the target folder's own extension is current (write_tree reuses it).  ``built()`` waits for the child: whether
    it compiled the extension; if it failed, write_tree builds again and reports the error."""

    def __init__(self, target: Path, name: str):
        self.target, self.name = Path(target), name
        self._pool = self._future = None

    def __call__(self, files: dict[str, str]) -> None:
        import concurrent.futures
        import multiprocessing

        sources = _sources(files)
        texts = [sources[f"{self.name}{s}"].encode("utf-8") for s in C_FILES]
        if (threading.active_count() > 1 or "fork" not in multiprocessing.get_all_start_methods()
                or (self.target.is_dir() and build.is_current(self.target, self.name, texts))):
            return
        self._pool = concurrent.futures.ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("fork"))
        self._future = self._pool.submit(extension, sources, self.name)

    def built(self) -> bool:
        if self._future is None:
            return False
        try:
            return self._future.result()[1]
        except Exception:  # noqa: BLE001  (write_tree's own build raises it again, in this process)
            return False
        finally:
            self.close()

    def close(self) -> None:
        if self._pool is not None:
            self._pool.shutdown(wait=True, cancel_futures=True)
            self._pool = None


def compile(files: dict[str, str], name: str) -> build.CModel:  # noqa: A001  (the pipeline's verb)
    """The compiled model of these sources (the C, header and cdef of ``files``; others are
    ignored), built once per user in the cache and loaded once per process."""
    return _loaded(files, name, lambda sources: extension(sources, name)[0])


def load_built(folder: Path, files: dict[str, str], name: str) -> build.CModel:
    """The extension of ``files`` that ``folder`` holds (write_tree's temporary folder, say),
    loaded once per process as ``compile`` loads it."""
    return _loaded(files, name, lambda sources: build.extensions(folder, name)[0])


def _loaded(files: dict[str, str], name: str, so_of) -> build.CModel:
    """The model of these sources loaded in this process (its content hash the key), else loaded
    from the extension ``so_of(sources)`` gives."""
    sources = _sources(files)
    memo = hashlib.sha256("\0".join(f"{k}\0{sources[k]}" for k in sorted(sources)).encode("utf-8")).hexdigest()
    with _LOCK:
        if memo in _LOADED:
            return _LOADED[memo]
    model = build.CModel(so_of(sources), name)
    with _LOCK:
        return _LOADED.setdefault(memo, model)


def compiled(spec, qdd_form: str = "auto", der_form: str = "auto", loops: str = "auto",
             regressor: bool = False, hessian: bool = False) -> tuple[build.CModel, Model]:
    """A parsed spec's compiled model and its derivation (without the LaTeX); with ``regressor``,
    the model with its regressor functions, with ``hessian`` with its second derivatives.  The model is held to the independent model once per
    process (``checked``): every command that runs a model runs a checked one."""
    files, model = derive_and_render(spec, targets=("c",), qdd_form=qdd_form, der_form=der_form, loops=loops,
                                     regressor=regressor, hessian=hessian)
    return checked(spec, compile(files, spec.name)), model


_CHECKED: dict = {}  # id of a compiled model (kept in _LOADED) → what the self-check compared


def checked(spec, cm: build.CModel) -> build.CModel:
    """``cm``, the compiled model of ``spec``, held to the independent model (selfcheck.py) the first
    time this process meets it; an EmittedModelError if they differ."""
    self_check(spec, cm)
    return cm


def self_check(spec, cm: build.CModel) -> dict[str, float]:
    """The functions of ``cm`` the self-check compared with the independent model of ``spec``,
    each with its margin (selfcheck.check), checked once per process."""
    with _LOCK:
        found = _CHECKED.get(id(cm))
    if found is None:
        found = selfcheck.check(spec, cm, "C")
        with _LOCK:
            _CHECKED[id(cm)] = found
    return found


# --------------------------------------------------------------------------- write
def is_ours(directory: Path) -> bool:
    """A folder we may replace: missing, empty, or written by this generator (it has our MANIFEST.json)."""
    import json

    if not directory.exists():
        return True
    if not directory.is_dir():
        return False
    if not any(directory.iterdir()):
        return True
    try:
        return "spec_sha256" in json.loads((directory / "MANIFEST.json").read_text())
    except (OSError, ValueError):
        return False


def ours_in(directory: Path, name: str) -> set[str]:
    """The files of ``directory`` that gyrochain wrote: those its MANIFEST.json lists, the
    manifest itself, and the model's compiled extension with its key file."""
    import json

    found = set()
    try:
        found |= set(json.loads((directory / "MANIFEST.json").read_text()).get("files", {})) | {"MANIFEST.json"}
    except (OSError, ValueError, AttributeError):
        pass
    found |= {p.name for p in build.extensions(directory, name)}
    found |= {build.key_path(directory, name).name} if build.key_path(directory, name).exists() else set()
    return {f for f in found if "/" not in f and f not in (".", "..")}


def umask_mode(mode: int = 0o777) -> int:
    """``mode`` less the process's umask: how the user's own tools would create the file or folder."""
    mask = os.umask(0)
    os.umask(mask)
    return mode & ~mask


def write_tree(files: dict[str, str], target: Path, build_it: bool, name: str, ahead: BuildAhead | None = None,
               verify=None) -> str | None:
    """Write every file into a temporary folder beside ``target`` with its extension, then move
    them into ``target`` one by one (a rename each: no file is ever half-written) and remove the
    files of the previous generation that are no longer produced.  Nothing else in ``target`` is
    touched: a file gyrochain did not write (a build folder, notes) stays.  Folders and files get
    the user's umask.  The extension is the folder's own when it was built from the same C,
    header and cdef with the same flags and compiler (build.build_key), else the model cache's
    (``extension``: compiled now only if no process built it before, ``ahead``'s child included):
    returns "compiled", "reused" or None (no build).  ``verify``: called with the temporary folder once
    every file and the extension are there, before anything moves into ``target``; what it raises
    leaves ``target`` as it was."""
    target = Path(target)
    with folders_for(target):  # an interrupted first run leaves no empty generated/
        made = not target.exists()
        tmp = Path(tempfile.mkdtemp(prefix=f".{target.name}.tmp-", dir=target.parent))
        how = None
        try:
            for rel, text in sorted(files.items()):
                with open(tmp / rel, "w", encoding="utf-8", newline="\n") as fh:
                    fh.write(text)
            if build_it:  # the folder's own extension if it is current, else the cache's (built now if need be)
                if target.is_dir() and build.reuse_extension(target, tmp, name):
                    how = "reused"
                else:
                    built_ahead = ahead is not None and ahead.built()
                    so, built = extension(files, name)
                    built = built or built_ahead
                    shutil.copy2(so, tmp / so.name)
                    build.key_path(tmp, name).write_text(build.build_key(tmp, name) + "\n")
                    how = "compiled" if built else "reused"
            if verify is not None:
                verify(tmp)
            file_mode = umask_mode(0o666)
            for f in tmp.iterdir():
                os.chmod(f, file_mode | (0o111 & umask_mode() if f.suffix == ".so" else 0))
            if made:
                target.mkdir(mode=umask_mode())
            stale = ours_in(target, name) - {f.name for f in tmp.iterdir()}
            for f in sorted(tmp.iterdir(), key=lambda f: f.name == "MANIFEST.json"):  # the manifest last
                f.replace(target / f.name)
            for rel in sorted(stale):
                (target / rel).unlink(missing_ok=True)
        except BaseException:
            if made and target.exists():
                shutil.rmtree(target, ignore_errors=True)  # only what this call put there
            raise
        finally:
            shutil.rmtree(tmp, ignore_errors=True)
    return how
