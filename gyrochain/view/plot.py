"""``plot``: the pictures of a sweep store (matplotlib, the ``sweep`` extra)."""
from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from ..ensembles import sweep as sw
from ..chainspec.spec import SpecError


FORMATS = ("png", "pdf", "svg")  # the images plot writes (matplotlib's Agg, no extra library)


NO_VALUE = "0.82"  # the grey of points without a value (no flip within t1, a failed run): no colour map's


def store(path: str | Path, output: str | Path, measure: str = "", component: int | str = 0, cmap: str = "",
          log: bool = False, dpi: int = 150, note=None) -> Path:
    """A heat map (two varied quantities), a scatter (random samples) or a curve (one) of a sweep
    store's measure, written to ``output`` (png, pdf, svg); returns its path.  Points without a
    value (no flip within t1, a run that failed) are grey on a map and said so in a legend; the
    points of chunks not computed (an interrupted sweep, a chunk damaged on disk) are white, and
    ``note(line)`` is told how many."""
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
    values, comp = _values(data, measure, component)
    computed = data["computed"]
    if note is not None and missing_note(data):
        note(missing_note(data))
    values = np.where(computed, values, np.nan)  # a chunk not (or no longer) computed has no value: not "no flip"
    names = [v[0] for v in a["vary"]]
    if len(names) > 2:
        raise SpecError("store", f"plot shows one or two varied quantities; this sweep varies {len(names)}")
    if not names:
        raise SpecError("store", f"{path} holds one run (its sweep varied nothing): plot draws a measure over one or two "
                        "varied quantities (sweep --vary NAME=lo:hi:N); `gyrochain animate` shows one motion")
    if len(names) == 1 and cmap:
        raise SpecError("--cmap", "a curve has no colours (the sweep varies one quantity)")
    plt, colormap = _matplotlib(cmap or ("OrRd" if measure == "floquet" else "viridis"))
    if log and not np.any(np.isfinite(values) & (values > 0)):
        raise SpecError("--log", f"{measure} has no positive value to draw on a logarithmic scale")
    label = _measure_label(measure, comp, data["attrs"])
    fig, ax = plt.subplots(figsize=(6.4, 5.2) if len(names) == 2 else (6.4, 4.0), dpi=dpi)
    if len(names) == 2:
        _map(fig, ax, data, names, values, colormap, log, label, computed)
    else:
        x = data["coords"][names[0]]
        order = np.argsort(x)
        ax.plot(x[order], values[order], ".-" if len(x) < 200 else "-")
        if log:
            ax.set_yscale("log")
            _plain_log(ax.yaxis)
        ax.set_xlabel(_axis_label(names[0]))
        ax.set_ylabel(label)
    title = f"{data['attrs']['spec_name']}: {label.split(' (')[0]}"
    if measure == "flip_time":
        title += "\n" + _flip_definition(data["attrs"])
    ax.set_title(title, fontsize=10)
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


def _values(data: dict, measure: str, component: int | str) -> tuple[np.ndarray, str]:
    """The measure's values per point and, for ``final``, the state component's name (phiK or
    phidotK), for ``lyapunov_spectrum`` the exponent's (lambdaK, K = 1 the largest); --component
    takes the name or its 0-based index."""
    values = data[measure]
    if measure not in sw.EXTRA_DIM:
        if component not in (0, "0", "", None):
            raise SpecError("--component", f"only the measures {' and '.join(sw.EXTRA_DIM)} have components "
                                            f"({measure} is one number per point)")
        return values, ""
    dim = values.shape[-1]
    n = dim // 2
    if measure == "final":
        names = [f"phi{k}" for k in range(1, n + 1)] + [f"phidot{k}" for k in range(1, n + 1)]
    else:
        names = [f"lambda{k}" for k in range(1, dim + 1)]
    comp = str(component)
    if comp.isdigit() and int(comp) < dim:
        comp = names[int(comp)]
    if comp not in names:
        raise SpecError("--component", f"one of {', '.join(names)} (or 0..{dim - 1}), got {component!r}")
    return values[..., names.index(comp)], comp


def _matplotlib(cmap: str):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        raise SpecError("plot", "needs matplotlib: pip install 'gyrochain[plot]'") from None
    if cmap not in matplotlib.colormaps:
        raise SpecError("--cmap", f"{cmap!r} is not a matplotlib colour map (for example viridis, magma, cividis)")
    return plt, matplotlib.colormaps[cmap].with_extremes(bad=NO_VALUE)


def missing_note(data: dict) -> str:
    """What a partial store lacks, as plot says it: the chunks not computed (an interrupted sweep)
    and those damaged on disk; "" for a complete store."""
    n_chunks = len(data["done"])
    lost = n_chunks - int(np.sum(data["done"]))
    if not lost:
        return ""
    points = int(np.sum(~data["computed"]))
    damaged = f" ({len(data['damaged'])} of them damaged on disk)" if len(data["damaged"]) else ""
    return (f"note: {lost} of {n_chunks} chunks of the store are not computed{damaged}: {points} points drawn "
            "white as 'not computed'; run the same sweep again to finish it")


def _map(fig, ax, data: dict, names: list, values: np.ndarray, colormap, log: bool, label: str, computed=None) -> None:
    """A heat map of a grid or a scatter of random samples, with a colour bar (readable ticks on a
    logarithmic one) and a legend entry for the points without a value."""
    from matplotlib.colors import LogNorm
    from matplotlib.patches import Patch

    norm = LogNorm() if log else None
    if "Floquet" in label:
        _stable_region(fig, ax, data, names, values, colormap, label)
        return
    if data["attrs"]["args"]["random"]:
        art = ax.scatter(data["coords"][names[0]], data["coords"][names[1]], c=values, s=4, cmap=colormap, norm=norm,
                         plotnonfinite=True)
    else:
        art = ax.pcolormesh(data["coords"][names[0]], data["coords"][names[1]], np.ma.masked_invalid(values.T),
                            shading="nearest", cmap=colormap, norm=norm)
    bar = fig.colorbar(art, ax=ax, label=label)
    if log:
        _plain_log(bar.ax.yaxis)
    ax.set_xlabel(_axis_label(names[0]))
    ax.set_ylabel(_axis_label(names[1]))
    computed = np.ones(values.shape, bool) if computed is None else computed
    missing = int(np.sum(~np.isfinite(values) & computed))
    handles = []
    if missing:
        what = "no flip" if "flip" in label else "no value"
        handles.append(Patch(facecolor=NO_VALUE, edgecolor="0.4", label=f"{what} ({missing} points)"))
    if not computed.all():
        from matplotlib.colors import ListedColormap

        blank = np.ma.masked_where(computed, np.zeros(values.shape))
        if data["attrs"]["args"]["random"]:
            ax.scatter(data["coords"][names[0]][~computed], data["coords"][names[1]][~computed], c="white", s=4,
                       edgecolors="0.6", linewidths=0.3)
        else:
            ax.pcolormesh(data["coords"][names[0]], data["coords"][names[1]], blank.T, shading="nearest",
                          cmap=ListedColormap(["white"]))
        handles.append(Patch(facecolor="white", edgecolor="0.4", label=f"not computed ({int(np.sum(~computed))} points)"))
    if handles:
        ax.legend(handles=handles, loc="upper right", fontsize=8, framealpha=0.9)


STABLE = "#c6dbef"  # the colour of the stable region of a floquet map (a pale blue, in no default colour map)


def _stable_region(fig, ax, data: dict, names: list, values: np.ndarray, colormap, label: str) -> None:
    """A floquet map: the stable region (every |μ| ≤ 1 + floquet.MU_TOL) in one colour, the unstable
    one coloured by the largest |μ| on a logarithmic scale, the boundary a black line."""
    from matplotlib.colors import ListedColormap, LogNorm
    from matplotlib.patches import Patch

    from ..analysis.floquet import MU_TOL

    colormap = colormap.with_extremes(bad=(0.0, 0.0, 0.0, 0.0))  # the unstable layer leaves the rest uncovered
    stable = np.isfinite(values) & (values <= 1.0 + MU_TOL)
    unstable = np.where(np.isfinite(values) & ~stable, values, np.nan)
    x, y = data["coords"][names[0]], data["coords"][names[1]]
    handles = [Patch(facecolor=STABLE, edgecolor="0.4", label=f"stable: every |μ| ≤ 1 ({int(stable.sum())} points)")]
    if data["attrs"]["args"]["random"]:
        ax.scatter(x[stable], y[stable], c=STABLE, s=4)
        art = ax.scatter(x[~stable], y[~stable], c=unstable[~stable], s=4, cmap=colormap, norm=LogNorm(), plotnonfinite=True)
    else:
        ax.pcolormesh(x, y, np.ma.masked_where(~stable.T, np.ones_like(values.T)), shading="nearest",
                      cmap=ListedColormap([STABLE]))
        art = ax.pcolormesh(x, y, np.ma.masked_invalid(unstable.T), shading="nearest", cmap=colormap,
                            norm=LogNorm(vmin=1.0, vmax=max(np.nanmax(unstable), 1.0 + 1e-3)) if np.any(np.isfinite(unstable)) else None)
        if stable.any() and (~stable).any():
            ax.contour(x, y, stable.T.astype(float), levels=[0.5], colors="k", linewidths=0.8)
    if np.any(np.isfinite(unstable)):
        _plain_log(fig.colorbar(art, ax=ax, label=label).ax.yaxis)
    missing = int(np.sum(~np.isfinite(values)))
    if missing and not data["attrs"]["args"]["random"]:
        ax.pcolormesh(x, y, np.ma.masked_where(np.isfinite(values.T), np.ones_like(values.T)), shading="nearest",
                      cmap=ListedColormap([NO_VALUE]))
    if missing:
        handles.append(Patch(facecolor=NO_VALUE, edgecolor="0.4", label=f"no equilibrium for all t ({missing} points)"))
    ax.legend(handles=handles, loc="upper right", fontsize=8, framealpha=0.9)
    ax.set_xlabel(_axis_label(names[0]))
    ax.set_ylabel(_axis_label(names[1]))


def _plain_log(axis) -> None:
    """A logarithmic axis numbered 1, 2, 5 per decade in plain notation (0.2, 6, 500; not 6 × 10⁰),
    without the unlabelled minor numbers matplotlib adds on a short range."""
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    axis.set_major_locator(LogLocator(subs=(1.0, 2.0, 5.0)))
    axis.set_minor_locator(LogLocator(subs="all"))
    axis.set_major_formatter(FuncFormatter(lambda v, _pos: f"{v:g}"))
    axis.set_minor_formatter(NullFormatter())


def _flip_definition(attrs: dict) -> str:
    """What flip_time measured, as the plot states it."""
    if attrs.get("flip_angles", "relative") == "absolute":
        return "the first time a link's absolute angle φ¹+…+φᵏ passes the upright (±π)"
    return "the first time a joint angle φᵏ passes ±π"


def _axis_label(name: str) -> str:
    m = re.fullmatch(r"(phi|phidot|link)(\d+)", name)
    if not m:
        return name
    if m.group(1) == "link":
        k = int(m.group(2))
        total = {1: "\\varphi^1", 2: "\\varphi^1 + \\varphi^2"}.get(k, f"\\varphi^1 + \\ldots + \\varphi^{{{k}}}")
        return f"link {k}: ${total}$ at t = 0 (rad)"
    return f"$\\varphi^{{{m.group(2)}}}$ (rad)" if m.group(1) == "phi" else f"$\\dot\\varphi^{{{m.group(2)}}}$ (rad/s)"


def _measure_label(measure: str, component: str, attrs: dict) -> str:
    t1 = attrs["args"]["t1"]
    if measure == "final":
        return f"{_axis_label(component).replace(' (', f' at t = {t1:g} s (')}"
    if measure == "lyapunov_spectrum":
        k = component.removeprefix("lambda")
        return f"Lyapunov exponent $\\lambda_{{{k}}}$ (1/s{', the largest' if k == '1' else ''})"
    return {"flip_time": f"flip time (s; grey: none within {t1:g} s)", "energy_error": "largest |E(t) - E(0)| (J)",
            "lyapunov": "largest Lyapunov exponent (1/s)", "floquet": "largest Floquet multiplier |μ|",
            "code": "integrator return code"}[measure]
