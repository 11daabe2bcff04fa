"""Appendix B: the spec file as a listing whose text is the file's, for every PDF reader.

The document is typeset by LuaLaTeX with a monospaced OpenType font that has the glyphs of the
file (DejaVu Sans Mono: Latin, Greek, super- and subscripts, ≈, arrows), so each character of the
file is a glyph whose text is that character: poppler's ``pdftotext``, MuPDF and a copy from any
viewer read the file back.  Each line of the file is a row with its number in the margin; a line
longer than the text width continues on rows of its own, marked in the margin by a drawn hook
(a path, not a character: it adds nothing to the text).  Spaces are the font's space glyph, so
indentation and runs of blanks are in the text too.  Nothing here reads fonts: a character the
font lacks is found by TeX (``\\iffontchar``) and drawn as a boxed "?" whose ActualText is the
character (MuPDF reads it; poppler has no text for it).
"""
from __future__ import annotations

from dataclasses import dataclass

COLUMNS = 92  # columns of the listing: 92 × 0.602 em of 8 pt type = 443 pt, inside A4's and letter's text width
TAB = 8  # a tab is drawn as an arrow and the spaces to the next multiple of 8 columns
# characters TeX reads as commands in the rows' text: each is typeset as its own glyph
_SPECIAL = set("\\{}$&#^_%~")


@dataclass(frozen=True)
class Row:
    number: int | None  # the file's line number; None on a continuation row
    text: str  # TeX: the row's characters, each one glyph


def _char(ch: str) -> str:
    if ch == " ":
        return r"\gcsp "
    if ch in _SPECIAL:
        return rf"\char{ord(ch)} "
    if ch.isascii() and ch.isprintable():
        return ch
    return rf"\gcu{{{ord(ch):X}}}{{{ch.encode('utf-16-be').hex().upper()}}}"


def _expanded(line: str) -> list[tuple[str, int]]:
    """The line's characters with the columns each takes (a tab: to the next multiple of TAB)."""
    out, col = [], 0
    for ch in line:
        span = TAB - col % TAB if ch == "\t" else 1
        out.append((ch, span))
        col += span
    return out


def _break(chars: list[tuple[str, int]], width: int) -> int:
    """Where a row of more than ``width`` columns ends: before a blank in its last third that
    follows a character that is not one (the blank starts the next row, so the row ends with a
    glyph and no blank is lost), else at the width."""
    cols, col = [], 0
    for _, span in chars:
        cols.append(col)
        col += span
    fits = max(1, sum(1 for i, c in enumerate(cols) if c + chars[i][1] <= width))
    for i in range(fits, max(1, fits - width // 3), -1):
        if i < len(chars) and chars[i][0] in " \t" and chars[i - 1][0] not in " \t":
            return i
    while fits > 1 and chars[fits - 1][0] in " \t":  # a hard break: the row still ends with a glyph
        fits -= 1
    return fits


def rows(text: str, width: int = COLUMNS) -> list[Row]:
    """The listing's rows: each line of ``text`` as one row, or as several when it is longer
    than ``width`` columns."""
    out = []
    for number, line in enumerate(text.split("\n"), start=1):
        chars = _expanded(line.rstrip(" \t"))
        first = True
        while first or chars:
            cut = _break(chars, width) if sum(s for _, s in chars) > width else len(chars)
            body = "".join(r"\gctab{%d}" % span if ch == "\t" else _char(ch) for ch, span in chars[:cut])
            out.append(Row(number if first else None, body))
            chars, first = chars[cut:], False
    return out


def listing(text: str) -> dict:
    """What the template lays out: the rows, the width in columns and whether the file has tabs."""
    return dict(rows=rows(text), columns=COLUMNS, tab=TAB, tabs="\t" in text)
