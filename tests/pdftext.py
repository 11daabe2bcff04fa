"""The text of a generated document's Appendix B as a PDF reader sees it (issue 49, item 3).

A reader of the printed listing, written apart from the printer: every character that MuPDF
extracts from the PDF (the ActualText of a drawn Greek letter, subscript or ≈ is the character it
stands for) is put back on its line and in its column.  The line is the line number in the margin
whose baseline is nearest; the column is the typewriter column its glyph starts in (its origin),
counted from the text's left edge.  Spaces are the columns between glyphs, so a run of blanks and
the indentation come back as they were; blanks at the end of a line, which no page shows, do not.
"""
from __future__ import annotations

import statistics

LEFT = 18 / 25.4 * 72  # the documents' left margin, 18 mm (model.tex.jinja's geometry)
TAB = 8


def _chars(page):
    raw = page.get_text("rawdict")
    for block in raw["blocks"]:
        for line in block.get("lines", []):
            for span in line["spans"]:
                for c in span["chars"]:
                    yield c["c"], span["size"], c["bbox"], c["origin"]


def listing(pdf) -> str:
    """The listing's text: its lines, numbered in the margin, joined by newlines."""
    import pymupdf

    text: dict[int, list[tuple[int, str]]] = {}
    with pymupdf.open(pdf) as doc:
        for page in doc:
            chars = [c for c in _chars(page) if c[0] not in " \n"]  # MuPDF's spaces are its guesses
            numbers: dict[float, list] = {}
            for ch, size, bbox, origin in chars:
                if bbox[2] <= LEFT and ch.isdigit():
                    numbers.setdefault(round(origin[1], 1), []).append((bbox[0], ch))
            if not numbers:
                continue
            baselines = {y: int("".join(ch for _, ch in sorted(ds))) for y, ds in numbers.items()}
            body = [(ch, size, bbox, origin) for ch, size, bbox, origin in chars if bbox[0] >= LEFT]
            pitch = _pitch(body, baselines)
            for y, number in baselines.items():
                text.setdefault(number, [])
            for ch, size, bbox, origin in body:
                y = min(baselines, key=lambda b: abs(b - origin[1]))
                if abs(y - origin[1]) < 3.5:
                    col = round((origin[0] - LEFT) / pitch)
                    text[baselines[y]].append((col, ch))
    assert sorted(text) == list(range(1, len(text) + 1)), "the listing's line numbers do not run 1, 2, …"
    out = []
    for number in sorted(text):
        line, col = "", 0
        for c, ch in sorted(text[number]):
            assert c >= col, f"line {number}: two characters in column {c}"
            line += " " * (c - col) + ch
            col = c + 1 if ch != "\t" else (c // TAB + 1) * TAB
        out.append(line)
    return "\n".join(out)


def _pitch(body, baselines) -> float:
    """The width of a typewriter column: the advance of the listing's ASCII letters."""
    on_lines = [(ch, bbox) for ch, size, bbox, origin in body
                if min(abs(origin[1] - y) for y in baselines) < 0.5 and ch.isascii() and ch.isalnum()]
    return statistics.median(bbox[2] - bbox[0] for _, bbox in on_lines)
