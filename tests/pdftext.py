"""The text of a generated document's Appendix B as a PDF reader sees it.

A reader of the printed listing, written apart from the printer: every character that MuPDF
extracts from the PDF in the listing's monospaced font (the ActualText of a drawn tab is the tab
it stands for) is put back on its line and in its column.  A row's line is the number in the
margin on its baseline; a row with no number continues the line above it (a line longer than
the text width).  The column is the monospaced column its glyph starts in (its origin), counted
from the text's left edge, so a run of blanks and the indentation come back as they were; blanks
at the end of a line, which no page shows, do not.  ``page_text`` is what a plain text extraction
gives (poppler's pdftotext, MuPDF's get_text()), for the tests that compare it whitespace aside.
"""
from __future__ import annotations

import shutil
import statistics
import subprocess

LISTING_FONT = "DejaVuSansMono"
TAB = 8


def _chars(page):
    raw = page.get_text("rawdict")
    for block in raw["blocks"]:
        for line in block.get("lines", []):
            for span in line["spans"]:
                if LISTING_FONT not in span["font"]:
                    continue
                for c in span["chars"]:
                    yield c["c"], c["bbox"], c["origin"]


def listing(pdf) -> str:
    """The listing's text: its lines, numbered in the margin, joined by newlines."""
    import pymupdf

    rows = []  # (number or None, [(x, ch)]) in reading order
    with pymupdf.open(pdf) as doc:
        for page in doc:
            chars = [c for c in _chars(page) if c[0] not in " \n"]  # spaces come back from the columns
            if not chars:
                continue
            # the text's left edge: the leftmost glyph that is not a digit (a line number is a digit left of it)
            left = min(origin[0] for ch, _, origin in chars if not ch.isdigit())
            pitch = _pitch(chars)
            numbers: dict[float, str] = {}
            body: dict[float, list] = {}
            for ch, bbox, origin in sorted(chars, key=lambda c: c[2][0]):
                y = round(origin[1], 1)
                if bbox[2] < left - 2:
                    numbers[y] = numbers.get(y, "") + ch
                else:
                    body.setdefault(y, []).append((round((origin[0] - left) / pitch), ch))
            for y in sorted(set(numbers) | set(body)):
                rows.append((int(numbers[y]) if y in numbers else None, body.get(y, [])))
    lines: list[list] = []
    numbers_seen = []
    for number, row in rows:
        if number is not None:
            lines.append([row])
            numbers_seen.append(number)
        else:
            assert lines, "a continuation row before the first numbered line"
            lines[-1].append(row)
    assert numbers_seen == list(range(1, len(numbers_seen) + 1)), "the listing's line numbers do not run 1, 2, …"
    out = []
    for parts in lines:
        line, col = "", 0
        for row in parts:
            base = col  # a continuation row starts where the row before it ended
            for c, ch in row:
                c += base
                assert c >= col, f"line {len(out) + 1}: two characters in column {c}"
                line += " " * (c - col) + ch
                col = c + 1 if ch != "\t" else (c // TAB + 1) * TAB
        out.append(line)
    return "\n".join(out)


def _pitch(chars) -> float:
    """The width of a monospaced column: the advance of the listing's letters."""
    return statistics.median(bbox[2] - bbox[0] for ch, bbox, _ in chars if ch.isascii() and ch.isalpha())


def pdftotext(pdf) -> str | None:
    """poppler's plain text of the PDF (as Evince and Okular read it), None without pdftotext."""
    if shutil.which("pdftotext") is None:
        return None
    return subprocess.run(["pdftotext", "-enc", "UTF-8", str(pdf), "-"], capture_output=True, text=True,
                          check=True, timeout=120).stdout


def mupdf_text(pdf) -> str:
    """MuPDF's plain text of the PDF, page after page."""
    import pymupdf

    with pymupdf.open(pdf) as doc:
        return "".join(page.get_text() for page in doc)


def missing_lines(text: str, source: str) -> list[str]:
    """The lines of ``source`` that ``text`` does not contain, whitespace aside (a line wrapped
    on the page, a run of blanks, the numbers in the margin between lines do not count)."""
    flat = "".join(text.split())
    return [line for line in source.split("\n") if "".join(line.split()) not in flat]
