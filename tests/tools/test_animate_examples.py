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

from conftest import ONE_ARM  # noqa: E402
from test_animate import changed, frames_of, param_args  # noqa: E402

SPECS = Path(__file__).resolve().parents[2] / "specs"


# --------------------------------------------------------------------------- every example, GIF and HTML
@pytest.mark.parametrize("name", ONE_ARM)
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


def test_a_motion_at_rest_animates(tmp_path):
    """The Furuta pendulum hanging at rest, asked for (--phi 0,0 --phidot 0,0; without a state it
    would get a push): every frame the same, few colours in the GIF's palette."""
    gif = tmp_path / "rest.gif"
    assert main(["animate", str(SPECS / "furuta.toml"), "-o", str(gif), "--t1", "1", "--fps", "10", "-q",
                 "--phi", "0,0", "--phidot", "0,0"]) == 0
    fr = frames_of(gif)
    assert len(fr) == 11 and all(changed(fr[0], f) < 80 for f in fr)  # only the clock changes
    assert changed(fr[0], Image.new("RGB", fr[0].size, (255, 255, 255))) > 500
