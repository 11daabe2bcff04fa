"""The phone variant of each chart of the documentation: X.phone.png beside X.png.

A chart drawn for a desktop page (6 to 13 inches wide, 7 to 12 pt text) is shown 342 px wide on a
390 px phone, where its text would be 5 to 8 px tall. Its phone variant is the same figure laid
out again: its panels one under the other, 3.5 inches wide, every text at least 9 pt, so that at
342 px each letter is at least 11 px. The site shows it on narrow screens (mkdocs_hooks.py: a
``<picture>`` whose ``<source>`` is X.phone.png), and its PNG records its width in inches and its
smallest text in points, which the docs test turns into pixels on the phone.

    python examples/phone_figures.py SCRIPT [ARGS...]      run a figure script
    python examples/phone_figures.py -m MODULE [ARGS...]   run a module (gyrochain plot ...)

Either way each PNG the program saves also gets its phone variant; bench/report.py calls
``save_phone`` itself.
"""
from __future__ import annotations

import runpy
import sys
import re
from pathlib import Path

WIDTH_IN = 3.5  # the figure's width on a phone, in inches: 342 px for 252 pt, 1.36 px a point
SMALLEST_PT = 9.0  # 9 pt at 1.36 px a point: 12.2 px (11.5 px where a long label widens the figure 6 %)
PANEL_IN = 2.5  # the height of each panel, in inches
DPI = 200  # 700 px wide: sharp on a screen of two device pixels to a CSS pixel
LEGEND_DROP = 3.6  # how far under its axis a panel's legend hangs, in its letters' size: below the tick labels and the label
KEY = "gyrochain-phone"  # the PNG text chunk: "width_in=W smallest_pt=S"


def phone_path(path: Path) -> Path:
    """X.png -> X.phone.png; a file written beside and renamed (.X.png.tmp) names its target."""
    name = path.name
    if name.startswith(".") and name.endswith(".tmp"):
        name = name[1:-len(".tmp")]
    return path.with_name(Path(name).stem + ".phone.png")


def _wrap(text, width_pt: float) -> None:
    """A title, label or legend entry wider than ``width_pt`` broken into lines between words (a
    formula between dollars is one word), at about half an em a letter."""
    s = text.get_text()
    most = max(1, int(width_pt / (0.55 * text.get_fontsize())))
    lines = []
    for line in s.splitlines():
        words, out = re.findall(r"\$[^$]*\$\S*|\S+", line), ""
        for w in words:
            seen = len(re.sub(r"\\[a-z]+|[${}^_]", "", w))  # the letters a formula shows, roughly
            if out and len(re.sub(r"\\[a-z]+|[${}^_]", "", out)) + 1 + seen > most:
                lines.append(out)
                out = w
            else:
                out = f"{out} {w}" if out else w
        lines.append(out)
    if len(lines) > len(s.splitlines()):
        text.set_text("\n".join(lines))


def relayout(fig) -> float:
    """Lay ``fig`` out for a phone, in place: its panels in one column, WIDTH_IN wide, no text
    under SMALLEST_PT. Returns the smallest text size, in points, that the figure then has."""
    from matplotlib.text import Text

    panels = [a for a in fig.axes if a.get_subplotspec() is not None and not hasattr(a, "_colorbar")]
    panels.sort(key=lambda a: (not a.axison, a.get_subplotspec().rowspan.start, a.get_subplotspec().colspan.start))
    w, h = fig.get_size_inches()
    if len({(a.get_subplotspec().rowspan.start, a.get_subplotspec().colspan.start) for a in panels}) > 1:
        # a cell without axes (a legend's, say) gets a row as tall as its legend, after the panels
        rows = [PANEL_IN if a.axison else 0.22 * len(a.get_legend().get_texts() if a.get_legend() else []) + 0.1
                for a in panels]
        grid = fig.add_gridspec(len(panels), 1, height_ratios=rows)
        for i, a in enumerate(panels):
            a.set_subplotspec(grid[i])
        height = sum(rows) + 0.4
    else:
        height = max(PANEL_IN + 0.4, min(1.1 * WIDTH_IN, WIDTH_IN * h / w))
    for leg in list(fig.legends):  # a figure's legend in a row of columns: one column under the panels
        labels = [t.get_text() for t in leg.get_texts()]
        handles = leg.legend_handles
        leg.remove()
        fig.legend(handles, labels, loc="outside lower center", ncols=1, fontsize=SMALLEST_PT, frameon=False)
        height += 0.2 * len(labels)
    fig.set_size_inches(WIDTH_IN, height)
    for a in fig.axes:  # the tick labels are drawn again at each save, at the axis's own size
        for axis, ticks in (("x", a.get_xticklabels()), ("y", a.get_yticklabels())):
            a.tick_params(axis=axis, labelsize=max([SMALLEST_PT] + [t.get_fontsize() for t in ticks]))
    for t in fig.findobj(Text):
        if t.get_text() and t.get_visible():
            t.set_fontsize(max(SMALLEST_PT, t.get_fontsize()))
    for a in fig.axes:  # a panel's legend under its axis label, where it covers no data: the layout makes room
        leg = a.get_legend()
        if leg is None or not a.axison:  # (a cell that only holds a legend keeps it)
            continue
        labels = [t.get_text() for t in leg.get_texts()]
        handles = leg.legend_handles
        leg.remove()
        new = a.legend(handles, labels, loc="upper center", bbox_to_anchor=(0.5, 0.0), borderaxespad=LEGEND_DROP,
                       fontsize=SMALLEST_PT, frameon=False, ncols=1)
        for t in new.get_texts():
            _wrap(t, WIDTH_IN * 72 - 40)
        fig.set_size_inches(WIDTH_IN, fig.get_size_inches()[1] + 0.2 * sum(t.get_text().count("\n") + 1
                                                                            for t in new.get_texts()))
    across = WIDTH_IN * 72 - 30  # the figure's width in points, less a margin
    for leg in fig.legends:
        for t in leg.get_texts():
            _wrap(t, across)
    for a in fig.axes:
        _wrap(a.title, across)
        _wrap(a.xaxis.label, across)
        _wrap(a.yaxis.label, min(height, PANEL_IN) * 72 - 20)
    if fig._suptitle is not None:
        _wrap(fig._suptitle, across)
    try:
        fig.set_layout_engine("constrained")
    except RuntimeError:  # a colorbar of the old engine: keep it, and let tight_layout place things
        fig.set_layout_engine("tight")
    return min(t.get_fontsize() for t in fig.findobj(Text) if t.get_text() and t.get_visible())


def save_phone(fig, path: Path, text: dict | None = None) -> Path:
    """Write the phone variant of ``fig`` (saved for a desktop page at ``path``) beside it, with
    the PNG text chunks ``text`` besides its own."""
    import io

    from PIL import Image
    from PIL.PngImagePlugin import PngInfo

    out = phone_path(Path(path))
    smallest = relayout(fig)
    drawn = io.BytesIO()
    fig.savefig(drawn, format="png", dpi=DPI, bbox_inches="tight", pad_inches=0.04, metadata={"Software": None})
    with Image.open(drawn) as im:
        meta = PngInfo()
        for key, value in (text or {}).items():
            meta.add_text(key, value)
        meta.add_text(KEY, f"width_in={im.width / DPI:.3f} smallest_pt={smallest:.2f}")
        im.save(out, pnginfo=meta, optimize=True)
    return out


def _patched_savefig():
    """Figure.savefig that, after writing a PNG, writes its phone variant."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    original = Figure.savefig

    def savefig(self, fname, *args, **kwargs):
        original(self, fname, *args, **kwargs)
        fmt = kwargs.get("format") or Path(str(fname)).suffix.lstrip(".")
        if isinstance(fname, (str, Path)) and fmt.lower() == "png" and not Path(fname).stem.endswith(".phone"):
            target = phone_path(Path(fname))
            if target.name != Path(fname).name:
                print(f"wrote {save_phone(self, Path(fname))}", file=sys.stderr)

    Figure.savefig = savefig


def main(argv: list[str]) -> int:
    if not argv:
        print(__doc__.strip().splitlines()[0], file=sys.stderr)
        return 2
    _patched_savefig()
    if argv[0] == "-m":
        sys.argv = argv[1:]
        runpy.run_module(argv[1], run_name="__main__", alter_sys=True)
    else:
        sys.argv = argv
        runpy.run_path(argv[0], run_name="__main__")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
