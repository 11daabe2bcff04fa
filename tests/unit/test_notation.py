"""One symbol, one meaning: every symbol a generated document uses is in its notation table, and
no symbol is defined twice there (issue 49, item 4).  tests/texnotation.py is the scanner."""
from __future__ import annotations

import pytest

import texnotation
from conftest import ONE_ARM, ROOT


@pytest.mark.parametrize("name", ONE_ARM)
def test_every_symbol_of_a_committed_document_is_in_its_table(name):
    tex = (ROOT / "generated" / name / f"{name}.tex").read_text()
    assert texnotation.undefined(tex) == set()


def test_the_scanner_finds_an_undefined_and_a_doubly_defined_symbol():
    """The scan fails on the clashes issue 49 found: a letter used but not in the table, a letter
    defined twice, a parameter in serif type that reads as a document letter."""
    tex = (ROOT / "generated" / "gimbal" / "gimbal.tex").read_text()
    assert texnotation.undefined(tex.replace(r"\end{document}", r"$y_k$ \end{document}")) == set()  # Appendix B is text
    used = tex.replace(r"\section*{References}", r"With $\nu^k$ the \section*{References}")
    assert texnotation.undefined(used) == {"nu"}
    table_row = r"$g$ & m/s$^2$ &"
    assert table_row in tex
    twice = tex.replace(table_row, r"$g$, $k$ & m/s$^2$ &")
    with pytest.raises(ValueError, match="k is defined twice"):
        texnotation.undefined(twice)
    furuta = (ROOT / "generated" / "furuta_sym" / "furuta_sym.tex").read_text()
    assert r"$\mathsf{m}_{1}$" in furuta
    with pytest.raises(ValueError, match="m is defined twice"):
        texnotation.undefined(furuta.replace(r"$\mathsf{m}_{1}$", "$m_{1}$"))


def test_the_scanner_reads_fonts_accents_and_indices():
    assert texnotation.symbols(r"\mathsf{omega}_{1} + \mathsf{g}\,\mathcal E(\varphi)\,\mathbf{A}^k") == [
        "sf:omega", "sf:g", "cal:E", "varphi", "bf:A", "k"]
    assert texnotation.symbols(r"\hat{\mathbf e}^k_i\cdot\boldsymbol\lambda^p\,\dot\varphi^r x^{\mathsf T}") == [
        "bf:e", "k", "i", "bf:lambda", "p", "varphi", "r", "x"]
    assert texnotation.symbols(r"\int \Phi\,d\varphi + dE/dt + \text{a word} + \mathrm{rest} + \operatorname{sgn}(\pi)") == [
        "Phi", "varphi", "E", "t"]
