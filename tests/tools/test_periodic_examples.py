"""The example scripts behind the pictures of docs/periodic.md (run by `make plot`) run, on small
grids: Kapitza's stability chart and the nonlinear normal modes of the double pendulum."""
from __future__ import annotations

import pytest

from conftest import example_script

pytest.importorskip("matplotlib")


def test_kapitza_chart_draws(tmp_path):
    out = tmp_path / "chart.png"
    example_script("kapitza_chart").main(out, store=tmp_path / "k.zarr", na=9, nw=7)
    assert out.stat().st_size > 10_000


def test_normal_modes_draw(tmp_path, capsys):
    out = tmp_path / "nnm.png"
    example_script("nnm_periods").main(out)
    assert out.stat().st_size > 10_000
    said = capsys.readouterr().out
    assert "mode 1: 80 orbits" in said and "mode 2: 80 orbits" in said and "stopped" not in said
