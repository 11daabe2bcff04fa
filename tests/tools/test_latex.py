"""The LaTeX of every example is a standalone document that a real TeX engine compiles."""
from __future__ import annotations

import shutil
import subprocess

import pytest

import pdftext
from conftest import ONE_ARM, ROOT

NO_TEX = "no TeX engine: install Debian's texlive-latex-base (.ci/run does)"


def _file_text(text: str) -> str:
    """The spec file as a page can show it: without the blanks that end a line or the file."""
    return "\n".join(line.rstrip() for line in text.rstrip("\n").split("\n"))


def _appendix_b(pdf, source: str) -> None:
    """Appendix B's text, as a PDF reader extracts it (MuPDF), is the spec file's (issue 49)."""
    pytest.importorskip("pymupdf", reason="the PDF's text needs MuPDF: pip install pymupdf (the test extra has it)")
    got, want = pdftext.listing(pdf), _file_text(source)
    if got != want:
        bad = next(i for i, (a, b) in enumerate(zip(got.split("\n") + [""], want.split("\n") + [""])) if a != b)
        raise AssertionError(f"Appendix B line {bad + 1}: PDF {got.split(chr(10))[bad:bad + 1]!r}, "
                             f"file {want.split(chr(10))[bad:bad + 1]!r}")


@pytest.mark.skipif(shutil.which("pdflatex") is None, reason=NO_TEX)
@pytest.mark.parametrize("name", ONE_ARM)
def test_latex_compiles_to_pdf(name, tmp_path):
    tex = tmp_path / f"{name}.tex"
    tex.write_text((ROOT / "generated" / name / f"{name}.tex").read_text())
    res = subprocess.run(["pdflatex", "-interaction=nonstopmode", "-halt-on-error", tex.name], cwd=tmp_path,
                         capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stdout[-3000:]
    pdf = tmp_path / f"{name}.pdf"
    assert pdf.exists() and pdf.stat().st_size > 10_000
    log = (tmp_path / f"{name}.log").read_text(errors="replace")
    assert "Undefined control sequence" not in log
    # no box that runs into the margin or off the page (a long chain's tables), no character the
    # font lacks (issue 25: the build log is checked)
    assert "Overfull" not in log and "Missing character" not in log, [
        ln for ln in log.splitlines() if ln.startswith(("Overfull", "Missing character"))][:5]
    # no warning but longtable's on a first pass (its column widths settle on the second, as `make pdf` runs it)
    first_pass = ("Package longtable Warning: Column widths have changed", "Package longtable Warning: Table widths have changed")
    warned = [ln for ln in log.splitlines() if "Warning" in ln and not ln.startswith(first_pass)]
    assert not warned, warned[:5]
    _appendix_b(pdf, (ROOT / "specs" / f"{name}.toml").read_text())


TRICKY = (
    "# quotes: \u2018a\u2019 'b' `c` \"d\" \\end{verbatim} and {braces} _ ^ ~ | < > $ % & #\n"
    "# Greek: \u03c6 \u03c8 \u03c9 \u03b5 \u03d5 \u03a9 \u0391 \u0392, accents \u00ea \u00e9 \u00fc \u00df, "
    "marks \u00b2 \u00b9 \u2070 \u2083 \u2248 \u2264 \u00b1 \u00b0 \u00b5 \u2212 \u2192, unknown \u2603\n"
    "#\ttab\tstops\tx\n"
    "#  two  spaces,   three   , and a long line:" + " word" * 60 + "\n"
    "   \n"
)


@pytest.mark.skipif(shutil.which("pdflatex") is None, reason=NO_TEX)
def test_appendix_b_is_the_file_character_for_character(tmp_path):
    """Quotes, a verbatim's end, Greek, accents, super- and subscripts, ≈, an unknown character, tabs,
    runs of blanks and a line of 300 characters: the PDF's text is the file's."""
    from gyrochain import pipeline
    from gyrochain.spec import parse_spec

    source = (ROOT / "specs" / "gimbal.toml").read_text().replace('name = "gimbal"', 'name = "tricky"') + TRICKY
    text = pipeline.render(pipeline.derive(parse_spec(source)), targets=("latex",))["tricky.tex"]
    (tmp_path / "tricky.tex").write_text(text)
    res = subprocess.run(["pdflatex", "-interaction=nonstopmode", "-halt-on-error", "tricky.tex"], cwd=tmp_path,
                         capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stdout[-3000:]
    log = (tmp_path / "tricky.log").read_text(errors="replace")
    assert "Overfull" not in log and "Missing character" not in log, log[-2000:]
    _appendix_b(tmp_path / "tricky.pdf", source)


@pytest.mark.skipif(shutil.which("pdflatex") is None, reason=NO_TEX)
@pytest.mark.parametrize("name", ["panda", "spatial3", "furuta_sym"])
def test_the_base_parameters_section_compiles(name, tmp_path):
    """generate --regressor: the Panda's 50 base parameters, spatial3's numerical coefficients and
    furuta_sym's geometry at its [values], typeset without an overfull box."""
    from gyrochain import pipeline
    from gyrochain.spec import load_spec

    spec = load_spec(ROOT / "specs" / f"{name}.toml")
    text = pipeline.render(pipeline.derive(spec, regressor=True), targets=("latex",))[f"{name}.tex"]
    assert "the base parameters}" in text
    (tmp_path / f"{name}.tex").write_text(text)
    res = subprocess.run(["pdflatex", "-interaction=nonstopmode", "-halt-on-error", f"{name}.tex"], cwd=tmp_path,
                         capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stdout[-3000:]
    log = (tmp_path / f"{name}.log").read_text(errors="replace")
    assert "Overfull" not in log and "Missing character" not in log and "Undefined control sequence" not in log, [
        ln for ln in log.splitlines() if ln.startswith(("Overfull", "Missing character"))][:5]


def test_latex_has_the_paper_structure():
    text = (ROOT / "generated" / "gimbal" / "gimbal.tex").read_text()
    for part in [r"\alpha^{1,0}", r"\alpha^{2,1}", "M_{11}", "M_{12}", "M_{22}", "Q_{1}", r"\Gamma_{1}", "G_{1}",
                 "Energy (23)", "Momentum (27)", r"\mathrm{LDL}^{\mathsf T}"]:
        assert part in text, part
    # Nikolai's gyroscope: the rotor term of the gyroscopic moment shows its numbers
    assert "0.5" in text
    # the 3-link chain names its recursion quantities when the closed forms are too long
    big = (ROOT / "generated" / "spatial3" / "spatial3.tex").read_text()
    assert "M_{33}" in big and r"\dot\varphi^{3}" in big


def test_spec_text_prints_in_the_text_font():
    """The OT1 text font has no '<', '>' or '|': pdflatex would print '¿' for Kapitza's 'a^2 w^2 > …'
    (typewriter type has them: there they are the font's own)."""
    from gyrochain.printers.common import tex_escape

    assert tex_escape("a > b < c | d") == r"a \textgreater{} b \textless{} c \textbar{} d"
    from gyrochain.printers.texscene import description_tex

    assert description_tex("stable when a^2 < b") == r"stable when \texttt{a\textasciicircum{}2 \char60{} b}"
    tex = (ROOT / "generated" / "kapitza" / "kapitza.tex").read_text()
    description = next(ln for ln in tex.splitlines() if "stable when" in ln)
    # the ASCII formula stays code, as typed: typewriter type, escaped
    assert r"\texttt{a\textasciicircum{}2 w\textasciicircum{}2 \char62{} 2 g A11 / (m l)}" in description  # tt has >
    assert r"\texttt{phi = pi}" in description and ">" not in description
