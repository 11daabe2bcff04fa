"""The layout of the LaTeX's displays: how wide a line may be, the document's equation numbers,
equations in rows (two or three to a row when they are short), matrices side by side."""
from __future__ import annotations

from dataclasses import dataclass

from .texterms import visible

DISPLAY_WIDTH = 24  # ems of a formula's line beside its name and number on a portrait page of 11 pt type
TEXT_WIDTH = 41  # ems of the text width (455 pt of A4 with 25 mm margins, 468 pt of letter, in 11 pt type)
INLINE = float("inf")  # a formula in the text: TeX breaks it at its signs


@dataclass(frozen=True)
class TexEquation:
    lhs: str
    lines: tuple[str, ...]  # a Shown when the quantity was expanded
    paper: str = ""  # the paper's number of the same equation, if it has one


class Numbers:
    """The document's equation numbers, handed out as the template prints its displays: a number
    of its own for each, and the paper's beside it where the paper has the same equation."""

    def __init__(self):
        self.last = 0

    @property
    def peek(self) -> int:
        """The number the next display gets (for a sentence that refers to it)."""
        return self.last + 1

    def tag(self, paper: str = "") -> str:
        self.last += 1
        if paper:
            return rf"\tag*{{({self.last})\quad\text{{[paper ({paper})]}}}}"
        return rf"\tag{{{self.last}}}"


def _zero(lines) -> bool:
    return tuple(lines) == ("0",)


def block(eqs: list[TexEquation]) -> dict:
    """Equations to print, in the rows of the display (two to a row when every one is a short
    line: a long chain's M_kr), and the names of those that are zero (one line states them)."""
    rows = [e for e in eqs if not _zero(e.lines)]
    zero = [e.lhs for e in eqs if _zero(e.lines)]
    widest = max((visible(e.lhs) + visible(e.lines[0]) + 2 if len(e.lines) == 1 else TEXT_WIDTH for e in rows), default=0)
    per = max(1, min(3, int((TEXT_WIDTH - 4) // (widest + 2)))) if len(rows) > 2 else 1
    table = [rows[i:i + per] for i in range(0, len(rows), per)]
    return dict(rows=rows, table=table, zero=", ".join(f"${z}$" for z in zero))


def matrix_width(tex: str) -> float:
    """About how wide a printed pmatrix is set (texterms.visible): its widest column each."""
    body = tex.removeprefix(r"\begin{pmatrix}").removesuffix(r"\end{pmatrix}")
    rows = [row.split("&") for row in body.split(r"\\")]
    return sum(max(visible(r[j]) if j < len(r) else 0 for r in rows) + 1 for j in range(max(len(r) for r in rows)))


def per_row(cells: list[str], width: float) -> int:
    """How many matrices a row of a display or a table takes: two when each fits half the width."""
    return 2 if len(cells) > 1 and max(matrix_width(c) for c in cells) < width / 2 - 4 else 1


def term_counts(counts: list) -> str:
    """"1 term in $M$, 0 in $Q$, …": each count bound to its symbol, so no line breaks between them."""
    words = [f"{c}~term{'s' if c != 1 else ''} in~${sym}$" if i == 0 else f"{c}~in~${sym}$"
             for i, (sym, c) in enumerate(counts)]
    return ", ".join(words)
