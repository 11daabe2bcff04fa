"""The generated LaTeX typeset into a PDF by LuaLaTeX (``generate --pdf``).

Two passes, as the document's cross-references need; in the folder of the ``.tex``, whose auxiliary
files are removed when the PDF is made.  Where LuaLaTeX is missing or stops, one line says so
(the log kept for reading)."""
from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

from ..chainspec.spec import SpecError

NEEDS = "needs LuaLaTeX (on Debian: apt-get install texlive-luatex texlive-latex-recommended fonts-dejavu-core)"
AUXILIARY = (".aux", ".log", ".out", ".toc")


def available() -> None:
    """Raise the one-line error of ``--pdf`` where LuaLaTeX is not installed."""
    if shutil.which("lualatex") is None:
        raise SpecError("--pdf", NEEDS)


def pdf(tex: Path, timeout: float = 600.0) -> tuple[Path, int]:
    """Typeset ``tex`` (two passes): the PDF and its number of pages."""
    available()
    tex = Path(tex)
    log = tex.with_suffix(".log")
    for _ in range(2):
        try:
            r = subprocess.run(["lualatex", "-interaction=nonstopmode", "-halt-on-error", tex.name], cwd=tex.parent,
                               stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                               timeout=timeout)
        except subprocess.TimeoutExpired:
            raise SpecError("--pdf", f"LuaLaTeX took more than {timeout:.0f} s over {tex}; its log is {log}") from None
        if r.returncode != 0:
            raise SpecError("--pdf", f"LuaLaTeX stopped on {tex}: {_first_error(log)} (its log is {log})")
    made = tex.with_suffix(".pdf")
    pages = _pages(log)
    for suffix in AUXILIARY:
        tex.with_suffix(suffix).unlink(missing_ok=True)
    return made, pages


def _first_error(log: Path) -> str:
    try:
        text = log.read_text(encoding="utf-8", errors="replace")
    except OSError:
        return "no log was written"
    m = re.search(r"^! (.+)$", text, re.M)
    return m.group(1).strip() if m else "see the log"


def _pages(log: Path) -> int:
    try:
        m = re.search(r"Output written on .*?\((\d+) pages?", log.read_text(encoding="utf-8", errors="replace"), re.S)
    except OSError:
        return 0
    return int(m.group(1)) if m else 0
