"""The LaTeX of every example is a standalone document that a real TeX engine compiles."""
from __future__ import annotations

import shutil
import subprocess

import pytest

from conftest import ONE_ARM, ROOT


@pytest.mark.skipif(shutil.which("pdflatex") is None, reason="no TeX engine: install Debian's texlive-latex-base (.ci/run does)")
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


@pytest.mark.skipif(shutil.which("pdflatex") is None, reason="no TeX engine: install Debian's texlive-latex-base (.ci/run does)")
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
                 "Energy (23)", "Momentum (27)", r"LDL^{\mathsf T}"]:
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
