"""Every example animates (issue 16), in a file of its own so that pytest-xdist can run it beside
test_animate.py: each example's model is derived and compiled here."""
from __future__ import annotations

from pathlib import Path

import pytest

pytest.importorskip("PIL", reason="the view extra (Pillow) is not installed")
from PIL import Image  # noqa: E402

from gyrochain import animate  # noqa: E402
from gyrochain.cli import main  # noqa: E402
from gyrochain.spec import load_spec  # noqa: E402

from conftest import ONE_ARM, QUICK_EXAMPLES, example_params, tiered  # noqa: E402
from test_animate import changed, frames_of, param_args  # noqa: E402

SPECS = Path(__file__).resolve().parents[2] / "specs"


# --------------------------------------------------------------------------- every example, GIF and HTML
@pytest.mark.parametrize("name", tiered(ONE_ARM, QUICK_EXAMPLES))
def test_every_example_animates(name, tmp_path, capsys):
    """One command per example: a GIF whose frames move (every example is set moving with φ̇ = 1
    where its spec has no initial state) and a self-contained page."""
    spec = load_spec(SPECS / f"{name}.toml")
    rates = [] if spec.initial else ["--phidot", ",".join(["1"] * spec.n)]
    gif = tmp_path / f"{name}.gif"
    assert main(["animate", str(SPECS / f"{name}.toml"), "-o", str(gif), "--t1", "2", "--fps", "10", "--size", "160x120",
                 "-q", *rates, *param_args(name)]) == 0
    fr = frames_of(gif)
    assert len(fr) == 21 and fr[0].size == (160, 120)
    assert changed(fr[0], fr[10]) > 50 and changed(fr[10], fr[20]) > 50
    html = tmp_path / f"{name}.html"
    assert main(["animate", str(SPECS / f"{name}.toml"), "-o", str(html), "--t1", "2", "--fps", "10", "-q", *rates,
                 *param_args(name)]) == 0
    text = html.read_text(encoding="utf-8")
    assert "<script src" not in text and "http://" not in text and "https://" not in text  # offline: nothing fetched
    assert text.count('"frames":') == 1 and animate.MARKER in text


@pytest.mark.parametrize("name", tiered(ONE_ARM, QUICK_EXAMPLES))
def test_every_still_is_framed_and_its_labels_apart(name, tmp_path):
    """A still of every example (at t = 1.5 s, with the last 2 s of the tip's path): everything drawn
    — bodies, rings, the platform, the path, the labels — lies inside the canvas, the scene between
    the text lines and the legend; no two labels' boxes overlap and none covers a centre of mass."""
    spec = load_spec(SPECS / f"{name}.toml")
    rates = None if spec.initial else [1.0] * spec.n
    done = animate.render(SPECS / f"{name}.toml", tmp_path / f"{name}.png", frame=1.5, phidot=rates,
                          params=example_params(name) or {}, size=(480, 360))
    W, H = done["size"]
    top, bottom = done["area"]
    boxes = done["boxes"]
    assert len(boxes) > 5
    for kind, x0, y0, x1, y1 in boxes:
        assert -0.5 <= x0 and x1 <= W + 0.5 and top - 0.5 <= y0 and y1 <= bottom + 0.5, (kind, x0, y0, x1, y1, top, bottom)
    labels = [b[1:] for b in boxes if b[0] == "label"]
    dots = [b[1:] for b in boxes if b[0] == "dot"]

    def overlap(a, b):
        return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]

    assert labels and not [(a, b) for i, a in enumerate(labels) for b in labels[i + 1:] + dots if overlap(a, b)]


def test_the_long_chain_names_its_colour_map(tmp_path):
    """64 links: coloured by index along a map the legend names, not eight colours repeated."""
    from gyrochain import reference, scene

    spec = load_spec(SPECS / "cable64.toml")
    sc = scene.build(spec, reference.numeric(spec, {}), [0.0], [[0.0] * 128], trace=0.0)
    assert sc.legend[0] == ("bodymap", "bodies 1…64, from the first colour to the last")
    assert len(set(sc.colours)) == 64 and "#000000" not in sc.colours
    assert not set(sc.colours) & {"#555555", "#888888", "#F0E442"}  # the legend's symbols, the faint yellow


def test_the_clock_changes_every_frame_and_small_pictures_read():
    """At 200 frames/s the clock has three decimals (0.005, 0.010, …: no two frames read alike); the
    legend's text is 11 pixels or more at 360 pixels, and a picture too small for it has none."""
    from gyrochain import reference, scene
    from gyrochain.raster import Raster

    spec = load_spec(SPECS / "double_pendulum.toml")
    times = [0.0, 0.005, 0.01]
    sc = scene.build(spec, reference.numeric(spec, {}), times, [[0.5, 0.0, 0.0, 0.0]] * 3)
    assert Raster(sc, 360, 360).decimals == 3
    assert Raster(scene.build(spec, reference.numeric(spec, {}), [0.0, 0.04], [[0.5, 0, 0, 0]] * 2), 360, 360).decimals == 2
    r = Raster(sc, 360, 360)
    assert r.small.size / r.ss >= 11 and r.font.size / r.ss >= 12 and r.rows
    assert not Raster(sc, 160, 120).rows


def test_a_motion_at_rest_animates(tmp_path):
    """The Furuta pendulum hanging at rest, asked for (--phi 0,0 --phidot 0,0; without a state it
    would get a push): every frame the same, few colours in the GIF's palette."""
    gif = tmp_path / "rest.gif"
    assert main(["animate", str(SPECS / "furuta.toml"), "-o", str(gif), "--t1", "1", "--fps", "10", "-q",
                 "--phi", "0,0", "--phidot", "0,0"]) == 0
    fr = frames_of(gif)
    assert len(fr) == 11 and all(changed(fr[0], f) < 80 for f in fr)  # only the clock changes
    assert changed(fr[0], Image.new("RGB", fr[0].size, (255, 255, 255))) > 500
