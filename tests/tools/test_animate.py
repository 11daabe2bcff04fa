"""The viewer (issue 16): `animate` to GIF, MP4, PNG and HTML, the drawing against the geometry, bad
input, a sweep's point and a saved trajectory as sources, and the HTML page in a real browser."""
from __future__ import annotations

import math
import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

PIL = pytest.importorskip("PIL", reason="the view extra (Pillow) is not installed")
from PIL import Image, ImageChops  # noqa: E402

from gyrochain import animate, pipeline, reference, scene  # noqa: E402
from gyrochain.cli import main  # noqa: E402
from gyrochain.spec import load_spec, parse_spec  # noqa: E402

from conftest import example_params  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
SPECS = ROOT / "specs"
GIMBAL = SPECS / "gimbal.toml"
DP = SPECS / "double_pendulum.toml"


def param_args(name: str) -> list[str]:
    return [a for k, v in (example_params(name) or {}).items() for a in ("--param", f"{k}={v}")]


def frames_of(path: Path) -> list:
    im = Image.open(path)
    out = []
    for i in range(im.n_frames):
        im.seek(i)
        out.append(im.convert("RGB"))
    return out


def changed(a, b, tol: int = 0) -> int:
    """How many pixels differ between two pictures (by more than ``tol`` in the sum over R, G, B)."""
    d = np.asarray(ImageChops.difference(a.convert("RGB"), b.convert("RGB"))).astype(int).sum(axis=2)
    return int((d > tol).sum())


def fails(capsys, argv, field: str) -> str:
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and err.startswith(f"error: {field}:"), err
    return err


# --------------------------------------------------------------------------- the drawing against the geometry
def _colour_near(img, p, colour, radius=1) -> bool:
    """Whether some pixel within ``radius`` of p is close to ``colour``."""
    a = np.asarray(img.convert("RGB")).astype(int)
    x, y = int(round(p[0])), int(round(p[1]))
    want = np.array(animate._rgb(colour))
    win = a[max(0, y - radius):y + radius + 1, max(0, x - radius):x + radius + 1]
    return bool((np.abs(win - want).sum(axis=2) < 60).any())


def _still(spec_path, tmp_path, phi, view=(35.0, 20.0), extra=()):
    png = tmp_path / "still.png"
    assert main(["animate", str(spec_path), "--frame", "0", "--phi", ",".join(map(str, phi)), "--phidot",
                 ",".join(["0"] * len(phi)), "--view", f"{view[0]},{view[1]}", "-o", str(png), "-q", *extra]) == 0
    img = Image.open(png).convert("RGB")
    assert img.size == (480, 480)
    spec = load_spec(spec_path)
    ch = reference.numeric(spec)
    X = np.array([list(phi) + [0.0] * len(phi)])
    sc = scene.build(spec, ch, np.array([0.0]), X)
    raster = animate.Raster(sc, 480, 480, scene.Camera(math.radians(view[0]), math.radians(view[1])))
    return img, raster, ch


def _on_line(img, raster, p, q, colour, fractions=np.linspace(0.25, 0.9, 8)) -> float:
    """The share of points p + f (q − p) whose pixel is drawn in ``colour``."""
    px = raster.to_pixels(np.array([p + f * (q - p) for f in fractions]))
    return float(np.mean([_colour_near(img, (x, y), colour) for x, y, _ in px]))


def test_gimbal_still_matches_the_geometry(tmp_path):
    """The gimbal at t = 0 (φ = 0, 0.3): the vectors below are worked out by hand from (11)/(15)
    (θ¹ = 0, θ² = π/2), not by the code under test.  Each drawn bar must lie along them, and not
    along their mirror images, so a wrong transform or a mirrored projection fails."""
    img, raster, ch = _still(GIMBAL, tmp_path, (0.0, 0.3))
    O = np.zeros(3)  # O¹ = O² (s¹ = 0)
    e1 = np.array([1.0, 0.0, 0.0])  # the outer ring's axis: vertical (ê⁰₁, down)
    e2 = np.array([0.0, 0.0, -1.0])  # the inner ring's axis: e² = ê¹₁ cos θ² − ê¹₃ sin θ² = −ê⁰₃
    lam = np.array([math.cos(0.3), -math.sin(0.3), 0.0])  # the rotor axis ê²₃ = ê⁰₁ cos φ² − ê⁰₂ sin φ²
    geo = scene.Geometry(ch)
    blue, orange = scene.body_colour(1), scene.body_colour(2)
    # O's pixel lies on the drawn bars (both axes pass through it)
    x, y, _ = raster.to_pixels(O)
    assert _colour_near(img, (x, y), blue, 2) or _colour_near(img, (x, y), orange, 2)
    assert _on_line(img, raster, O, O + geo.bar[0] * e1, blue) >= 0.75
    assert _on_line(img, raster, O, O - geo.bar[0] * e1, blue) >= 0.75
    assert _on_line(img, raster, O, O + geo.bar[1] * e2, orange) >= 0.75
    wrong_e2 = np.array([0.0, 1.0, 0.0])  # the axis turned to ê⁰₂: nothing drawn there
    assert _on_line(img, raster, O, O + geo.bar[1] * wrong_e2, orange) <= 0.25
    # the rotor's axle: along λ, not along its mirror image (φ² of the other sign)
    r = 1.3 * geo.disc[1]
    assert _on_line(img, raster, O + 0.5 * r * lam, O + r * lam, orange, np.linspace(0.3, 0.95, 8)) >= 0.75
    mirror = np.array([math.cos(0.3), math.sin(0.3), 0.0])
    assert _on_line(img, raster, O + 0.5 * r * mirror, O + r * mirror, orange, np.linspace(0.3, 0.95, 8)) <= 0.25


def test_double_pendulum_still_links_end_at_the_joints(tmp_path):
    """φ = (0.7, −0.4): O² = ê¹₃ = (cos φ¹, −sin φ¹, 0) by (15) with θ¹ = π/2, |s¹| = 1; link 1 runs
    O¹ → O² and O²'s pixel lies on it; the mirrored placement is empty."""
    img, raster, ch = _still(DP, tmp_path, (0.7, -0.4))
    O1 = np.zeros(3)
    O2 = np.array([math.cos(0.7), -math.sin(0.7), 0.0])
    blue = scene.body_colour(1)
    x, y, _ = raster.to_pixels(O2)
    assert any(_colour_near(img, (x, y), scene.body_colour(k), 2) for k in (1, 2))
    assert _on_line(img, raster, O1, O2, blue, np.linspace(0.1, 0.4, 6)) >= 0.8
    mirror = np.array([math.cos(0.7), math.sin(0.7), 0.0])
    assert _on_line(img, raster, O1, mirror, blue, np.linspace(0.1, 0.4, 6)) <= 0.2


def test_camera_is_a_rotation():
    """The projection keeps handedness (right × up = towards the camera) and shows −ê⁰₁ up."""
    for az, el in ((0.3, 0.2), (-2.0, 1.0), (4.0, -0.5)):
        M = scene.Camera(az, el).matrix
        assert np.allclose(M @ M.T, np.eye(3), atol=1e-14)
        assert np.allclose(np.cross(M[0], M[1]), M[2], atol=1e-14)
        assert M[1] @ np.array([-1.0, 0, 0]) == pytest.approx(math.cos(el))


# --------------------------------------------------------------------------- files
def test_gif_png_mp4_sizes_frames_and_determinism(tmp_path, capsys):
    a, b = tmp_path / "a.gif", tmp_path / "b.gif"
    for p in (a, b):
        assert main(["animate", str(GIMBAL), "-o", str(p), "--t1", "1", "--fps", "20", "--size", "200x160", "-q"]) == 0
    assert a.read_bytes() == b.read_bytes()  # the same command, the same bytes
    fr = frames_of(a)
    assert len(fr) == 21 and fr[0].size == (200, 160)
    assert Image.open(a).info.get("duration") == 50
    assert all(changed(fr[i], fr[i + 1]) > 20 for i in range(0, 20, 5))
    png = tmp_path / "s.png"
    assert main(["animate", str(GIMBAL), "--frame", "0.5", "-o", str(png), "-q"]) == 0
    still = Image.open(png)
    assert still.size == (480, 480) and animate.MARKER in still.info.get("Software", "")
    # stills at two times differ; the GIF's background is the page's white, not a palette's near-white
    s0 = tmp_path / "s0.png"
    assert main(["animate", str(GIMBAL), "--frame", "0", "-o", str(s0), "-q"]) == 0
    assert changed(Image.open(s0), still) > 300
    assert fr[5].getpixel((2, 2)) == (255, 255, 255) and still.convert("RGB").getpixel((2, 2)) == (255, 255, 255)
    if shutil.which("ffmpeg") is None:
        pytest.skip("no ffmpeg on PATH: the .mp4 output is not checked")
    mp4 = tmp_path / "m.mp4"
    assert main(["animate", str(GIMBAL), "-o", str(mp4), "--t1", "1", "--fps", "20", "--size", "200x160", "-q"]) == 0
    data = mp4.read_bytes()
    assert data[4:8] == b"ftyp" and animate.MARKER.encode() in data
    probe = shutil.which("ffprobe")
    if probe:
        out = subprocess.run([probe, "-v", "error", "-count_frames", "-select_streams", "v:0", "-show_entries",
                              "stream=nb_read_frames,width,height", "-of", "csv=p=0", str(mp4)],
                             capture_output=True, text=True, timeout=60).stdout.strip()
        assert out == "200,160,21"


# --------------------------------------------------------------------------- bad input
def test_bad_input_one_line_and_no_file(tmp_path, capsys):
    out = tmp_path / "x.gif"
    fails(capsys, ["animate", str(GIMBAL), "-o", str(out), "--t1", "0"], "--t1")
    fails(capsys, ["animate", str(GIMBAL), "-o", str(out), "--t1", "0.01"], "--t1")  # one frame is no animation
    fails(capsys, ["animate", str(GIMBAL), "-o", str(out), "--fps", "0"], "--fps")
    fails(capsys, ["animate", str(GIMBAL), "-o", str(tmp_path / "x.avi")], "-o")
    fails(capsys, ["animate", str(GIMBAL), "-o", str(tmp_path / "x")], "-o")
    fails(capsys, ["animate", str(GIMBAL), "-o", str(tmp_path / "x.png")], "--frame")
    fails(capsys, ["animate", str(GIMBAL), "-o", str(out), "--phi", "1,2,3"], "--phi")
    fails(capsys, ["animate", str(GIMBAL), "-o", str(out), "--size", "7x9"], "--size")
    fails(capsys, ["animate", str(GIMBAL), "-o", str(out), "--at", "phi1=0"], "--at")
    # values that are no body's: a link without mass (was: the integrator's SINGULAR; now before any build)
    for name in ("m.gif", "m.html"):
        err = fails(capsys, ["animate", str(SPECS / "furuta_sym.toml"), "-o", str(tmp_path / name), "--param", "m2=0",
                             "--param", "J2=0", "--param", "J2z=0"], "body[2].m")
        assert "mass must be positive" in err
    assert sorted(os.listdir(tmp_path)) == []  # nothing written, no partial or temporary file left


def test_foreign_file_is_not_overwritten(tmp_path, capsys):
    mine = tmp_path / "notes.html"
    mine.write_text("my notes")
    fails(capsys, ["animate", str(GIMBAL), "-o", str(mine), "--t1", "1"], "-o")
    assert mine.read_text() == "my notes"
    ours = tmp_path / "a.html"
    assert main(["animate", str(GIMBAL), "-o", str(ours), "--t1", "1", "-q"]) == 0
    assert main(["animate", str(GIMBAL), "-o", str(ours), "--t1", "2", "-q"]) == 0  # ours: replaced
    assert main(["animate", str(GIMBAL), "-o", str(mine), "--t1", "1", "-q", "--force"]) == 0
    assert animate.MARKER in mine.read_text()


# --------------------------------------------------------------------------- other sources of the motion
def test_sweep_point_and_saved_trajectory(tmp_path, capsys):
    """A point of a sweep's store and a CSV from `simulate` animate as the same motion integrated
    from that state: the store gives the identical file, the CSV (the reference model's states at
    the frame times) a picture that differs by antialiasing at most."""
    pytest.importorskip("zarr", reason="the sweep extra is not installed")
    store = tmp_path / "s.zarr"
    assert main(["sweep", str(DP), "--vary", "phi1=-2:2:5", "--vary", "phi2=-1:1:3", "--t1", "1.5", "-q", "-o", str(store)]) == 0
    capsys.readouterr()
    a, b = tmp_path / "a.gif", tmp_path / "b.gif"
    assert main(["animate", str(store), "--at", "phi1=1.1,phi2=-0.9", "-o", str(a), "--size", "160x160", "-q"]) == 0
    assert "the nearest one is shown (phi1=1.1 → 1, phi2=-0.9 → -1)" in capsys.readouterr().err
    # the nearest grid point is (1, -1); the sweep's t1 = 1.5 s is the default
    assert main(["animate", str(DP), "--phi", "1,-1", "--phidot", "0,0", "--t1", "1.5", "-o", str(b), "--size", "160x160", "-q"]) == 0
    assert a.read_bytes() == b.read_bytes()
    fails(capsys, ["animate", str(store), "--at", "phi3=1", "-o", str(tmp_path / "c.gif")], "--at")
    fails(capsys, ["animate", str(store), "-o", str(tmp_path / "c.gif")], "--at")
    # a saved trajectory: simulate's CSV at 20 frames/s
    csv = tmp_path / "traj.csv"
    import contextlib
    import io

    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        assert main(["simulate", str(DP), "--phi", "1,-1", "--phidot", "0,0", "--t1", "1.5", "--steps", "30"]) == 0
    csv.write_text(buf.getvalue())
    c = tmp_path / "c.gif"
    # (no trace: the file's rows sample it coarser than the integrator's 4 per frame)
    assert main(["animate", str(DP), "--trajectory", str(csv), "--fps", "20", "-o", str(c), "--size", "160x160", "-q",
                 "--trace", "0"]) == 0
    d = tmp_path / "d.gif"
    assert main(["animate", str(DP), "--phi", "1,-1", "--phidot", "0,0", "--t1", "1.5", "--fps", "20", "-o", str(d),
                 "--size", "160x160", "-q", "--trace", "0"]) == 0
    fc, fd = frames_of(c), frames_of(d)
    assert len(fc) == len(fd) == 31
    assert all(changed(x, y, 60) < 40 for x, y in zip(fc, fd))
    assert changed(fc[0], fc[30]) > 200
    bad = tmp_path / "bad.csv"
    bad.write_text("t,phi1\n0,0\n")
    fails(capsys, ["animate", str(DP), "--trajectory", str(bad), "-o", str(tmp_path / "e.gif")], "--trajectory")


# --------------------------------------------------------------------------- the page in a browser
def _open(browser, page_file: Path, viewport=(800, 900)):
    errors, requests = [], []
    page = browser.new_page(viewport={"width": viewport[0], "height": viewport[1]})
    page.set_default_timeout(20_000)
    page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
    page.on("pageerror", lambda e: errors.append(str(e)))
    page.on("request", lambda r: requests.append(r.url) if not r.url.startswith("file:") else None)
    page.goto(page_file.as_uri())
    page.wait_for_function("window.gyroViewer !== undefined")
    return page, errors, requests


def _shot(locator):
    import io
    return Image.open(io.BytesIO(locator.screenshot())).convert("RGB")


def _centroid(img, colour) -> np.ndarray:
    a = np.asarray(img).astype(int)
    mask = np.abs(a - np.array(animate._rgb(colour))).sum(axis=2) < 40
    ys, xs = np.nonzero(mask)
    assert len(xs) > 30, f"too few pixels of {colour}"
    return np.array([xs.mean(), ys.mean()])


def test_html_and_raster_draw_the_same_picture(browser, tmp_path):
    """The page's renderer (viewer.js) and the raster one (Pillow) place the bodies alike: from the
    centre of body 1's pixels to body 2's points the same way in both (a mirrored or turned camera
    in either fails)."""
    args = ["--phi", "0.7,-0.4", "--phidot", "0,0", "--view", "35,20"]
    page_file = tmp_path / "dp.html"
    assert main(["animate", str(DP), "-o", str(page_file), "--t1", "1", "-q", *args]) == 0
    png = tmp_path / "dp.png"
    assert main(["animate", str(DP), "--frame", "0", "-o", str(png), "--size", "640x480", "-q", *args]) == 0
    page, errors, requests = _open(browser, page_file)
    page.click("#play")
    page.locator("#time").fill("0")
    html = _shot(page.locator("#scene"))
    page.close()
    raster = Image.open(png).convert("RGB")
    d_html = _centroid(html, scene.body_colour(2)) - _centroid(html, scene.body_colour(1))
    d_png = _centroid(raster, scene.body_colour(2)) - _centroid(raster, scene.body_colour(1))
    cos = d_html @ d_png / np.linalg.norm(d_html) / np.linalg.norm(d_png)
    assert cos > 0.99, (d_html, d_png)
    assert errors == [] and requests == []


def test_html_viewer_in_headless_chromium(browser, tmp_path):
    """The page in Debian's Chromium (driven by Playwright): no console error and no request leaves
    the file; the canvas is drawn; two times give two pictures; the slider moves the clock; a drag
    turns the view and the wheel zooms; the integral's plot is drawn with its cursor."""
    page_file = tmp_path / "gimbal.html"
    assert main(["animate", str(GIMBAL), "-o", str(page_file), "--t1", "4", "-q"]) == 0
    page, errors, requests = _open(browser, page_file)
    try:
        assert page.evaluate("gyroViewer.frames") == 101
        page.click("#play")  # pause the autoplay
        assert page.evaluate("gyroViewer.playing") is False
        canvas = page.locator("#scene")

        def shot():
            return _shot(canvas)

        slider = page.locator("#time")
        slider.fill("0")
        first = shot()
        assert page.inner_text("#clock") == "t = 0.00 s"
        blank = Image.new("RGB", first.size, (255, 255, 255))
        assert changed(first, blank) > 2000  # drawn
        slider.fill("50")
        assert page.inner_text("#clock") == "t = 2.00 s" and page.evaluate("gyroViewer.time") == 2.0
        later = shot()
        assert changed(first, later) > 500
        az = page.evaluate("gyroViewer.az")
        box = canvas.bounding_box()
        cx, cy = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
        page.mouse.move(cx, cy)
        page.mouse.down()
        page.mouse.move(cx + 120, cy + 30, steps=6)
        page.mouse.up()
        assert page.evaluate("gyroViewer.az") == pytest.approx(az - 1.2)
        turned = shot()
        assert changed(later, turned) > 500 and page.inner_text("#clock") == "t = 2.00 s"
        page.mouse.move(cx, cy)
        page.mouse.wheel(0, -300)
        page.wait_for_function("gyroViewer.zoom > 1.2")
        zoomed = shot()
        assert changed(turned, zoomed) > 500
        plot = _shot(page.locator("#plot"))
        assert changed(plot, Image.new("RGB", plot.size, (255, 255, 255))) > 300
        assert "energy" in page.evaluate("JSON.parse(document.getElementById('scene-data').textContent).integral.label")
        # the readout is the state of the frame: the C trajectory at t = 2 s
        model = pipeline.compiled(parse_spec(GIMBAL.read_text()))[0]
        spec = load_spec(GIMBAL)
        x = model.integrate([0.0, 2.0], list(spec.initial["phi"]) + list(spec.initial["phidot"]), rtol=1e-10, atol=1e-12)[-1]
        lines = page.inner_text("#state").splitlines()
        shown = [float(v) for line in lines for v in line.split("(")[1].split(")")[0].split(",")]
        assert np.allclose(shown, x, atol=6e-5), (shown, x)
        # arrow keys step a frame; a double click brings the first view back
        page.keyboard.press("ArrowRight")
        assert page.evaluate("gyroViewer.frame") == 51 and page.inner_text("#clock") == "t = 2.04 s"
        page.keyboard.press("ArrowLeft")
        page.keyboard.press("ArrowLeft")
        assert page.evaluate("gyroViewer.frame") == 49
        page.keyboard.press("End")
        assert page.evaluate("gyroViewer.frame") == 100 and page.inner_text("#clock") == "t = 4.00 s"
        page.keyboard.press("Home")
        assert page.evaluate("gyroViewer.frame") == 0
        page.mouse.dblclick(cx, cy)
        assert page.evaluate("gyroViewer.az") == pytest.approx(az) and page.evaluate("gyroViewer.zoom") == 1
        # playing advances the frame, at the chosen rate
        page.select_option("#speed", "0.25")
        assert page.evaluate("gyroViewer.rate") == 0.25
        page.click("#play")
        page.wait_for_function("gyroViewer.frame > 50 || gyroViewer.frame < 48", timeout=10_000)
    finally:
        page.close()
    assert errors == [], errors
    assert requests == [], requests


SHOTS = Path(os.environ.get("GYROCHAIN_SHOTS", "")) if os.environ.get("GYROCHAIN_SHOTS") else None


@pytest.mark.parametrize("viewport, side_by_side", [((1280, 800), True), ((390, 844), False)])
def test_the_viewer_fills_the_window_and_says_how_to_use_it(browser, tmp_path, viewport, side_by_side):
    """At 1280×800 the scene and the integral's plot stand side by side and the scene takes most of
    the width; on a phone (390×844) they are stacked; either way nothing scrolls sideways, the help
    is above the fold, and the page places the bodies as the raster does.  GYROCHAIN_SHOTS=folder
    keeps the screenshots to look at."""
    page_file, png = tmp_path / "dp.html", tmp_path / "dp.png"
    args = ["--phi", "0.7,-0.4", "--phidot", "0,0", "--view", "35,20", "-q"]
    assert main(["animate", str(DP), "-o", str(page_file), "--t1", "2", *args]) == 0
    assert main(["animate", str(DP), "--frame", "0", "-o", str(png), *args]) == 0
    page, errors, requests = _open(browser, page_file, viewport)
    try:
        page.click("#play")
        page.locator("#time").fill("0")
        box = {k: page.locator(k).bounding_box() for k in ("#scene", "#plot", "#help", "#state")}
        w, h = viewport
        assert page.evaluate("document.documentElement.scrollWidth") <= w
        assert box["#help"]["y"] + box["#help"]["height"] <= h
        if side_by_side:
            assert box["#scene"]["width"] > 0.5 * w and box["#plot"]["x"] >= box["#scene"]["x"] + box["#scene"]["width"]
            assert box["#scene"]["y"] + box["#scene"]["height"] <= h  # the scene fits the window
        else:
            assert box["#scene"]["width"] > 0.85 * w and box["#plot"]["y"] >= box["#scene"]["y"] + box["#scene"]["height"]
        html = _shot(page.locator("#scene"))
        if SHOTS:
            SHOTS.mkdir(parents=True, exist_ok=True)
            page.screenshot(path=str(SHOTS / f"viewer_{w}x{h}.png"), full_page=True)
    finally:
        page.close()
    raster = Image.open(png).convert("RGB")
    d_html = _centroid(html, scene.body_colour(2)) - _centroid(html, scene.body_colour(1))
    d_png = _centroid(raster, scene.body_colour(2)) - _centroid(raster, scene.body_colour(1))
    assert d_html @ d_png / np.linalg.norm(d_html) / np.linalg.norm(d_png) > 0.99, (d_html, d_png)
    assert errors == [] and requests == []


def test_the_legend_names_the_marks_the_picture_has(browser, tmp_path):
    """The legend is read off the drawn primitives: the gimbal's has rotors and no platform, the
    double pendulum neither, the ship a platform; the raster paints it in a band at the bottom and
    the page lists it under the scene."""
    def marks(spec_path, **kw):
        spec = load_spec(spec_path)
        ch = reference.numeric(spec)
        X = np.tile([0.1] * spec.n + [0.0] * spec.n, (3, 1))
        return [m for m, _ in scene.build(spec, ch, np.linspace(0, 1, 3), X, **kw).legend]

    assert marks(GIMBAL) == ["bodies", "bar", "ring", "dot", "disc", "triad", "trace"]  # two Cardan rings
    assert marks(DP) == ["bodies", "bar", "link", "dot", "triad", "trace"]
    assert "deck" in marks(SPECS / "ship_gimbal.toml") and "trace" not in marks(DP, trace=0.0)
    # the gimbal's rings: the outer one in the plane of l1 and l2, the inner one of l2 and the rotor's
    # axle, each of the radius of a thin ring of its inertia about its axis, r = sqrt(2 A11 / m)
    spec = load_spec(GIMBAL)
    ch = reference.numeric(spec)
    geo = scene.Geometry(ch)
    assert np.allclose(geo.ring, [math.sqrt(2 * 0.005 / 0.5), math.sqrt(2 * 0.006 / 1.2)])
    P = scene.pose(ch, np.array([0.4, 0.7]), 0.0)
    for k, w in ((0, P["e"][1]), (1, P["lam"][1])):
        u, v, r = scene.cardan_ring(geo, P, k)
        assert np.allclose(u, P["e"][k]) and abs(v @ u) < 1e-12 and abs(np.cross(u, v) @ w) < 1e-12
    assert geo.bar[1] > geo.ring[0]  # the inner axis reaches the outer ring's bearings
    assert not scene.Geometry(reference.numeric(load_spec(DP))).ring.any()  # rods off their axes: no ring
    png, page_file = tmp_path / "g.png", tmp_path / "g.html"
    assert main(["animate", str(GIMBAL), "--frame", "1", "-o", str(png), "-q"]) == 0
    img = np.asarray(Image.open(png).convert("RGB")).astype(int)
    band = img[-40:, :, :]
    assert (np.abs(band - 255).sum(axis=2) > 60).sum() > 300  # the legend's marks and words
    assert main(["animate", str(GIMBAL), "--t1", "1", "-o", str(page_file), "-q"]) == 0
    page, errors, _requests = _open(browser, page_file)
    try:
        text = page.inner_text("#legend")
    finally:
        page.close()
    assert text.startswith("body 1 2") and "joint axis" in text and "rotor" in text and errors == []


def _bar_through_disc(view=(40.0, 25.0)):
    """A disc in the plane x₁ = 0 (normal ê⁰₁) and a bar along its normal through its centre, as
    one frame; and the camera."""
    disc = ("disc", np.zeros(3), np.array([0.0, 1.0, 0.0]), np.array([0.0, 0.0, 1.0]), 0.5, "#009E73")
    bar = ("seg", np.array([-0.6, 0.0, 0.0]), np.array([0.6, 0.0, 0.0]), "#0072B2", 5.0)
    pts = np.array([[-0.6, 0, 0], [0.6, 0, 0], [0, 0.5, 0], [0, -0.5, 0], [0, 0, 0.5], [0, 0, -0.5]], float)
    sc = scene.Scene(name="t", times=np.array([0.0]), frames=[[bar, disc]], static=[], tip_times=np.array([0.0]),
                     tips=np.zeros((1, 3)), trace=0.0, size=1.0, gravity=False, points=pts)
    return sc, scene.Camera(math.radians(view[0]), math.radians(view[1]))


def test_a_bar_through_a_disc_shows_in_front_of_it_only_on_the_near_side():
    """The bar's half on the camera's side of the disc is painted over it, the far half under its
    translucent fill (sorted whole, either all of the bar or none of it was in front)."""
    sc, cam = _bar_through_disc()
    r = animate.Raster(sc, 320, 320, cam)
    img = np.asarray(r.frame(0)).astype(int)
    near_end, far_end = (np.array([-0.6, 0, 0]), np.array([0.6, 0, 0]))
    if cam.project(near_end)[2] < cam.project(far_end)[2]:
        near_end, far_end = far_end, near_end
    blue = np.array(animate._rgb("#0072B2"))
    for end, in_front in ((near_end, True), (far_end, False)):
        x, y, _ = r.to_pixels(0.2 * end)  # on the bar, within the disc's outline on the screen
        px = img[int(round(y)), int(round(x))]
        assert (np.abs(px - blue).sum() < 30) == in_front, (end, px)


def test_the_page_orders_a_bar_through_a_disc_as_the_raster_does(browser, tmp_path):
    """The same bar and disc in the page: the near half over the disc, the far half under it."""
    sc, cam = _bar_through_disc()
    page_file = tmp_path / "b.html"
    animate.write_html(sc, cam, page_file, "a bar through a disc")
    near_end, far_end = (np.array([-0.6, 0, 0]), np.array([0.6, 0, 0]))
    if cam.project(near_end)[2] < cam.project(far_end)[2]:
        near_end, far_end = far_end, near_end
    page, errors, _requests = _open(browser, page_file, (1280, 800))
    try:
        img = np.asarray(_shot(page.locator("#scene"))).astype(int)
        border = 1  # the canvas's CSS border: the screenshot includes it
        blue = np.array(animate._rgb("#0072B2"))
        for end, in_front in ((near_end, True), (far_end, False)):
            x, y = page.evaluate(f"gyroViewer.project({[float(v) for v in 0.2 * end]})")
            px = img[int(round(y)) + border, int(round(x)) + border]
            assert (np.abs(px - blue).sum() < 30) == in_front, (end, px)
    finally:
        page.close()
    assert errors == []


def test_the_page_fits_the_motion_not_a_sphere_around_it(browser, tmp_path):
    """spatial3's chaotic swing: the union of the drawn pixels over the run spans most of the
    canvas (the page fits the projected extent of every frame, as the raster does; a bounding
    sphere left two thirds of it empty)."""
    page_file = tmp_path / "s.html"
    assert main(["animate", str(SPECS / "spatial3.toml"), "--phi=-2,-0.75,-1.1", "--phidot", "0,0,0", "--t1", "4",
                 "--trace", "0", "-o", str(page_file), "-q"]) == 0
    page, errors, _requests = _open(browser, page_file, (1280, 800))
    try:
        page.click("#play")
        drawn = None
        for i in range(0, 101, 5):
            page.locator("#time").fill(str(i))
            a = np.asarray(_shot(page.locator("#scene"))).astype(int)
            mark = np.abs(a - 255).sum(axis=2) > 60
            drawn = mark if drawn is None else drawn | mark
    finally:
        page.close()
    drawn[-80:, :80] = False  # the gravity arrow
    drawn[:3, :] = drawn[-3:, :] = drawn[:, :3] = drawn[:, -3:] = False  # the border
    ys, xs = np.nonzero(drawn)
    assert max(np.ptp(xs) / drawn.shape[1], np.ptp(ys) / drawn.shape[0]) > 0.8, (np.ptp(xs), np.ptp(ys), drawn.shape)
    assert errors == []


def test_a_platform_faster_than_half_the_frame_rate_is_not_aliased(tmp_path, capsys):
    """Kapitza's pivot (w = 260 rad/s: 41.4 Hz) at 25 frames/s: detected, drawn with O1 held
    still (said on the picture and in a line), and the page's integral sampled at least 8 times
    per period of the pivot; the ship's slow heave is not fast; --no-follow draws it as sampled."""
    kap = load_spec(SPECS / "kapitza.toml")
    ch = reference.numeric(kap, dict(kap.values))
    times = animate.frame_times(2.0, 25.0, None)
    assert animate.fast_base(kap, ch, times) == pytest.approx(260 / (2 * math.pi), rel=0.02)
    ship = load_spec(SPECS / "ship_gimbal.toml")
    assert animate.fast_base(ship, reference.numeric(ship), times) == 0.0
    page = tmp_path / "k.html"
    assert main(["animate", str(SPECS / "kapitza.toml"), "--t1", "2", "-o", str(page)]) == 0
    err = capsys.readouterr().err
    assert "faster than half the frame rate (12.5 Hz)" in err and "--fps 175 draws the drive itself" in err
    data = _page_data(page)
    assert data["caption"].startswith("platform at 41") and len(data["integral"]["times"]) >= 8 * 41.4 * 2
    assert len(data["integral"]["times"]) == len(data["integral"]["values"])
    deck = [[p for p in f if p[0] == "plate"][0][1] for f in data["frames"]]
    assert np.allclose(deck, deck[0], atol=1e-12)  # O1 held still
    assert main(["animate", str(SPECS / "kapitza.toml"), "--t1", "2", "--no-follow", "-o", str(tmp_path / "n.html"), "-q"]) == 0
    deck = [[p for p in f if p[0] == "plate"][0][1] for f in _page_data(tmp_path / "n.html")["frames"]]
    assert np.ptp(np.array(deck)[:, 0]) > 0.015  # sampled: the pivot's 1 cm jumps between frames


def test_follow_keeps_the_platform_in_place(tmp_path, capsys):
    """--follow draws the ship's gimbal relative to O¹ = r₀(t): the outer ring's bar stays centred
    on the origin of the drawing, while without it the bar heaves with r₀(t) = (0.5 sin 0.6t, 0, 0)."""
    spec = load_spec(SPECS / "ship_gimbal.toml")
    ch = reference.numeric(spec)
    times = np.linspace(0.0, 3.0, 7)
    X = np.tile([0.0, 0.3, 0.0, 0.0], (len(times), 1))
    for follow in (False, True):
        sc = scene.build(spec, ch, times, X, follow=follow)
        for t, prims in zip(times, sc.frames):
            bar = [p for p in prims if p[0] == "seg" and p[3] == scene.body_colour(1) and p[4] == 5.0][0]
            centre = (bar[1] + bar[2]) / 2
            want = np.zeros(3) if follow else np.array([0.5 * math.sin(0.6 * t), 0.0, 0.0])
            assert np.allclose(centre, want, atol=1e-12)
    out = tmp_path / "f.gif"
    assert main(["animate", str(SPECS / "ship_gimbal.toml"), "--follow", "--t1", "1", "--fps", "10", "-o", str(out), "-q"]) == 0
    fails(capsys, ["animate", str(GIMBAL), "--follow", "-o", str(tmp_path / "g.gif")], "--follow")


def test_the_camera_follows_a_platform_that_moves_farther_than_the_chain(tmp_path, capsys):
    """By default the ship's gimbal (0.1 m) is followed on its 0.5 m heave and a line says so;
    --no-follow keeps the world view; Kapitza's 1 cm pivot under a 0.2 m pendulum is not followed."""
    spec = load_spec(SPECS / "ship_gimbal.toml")
    follows, why = animate._follows(spec, reference.numeric(spec), np.linspace(0, 10, 251))
    assert follows and "--no-follow" in why
    kap = load_spec(SPECS / "kapitza.toml")
    assert animate._follows(kap, reference.numeric(kap, dict(kap.values)), np.linspace(0, 10, 251)) == (False, "")
    for extra, note in (([], True), (["--no-follow"], False)):
        capsys.readouterr()
        assert main(["animate", str(SPECS / "ship_gimbal.toml"), *extra, "--frame", "1", "--size", "120x120",
                     "-o", str(tmp_path / "s.png")]) == 0
        assert ("the camera follows the platform's O1" in capsys.readouterr().err) == note


def test_a_spec_without_a_state_that_would_stand_still_gets_a_push(tmp_path, capsys):
    """furuta.toml has no [initial] and hangs at rest at φ = 0: animate draws the motion from
    φ = 0.2 in every joint and says so; a given state, even at rest, is drawn as given."""
    times, x = np.linspace(0, 1, 5), np.zeros((5, 4))
    spec = load_spec(SPECS / "furuta.toml")
    assert animate._still(spec, x, None, None, "") and not animate._still(spec, x, [0.0, 0.0], None, "")
    assert not animate._still(load_spec(GIMBAL), x, None, None, "")  # the gimbal has an [initial]
    assert main(["animate", str(SPECS / "furuta.toml"), "--frame", "1", "--size", "120x120", "-o", str(tmp_path / "f.png")]) == 0
    assert "drawing the motion from phi = 0.2, 0.2" in capsys.readouterr().err
    assert main(["animate", str(SPECS / "furuta.toml"), "--phi", "0,0", "--frame", "1", "--size", "120x120",
                 "-o", str(tmp_path / "g.png")]) == 0
    assert "drawing the motion" not in capsys.readouterr().err


def test_spec_text_is_escaped_in_the_page(tmp_path):
    """The spec's description is text in the page, never markup or script."""
    spec = tmp_path / "evil.toml"
    spec.write_text(GIMBAL.read_text().replace('description = "', 'description = "</script><script>alert(1)</script><b>x</b> '))
    page = tmp_path / "e.html"
    assert main(["animate", str(spec), "-o", str(page), "--t1", "1", "-q"]) == 0
    text = page.read_text()
    assert text.count("<script") == 2 and "<b>x</b>" not in text and "&lt;/script&gt;&lt;script&gt;alert(1)" in text


# --------------------------------------------------------------------------- the curve under the page
def _page_data(path: Path) -> dict:
    import json

    text = path.read_text(encoding="utf-8")
    start = text.index('<script id="scene-data" type="application/json">') + len('<script id="scene-data" type="application/json">')
    return json.loads(text[start:text.index("</script>", start)])


@pytest.mark.parametrize("case", ["controls_idle", "controls_working", "jacobi", "momentum", "moving_base"])
def test_integral_curve_is_the_integral_that_exists(case, tmp_path):
    """The page plots the first integral that exists, and it is conserved along the motion; where
    none exists the energy is plotted, labelled so, and it changes."""
    page = tmp_path / "p.html"
    spec, extra = {
        "controls_idle": (SPECS / "spatial3.toml", ["--phi=-2,-0.75,-1.1"]),  # a control torque held at 0
        "controls_working": (SPECS / "spatial3.toml", ["--phi=-2,-0.75,-1.1", "--u", "0.2"]),
        "jacobi": (SPECS / "turntable.toml", param_args("turntable")),
        "momentum": (None, []),
        "moving_base": (SPECS / "ship_gimbal.toml", []),
    }[case]
    if spec is None:  # the gimbal with a damper in the inner ring: energy decays, (27) holds
        spec = tmp_path / "damped_gimbal.toml"
        spec.write_text(GIMBAL.read_text().replace('lambda = [0.0, 0.0, 0.5]', 'lambda = [0.0, 0.0, 0.5]\ndamping = 0.002'))
    assert main(["animate", str(spec), "-o", str(page), "--t1", "3", "-q", *extra]) == 0
    curve = _page_data(page)["integral"]
    v = np.array(curve["values"])
    rel = np.ptp(v) / abs(v[0])
    want = {"controls_idle": "energy T − U (23), an integral", "controls_working": "energy T − U (23), not an integral here",
            "jacobi": "Jacobi integral, conserved", "momentum": "momentum (27), an integral",
            "moving_base": "energy T − U (23), not an integral here"}[case]
    assert curve["label"] == want
    assert curve["conserved"] is ("not an integral" not in want)  # the page plots a conserved one as its deviation
    if "not an integral" in want:
        assert rel > 1e-4
    else:
        assert rel < 1e-8
