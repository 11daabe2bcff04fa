"""The symbols a generated document uses, and the ones its notation table defines (issue 49, item 4).

A scanner of the printed LaTeX written apart from the printer: every letter in math mode — a
Latin letter, a Greek letter, in its font (bold, sans serif, calligraphic) and with its accents
(a dot, a hat, a ring) dropped — is a symbol; indices are symbols too.  Upright words
(``\\mathrm{rest}``, ``\\text{…}``, ``\\operatorname{sgn}``), the functions sin, cos, …, and numbers
are not.  The notation table is the tabular after "\\section*{Notation}": its first column
lists the symbols it defines, the first symbol of each comma-separated item being the one defined.
"""
from __future__ import annotations

import re

GREEK = {"ell", "alpha", "beta", "gamma", "delta", "epsilon", "varepsilon", "zeta", "eta", "theta", "vartheta", "iota", "kappa",
         "varkappa", "lambda", "mu", "nu", "xi", "pi", "varpi", "rho", "varrho", "sigma", "tau", "upsilon", "phi", "varphi",
         "chi", "psi", "omega", "Gamma", "Delta", "Theta", "Lambda", "Xi", "Pi", "Sigma", "Upsilon", "Phi", "Psi", "Omega"}
FONTS = {"mathbf": "bf", "boldsymbol": "bf", "mathsf": "sf", "mathcal": "cal", "mathfrak": "frak"}
UPRIGHT = r"\\(?:text|texttt|mathrm|operatorname|textrm|textit|emph|label|mbox)\s*\{[^{}]*\}"
# π is the number, d the differential (d\varphi, \frac{d}{dt}), e never a symbol alone (none is printed)
NUMBERS = {"pi"}


def math_segments(tex: str) -> list[str]:
    """The document's math: $…$, \\[…\\], align*, without the comments, the spec's description (its
    symbols are the user's, defined in its words) and Appendix B (the spec as text)."""
    tex = re.sub(r"(?<!\\)%.*", "", tex)
    tex = tex.split(r"\section*{Appendix B", 1)[0]
    tex = re.sub(r"\\begin\{quote\}.*?\\end\{quote\}", " ", tex, count=1, flags=re.S)  # the spec's description, the user's words
    body = tex.split(r"\begin{document}", 1)[-1]
    out = []
    for m in re.finditer(r"\\begin\{(align\*|equation\*)\}(.*?)\\end\{\1\}|\\\[(.*?)\\\]|(?<!\\)\$(.+?)(?<!\\)\$", body, flags=re.S):
        out.append(m.group(2) or m.group(3) or m.group(4) or "")
    return out


def symbols(math: str) -> list[str]:
    """The symbols of a piece of math, in order, each as 'x', 'alpha', 'bf:e', 'sf:l'."""
    math = re.sub(UPRIGHT, " ", math)
    math = re.sub(r"\\(?:begin|end)\{[a-z*]+\}", " ", math)
    math = re.sub(r"\^\{?\\mathsf\s*\{?T\}?\}?", " ", math)  # the transpose
    math = re.sub(r"\\(?:frac\{d\}\{dt\}|,|;|!|quad|qquad)", " ", math)
    math = re.sub(r"(?<![A-Za-z\\])d(?=[A-Za-z]|\\varphi|\\psi)", " ", math)  # differentials: dφ, dt, dE
    # a font's group is one symbol: \mathsf{omega}, \mathsf{g}, \mathcal{E}, \mathbf{A}
    math = re.sub(r"\\(mathbf|boldsymbol|mathsf|mathcal|mathfrak)\s*\{\\?([A-Za-z]+)\}",
                  lambda m: f" \\{m.group(1)} \\{m.group(2)} " if m.group(2) in GREEK else f" \\{m.group(1)} {m.group(2)}@ ", math)
    out = []
    pos = 0
    token = re.compile(r"\\([A-Za-z]+)\s*|([A-Za-z]+@|[A-Za-z])|.", re.S)
    font = None
    while pos < len(math):
        m = token.match(math, pos)
        pos = m.end()
        word, letter = m.group(1), m.group(2)
        if word in FONTS:
            font = FONTS[word]
            continue
        if word is not None:
            if word in GREEK and word not in NUMBERS:
                out.append(f"{font}:{word}" if font else word)
            font = None if word not in ("hat", "dot", "ddot", "mathring", "bar", "tilde") else font
            continue
        if letter is not None:
            letter = letter.rstrip("@")
            out.append(f"{font}:{letter}" if font else letter)
            font = None
            continue
        if m.group() not in "{ ":
            font = None
    return out


def table(tex: str) -> list[tuple[str, str]]:
    """The notation table's rows: (first column, meaning)."""
    part = tex.split(r"\section*{Notation}", 1)[1]
    part = part[part.index(r"\endhead"):part.index(r"\end{longtable}")]
    rows = part.split("\n")[1:]
    return [tuple(r.rstrip().removesuffix(r"\\").split(" & ", 1)) for r in rows if " & " in r]


def defined(tex: str) -> dict[str, int]:
    """Each symbol the table defines -> the row that defines it; a symbol defined twice raises."""
    out: dict[str, int] = {}
    for i, (left, _) in enumerate(table(tex)):
        for item in re.findall(r"\$(.+?)\$", left):
            syms = symbols(item)
            if not syms:
                continue
            head = syms[0]
            if head in out and out[head] != i:
                raise ValueError(f"{head} is defined twice in the notation table (rows {out[head] + 1} and {i + 1})")
            out[head] = i
    return out


def undefined(tex: str) -> set[str]:
    """The symbols the document uses that its notation table does not define."""
    known = defined(tex)
    used = {s for seg in math_segments(tex) for s in symbols(seg)}
    return used - set(known)
