"""``plot``: the pictures of a sweep store (matplotlib, the ``sweep`` extra)."""
from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from . import sweep as sw
from .spec import SpecError


FORMATS = ("png", "pdf", "svg")  # the images plot writes (matplotlib's Agg, no extra library)


def store(path: str | Path, output: str | Path, measure: str = "", component: int = 0, cmap: str = "viridis",
          log: bool = False, dpi: int = 150) -> Path:
    """A heat map (two varied quantities), a scatter (random samples) or a curve (one) of a sweep
    store's measure, written to ``output`` (png, pdf, svg); returns its path."""
    output = Path(output)
    if output.suffix.lower().lstrip(".") not in FORMATS:
        raise SpecError("-o", f"{output.name}: an image type plot does not write (give .{', .'.join(FORMATS)})")
    if not 10 <= dpi <= 2400:
        raise SpecError("--dpi", f"must be from 10 to 2400, got {dpi}")
    if not Path(path).exists():
        raise SpecError("store", f"{path}: no such store")
    if sw.stored_attrs(path) is None:
        raise SpecError("store", f"{path} is not a sweep store (make one with the sweep command)")
    data = sw.read(path)
    a = data["attrs"]["args"]
    measure = measure or a["measures"][0]
    if measure not in data:
        raise SpecError("--measure", f"{measure!r} is not in the store (it has {', '.join(a['measures'])})")
    values = data[measure]
    if measure == "final":
        dim = values.shape[-1]
        if not 0 <= component < dim:
            raise SpecError("--component", f"the state has components 0..{dim - 1}, got {component}")
        values = values[..., component]
    elif component:
        raise SpecError("--component", f"only the measure final has components ({measure} is one number per point)")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        raise SpecError("plot", "needs matplotlib: pip install 'gyrochain[plot]'") from None
    if cmap not in matplotlib.colormaps:
        raise SpecError("--cmap", f"{cmap!r} is not a matplotlib colour map (for example viridis, magma, cividis)")
    names = [v[0] for v in a["vary"]]
    if log and not np.any(np.isfinite(values) & (values > 0)):
        raise SpecError("--log", f"{measure} has no positive value to draw on a logarithmic scale")
    label = _measure_label(measure, component, data["attrs"])
    fig, ax = plt.subplots(figsize=(6.4, 5.2) if len(names) == 2 else (6.4, 4.0), dpi=dpi)
    if len(names) == 2 and not a["random"]:
        x, y = data["coords"][names[0]], data["coords"][names[1]]
        norm = None
        if log:
            from matplotlib.colors import LogNorm
            norm = LogNorm()
        im = ax.pcolormesh(x, y, values.T, shading="nearest", cmap=cmap, norm=norm)
        fig.colorbar(im, ax=ax, label=label)
        ax.set_xlabel(_axis_label(names[0]))
        ax.set_ylabel(_axis_label(names[1]))
    elif len(names) == 2:
        sc = ax.scatter(data["coords"][names[0]], data["coords"][names[1]], c=values, s=4, cmap=cmap)
        fig.colorbar(sc, ax=ax, label=label)
        ax.set_xlabel(_axis_label(names[0]))
        ax.set_ylabel(_axis_label(names[1]))
    elif len(names) == 1:
        x = data["coords"][names[0]]
        order = np.argsort(x)
        ax.plot(x[order], values[order], ".-" if len(x) < 200 else "-")
        if log:
            ax.set_yscale("log")
        ax.set_xlabel(_axis_label(names[0]))
        ax.set_ylabel(label)
    else:
        raise SpecError("store", f"plot shows one or two varied quantities; this sweep varies {len(names)}")
    ax.set_title(f"{data['attrs']['spec_name']}: {label}")
    fig.tight_layout()
    output.parent.mkdir(parents=True, exist_ok=True)
    tmp = output.with_name(f".{output.name}.tmp")  # written beside and renamed: never half an image
    try:
        fig.savefig(tmp, format=output.suffix.lower().lstrip("."))
        tmp.replace(output)
    finally:
        plt.close(fig)
        tmp.unlink(missing_ok=True)
    return output


def _axis_label(name: str) -> str:
    m = re.fullmatch(r"(phi|phidot)(\d+)", name)
    if not m:
        return name
    return f"$\\varphi^{{{m.group(2)}}}$ (rad)" if m.group(1) == "phi" else f"$\\dot\\varphi^{{{m.group(2)}}}$ (rad/s)"


def _measure_label(measure: str, component: int, attrs: dict) -> str:
    t1 = attrs["args"]["t1"]
    return {"flip_time": f"flip time (s; blank: none within {t1:g} s)", "energy_error": "largest |E(t) - E(0)|",
            "lyapunov": "largest Lyapunov exponent (1/s)", "code": "integrator return code"}.get(
        measure, f"final state component {component}")
