"""The LaTeX of every example is a standalone document that a real TeX engine compiles."""
from __future__ import annotations

import re
import shutil
import subprocess

import pytest

import pdftext
import texread
from conftest import EXAMPLES, ROOT

NO_TEX = "no LuaLaTeX: install Debian's texlive-luatex, texlive-latex-recommended and fonts-dejavu-core (.ci/run does)"
needs_tex = pytest.mark.skipif(shutil.which("lualatex") is None, reason=NO_TEX)
A4 = (595.28, 841.89)  # points
LETTER = (612.0, 792.0)


def _file_text(text: str) -> str:
    """The spec file as a page can show it: without the blanks that end a line or the file."""
    return "\n".join(line.rstrip() for line in text.rstrip("\n").split("\n"))


def typeset(folder, name: str) -> tuple:
    """``make pdf``'s two LuaLaTeX passes (the tables' widths settle on the first): the PDF and
    the second pass's log."""
    for _ in range(2):
        res = subprocess.run(["lualatex", "-interaction=nonstopmode", "-halt-on-error", f"{name}.tex"], cwd=folder,
                             capture_output=True, text=True, timeout=600)
        assert res.returncode == 0, res.stdout[-3000:]
    return folder / f"{name}.pdf", (folder / f"{name}.log").read_text(errors="replace")


def check_log(log: str) -> None:
    """No warning, no character the fonts lack, no box that runs into the margin by more than 1 pt."""
    lines = log.splitlines()
    overfull = [ln for ln in lines if ln.startswith("Overfull") and float(re.search(r"\(([\d.]+)pt", ln).group(1)) > 1.0]
    assert not overfull, overfull[:5]
    bad = [ln for ln in lines if "Warning" in ln or "Missing character" in ln or "Undefined control sequence" in ln]
    assert not bad, bad[:5]


def check_pages(pdf, paper=A4) -> int:
    """Every page portrait and of the paper's size (no page wider than it); the number of pages."""
    pymupdf = pytest.importorskip("pymupdf", reason="the PDF's pages need MuPDF: pip install pymupdf (the test extra has it)")
    with pymupdf.open(pdf) as doc:
        sizes = {(round(p.rect.width, 2), round(p.rect.height, 2)) for p in doc}
        count = doc.page_count
    assert sizes == {paper}, f"page sizes {sorted(sizes)}, expected {paper} (portrait)"
    return count


def check_appendix_b(pdf, source: str) -> None:
    """Appendix B's text is the spec file's: every line of it in poppler's pdftotext and in MuPDF's
    get_text(), whitespace aside, and character for character by the glyphs' places (MuPDF)."""
    pytest.importorskip("pymupdf", reason="the PDF's text needs MuPDF: pip install pymupdf (the test extra has it)")
    poppler = pdftext.pdftotext(pdf)
    assert poppler is not None, "no pdftotext: install Debian's poppler-utils (.ci/run does)"
    assert pdftext.missing_lines(poppler, source) == [], "pdftotext"
    assert pdftext.missing_lines(pdftext.mupdf_text(pdf), source) == [], "MuPDF"
    got, want = pdftext.listing(pdf), _file_text(source)
    if got != want:
        bad = next(i for i, (a, b) in enumerate(zip(got.split("\n") + [""], want.split("\n") + [""])) if a != b)
        raise AssertionError(f"Appendix B line {bad + 1}: PDF {got.split(chr(10))[bad:bad + 1]!r}, "
                             f"file {want.split(chr(10))[bad:bad + 1]!r}")


@needs_tex
@pytest.mark.parametrize("name", EXAMPLES)
def test_every_example_typesets_on_portrait_a4(name, tmp_path):
    """generated/NAME/NAME.tex as committed: no warning, no overfull box, every page portrait A4,
    and Appendix B's text the spec's for both PDF readers."""
    (tmp_path / f"{name}.tex").write_text((ROOT / "generated" / name / f"{name}.tex").read_text())
    pdf, log = typeset(tmp_path, name)
    check_log(log)
    pages = check_pages(pdf)
    check_appendix_b(pdf, (ROOT / "specs" / f"{name}.toml").read_text())
    if name == "ur5":  # six joints in closed form, each velocity group by its coefficients: about two pages a joint
        assert pages <= 18, f"ur5.pdf has {pages} pages"


def test_the_text_readers_find_a_changed_line():
    """The check can fail: a line the PDF does not have is reported, whitespace aside."""
    assert pdftext.missing_lines("a  b\nc\n12  d = 1", "ab c\nd=1\nd = 2") == ["d = 2"]
    assert pdftext.missing_lines("ê¹ points", "ê¹₃ points") == ["ê¹₃ points"]


TRICKY = (
    "# quotes: \u2018a\u2019 'b' `c` \"d\" \\end{verbatim} and {braces} _ ^ ~ | < > $ % & #\n"
    "# Greek: \u03c6 \u03c8 \u03c9 \u03b5 \u03d5 \u03a9 \u0391 \u0392, accents \u00ea \u00e9 \u00fc \u00df, "
    "marks \u00b2 \u00b9 \u2070 \u2083 \u2248 \u2264 \u00b1 \u00b0 \u00b5 \u2212 \u2192, snowman \u2603\n"
    "#\ttab\tstops\tx\n"
    "#  two  spaces,   three   , and a long line:" + " word" * 60 + "\n"
    "#" + "x" * 150 + "\n"
    "   \n"
)


@needs_tex
@pytest.mark.parametrize("paper", ["a4", "letter"])
def test_appendix_b_is_the_file_character_for_character(paper, tmp_path):
    """Quotes, a verbatim's end, Greek, accents, super- and subscripts, ≈, tabs, runs of blanks, a
    line of 300 characters wrapped at blanks and one of 150 without any: the PDF's text is the
    file's, on A4 and on US letter (generate --paper letter)."""
    from gyrochain import pipeline
    from gyrochain.spec import parse_spec

    source = (ROOT / "specs" / "gimbal.toml").read_text().replace('name = "gimbal"', 'name = "tricky"') + TRICKY
    text = pipeline.render(pipeline.derive(parse_spec(source)), targets=("latex",), paper=paper)["tricky.tex"]
    (tmp_path / "tricky.tex").write_text(text)
    pdf, log = typeset(tmp_path, "tricky")
    check_log(log)
    check_pages(pdf, A4 if paper == "a4" else LETTER)
    check_appendix_b(pdf, source)


@needs_tex
@pytest.mark.parametrize("name", ["panda", "spatial3", "furuta_sym"])
def test_the_base_parameters_section_compiles(name, tmp_path):
    """generate --regressor: the Panda's 50 base parameters, spatial3's numerical coefficients and
    furuta_sym's geometry at its [values], typeset without a warning or an overfull box."""
    from gyrochain import pipeline
    from gyrochain.spec import load_spec

    spec = load_spec(ROOT / "specs" / f"{name}.toml")
    text = pipeline.render(pipeline.derive(spec, regressor=True), targets=("latex",))[f"{name}.tex"]
    assert "the base parameters}" in text
    (tmp_path / f"{name}.tex").write_text(text)
    _, log = typeset(tmp_path, name)
    check_log(log)


def test_latex_has_the_paper_structure():
    text = (ROOT / "generated" / "gimbal" / "gimbal.tex").read_text()
    for part in [r"\alpha^{1,0}", r"\alpha^{2,1}", "M_{11}", "M_{12}", "M_{22}", "Q_{1}", r"\Gamma_{1}", "G_{1}",
                 "the paper's (23)", "Momentum, the paper's (27)", r"\mathrm{LDL}^{\mathsf T}"]:
        assert part in text, part
    # Nikolai's gyroscope: the rotor term of the gyroscopic moment shows its numbers
    assert "0.5" in text
    # the 3-link chain names its recursion quantities when the closed forms are too long
    big = (ROOT / "generated" / "spatial3" / "spatial3.tex").read_text()
    assert "M_{33}" in big and r"\dot\varphi^{3}" in big


def test_text_is_set_as_code_math_or_words():
    """One typesetter for the description and the sentences from the facts: options, arguments,
    files and field names in typewriter type; ASCII formulas as the document's math (a spec
    parameter as the document prints it); words escaped; never one thing split across the three."""
    from gyrochain.printers.textype import typeset

    params = {"a": r"\mathsf{a}", "w": r"\mathsf{w}"}
    kapitza = (ROOT / "specs" / "kapitza.toml").read_text()
    import tomllib

    text = typeset(tomllib.loads(kapitza)["description"], params)
    assert r"$\mathsf{a}^{2} \mathsf{w}^{2} > 2 g A_{11} / (m d)$" in text
    assert r"at $\mathsf{a} = 0.01$ it holds from $\mathsf{w} = 198.09$~rad/s" in text
    assert typeset("the multipliers (steady --vary w=150:300:16) say", params) == (
        r"the multipliers (\texttt{steady -{}-{}vary w=\allowbreak{}150:\allowbreak{}300:\allowbreak{}16}) say")
    assert r"$\varphi = \pi$" in text
    assert typeset("the modes (g/l)(2 -+ sqrt 2)") == r"the modes $(g / l) (2 \mp \sqrt{2})$"
    assert typeset("work by body[2].force[1]; O1 on l1") == r"work by \texttt{body[2].force[1]}; $O^{1}$ on $l^{1}$"
    assert typeset("from panda_link0 in panda.urdf, P_cr = 2 k / l") == (
        r"from \texttt{panda\_link0} in \texttt{panda.urdf}, $P_{\mathrm{cr}} = 2 k / l$")
    assert typeset("rotor at 555 rad/s; quotes `x_1 = {y}` & 50% of $5") == (
        r"rotor at 555 rad/s; quotes \texttt{x\_1 = \{y\}} \& 50\% of \$5")
    assert typeset("axis ê²₃ at φ¹ ≈ 0") == r"axis ê$^{2}_{3}$ at $\varphi^{1} \approx 0$"
    # the description's own characters of mathematics, kept as written (they were set as "? ?"), and a
    # bracket the formula opens and the text closes left to the text (it was closed twice)
    assert typeset("the rotor (λ² = 0.3 kg m²/s along ê²₃) spins") == (
        r"the rotor ($\lambda^{2} = 0.3 \mathrm{kg} m^{2} / s$ along ê$^{2}_{3}$) spins")
    assert typeset("a²w² > 2 g A11/(m l)") == r"$a^{2} w^{2} > 2 g A_{11} / (m l)$"
    assert typeset("ω = 3 rad/s, ≠ 0") == r"$\omega = 3$~rad/s, $\ne 0$"
    assert typeset("base.rotation (l1 does not stay vertical), e.g. 2 kg") == (
        r"\texttt{base.rotation} ($l^{1}$ does not stay vertical), e.g. 2 kg")


def test_no_document_prints_code_identities_or_ascii_maths():
    """Every committed document: no name of the emitted code in a formula, no line x = x, and no
    ASCII maths (^, _, *) in its text outside math and code."""

    for name in EXAMPLES:
        tex = (ROOT / "generated" / name / f"{name}.tex").read_text()
        assert scan(tex, name) == [], name


def scan(tex: str, name: str) -> list[str]:
    """What the document must not print (see the test above)."""
    from gyrochain import pipeline
    from gyrochain.spec import load_spec

    model = pipeline.derive(load_spec(ROOT / "specs" / f"{name}.toml"))
    code_names = {a.name for a, _ in model.kin.prog.defs} | {f"{name}_{fn}" for fn in ("qdd", "rhs")}
    body = tex.split(r"\begin{document}", 1)[1].split(r"\section*{Appendix B", 1)[0]
    body = re.sub(r"(?<!\\)%.*", "", body)
    found = []
    math = re.findall(r"\\begin\{(align\*|equation\*|gather\*|multline\*)\}(.*?)\\end\{\1\}|\\\[(.*?)\\\]|(?<!\\)\$(.+?)(?<!\\)\$", body, flags=re.S)
    for m in math:
        seg = m[1] or m[2] or m[3]
        for word in re.findall(r"\\mathrm\{([^{}]*)\}", seg):
            if re.fullmatch(r"[A-Za-z]+\d+[A-Za-z]\w*|.*\\_.*", word) or word.replace("\\_", "_") in code_names:
                found.append(f"a name of the code in a formula: {word}")
        for word in re.findall(r"(?<![\\A-Za-z])[A-Za-z]+\d+[A-Za-z_]\w*", seg):
            if word in code_names:
                found.append(f"a name of the code in a formula: {word}")
    eqs = list(texread.equations(tex).items()) + texread.recursion(tex)
    found += [f"an identity: {lhs} = {rhs}" for lhs, rhs in eqs if lhs.strip() == rhs.strip()]
    text = re.sub(r"\\begin\{(align\*|equation\*|gather\*|multline\*|longtable)\}.*?\\end\{\1\}|\\\[.*?\\\]|(?<!\\)\$.+?(?<!\\)\$", " ", body, flags=re.S)
    text = re.sub(r"\\texttt\{(?:[^{}]|\{[^{}]*\})*\}|\\(?:sub)*section\*|\\[A-Za-z]+\*?|\\[\^_*]", " ", text)
    for ch in "^_*":
        for m in re.finditer(re.escape(ch), text):
            found.append(f"ASCII maths in the text: {text[max(0, m.start() - 40):m.end() + 40]!r}")
    found += reader_scan(body, math)
    return found


def reader_scan(body: str, math: list) -> list[str]:
    """What a referee reading the document page by page must not meet: a power written on an index
    (a superscript after a superscript, or a power set as a bare superscript on a symbol whose
    superscript is an index, φ̇² for (φ̇)²), a "?" where a character was lost, a command line or a
    field name of the spec in the prose, a row of the notation table whose symbols the document
    never writes, and a formula's continued line a page may separate from its first (\\ not \\*)."""
    found = []
    for m in math:
        seg = m[1] or m[2] or m[3]
        for hit in re.finditer(r"\^\{[^{}]*\}\s*\^|(?:\\varphi|\\psi|\\dot\\varphi|\\dot\\psi|\\ddot\\varphi)\^\d", seg):
            found.append(f"a power on an index: {seg[max(0, hit.start() - 30):hit.end() + 10]!r}")
        if "?" in seg:
            found.append(f"a lost character in a formula: {seg[:60]!r}")
    prose = re.sub(r"\\begin\{(align\*|equation\*|gather\*|multline\*)\}.*?\\end\{\1\}|(?<!\\)\$.+?(?<!\\)\$", " ", body, flags=re.S)
    for pattern, what in ((r"-\{\}-\{\}[a-z]|(?<![\w-])--[a-z]", "a command-line option"),
                          (r"body\[\d+\]\.|base\.(?:rotation|position)|\[initial\]|\[values\]", "a field name of the spec"),
                          (r"\?\s*\?", "a lost character")):
        for hit in re.finditer(pattern, prose):
            found.append(f"{what} in the prose: {prose[max(0, hit.start() - 40):hit.end() + 40]!r}")
    for block in re.findall(r"\\begin\{align\*\}(.*?)\\end\{align\*\}", body, flags=re.S):
        for hit in re.finditer(r"\\\\(?!\*)\s*\n&\\quad", block):
            found.append(f"an equation that may break across pages: {block[max(0, hit.start() - 60):hit.end()]!r}")
    table = re.search(r"symbol & unit & meaning.*?\\end\{longtable\}", body, flags=re.S)
    rest = body.replace(table.group(0), " ") if table else body
    for row in (table.group(0).split(r"\\") if table else []):
        syms = re.findall(r"\$([^$]+)\$", row.split("&")[0])
        heads = [re.split(r"[\^_]", sym, maxsplit=1)[0].strip() for sym in syms]
        if heads and not any(re.search(r"(?<![A-Za-z\\])" + re.escape(h) + r"(?![A-Za-z])", rest) for h in heads):
            found.append(f"a notation row the document does not use: {row.strip()[:60]!r}")
    return found


def test_the_scan_finds_what_it_forbids():
    """The scan can fail: a code name, an identity and ASCII maths planted in a document."""
    tex = (ROOT / "generated" / "ur5" / "ur5.tex").read_text()
    assert scan(tex, "ur5") == []
    planted = tex.replace(r"\section*{Integrals}", r"$M_{15} = \mathrm{j2r16}$ and a^2 \section*{Integrals}")
    found = scan(planted, "ur5")
    assert any("j2r16" in f for f in found) and any("ASCII" in f for f in found), found
    panda = (ROOT / "generated" / "panda" / "panda.tex").read_text()
    assert scan(panda, "panda") == []
    first = panda.index("\n", panda.index(r"\begin{align*}", panda.index(texread.SHARES))) + 1  # a body's first quantity
    lhs, end = panda[first:panda.index(" &= ", first)], panda.index(r" \tag", first)
    assert any("identity" in f for f in scan(panda[:first] + f"{lhs} &= {lhs}" + panda[end:], "panda"))
    # a referee's complaints, each planted once
    for plant, what in ((r"$J\dot\psi^2 + C$", "a power on an index"), (r"$x^{2}^{2}$", "a power on an index"),
                        (r"$(? ? = 0.3)$", "a lost character"), (r"(steady -{}-{}vary w=1:2:3)", "a command-line option"),
                        (r"work is done by \texttt{body[1].damping}", "a field name"),
                        ("\\hline\n$\\Xi^k$ & 1 & never used \\\\\n", "a notation row"),
                        ("\\begin{align*}\nx &= a \\\\\n&\\quad + b\n\\end{align*}", "an equation that may break")):
        at = r"\section*{Integrals}" if what != "a notation row" else r"\endfoot" + "\n"
        bad = tex.replace(at, at + plant + "\n", 1)
        assert any(f.startswith(what) for f in scan(bad, "ur5")), (what, scan(bad, "ur5"))


def test_the_citation_file_is_the_package_s():
    """CITATION.cff cites this version under the package's licence, and says what our copy of the
    paper lacks instead of inventing it; every document cites the tool and the paper so."""
    import yaml

    from gyrochain import __version__

    cff = yaml.safe_load((ROOT / "CITATION.cff").read_text())
    assert cff["cff-version"] == "1.2.0" and cff["version"] == __version__ and cff["license"] == "MIT"
    paper = cff["references"][0]
    assert "Not given" in paper["authors"][0]["name"] and "year" not in paper
    for name in EXAMPLES:
        tex = (ROOT / "generated" / name / f"{name}.tex").read_text()
        assert f"gyrochain {__version__}: equations of compound spatial pendulums" in tex
        assert "Our copy of the paper gives neither its authors nor its year" in tex


def test_generate_sets_the_paper_it_is_asked(tmp_path):
    """generate --paper letter: the document's page is US letter and its header says how to make
    it again; a paper the option does not know, a typo of the option: one line, exit 2, nothing written."""
    import sys

    def gen(*args):
        return subprocess.run([sys.executable, "-m", "gyrochain", "generate", "-q", "--no-build", *args],
                              capture_output=True, text=True, cwd=tmp_path, timeout=300)

    spec = ROOT / "specs" / "kapitza.toml"
    res = gen(str(spec), "--paper", "letter", "-o", "letter")
    assert res.returncode == 0, res.stderr
    tex = (tmp_path / "letter" / "kapitza.tex").read_text()
    assert r"\documentclass[11pt,letterpaper]{article}" in tex and "[letterpaper,margin=1in]{geometry}" in tex
    assert "gyrochain generate kapitza.toml --paper letter" in tex.splitlines()[1]
    assert "--paper" not in (ROOT / "generated" / "kapitza" / "kapitza.tex").read_text().splitlines()[1]
    for args, word in (((str(spec), "--paper", "a5", "-o", "a5"), "--paper"), ((str(spec), "--papr", "letter", "-o", "a5"), "--papr")):
        res = gen(*args)
        assert res.returncode == 2 and len(res.stderr.strip().splitlines()) == 1 and word in res.stderr, res.stderr
        assert "Traceback" not in res.stderr and not (tmp_path / "a5").exists()


@needs_tex
def test_generate_pdf_typesets_the_document(tmp_path):
    """generate --pdf: the folder gets NAME.pdf from two LuaLaTeX passes (and no auxiliary files),
    the report says how many pages, and they are the PDF's; a document LuaLaTeX stops on is one line
    with TeX's error and the log to read."""
    import sys

    res = subprocess.run([sys.executable, "-m", "gyrochain", "generate", "-q", "--no-build", "--pdf",
                          str(ROOT / "specs" / "kapitza.toml"), "-o", "k"], capture_output=True, text=True, cwd=tmp_path,
                         timeout=600)
    assert res.returncode == 0, res.stderr
    pages = int(re.search(r"^typeset k/kapitza\.pdf: (\d+) pages$", res.stdout, re.M).group(1))
    assert check_pages(tmp_path / "k" / "kapitza.pdf") == pages >= 2
    assert not [p.name for p in (tmp_path / "k").iterdir() if p.suffix in (".aux", ".log", ".out", ".toc")]

    from gyrochain import typeset
    from gyrochain.spec import SpecError

    bad = tmp_path / "bad.tex"
    bad.write_text("\\documentclass{article}\\begin{document}\\nosuchcommand\\end{document}\n")
    with pytest.raises(SpecError, match=r"--pdf: LuaLaTeX stopped on .*bad\.tex: Undefined control sequence\. \(its log is .*bad\.log\)"):
        typeset.pdf(bad)
    assert (tmp_path / "bad.log").exists()


def test_generate_pdf_without_lualatex_says_so(tmp_path):
    """Without LuaLaTeX on the PATH, generate --pdf is one line before any work: exit 2, nothing written."""
    import os
    import sys

    env = dict(os.environ, PATH=str(tmp_path / "empty"))
    res = subprocess.run([sys.executable, "-m", "gyrochain", "generate", "--no-build", "--pdf",
                          str(ROOT / "specs" / "kapitza.toml"), "-o", "k"], capture_output=True, text=True, cwd=tmp_path,
                         env=env, timeout=300)
    assert res.returncode == 2 and res.stdout == "", (res.stdout, res.stderr)
    assert res.stderr.strip() == "error: --pdf: needs LuaLaTeX (on Debian: apt-get install texlive-luatex " \
                                 "texlive-latex-recommended fonts-dejavu-core)"
    assert not (tmp_path / "k").exists()
