"""``python -m gyrochain animate``: the motion of a spec as a GIF, MP4, PNG still or one offline HTML viewer.

    trajectory  the emitted C's DOP853 with dense output at the frame times (``motion``), or a
                saved trajectory: a CSV as ``simulate`` prints it (``read_csv``) or a point of a
                sweep store (``sweep_point``)
    scene       the spec's geometry at every frame (``scene.build``)
    picture     ``raster.Raster`` paints the primitives with Pillow (2× supersampled), ``write_gif`` /
                ``write_mp4`` / ``write_png`` encode; ``write_html`` puts the primitives, the
                viewer's script (templates/viewer.js) and the integral's curve in one file

Every output is written beside its place and renamed into it: a failed run leaves no partial file.
An existing file is replaced only if this command wrote it (its bytes carry MARKER) or with --force.
"""
from __future__ import annotations

import json
import math
import os
import shutil
import subprocess
from pathlib import Path

import numpy as np

from .. import TEMPLATES, __version__
from ..models import files
from .raster import Raster, _rgb  # the painter (animate.Raster, as before)
from .scene import FRAME_COLOUR, PLATFORM_COLOUR, TRACE_COLOUR, Camera, Scene
from ..chainspec.spec import SpecError

MARKER = "gyrochain animate"
EXTENSIONS = (".gif", ".mp4", ".html", ".png")


# --------------------------------------------------------------------------- trajectories
MAX_FRAMES = 10_000  # frames of one animation past which animate asks for --yes (a GIF of 480 x 480: ~2 GB of pixels)


def frame_times(t1: float, fps: float, frame: float | None, sub: int = 1, yes: bool = False) -> np.ndarray:
    """The output times: 0, 1/fps, … ≤ t1, or the single time ``frame`` (a still); with sub > 1,
    ``sub`` times per frame interval (the frames are every sub-th).  More than MAX_FRAMES frames
    are refused unless ``yes``."""
    if not (math.isfinite(fps) and fps > 0):
        raise SpecError("--fps", f"{float(fps):g}: must be a positive number")
    if frame is not None:
        if not (math.isfinite(frame) and frame >= 0):
            raise SpecError("--frame", f"{float(frame):g}: must be a time >= 0")
        return np.array([frame])
    if not (math.isfinite(t1) and t1 > 0):
        raise SpecError("--t1", f"{float(t1):g}: the time range [0, t1] needs t1 > 0")
    count = int(math.floor(t1 * fps + 1e-9)) + 1
    if count < 2:
        raise SpecError("--t1", f"[0, {t1:g}] s at {fps:g} frames/s holds a single frame; make t1 >= {1 / fps:g} s or raise --fps")
    if count > MAX_FRAMES and not yes:
        raise SpecError("--t1" if t1 * 25.0 > MAX_FRAMES else "--fps",
                        f"{t1:g} s at {fps:g} frames/s is {count} frames (more than {MAX_FRAMES}); a shorter --t1, a lower "
                        "--fps, or --yes to draw them all")
    return np.arange((count - 1) * sub + 1) / (fps * sub)


def read_csv(path: str, n: int, fps: float, frame: float | None) -> tuple:
    """A saved trajectory (columns t, phi1…phin and optionally phidot1…phidotn, as ``simulate``
    prints it), at the frame times over the file's span (or at ``frame``): φ linear between the
    rows, φ̇ the file's or 0.  Returns the times, the states, whether φ̇ was given, and the file's
    own times and states (for the trace)."""
    names, data = files.read_table(path, "--trajectory", ["t"] + [f"phi{k}" for k in range(1, n + 1)],
                                   f"t, phi1..phi{n}[, phidot1..phidot{n}], as simulate writes it")
    ft = data[:, names.index("t")]
    if frame is not None:
        frame_times(0.0, fps, frame)
        if not ft[0] <= frame <= ft[-1]:
            raise SpecError("--frame", f"{frame:g} s is outside the trajectory's [{ft[0]:g}, {ft[-1]:g}] s")
        t = np.array([frame])
    else:
        t = ft[0] + frame_times(ft[-1] - ft[0], fps, None)
    has_rate = all(f"phidot{k}" in names for k in range(1, n + 1))
    cols = [names.index(f"phi{k}") for k in range(1, n + 1)]
    cols += [names.index(f"phidot{k}") for k in range(1, n + 1)] if has_rate else []
    X = np.zeros((len(t), 2 * n))
    rows = np.zeros((len(ft), 2 * n))
    for j, c in enumerate(cols):
        X[:, j] = np.interp(t, ft, data[:, c])
        rows[:, j] = data[:, c]
    return t, X, has_rate, ft, rows


def integral_curve(model, derived, X, times, u, params) -> dict | None:
    """The curve under the HTML scene: the first integral that exists (energy (23), else the
    Jacobi integral, else the momentum (27)), or the energy where none does.  A control torque
    held at zero does no work: with it the integrals it would remove still hold."""
    ints = derived.integrals
    kw = dict(params=params)
    idle = u is None or not np.any(np.asarray(u) != 0)  # the control torques do no work
    energy = all(r.startswith("control") and idle for r in ints.energy_reasons)
    momentum = model.has_momentum and (ints.has_momentum_integral or (
        ints.momentum_condition is None and bool(ints.momentum_reasons)
        and all(r == "control torque in joint 1" and idle for r in ints.momentum_reasons)))
    unit, conserved = "J", True
    if energy:
        label, f = "energy T − U (23), an integral", lambda x, t: model.energy(x, t=t, **kw)
    elif model.has_jacobi:
        label, f = "Jacobi integral, conserved", lambda x, t: model.jacobi(x, **kw)
    elif momentum:
        label, f, unit = "momentum (27), an integral", lambda x, t: model.momentum(x, t=t, **kw), "kg m²/s"
    else:
        label, f = "energy T − U (23), not an integral here", lambda x, t: model.energy(x, t=t, **kw)
        conserved = False
    return {"label": label, "unit": unit, "conserved": conserved,
            "values": [float(f(np.asarray(x, float), float(t))) for x, t in zip(X, times)]}


# --------------------------------------------------------------------------- writing
class Output:
    """A file written beside its place (``tmp``) and renamed into it when the ``with`` block ends
    without an error; removed when it ends with one."""

    def __init__(self, path: str | Path, force: bool = False):
        self.path = Path(path)
        ext = self.path.suffix.lower()
        if ext not in EXTENSIONS:
            raise SpecError("-o", f"unknown extension {self.path.suffix or '(none)'!r} of {self.path.name} (one of {', '.join(EXTENSIONS)})")
        self.ext = ext
        if self.path.is_dir():
            raise SpecError("-o", f"{self.path} is a folder")
        if self.path.exists() and not force and not is_ours(self.path):
            raise SpecError("-o", f"{self.path} exists and was not written by animate; choose another path or give --force")
        files.writable(self.path)
        self.tmp = self.path.parent / f".{self.path.stem}.tmp-{os.getpid()}{ext}"

    def __enter__(self):
        self.path.parent.mkdir(parents=True, exist_ok=True)
        return self

    def __exit__(self, exc_type, exc, tb):
        if exc_type is None:
            os.replace(self.tmp, self.path)
        else:
            self.tmp.unlink(missing_ok=True)
        return False


def is_ours(path: Path) -> bool:
    try:
        with open(path, "rb") as f:
            return MARKER.encode() in f.read()
    except OSError:
        return False


def write_png(raster: Raster, path: Path) -> None:
    from PIL.PngImagePlugin import PngInfo

    info = PngInfo()
    info.add_text("Software", f"{MARKER} {__version__}")
    raster.frame(0).save(path, format="PNG", pnginfo=info, optimize=True)


def write_gif(raster: Raster, path: Path, fps: float) -> None:
    Image = raster.Image
    frames = [raster.frame(i) for i in range(len(raster.scene.times))]
    # one palette for all frames (from a sample of them): no flicker between frames' palettes
    sample = frames[:: max(1, len(frames) // 8)][:8]
    strip = Image.new("RGB", (raster.W, raster.H * len(sample)))
    for j, f in enumerate(sample):
        strip.paste(f, (0, raster.H * j))
    # a median cut averages colours: the scene's own colours are added exactly (white stays white)
    own = [Raster.BACKGROUND, (30, 30, 30), (40, 40, 40), (60, 60, 60), (85, 85, 85)] + [_rgb(c) for c in dict.fromkeys(raster.scene.colours + [FRAME_COLOUR, TRACE_COLOUR, PLATFORM_COLOUR])]
    cut = strip.quantize(colors=256 - len(own), method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE)
    got = cut.getpalette() or []  # fewer entries than asked where the frames have few colours
    entries = [tuple(c) for c in own] + [tuple(got[3 * i:3 * i + 3]) for i in range(min(len(got) // 3, 256 - len(own)))]
    entries += [entries[0]] * (256 - len(entries))
    palette = np.array(entries, dtype=np.int64)
    flat = [v for c in entries for v in c]
    lut = np.zeros(1 << 24, dtype=np.uint8)  # RGB → palette index, filled for the colours met
    seen = np.zeros(1 << 24, dtype=bool)
    q = []
    for f in frames:  # each pixel to its nearest palette colour (exact where the colour is in it)
        a = np.asarray(f, dtype=np.int32)
        key = (a[..., 0] << 16) | (a[..., 1] << 8) | a[..., 2]
        new = np.unique(key[~seen[key]])
        if len(new):
            cols = np.stack([new >> 16, (new >> 8) & 255, new & 255], axis=1).astype(np.int64)
            lut[new] = np.argmin(((cols[:, None, :] - palette[None, :, :]) ** 2).sum(axis=2), axis=1)
            seen[new] = True
        img = Image.fromarray(lut[key], mode="P")
        img.putpalette(flat)
        q.append(img)
    q[0].save(path, format="GIF", save_all=True, append_images=q[1:], duration=round(1000 / fps), loop=0,
              comment=f"{MARKER} {__version__}".encode(), optimize=False, disposal=1)


def write_mp4(raster: Raster, path: Path, fps: float) -> None:
    exe = shutil.which("ffmpeg")
    if exe is None:
        raise SpecError("-o", ".mp4 needs ffmpeg on PATH (apt-get install ffmpeg); write .gif or .html instead")
    W, H = raster.W, raster.H
    cmd = [exe, "-loglevel", "error", "-y", "-f", "rawvideo", "-pix_fmt", "rgb24", "-s", f"{W}x{H}", "-r", f"{fps:g}",
           "-i", "-", "-c:v", "libx264", "-pix_fmt", "yuv420p", "-movflags", "+faststart", "-metadata",
           f"comment={MARKER} {__version__}", "-f", "mp4", str(path)]
    proc = subprocess.Popen(cmd, stdin=subprocess.PIPE, stderr=subprocess.PIPE)
    try:
        for i in range(len(raster.scene.times)):
            proc.stdin.write(raster.frame(i).tobytes())
        proc.stdin.close()
        err = proc.stderr.read().decode(errors="replace").strip()
        if proc.wait(timeout=120) != 0:
            raise SpecError("-o", f"ffmpeg failed: {err.splitlines()[-1] if err else proc.returncode}")
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()


# --------------------------------------------------------------------------- the HTML viewer
def _num(x) -> float:
    """A coordinate for the page: 6 significant digits (the page is a picture, not data)."""
    return float(f"{float(x):.6g}")


def _prim_json(prim) -> list:
    out = [prim[0]]
    for a in prim[1:]:
        if isinstance(a, str):
            out.append(a)
        elif np.ndim(a) == 0:
            out.append(_num(a))
        else:
            out.append([_num(v) for v in a])
    return out


def _hull(P: np.ndarray) -> np.ndarray:
    """The vertices of the key points' convex hull: their projection's bounding box is that of all
    the points, for every camera, in a few hundred points instead of thousands."""
    from scipy.spatial import ConvexHull, QhullError

    try:
        return P[ConvexHull(P, qhull_options="QJ").vertices]
    except (QhullError, ValueError):  # too few points
        return P


def scene_json(scene: Scene, camera: Camera) -> str:
    P = scene.points
    lo, hi = P.min(axis=0), P.max(axis=0)
    centre = (lo + hi) / 2
    data = {
        "name": scene.name,
        "times": [_num(t) for t in scene.times],
        "static": [_prim_json(p) for p in scene.static],
        "frames": [[_prim_json(p) for p in fr] for fr in scene.frames],
        "tipTimes": [_num(t) for t in scene.tip_times],
        "tips": [[_num(v) for v in p] for p in scene.tips],
        "trace": scene.trace,
        "traceColour": TRACE_COLOUR,
        "frameColour": FRAME_COLOUR,
        "platformColour": PLATFORM_COLOUR,
        "bodyColours": scene.colours,
        "gravity": scene.gravity,
        "centre": [_num(v) for v in centre],
        "radius": _num(float(np.max(np.linalg.norm(P - centre, axis=1))) or 1.0),
        "hull": [[_num(v) for v in p] for p in _hull(P)],  # the page fits these, as the raster fits all
        "camera": {"az": camera.az, "el": camera.el},
        "integral": scene.integral,
        "legend": scene.legend,
        "caption": scene.caption,
        "states": None if scene.states is None else [[_num(v) for v in x] for x in scene.states],
    }
    # JSON inside <script>: no "</" may close the element early
    return json.dumps(data, separators=(",", ":"), ensure_ascii=False, allow_nan=False).replace("</", "<\\/")


def write_html(scene: Scene, camera: Camera, path: Path, description: str) -> None:
    import jinja2
    from markupsafe import Markup

    env = jinja2.Environment(loader=jinja2.FileSystemLoader(str(TEMPLATES)), autoescape=True, undefined=jinja2.StrictUndefined,
                             keep_trailing_newline=True)
    script = (TEMPLATES / "viewer.js").read_text(encoding="utf-8")
    html = env.get_template("viewer.html.jinja").render(
        name=scene.name, description=description, marker=f"{MARKER} {__version__}",
        data=Markup(scene_json(scene, camera)), script=Markup(script))
    path.write_text(html, encoding="utf-8")


# --------------------------------------------------------------------------- the command
def _motion_of(source, phi, phidot, u, params, t1, at) -> tuple:
    """(spec, x₀, u, parameters, t1, description, note) of a spec (path or parsed) or a store's point
    (the note says when --at was not a grid point)."""
    from ..ensembles import sweep
    from ..chainspec.physical import run_values
    from ..analysis.simulate import initial_state, torques
    from ..chainspec.spec import load_spec, parse_spec

    if isinstance(source, (str, Path)) and Path(source).is_dir():  # a sweep store: its spec, state, parameters
        if phi is not None or phidot is not None or params or u is not None:
            raise SpecError("--at", "the state, parameters and torques come from the sweep's point; drop --phi/--phidot/--param/--u")
        pt = sweep_point(source, at)
        spec = parse_spec(pt["spec_text"])
        description = f"{spec.description} (sweep {Path(source).name}: {pt['label']})"
        return spec, list(pt["x0"]), pt["u"] or None, pt["params"], t1 if t1 is not None else pt["t1"], description, pt["note"]
    spec = load_spec(source) if isinstance(source, (str, Path)) else source
    if at:
        raise SpecError("--at", "a point of a sweep: give the sweep's store as SPEC")
    x0 = initial_state(spec, phi, phidot)
    return spec, x0, torques(spec, u), run_values(spec, params), t1 if t1 is not None else 10.0, spec.description, ""


def _still(spec, X: np.ndarray, phi, phidot, at: str) -> bool:
    """No state given, none in the spec, and the motion from φ = 0 at rest stays there."""
    if phi is not None or phidot is not None or at or spec.initial:
        return False
    return bool(np.all(np.isfinite(X))) and float(np.max(np.abs(X - X[:1]))) < 1e-9


def fast_base(spec, ch, times) -> float:
    """The frequency (Hz) of the platform's translation where it is faster than half the frame rate
    of ``times`` (frames would sample it with aliasing: Kapitza's 41 Hz pivot at 25 frames/s), else 0.
    Judged on 16 samples per frame: fast when O¹ sweeps most of its range within a frame."""
    from ..derive import reference

    if spec.base is None or len(times) < 2:
        return 0.0
    t = np.linspace(times[0], times[-1], 16 * (len(times) - 1) + 1)
    r0 = np.array([reference.platform(ch, float(x))[3] for x in t], float)
    span = float(np.max(np.ptp(r0, axis=0)))
    if span <= 0:
        return 0.0
    within = np.ptp(r0[:-1].reshape(len(times) - 1, 16, 3), axis=1).max(axis=1)
    if float(np.median(within)) < 0.5 * span:
        return 0.0
    d = (r0 - r0.mean(axis=0)) @ np.linalg.svd(r0 - r0.mean(axis=0), full_matrices=False)[2][0]  # the main direction
    crossings = int(np.sum(np.signbit(d[1:]) != np.signbit(d[:-1])))
    return crossings / (2.0 * (t[-1] - t[0]))


def _follows(spec, ch, times) -> tuple[bool, str]:
    """Whether the camera follows the platform's O¹ by default: where O¹ moves farther than the
    chain reaches, the world view would show a small chain drifting; and the line that says so."""
    from ..derive import reference
    from . import scene

    if spec.base is None:
        return False, ""
    r0 = np.array([reference.platform(ch, float(t))[3] for t in times[:: max(1, len(times) // 400)]], float)
    excursion = float(np.max(np.linalg.norm(r0 - r0[:1], axis=1)))
    reach = scene.Geometry(ch).size
    if excursion <= reach:
        return False, ""
    return True, (f"the camera follows the platform's O1 (it moves {excursion:.3g} m, the chain reaches "
                  f"{reach:.3g} m; --no-follow for the world view)")


def render(source, output, *, phi=None, phidot=None, u=None, params=None, t1=None, fps: float = 25.0,
           frame: float | None = None, at: str = "", trajectory: str = "", size=(480, 480), view=None,
           trace: float = 2.0, follow: bool | None = None, rtol: float = 1e-10, force: bool = False, yes: bool = False) -> dict:
    """The motion of a spec (a path or a parsed spec) or of a sweep store's point (``at``) as
    ``output`` (.gif, .mp4, .html, or a .png still at ``frame``).  ``view``: (azimuth, elevation)
    in degrees, default fitted to the motion.  ``follow`` None: the camera follows the platform's
    O¹ where it moves farther than the chain reaches.  A spec without [initial] that would stand
    still at φ = 0 is given a small push (0.2 rad in every joint), and the note says so.  Returns
    the path, the frame times, the size and the note (what was chosen for the user)."""
    from ..models import pipeline
    from ..derive import reference
    from . import scene
    from ..analysis.simulate import motion

    out = Output(output, force=force)  # the extension and an existing file first
    if out.ext == ".png" and frame is None:
        raise SpecError("--frame", "a .png is one still: give --frame T (seconds)")
    spec, x0, u, params, t1, description, note = _motion_of(source, phi, phidot, u, params, t1, at)
    try:
        ch = reference.numeric(spec, params)
    except ValueError as exc:
        raise SpecError("--param", str(exc)) from None
    if not (trace >= 0 and math.isfinite(trace)):
        raise SpecError("--trace", "must be a number of seconds >= 0")
    sub = 4  # the trace is sampled 4 times per frame: smooth where the tip moves fast
    if trajectory:
        times, X, has_rate, fine, fine_X = read_csv(trajectory, spec.n, fps, frame)
    elif frame is not None:
        times, has_rate = frame_times(t1, fps, frame), True
        fine = np.unique(np.concatenate([np.linspace(max(0.0, frame - trace), frame, 100), times]))
    else:
        fine, has_rate = frame_times(t1, fps, None, sub, yes), True
        times = fine[::sub]
    model, derived = pipeline.compiled(spec)
    if follow and spec.base is None:
        raise SpecError("--follow", "the spec has no [base]: there is no platform to follow")
    if not trajectory:
        fine_X = motion(model, fine, x0, u=u, params=params or None, rtol=rtol, atol=rtol * 1e-2)
        if _still(spec, fine_X, phi, phidot, at):
            x0 = [0.2] * spec.n + [0.0] * spec.n
            note = (f"the spec has no [initial] and stays at rest at phi = 0: drawing the motion from phi = "
                    f"{', '.join(['0.2'] * spec.n)} (give --phi/--phidot to choose)")
            fine_X = motion(model, fine, x0, u=u, params=params or None, rtol=rtol, atol=rtol * 1e-2)
        X = fine_X[np.searchsorted(fine, times)]
    fast = fast_base(spec, ch, times) if not trajectory and frame is None else 0.0
    if fast and follow is None:  # drawn relative to the pivot, the integral sampled finely enough
        follow = True
        note = "\n".join(filter(None, [note, f"the platform moves at {fast:.3g} Hz, faster than half the frame rate "
                                              f"({fps / 2:g} Hz): drawn relative to its O1, held still (--no-follow: as sampled; "
                                              f"--fps {25 * math.ceil(4 * fast / 25):g} draws the drive itself, four frames a cycle)"]))
    if has_rate and fast:
        t_int = np.linspace(times[0], times[-1], (len(times) - 1) * max(4, math.ceil(10 * fast / fps)) + 1)
        X_int = motion(model, t_int, x0, u=u, params=params or None, rtol=rtol, atol=rtol * 1e-2)
        integral = dict(integral_curve(model, derived, X_int, t_int, u, params or None), times=[float(v) for v in t_int])
    else:
        integral = integral_curve(model, derived, X, times, u, params or None) if has_rate else None
    if follow is None:
        follow, why = _follows(spec, ch, fine)
        note = "\n".join(filter(None, [note, why]))
    sc = scene.build(spec, ch, times, X, trace=trace, integral=integral, tip_times=fine, tip_X=fine_X,
                     rates=has_rate, follow=follow)
    if fast and follow:
        sc.caption = f"platform at {fast:.3g} Hz (> {fps / 2:g} Hz): O1 held still"
    camera = scene.Camera(math.radians(view[0]), math.radians(view[1])) if view else scene.default_camera(sc.points)
    raster = None
    with out:
        if out.ext == ".html":
            write_html(sc, camera, out.tmp, description)
        else:
            raster = Raster(sc, size[0], size[1], camera)
            {".gif": lambda: write_gif(raster, out.tmp, fps), ".png": lambda: write_png(raster, out.tmp),
             ".mp4": lambda: write_mp4(raster, out.tmp, fps)}[out.ext]()
    # what the last frame drew, in its pixels (kind, x0, y0, x1, y1), and where the scene may go
    drawn = dict(boxes=raster.boxes, area=(raster.top, raster.H - raster.band), size=(raster.W, raster.H)) if raster else {}
    return dict(path=out.path, times=times, bytes=out.path.stat().st_size, note=note, **drawn)


def sweep_point(store: str | Path, at: str) -> dict:
    """One point of a sweep store, to be seen again: the spec text, the initial state, the
    parameters and torques, and the sweep's t1.  ``at`` is ``name=value,…`` for every varied name
    of a grid (the nearest grid value is taken) or the sample's index of a --random sweep."""
    from ..ensembles import sweep

    attrs = sweep.stored_attrs(store)
    if attrs is None:
        raise SpecError("SPEC", f"{store} is neither a spec file nor a sweep store")
    args = dict(attrs["args"])
    args["vary"] = [tuple(v) for v in args["vary"]]
    plan = sweep.Plan(sweep.Sweep(spec_text=attrs["spec"], **args))
    names = plan.names
    if not at and not names:  # a sweep of one trajectory: its only point
        at = "0"
    if not at:
        raise SpecError("--at", f"which point of the sweep? give {'an index 0..' + str(plan.shape[0] - 1) if plan.points is not None else ','.join(f'{nm}=VALUE' for nm in names)}")
    if plan.points is not None:
        try:
            i = int(at)
        except ValueError:
            raise SpecError("--at", f"{at!r}: a --random sweep's points are numbered 0..{plan.shape[0] - 1}") from None
        if not 0 <= i < plan.shape[0]:
            raise SpecError("--at", f"{i}: a --random sweep's points are numbered 0..{plan.shape[0] - 1}")
        values = plan.points[i]
        label, note = f"sample {i}", ""
    else:
        want = {}
        for item in at.split(","):
            nm, eq, val = item.partition("=")
            nm = nm.strip()
            if not eq or nm not in names:
                raise SpecError("--at", f"{item!r}: expected name=value with name one of {', '.join(names)}")
            try:
                want[nm] = float(val)
            except ValueError:
                raise SpecError("--at", f"{item!r}: the value is not a number") from None
        missing = [nm for nm in names if nm not in want]
        if missing:
            raise SpecError("--at", f"no value for the varied {missing[0]}")
        values, snapped = [], []
        for j, nm in enumerate(names):
            axis = plan.axes[j]
            lo, hi = min(axis[0], axis[-1]), max(axis[0], axis[-1])
            step = abs(axis[1] - axis[0]) if len(axis) > 1 else 0.0
            if not (lo - 0.5 * step - 1e-12 * max(1.0, abs(lo)) <= want[nm] <= hi + 0.5 * step + 1e-12 * max(1.0, abs(hi))):
                raise SpecError("--at", f"{nm}={want[nm]:g} is outside the sweep's grid ({nm} from {axis[0]:g} to {axis[-1]:g})")
            v = float(axis[int(np.argmin(np.abs(axis - want[nm])))])
            if abs(v - want[nm]) > 1e-9 * max(1.0, abs(v)):
                snapped.append(f"{nm}={want[nm]:g} → {v:.6g}")
            values.append(v)
        values = np.array(values)
        label = ", ".join(f"{nm} = {v:.6g}" for nm, v in zip(names, values))
        note = ("--at: not a point of the grid; the nearest one is shown (" + ", ".join(snapped) + ")") if snapped else ""
    x0 = sweep.start_states(plan, np.asarray(values, float)[None, :])[0]
    params = dict(plan.params, **{nm: float(values[j]) for j, nm in enumerate(names) if nm in plan.param_names})
    return dict(spec_text=attrs["spec"], x0=x0, params=params, u=list(plan.sweep.u), t1=plan.sweep.t1, label=label, note=note)
