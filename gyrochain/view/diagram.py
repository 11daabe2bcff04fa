"""``plot BRANCHES.csv`` (or ``.zarr``): the bifurcation diagram of ``gyrochain continue``'s file (matplotlib).

The branches over the first parameter, one coordinate up the page: stable stretches solid,
unstable ones dashed, each special point marked and labelled with its kind (LP fold, BP branch
point, KC a collision on the imaginary axis, H Hopf, +1 and PD a Floquet multiplier through +1 or
−1, NS a Neimark–Sacker pair). With curves in two parameters (a second ``--vary``), a second panel
draws them in the parameters' plane: the stability chart as a few curves.
"""
from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from ..chainspec.spec import SpecError

FORMATS = ("png", "pdf", "svg")
STYLES = ("-", "--", ":", "-.")
UNITS = {"phi": "rad", "phidot": "rad/s", "period": "s", "amp": "rad"}
MARKERS = {"LP": "s", "BP": "D", "KC": "o", "RC": "o", "H": "^", "+1": "o", "PD": "v", "NS": "^", "KCm": "o"}


def read(path: str | Path) -> tuple[list[str], list[dict]]:
    """The header and rows of a file or store ``continue`` wrote (SpecError if it is not one)."""
    if Path(path).is_dir():
        from ..analysis import branches

        if not branches.is_store(path):
            raise SpecError("store", f"{path} is not a store of gyrochain continue")
        return branches.read_store(path)
    try:
        with open(path, newline="", encoding="utf-8") as fh:
            rows = list(csv.DictReader(fh))
            header = list(rows[0]) if rows else []
    except FileNotFoundError:
        raise SpecError("store", f"{path}: no such file") from None
    except (UnicodeDecodeError, csv.Error):
        raise SpecError("store", f"{path} is not a file of gyrochain continue") from None
    if not rows or header[:2] != ["part", "kind"] or "verdict" not in header:
        raise SpecError("store", f"{path} is not a file of gyrochain continue (its header starts part,kind)")
    return header, rows


def _stable(verdict: str) -> bool:
    return not verdict.startswith("unstable")


def plot(path: str | Path, output: str | Path, component: str = "", dpi: int = 150) -> Path:
    """The diagram of the file at ``path``, written to ``output`` (png, pdf, svg)."""
    output = Path(output)
    if output.suffix.lower().lstrip(".") not in FORMATS:
        raise SpecError("-o", f"{output.name}: an image type plot does not write (give .{', .'.join(FORMATS)})")
    header, rows = read(path)
    params = header[2:header.index("phi1")]
    states = header[header.index("phi1"):header.index("verdict")]  # the angles; a periodic orbit's rates and period too
    phis = [h for h in states if h[3:].isdigit() and h[:3] == ("amp" if "period" in states else "phi")]
    branch_rows = [r for r in rows if r["part"].startswith("branch")]
    curve_rows = [r for r in rows if r["part"].startswith("curve")]
    if component in ("", "0"):  # the coordinate that moves most along the branches
        spread = {p: np.ptp([float(r[p]) for r in branch_rows]) if branch_rows else 0.0 for p in phis}
        component = max(phis, key=lambda p: (spread[p], -phis.index(p)))
    if component not in states:
        raise SpecError("--component", f"{component!r}: the diagram draws one of {', '.join(states)}")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    panels = 2 if curve_rows else 1
    fig, axes = plt.subplots(panels, 1, figsize=(6.4, 4.4 * panels), squeeze=False)  # one under the other
    _branches(axes[0, 0], branch_rows, params[0], component)
    if curve_rows:
        _curves(axes[1, 0], curve_rows, params)
    fig.tight_layout()
    output.parent.mkdir(parents=True, exist_ok=True)
    tmp = output.with_name(f".{output.name}.tmp")
    try:
        fig.savefig(tmp, format=output.suffix.lower().lstrip("."), dpi=dpi)
        tmp.replace(output)
    finally:
        plt.close(fig)
        tmp.unlink(missing_ok=True)
    return output


def _branches(ax, rows, name: str, component: str) -> None:
    parts = list(dict.fromkeys(r["part"] for r in rows))
    for i, part in enumerate(parts):
        pts = [r for r in rows if r["part"] == part]  # the points and the special points, in the branch's order
        x = np.array([float(r[name]) for r in pts])
        y = np.array([float(r[component]) for r in pts])
        colour = f"C{i % 10}"
        styles = []  # each chord in the style of its ordinary ends (a special point's own is moot)
        for k in range(len(pts) - 1):
            ends = [r for r in (pts[k], pts[k + 1]) if not r["kind"]] or [pts[k]]
            styles.append("-" if all(_stable(r["verdict"]) for r in ends) else "--")
        k = 0
        while k < len(styles):  # a run of chords of one style as one line, so that its dashes show
            j = k
            while j + 1 < len(styles) and styles[j + 1] == styles[k]:
                j += 1
            ax.plot(x[k:j + 2], y[k:j + 2], styles[k], color=colour, lw=1.8)
            k = j + 1
        for r in (r for r in rows if r["part"] == part and r["kind"]):
            px, py = float(r[name]), float(r[component])
            ax.plot(px, py, MARKERS.get(r["kind"], "o"), color="k", ms=6, zorder=3)
            ax.annotate(r["kind"], (px, py), textcoords="offset points", xytext=(5, 5), fontsize=9)
    ax.margins(y=0.12)  # room for the labels of a branch along the frame
    ax.plot([], [], "-", color="0.3", label="stable")
    ax.plot([], [], "--", color="0.3", label="unstable")
    ax.legend(fontsize=9, loc="best")
    ax.set_xlabel("energy above the equilibrium's (J)" if name == "energy" else name)
    ax.set_ylabel(f"{component} ({UNITS[component.rstrip('0123456789')]})")
    orbits = "period" in rows[0] if rows else False
    ax.set_title("branches of periodic orbits" if orbits else "branches of equilibria", fontsize=10)
    ax.grid(alpha=0.3)


def _curves(ax, rows, params) -> None:
    a, b = params[0], params[1]
    for i, part in enumerate(dict.fromkeys(r["part"] for r in rows)):
        pts = [r for r in rows if r["part"] == part]
        ax.plot([float(r[a]) for r in pts], [float(r[b]) for r in pts], STYLES[i % len(STYLES)], color=f"C{i % 10}",
                lw=1.8, label=f"{part}: {pts[0]['kind']}")  # a style each: curves that nearly coincide both show
    ax.set_xlabel(a)
    ax.set_ylabel(b)
    ax.set_title("the special points' curves (stability boundaries)", fontsize=10)
    ax.legend(fontsize=9, loc="best")
    ax.grid(alpha=0.3)
