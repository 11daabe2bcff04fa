"""Build-time steps of the documentation site (MkDocs hooks, named in mkdocs.yml).

The release: the site's name carries the package's version, and CHANGELOG.md is its page
changelog.md.

Formulas: the pages write the paper's notation as TeX between dollars (``$\\alpha^{kl}_{ij}$``,
``$$...$$`` for a display), which GitHub typesets as it shows the Markdown; pymdownx.arithmatex
marks them, and here each becomes MathML, which browsers typeset themselves.  Nothing is fetched
when a page is opened (no KaTeX or MathJax from a CDN, no script at all), and the site works from
``file://``.  MathML Core has no ``mathvariant="bold"``, so bold letters become the Unicode
mathematical bold letters, which every math font has, and sin, cos, … get TeX's thin spaces.
"""
from __future__ import annotations

import html
import re

from latex2mathml.converter import convert

_MATH = re.compile(r'<(span|div) class="arithmatex">\s*\\[(\[](.*?)\\[)\]]\s*</\1>', re.S)
_FUNCTION = re.compile(r"(?<!<msup>)<mi>(sin|cos|tan|log|exp|det)</mi>")
_FUNCTION_POWER = re.compile(r"<msup><mi>(sin|cos|tan|log|exp|det)</mi>(.*?)</msup>")  # sin² x: the space outside the power
_BOLD = re.compile(r'<mi mathvariant="(bold|bold-italic)">([^<]+)</mi>')
_LATIN_BOLD, _LATIN_BOLD_ITALIC = 0x1D400, 0x1D468  # A..Z then a..z
_GREEK_BOLD, _GREEK_BOLD_ITALIC = 0x1D6C2, 0x1D736  # α..ω


def _bold(letters: str, italic: bool) -> str:
    out = []
    for ch in html.unescape(letters):
        o = ord(ch)
        if "A" <= ch <= "Z" or "a" <= ch <= "z":
            base = _LATIN_BOLD_ITALIC if italic else _LATIN_BOLD
            out.append(chr(base + (o - 65 if ch <= "Z" else 26 + o - 97)))
        elif 0x3B1 <= o <= 0x3C9:  # α..ω
            out.append(chr((_GREEK_BOLD_ITALIC if italic else _GREEK_BOLD) + o - 0x3B1))
        else:
            out.append(ch)
    return "<mi>" + "".join(out) + "</mi>"


def mathml(tex: str, display: bool) -> str:
    """One formula as MathML (bold letters as Unicode bold)."""
    ml = convert(html.unescape(tex).strip(), display="block" if display else "inline")
    ml = _BOLD.sub(lambda m: _bold(m[2], m[1] == "bold-italic"), ml)
    # a thin space on either side of sin, cos, …, as TeX sets them (sin θ cos φ, not sinθcosφ)
    ml = _FUNCTION.sub(r'<mspace width="0.167em"></mspace><mi>\1</mi><mspace width="0.167em"></mspace>', ml)
    return _FUNCTION_POWER.sub(r'<mspace width="0.167em"></mspace><msup><mi>\1</mi>\2</msup><mspace width="0.167em"></mspace>', ml)


def _formula(kind: str, tex: str) -> str:
    """A formula of the page: inline, or a display in a box that scrolls sideways where it is wider
    than the page (a phone), which site.js shades and says."""
    if kind != "div":
        return mathml(tex, False)
    return f'<div class="gc-display">{mathml(tex, True)}</div>'


def _version() -> str:
    """The package's version, from the one place it is written (without importing the package)."""
    from pathlib import Path

    text = (Path(__file__).parent / "gyrochain" / "__init__.py").read_text(encoding="utf-8")
    return re.search(r'^__version__ = "([^"]+)"', text, re.M)[1]


def on_config(config, **_):
    """The version in the site's name: every page's header says which release it documents."""
    config["site_name"] = f"gyrochain {_version()}"
    return config


def on_files(files, config, **_):
    """CHANGELOG.md, at the repository's root where GitHub shows it, is also the site's page
    changelog.md (mkdocs.yml's nav names it)."""
    from pathlib import Path

    from mkdocs.structure.files import File

    text = (Path(config["config_file_path"]).parent / "CHANGELOG.md").read_text(encoding="utf-8")
    files.append(File.generated(config, "changelog.md", content=text))
    return files


_CELL_CODE = re.compile(r"(<td>)(.*?)(</td>)", re.S)
_SHORT_HYPHENATED = re.compile(r"(?<!<pre>)<code>([^<]{0,30}-[^<]{0,30})</code>")  # a flag with its argument: one line
SHORT = 32  # letters of an inline code kept on one line (a phone's column holds about 40 of them)
LONG = 25  # a code of a table cell this long may wrap (a signature, a list of choices); shorter ones stay whole
_CODE = re.compile(r"<code>([^<]+)</code>")
_MATH_PUNCT = re.compile(r"(<math\b(?:(?!</math>).)*</math>)([.,;:!?)]+)", re.S)  # one formula, the punctuation after it


def wrap_long_code(content: str) -> str:
    """A long code in a table cell gets the class gc-wrap (site.css lets it wrap), and a break
    opportunity after each comma; a short one (a flag, a name) is never broken."""
    def long_code(c):
        if len(html.unescape(c[1])) < LONG:
            return c[0]
        parts = [f'<span class="gc-nobreak">{t}</span>' if "-" in t else t for t in re.split(r"(?<=[,/])", c[1])]
        return '<code class="gc-wrap">' + "<wbr>".join(parts) + "</code>"  # a break after a comma or slash, never at a hyphen

    def cell(m):
        return m[1] + _CODE.sub(long_code, m[2]) + m[3]

    def whole(m):
        return '<code class="gc-whole">' + m[1] + "</code>" if len(html.unescape(m[1])) <= SHORT else m[0]

    content = _CELL_CODE.sub(cell, content)
    return _SHORT_HYPHENATED.sub(whole, content)


def keep_punctuation(content: str) -> str:
    """A formula and the punctuation right after it on one line (a browser may break between them)."""
    return _MATH_PUNCT.sub(r'<span class="gc-nobreak">\1\2</span>', content)


def on_page_content(content: str, page, config, **_) -> str:
    from pathlib import Path, PurePosixPath

    here = Path(config["docs_dir"]) / PurePosixPath(page.file.src_uri).parent

    def phone(src: str) -> str | None:
        """The phone variant of a chart, X.phone.png beside X.png (examples/phone_figures.py), if drawn."""
        variant = str(PurePosixPath(src).with_suffix(".phone.png"))
        return variant if src.endswith(".png") and (here / variant).is_file() else None

    return keep_punctuation(wrap_long_code(figures(_MATH.sub(lambda m: _formula(m[1], m[2]), content), phone)))


_ROOTED = re.compile(r'((?:href|src)=")/(?!/)')


def on_post_build(config, **_) -> None:
    """The 404 page is written for a server (every link and asset from the site's root, ``/``):
    made relative like the other pages, it also loads from ``file://`` (it sits at the root)."""
    from pathlib import Path

    page = Path(config["site_dir"]) / "404.html"
    if page.exists():
        text = _ROOTED.sub(r"\1./", page.read_text(encoding="utf-8"))
        text = text.replace('"base": "/"', '"base": "."').replace('"/assets/', '"./assets/')
        page.write_text(text, encoding="utf-8")


PHONE = "(max-width: 44.9375em)"  # Material's narrowest layout: the page's text column alone
_FIGURES = re.compile(r"<p>((?:\s*<img [^>]*/?>\s*)+)</p>")
_CELL = re.compile(r"<td>\s*(<img [^>]*/?>)\s*</td>")
_IMG = re.compile(r"<img [^>]*/?>")
_ALT = re.compile(r'alt="([^"]*)"')
_SRC = re.compile(r'src="([^"]*)"')


_INLINE = re.compile(r"\\\((.*?)\\\)")  # a formula of the alternative text, as arithmatex left it: \(...\)
_SYMBOLS = {"varphi": "φ", "theta": "θ", "lambda": "λ", "omega": "ω", "psi": "ψ", "delta": "δ", "pi": "π",
            "varepsilon": "ε", "alpha": "α", "beta": "β", "Phi": "Φ", "Omega": "Ω", "mathcal{E}": "𝓔"}
_SUPERSCRIPT = str.maketrans("0123456789+-kjirn", "⁰¹²³⁴⁵⁶⁷⁸⁹⁺⁻ᵏʲⁱʳⁿ")
_SUBSCRIPT = str.maketrans("0123456789+-", "₀₁₂₃₄₅₆₇₈₉₊₋")


def _plain(tex: str) -> str:
    """A formula as text for the alternative text of a picture (read aloud, or shown without the
    picture): Greek letters as letters, simple indices as Unicode indices."""
    s = html.unescape(tex)
    s = re.sub(r"\\(ddot|dot)\s*\\?(\w+)", lambda m: "\\" + m[2] + ("\u0308" if m[1] == "ddot" else "\u0307"), s)
    s = re.sub(r"\\(mathcal\{E\}|[A-Za-z]+)", lambda m: _SYMBOLS.get(m[1], m[1]), s)
    s = re.sub(r"\^\{?([0-9+\-kjirn]+)\}?", lambda m: m[1].translate(_SUPERSCRIPT), s)
    s = re.sub(r"_\{?([0-9+\-]+)\}?", lambda m: m[1].translate(_SUBSCRIPT), s)
    return s.replace("{", "").replace("}", "")


def _figure(img: str, phone=lambda src: None) -> str:
    """An image with its alternative text shown beneath it as the caption (Markdown has no caption);
    a formula of that text ($...$ in the page) is typeset in the caption and plain in the ``alt``.
    The picture links to itself: on a phone a tap opens it at full size, to zoom. A chart with a
    phone variant (``phone(src)``) shows it on a narrow screen, where the desktop one's text is too small."""
    alt, src = _ALT.search(img), _SRC.search(img)
    linked = f'<a class="gc-enlarge" href="{src.group(1)}">{{}}</a>' if src else "{}"
    narrow = phone(src.group(1)) if src else None
    if narrow:
        linked = linked.format(f'<picture><source media="{PHONE}" srcset="{narrow}">{{}}</picture>')
    if not (alt and alt.group(1).strip()):
        return f'<figure class="gc-figure">{linked.format(img)}</figure>'
    text = alt.group(1)
    caption = _INLINE.sub(lambda m: mathml(m.group(1), False), text)
    img = img.replace(alt.group(0), 'alt="' + html.escape(_INLINE.sub(lambda m: _plain(m.group(1)), text), quote=True) + '"')
    return f'<figure class="gc-figure">{linked.format(img)}<figcaption>{caption}</figcaption></figure>'


def figures(content: str, phone=lambda src: None) -> str:
    """Images alone in a paragraph or a table cell become figures with visible captions."""
    content = _FIGURES.sub(lambda m: "".join(_figure(i, phone) for i in _IMG.findall(m.group(1))), content)
    return _CELL.sub(lambda m: f"<td>{_figure(m.group(1), phone)}</td>", content)
