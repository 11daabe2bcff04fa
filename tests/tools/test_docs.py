"""The README and the docs: every code block runs (tests/docrun.py says how), every link resolves,
and the site builds with warnings as errors."""
from __future__ import annotations

import os
import re
import subprocess
import sys
import time
from pathlib import Path

import pytest

from conftest import ROOT, tiered

sys.path.insert(0, str(ROOT / "tests"))
import docrun  # noqa: E402

PAGES = docrun.pages()


# make test runs the README's blocks, the first page a user reads; make test-all every page's (a
# documentation page's commands are the commands' own tests, shown)
@pytest.mark.parametrize("page", tiered(PAGES, {"README.md"}, key=lambda p: p.name), ids=[str(p.relative_to(ROOT)) for p in PAGES])
def test_every_block_of_the_page_runs(page, tmp_path):
    counts = docrun.run_page(page, tmp_path / "work")
    assert sum(counts[k] for k in docrun.KINDS) + counts["skipped"] + counts["installed"] == len(docrun.blocks(page))


def test_what_the_pages_hold():
    """Every block is of a kind the runner knows, and only a cluster's recipe and what needs a CUDA card
    or toolkit are not run (the GPU's path is tested on its host form: tests/tools/test_sweep_gpu.py)."""
    kinds, skips = {}, []
    for page in PAGES:
        for b in docrun.blocks(page):
            assert b.kind in docrun.KINDS, f"{b.where}: {b.kind!r}"
            kinds[b.kind] = kinds.get(b.kind, 0) + 1
            if b.skip:
                skips.append(f"{b.where} ({b.skip})")
    print(f"\ndocs: {sum(kinds.values())} blocks {kinds}; not run: {skips}")
    others = [s for s in skips if "(needs a CUDA" not in s and "(needs the CUDA toolkit)" not in s]
    assert kinds.get("console", 0) >= 10 and len(others) <= 1 and len(skips) - len(others) <= 2, (kinds, skips)


LINK = re.compile(r"\]\((?!https?://|#|mailto:)([^)\s]+?)(?:#[^)]*)?\)")


INTERNAL = re.compile(r"\bissues? #?\d+|\bthe issue's\b|\b(?:previous|last|this) stop\b|\bstop \d+\b", re.I)


def test_every_example_is_in_the_getting_started_table():
    """The table of examples names every spec the package ships, and no other."""
    text = (ROOT / "docs" / "getting-started.md").read_text(encoding="utf-8")
    listed = set(re.findall(r"^\| `([\w]+\.toml)` \|", text, re.M))
    assert listed == {p.name for p in (ROOT / "specs").glob("*.toml")}, listed ^ {p.name for p in (ROOT / "specs").glob("*.toml")}


def test_every_example_has_a_gallery_card():
    """docs/gallery.md: a card per example spec, in the order of Getting started's table, with its
    picture and the two commands that draw it (checked against the parsers here; the docs test runs
    them, and make gallery draws the pictures with them)."""
    import shlex

    from gyrochain import parsers
    from gyrochain.starter import KINDS

    text = (ROOT / "docs" / "gallery.md").read_text(encoding="utf-8")
    cards = re.findall(r"^### (\w+)\n\n!\[([^\]]+)\]\(img/gallery/(\w+)\.png\)\n\n(.+?)\n\n```console\n(.*?)```", text, re.S | re.M)
    names = [c[0] for c in cards]
    assert sorted(names) == sorted(p.stem for p in (ROOT / "specs").glob("*.toml")), names
    table = re.findall(r"^\| `([\w]+)\.toml` \|", (ROOT / "docs" / "getting-started.md").read_text(encoding="utf-8"), re.M)
    assert names == table
    ap = parsers.build("gyrochain", "", "0", KINDS)
    for name, alt, picture, line, block in cards:
        assert picture == name and (ROOT / "docs" / "img" / "gallery" / f"{name}.png").is_file(), name
        assert len(alt.split()) >= 8 and len(line.split()) >= 6, name  # says what it shows, and what it is for
        lines = [shlex.split(x[2:]) for x in block.splitlines() if x.startswith("$ ")]
        assert [a[:3] for a in lines] == [["gyrochain", "examples", "copy"], ["gyrochain", "animate", f"{name}.toml"]]
        assert lines[0][3:] == [name] and lines[1][-2:] == ["-o", f"{name}.png"], lines
        args = ap.parse_args(lines[1][1:])
        assert args.frame is not None, name  # a still, not an animation


def test_the_command_reference_has_every_command_and_option():
    """docs/reference/commands.md: a section per command (and per action of examples) with the table
    the parsers give (name, argument, default, meaning), so that the options and defaults cannot
    drift; every option is in its command's table, and no command the parser lacks."""
    import argparse

    from gyrochain.commandline import reference

    page = (ROOT / "docs" / "reference" / "commands.md").read_text(encoding="utf-8")
    assert reference.render(page) == page, "stale: run python -m gyrochain.commandline.reference docs/reference/commands.md"
    sections = re.findall(r"^##+ `([a-z ]+)`", page, re.M)
    assert sections == list(reference.commands()), sections
    regions = dict((m[2], m[3]) for m in reference.REGION.finditer(page))
    for name, parser in reference.commands().items():
        rows = {r.split(" | ")[0].lstrip("| ") for r in regions[name].splitlines() if r.startswith("| `")}
        for action in parser._actions:
            if isinstance(action, (argparse._HelpAction, argparse._SubParsersAction)):
                continue
            want = ", ".join(f"`{o}`" for o in action.option_strings) or f"`{action.metavar or action.dest}`"
            assert want in rows, (name, want)
    # a default the help states is in the default column, not left in the meaning
    assert "| `--t1` | `T1` | 1 | end time, s |" in regions["simulate"]
    assert "default:" not in "".join(regions.values())


def test_the_changelog_has_this_version():
    """CHANGELOG.md: what is unreleased first (when anything is), then this package's version as the
    newest release."""
    from gyrochain import __version__

    heads = re.findall(r"^## (.+)$", (ROOT / "CHANGELOG.md").read_text(encoding="utf-8"), re.M)
    released = heads[1:] if heads[0] == "Unreleased" else heads
    assert released[0].startswith(f"{__version__} ("), heads[:2]


def test_the_c_api_page_names_every_emitted_function():
    """Every function a committed model's header declares is on docs/c-api.md (as NAME_… or the
    gimbal's name), so a new emitted function cannot go undocumented."""
    api = (ROOT / "docs" / "c-api.md").read_text(encoding="utf-8")
    missing = set()
    for header in sorted((ROOT / "generated").glob("*/*.h")):
        name = header.stem
        for fn in set(re.findall(rf"\b{name}_(\w+)\s*\(", header.read_text(encoding="utf-8"))):
            if not re.search(rf"\b(?:NAME|gimbal)_{fn}\b", api):
                missing.add(f"{name}_{fn}")
    assert len(list((ROOT / "generated").glob("*/*.h"))) >= 10
    assert not missing, sorted(missing)


def test_the_c_api_page_names_every_function_of_the_python_module():
    """Every public function, class and constant of a committed model's Python module is on
    docs/c-api.md, so that one the printer adds cannot go undocumented."""
    import ast

    api = (ROOT / "docs" / "c-api.md").read_text(encoding="utf-8")
    names = set()
    for module in sorted((ROOT / "generated").glob("*/*.py")):
        for node in ast.parse(module.read_text(encoding="utf-8")).body:
            if isinstance(node, (ast.FunctionDef, ast.ClassDef)) and not node.name.startswith("_"):
                names.add(node.name)
            elif isinstance(node, ast.Assign):
                for target in node.targets:
                    for n in (target.elts if isinstance(target, ast.Tuple) else [target]):
                        if isinstance(n, ast.Name) and not n.id.startswith("_"):
                            names.add(n.id)
    assert {"qdd", "quad_state", "jacobi", "HAS_QUADRATURES", "SeparatrixError"} <= names
    missing = sorted(n for n in names if not re.search(rf"`{n}\b", api))
    assert not missing, missing


def test_no_words_of_our_internal_work():
    """What users read speaks of the tool, not of the team's work items (issue numbers, stops)."""
    pages = [ROOT / "README.md", ROOT / "README-pypi.md", ROOT / "CHANGELOG.md", *sorted((ROOT / "docs").rglob("*.md"))]
    found = [f"{p.relative_to(ROOT)}:{i}: {m.group(0)!r}" for p in pages
             for i, line in enumerate(p.read_text(encoding="utf-8").splitlines(), start=1) for m in INTERNAL.finditer(line)]
    assert not found, found
    assert INTERNAL.search("the last before issue 50") and INTERNAL.search("in the noisy one of the previous stop")


def _report():
    import importlib.util

    spec = importlib.util.spec_from_file_location("bench_report", ROOT / "bench" / "report.py")
    report = importlib.util.module_from_spec(spec)
    sys.modules["bench_report"] = report  # its dataclasses look their module up
    spec.loader.exec_module(report)
    return report


def test_every_benchmark_table_and_chart_is_its_csv():
    """docs/benchmarks.md: every table is what bench/report.py makes of its CSV files, with the
    machine and date that bench/results/machines.csv gives them; every chart of the page was drawn
    from the CSV files of its table as they are now (the hashes in the PNG)."""
    report = _report()
    assert report.check() == []
    text = report.PAGE.read_text(encoding="utf-8")
    shown = set(re.findall(r"<!-- table: ([\w-]+) -->", text))
    assert shown == set(report.TABLES), shown ^ set(report.TABLES)
    pictures = {m for page in (ROOT / "docs").rglob("*.md")
                for m in re.findall(r"\]\(bench-results/([\w.]+\.png)\)", page.read_text(encoding="utf-8"))}
    assert pictures == set(report.CHARTS), pictures ^ set(report.CHARTS)  # every chart of the site is drawn from CSV
    outside = re.sub(r"<!-- table: [\w-]+ -->.*?<!-- /table -->", "", text, flags=re.S)
    heads = re.findall(r"^(\|[^\n]*)\n\|---", outside, re.M)
    assert all(h.startswith(("| machine |", "| command |")) for h in heads), heads  # no figures typed by hand
    # a figure typed by hand is found, and so is a table from two machines
    edited = text.replace("<!-- table: robots -->\n| arm", "<!-- table: robots -->\n| arm ", 1)
    assert edited != text and report.page(edited) == text
    with pytest.raises(SystemExit, match="one table, one machine"):
        report.provenance(("speed.csv", "speed_O3_march_native.csv"))


@pytest.mark.parametrize("page", PAGES, ids=[str(p.relative_to(ROOT)) for p in PAGES])
def test_every_relative_link_resolves_inside_the_repository(page):
    text = page.read_text()
    prose = re.sub(r"`[^`\n]*`", "", re.sub(r"^[ \t]*```.*?^[ \t]*```", "", text, flags=re.S | re.M))  # not code
    for target in LINK.findall(prose):
        path = (page.parent / target).resolve()
        assert path.exists(), f"{page.name}: link to {target}, which does not exist"
        assert path.is_relative_to(ROOT), f"{page.name}: link to {target}, outside the repository"
    assert "../shared" not in text and "DIGEST" not in text


def test_the_index_page_stands_alone():
    """README-pypi.md is the long description the package index shows: no link or image that only
    resolves inside the repository, no make (a pip user has no Makefile), and the tour a pip user
    types is there for test_install.py to run."""
    text = (ROOT / "README-pypi.md").read_text()
    assert not LINK.findall(text) and "![" not in text and "<img" not in text
    assert not re.search(r"\bmake\b", text) and ".venv" not in text and "specs/" not in text
    tour = [b for b in docrun.blocks(ROOT / "README-pypi.md") if b.installed]
    assert tour and tour[0].kind == "console" and '$ pip install "gyrochain[sweep,view]"' in tour[0].text


# --------------------------------------------------------------------------- the runner fails on stale docs
STALE = {
    "a command that no longer exists": "```console\n$ gyrochain simulat specs/gimbal.toml\n```\n",
    "an option renamed": "```console\n$ gyrochain simulate specs/gimbal.toml --t-end 1\n```\n",
    "output that changed": "```console\n$ gyrochain check specs/gimbal.toml\nspecs/gimbal.toml: ok (gimbal, n = 3, ...)\n```\n",
    "a spec that moved": "```console\n$ gyrochain check specs/gimbals.toml\n```\n",
    "an error that is no longer one": "```console\n$ gyrochain check specs/gimbal.toml\nerror: ...\n```\n",
    "a make target that is gone": "```console\n$ make benchmark\n```\n",
    "a prototype that changed": "```c\nint NAME_qdd(const double *x, const double *u, double *qdd);\n```\n",
    "a Python call that changed": "```console\n$ gyrochain generate -q specs/gimbal.toml\n```\n\n```python\nfrom gyrochain.build import load\nload('generated/gimbal').qdd_fast([0, 0, 0, 0])\n```\n",
    "a spec field that is gone": "```toml\nname = \"xa\"\ng = 9.81\n[[body]]\ntheta = 0\nmass = 1\n```\n",
    "a command hidden in a text block": "```text\n$ gyrochain check specs/gimbal.toml\n```\n",
    "a block without a kind": "```\ngyrochain check specs/gimbal.toml\n```\n",
}


@pytest.mark.parametrize("what", STALE)
def test_a_stale_example_fails(what, tmp_path):
    page = tmp_path / "stale.md"
    with pytest.raises(AssertionError):
        docrun.run_page(page, tmp_path / "work", text="# A page\n\n" + STALE[what])


def test_the_same_examples_written_right_pass(tmp_path):
    """The control for the stale ones: the same blocks as they stand today pass."""
    page = tmp_path / "fresh.md"
    text = ("```console\n$ gyrochain check specs/gimbal.toml\nspecs/gimbal.toml: ok (gimbal, n = 2, ...)\n"
            "$ gyrochain check specs/gimbals.toml\nerror: ...\n$ gyrochain generate -q specs/gimbal.toml\n```\n\n"
            "```c\nint NAME_qdd(const double *x, const double *u, const NAME_params *p, double *qdd);\n```\n\n"
            "```python\nfrom gyrochain.build import load\nload('generated/gimbal').qdd([0, 0, 0, 0])\n```\n\n"
            "```toml\nname = \"xa\"\ng = 9.81\n[[body]]\ntheta = 0\nm = 1\nc = [0, 0, 0.1]\n"
            "I_c = [0.01, 0.01, 0.01, 0, 0, 0]\n```\n")
    counts = docrun.run_page(page, tmp_path / "work", text=text)
    assert counts["commands"] == 3 and counts["c"] == counts["python"] == counts["toml"] == 1


def test_output_patterns():
    assert docrun.matches(["a ... b", "...", "end"], "a 1.5 b\nx\ny\nend\n")
    assert docrun.matches(["a ... b", "...", "end"], "a  b\nend\n")
    assert not docrun.matches(["a ... b", "end"], "a 1 c\nend\n")
    assert not docrun.matches(["a"], "a\nb\n")


def test_numbers_within_a_tolerance(tmp_path):
    """A block marked ``numbers within TOL`` shows its figures in full: each printed figure must be
    the shown one within TOL, or within half a unit of the shown last digit; text stays exact."""
    shown = ["beta1  Axx1 + Azz2   0.0141   2.1e-05   0.15%", "cond 12.3 ... done"]
    assert docrun.matches(shown, "beta1  Axx1 + Azz2   0.01412   2.13e-05   0.151%\ncond 12.5 of it done\n", 0.05)
    assert not docrun.matches(shown, "beta1  Axx1 + Azz2   0.0160   2.1e-05   0.15%\ncond 12.3 done\n", 0.05)
    assert not docrun.matches(shown, "beta1  Axx2 + Azz2   0.0141   2.1e-05   0.15%\ncond 12.3 done\n", 0.05)
    assert docrun.matches(["x 0.0030"], "x 0.00304\n", 0.0) and not docrun.matches(["x 0.0030"], "x 0.0031\n", 0.0)
    assert not docrun.matches(["x 0.0141"], "x 0.01412\n")  # without the mark, exact
    # a column aligned by its numbers' width: the spaces before a number follow the printed number
    shown = ["  beta6  Axz2   1.49029e-05    9.98e-06      67%"]
    assert docrun.matches(shown, "  beta6  Axz2   1.48296e-05       1e-05      67%\n", 0.05)
    assert not docrun.matches(shown, "  beta6  Axz2   1.48296e-05       1e-05      67%  extra\n", 0.05)
    assert not docrun.matches(["a b 1.0"], "ab 1.0\n", 0.05)  # a space is still needed where one is shown
    page = tmp_path / "p.md"
    page.write_text("<!-- docs-test: numbers within 2% -->\n```console\n$ gyrochain --version\n```\n")
    assert docrun.blocks(page)[0].within == 0.02


# --------------------------------------------------------------------------- the site
@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    """The site as `make docs` builds it (warnings are errors), once for the module."""
    pytest.importorskip("mkdocs", reason="the docs extra (make docs installs it)")
    pytest.importorskip("mkdocstrings", reason="the docs extra (make docs installs it)")
    pytest.importorskip("material", reason="the docs extra (make docs installs it)")
    out = tmp_path_factory.mktemp("site") / "site"
    r = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "-q", "-d", str(out)], cwd=ROOT,
                       capture_output=True, text=True, timeout=600, env=dict(os.environ, NO_MKDOCS_2_WARNING="1"))
    assert r.returncode == 0, r.stdout + r.stderr
    return out


def test_the_site_builds_with_warnings_as_errors(site):
    from gyrochain import __version__

    assert (site / "index.html").exists() and (site / "reference" / "api.html").exists()
    # the release it documents: its version on every page, its changelog a page of the site
    assert f"gyrochain {__version__}" in (site / "index.html").read_text()
    changes = (site / "changelog.html").read_text()
    assert f"{__version__} (" in changes and "<h2" in changes
    api = (site / "reference" / "api.html").read_text()
    assert "derive_and_render" in api and "load_spec" in api  # the docstrings made it in
    conventions = (site / "conventions.html").read_text()
    assert conventions.count("<math") > 40 and "\\hat" not in conventions  # the formulas typeset, as MathML


def test_every_list_renders_as_a_list(site):
    """A Markdown list right under a paragraph's line is one paragraph to MkDocs (GitHub renders a
    list): no paragraph of the site holds a line that starts as a list item."""
    import html
    import re

    found = []
    for page in sorted(site.rglob("*.html")):
        for para in re.findall(r"<p>(.*?)</p>", page.read_text(encoding="utf-8"), flags=re.S):
            text = html.unescape(re.sub(r"<[^>]+>", "", para))
            if re.search(r"\n\s*(?:[-*+]|\d+\.) \S", text):
                found.append(f"{page.relative_to(site)}: {text.strip()[:70]!r}")
    assert not found, found


def test_every_picture_has_a_visible_caption(site):
    """Markdown's alternative text is only read aloud or shown when the picture fails: on the site
    every picture of a page is a figure whose caption shows that text."""
    import re

    bare, terse = [], []
    for page in sorted(site.glob("*.html")):
        text = page.read_text(encoding="utf-8")
        article = text.split("<article", 1)[1].split("</article>", 1)[0] if "<article" in text else ""
        for m in re.finditer(r"<img [^>]*>", article):
            after = article[m.end():m.end() + 8000]
            alt = re.search(r'alt="([^"]*)"', m.group(0))
            # (the picture links to itself; a chart with a phone variant is a <picture>)
            caption = re.match(r"(?:</picture>)?(?:</a>)?<figcaption>(.*?)</figcaption>", after, re.S)
            shown = re.sub(r"<math.*?</math>|</?span[^>]*>", "x", caption.group(1), flags=re.S) if caption else ""
            if not (caption and alt and alt.group(1).strip()) or "\\(" in shown or "<" in shown:
                bare.append(f"{page.name}: {m.group(0)[:80]}")
            elif len(alt.group(1).split()) < 4:
                terse.append(f"{page.name}: {alt.group(1)!r}")
    assert not bare, bare
    assert not terse, terse  # a caption says what the picture shows, not only its name


# Maths written as text: a letter with a Unicode index or accent (φ̈ʳ, ê¹₁, ẋ), a root or a partial
# sign, or TeX's _ and ^ on a short name (ê^k_2, M_kr); identifiers such as fast_gyro are not.
RAW_MATHS = re.compile("[\u0300-\u036f\u1e00-\u1eff\u2070-\u209f\u00b2\u00b3\u00b9\u1d2c-\u1d6a\u1d9b-\u1dbf"
                       "\u221a\u2202\u2112\U0001d4d4]|(?<![\\w\\\\/.-])[^\\W\\d_]{1,2}[_^]\\{?[\\w,+\\-\u2212]{1,4}\\}?(?![\\w/.])")


def raw_maths(page_html: str) -> list[str]:
    """Formulas of a page written as text outside code and MathML, with a little context."""
    import html

    article = page_html.split("<article", 1)[1].split("</article>", 1)[0] if "<article" in page_html else page_html
    text = re.sub(r"<(script|style|pre|code|math|svg)\b.*?</\1>", " ", article, flags=re.S)
    text = html.unescape(re.sub(r"<[^>]+>", " ", text))
    return [text[max(0, m.start() - 30):m.end() + 20].replace("\n", " ") for m in RAW_MATHS.finditer(text)]


def test_one_notation_every_formula_typeset(site):
    """Every formula of the site is MathML (typeset by the browser, as the PDFs typeset it): no
    Unicode indices or accents, and no _ or ^ maths, in the text of any page outside code."""
    for written in ("φ̈ʳ", "ê^k_2", "M_kr", "ẋ", "ê¹₁", "∂ℒ"):
        assert raw_maths(f"<article><p>the {written} here</p></article>"), written
    assert not raw_maths("<article><p><code>M_kr</code> fast_gyro RK4_LANES <math><mi>φ</mi></math></p></article>")
    found = {str(p.relative_to(site)): raw_maths(p.read_text(encoding="utf-8")) for p in sorted(site.rglob("*.html"))}
    found = {k: v for k, v in found.items() if v}
    assert not found, found


def _offline(browser, viewport=(1280, 800)):
    """A page of a browser that lets nothing leave the file system (every other request aborted
    and recorded) and records the console's errors."""
    left, errors = [], []
    ctx = browser.new_context(viewport={"width": viewport[0], "height": viewport[1]})
    ctx.route("**/*", lambda route: route.continue_() if route.request.url.startswith("file://")
              else (left.append(route.request.url), route.abort()))
    page = ctx.new_page()
    page.set_default_timeout(20_000)
    page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
    page.on("pageerror", lambda e: errors.append(str(e)))
    return ctx, page, left, errors


_RAW_TEX = """() => {
    const out = [], walk = document.createTreeWalker(document.querySelector('article'), NodeFilter.SHOW_TEXT);
    while (walk.nextNode()) {
        const node = walk.currentNode, text = node.textContent;
        if (node.parentElement.closest('code, pre, math, script, style')) continue;
        const i = text.search(/[\\^_]\\{|\\$[^\\s$]|\\\\[a-z]+\\{/);
        if (i >= 0) out.push(text.slice(Math.max(0, i - 30), i + 30));
    }
    return out;
}"""


def test_the_site_from_a_file_offline(site, browser):
    """Opened from file:// with the network blocked: every navigation link and a search lead to
    content, nothing leaves the file system, no console error, no raw TeX outside code."""
    ctx, page, left, errors = _offline(browser)
    try:
        page.goto((site / "index.html").as_uri())
        links = page.eval_on_selector_all("nav.md-nav--primary a.md-nav__link[href]", "els => els.map(e => e.href)")
        pages = sorted({u.split("#")[0] for u in links})
        in_nav = len(re.findall(r":\s*[\w/.-]+\.md\s*$", (ROOT / "mkdocs.yml").read_text(), re.M))
        assert len(pages) == in_nav and all(u.startswith("file://") and u.endswith(".html") for u in pages), pages
        raw = {}
        for url in pages:
            page.goto(url)
            assert page.locator("article h1").count() == 1, url  # a page, not a folder listing
            found = page.evaluate(_RAW_TEX)
            if found:
                raw[url.rsplit("/", 1)[1]] = found
        assert not raw, raw
        page.goto((site / "index.html").as_uri())
        started = time.perf_counter()
        page.fill("input.md-search__input", "gimbal")
        # the offline search builds its index in a worker (every file read through the test's router): seconds on
        # a quiet machine, more on a busy one
        try:
            page.wait_for_selector(".md-search-result__item a", timeout=90_000)
        except Exception as exc:  # say what the page saw: its console, what it tried to fetch, the search box's state
            state = page.evaluate("() => [document.querySelector('.md-search__output')?.innerText?.slice(0, 200), "
                                  "typeof window.Worker, location.href]")
            raise AssertionError(f"no search result: {exc}; console errors {errors}; requests that left {left}; "
                                 f"search box {state}") from None
        print(f"search: the first results after {time.perf_counter() - started:.1f} s")
        hits = page.eval_on_selector_all(".md-search-result__item a", "els => els.map(e => e.href)")
        assert len(hits) >= 5
        page.goto(hits[0])
        assert "gimbal" in page.inner_text("article").lower()
        page.goto((site / "spec.html").as_uri())
        assert page.locator(".highlight .k, .highlight .s, .highlight .n").count() > 20  # highlighted at build time
        assert not left, left
        assert not errors, errors
    finally:
        ctx.close()


def test_the_404_page_loads_offline(site, browser):
    """The page a server shows for a missing address, opened from file://: its styles and scripts
    load (nothing leaves the file system, no console error) and its links lead to pages."""
    ctx, page, left, errors = _offline(browser)
    try:
        page.goto((site / "404.html").as_uri())
        assert page.locator("h1").first.inner_text().strip() == "404 - Not found"
        assert page.evaluate("getComputedStyle(document.body).fontFamily") != ""
        links = page.eval_on_selector_all("nav.md-nav--primary a.md-nav__link[href]", "els => els.map(e => e.href)")
        assert links and all(u.startswith(site.as_uri()) and u.split("#")[0].endswith(".html") for u in links), links[:5]
        page.goto(links[0])
        assert page.locator("article h1").count() == 1
        assert not left, left
        assert not errors, errors
    finally:
        ctx.close()


_TABLES = """() => [...document.querySelectorAll('article table')].map(t => {
    const wrap = t.closest('.md-typeset__scrollwrap'), r = wrap.getBoundingClientRect();
    const hint = wrap.previousElementSibling, heads = [...t.rows[0].cells];
    return {wide: t.getBoundingClientRect().width > r.width + 1, scrolls: getComputedStyle(wrap).overflowX,
            cue: !!(hint && hint.classList.contains('gc-scroll-hint') && hint.getBoundingClientRect().height > 0
                    && wrap.classList.contains('gc-scrolls')),
            heads: heads.map(c => [c.innerText.trim(), c.getBoundingClientRect().right <= r.right + 1])};
})"""


def test_tables_fit_or_say_they_scroll(site, browser):
    """At 1280 px no table is wider than the text column without a scroll cue, and the ratio
    column of the forward-dynamics benchmark is in sight."""
    ctx, page, left, errors = _offline(browser)
    try:
        hidden, wide = [], 0
        for f in sorted(site.rglob("*.html")):
            page.goto(f.as_uri())
            for t in page.evaluate(_TABLES):
                if t["wide"] and not all(inside for _, inside in t["heads"]):  # (a column out of sight)
                    wide += 1
                    if not (t["cue"] and t["scrolls"] in ("auto", "scroll")):
                        hidden.append((f.name, t["heads"][:3]))
        assert not hidden, hidden
        page.goto((site / "benchmarks.html").as_uri())
        heads = dict(page.evaluate(_TABLES)[0]["heads"])
        assert heads["ours"] and heads["the fastest peer"] and heads["the peer's time / ours"]  # the summary in sight
        assert wide >= 1  # the check has met a wide table
    finally:
        ctx.close()


_FORMULAS = """() => [...document.querySelectorAll('article .gc-display')].map(b => {
    const hint = b.previousElementSibling;
    return {wide: b.scrollWidth > b.clientWidth + 1,
            scrolls: getComputedStyle(b).overflowX,
            cue: !!(hint && hint.classList.contains('gc-scroll-hint') && b.classList.contains('gc-scrolls'))};
})"""

_SIZES = """() => [...document.querySelectorAll('article p math')].slice(0, 20).map(m => {
    const p = m.closest('p');
    return [parseFloat(getComputedStyle(m).fontSize), parseFloat(getComputedStyle(p).fontSize)];
})"""


def test_formulas_on_a_phone(site, browser):
    """At 390 px a displayed formula wider than the screen scrolls sideways with the cue a table has,
    and an inline formula is set at least at the size of the text around it."""
    ctx, page, left, errors = _offline(browser, viewport=(390, 844))
    try:
        hidden, wide, small = [], 0, []
        for f in sorted(site.glob("*.html")):
            page.goto(f.as_uri())
            for i, b in enumerate(page.evaluate(_FORMULAS)):
                if b["wide"]:
                    wide += 1
                    if not (b["cue"] and b["scrolls"] in ("auto", "scroll")):
                        hidden.append((f.name, i))
            small += [(f.name, s) for s in page.evaluate(_SIZES) if s[0] < s[1]]
        # and a formula made wider than the screen gets the cue once the page notices (a resize)
        page.goto((site / "spec.html").as_uri())
        box = page.locator("article .gc-display").first
        box.evaluate("b => { const m = b.querySelector('math'); m.append(m.firstElementChild.cloneNode(true), "
                     "m.firstElementChild.cloneNode(true)); window.dispatchEvent(new Event('resize')); }")
        made = page.evaluate(_FORMULAS)[0]
        wide += made["wide"]
        if not (made["wide"] and made["cue"]):
            hidden.append(("spec.html, widened", made))
        assert not hidden, hidden
        assert wide >= 1  # a phone has met a formula wider than its screen
        assert not small, small[:5]
    finally:
        ctx.close()


def test_the_extras_table_is_the_package_s():
    """The README's and Getting started's table of extras: the same rows, each an extra that
    pyproject.toml defines, and every extra a user installs in it (not the ones of the tests, the
    site and the benchmarks)."""
    import tomllib

    def table(path):
        text = path.read_text(encoding="utf-8")
        rows = re.findall(r"^\| `(\w+)` \| (.*)$", text, re.M)
        return {k: v.replace("](docs/", "](") for k, v in rows}
    readme, start = table(ROOT / "README.md"), table(ROOT / "docs" / "getting-started.md")
    assert readme == start and readme, (readme, start)
    extras = set(tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["optional-dependencies"])
    for_us = {"test", "browser", "docs", "robots", "rollout", "bench"}  # the tests', the site's and the benchmarks'
    assert set(readme) == extras - for_us, (set(readme), extras - for_us)


def test_every_spec_field_is_in_the_table():
    """docs/spec.md's table of fields has a row for every field the spec parser accepts: the top
    level, a body's, a rotor's, a limit's, the platform's, a force's and a moment's, the initial
    state's."""
    from gyrochain.chainspec import spec, tables

    page = (ROOT / "docs" / "spec.md").read_text(encoding="utf-8")
    part = page.split("## Every field", 1)[1].split("\n## ", 1)[0]
    rows = set(re.findall(r"^\| `([^`]+)` \|", part, re.M))
    want = {f"[{f}]" if f in ("base", "initial", "values") else "[[body]]" if f == "body" else f for f in spec.TOP_FIELDS}
    want |= {f for f in spec.BODY_FIELDS if f not in ("force", "moment")} | {"[[body.force]]", "[[body.moment]]"}
    want |= {f"rotor.{f}" for f in spec.ROTOR_FIELDS} | {f"limits.{f}" for f in tables.KEYS}
    want |= {"base.position", "base.rotation", "force.point", "force.F", "force.frame", "moment.M", "moment.frame",
             "initial.phi", "initial.phidot"}
    assert want <= rows, want - rows
    assert not rows - want, rows - want  # no row for a field the parser refuses


def test_the_api_page_has_every_public_name(site):
    """The Python API page documents every public method of CModel (its own and the derivatives'
    mixin), every name of gyrochain.casadi, and the entry points the guides import (a name without
    a docstring would be left out of the page silently)."""
    import gyrochain.casadi
    from gyrochain.build import CModel

    ids = set(re.findall(r'id="(gyrochain\.[\w.]+)"', (site / "reference" / "api.html").read_text(encoding="utf-8")))
    names = {f"CModel.{m}" for m in dir(CModel) if not m.startswith("_") and callable(getattr(CModel, m))}
    names |= set(gyrochain.casadi.__all__) | {"load_spec", "parse_spec", "ChainSpec", "SpecError", "derive", "render",
                                              "compile", "derive_and_render", "load", "load_python", "ModelError"}
    missing = sorted(n for n in names if not any(i.endswith("." + n) for i in ids))
    assert not missing, missing


# A picture of a printed page (the tutorial's PDF, set for paper): its letters are the page's, too
# small at 342 px whatever is done to the picture; on a phone it is read enlarged (a tap opens it).
PRINTED_PAGES = {"tutorial_page.png"}
SMALLEST_PX = 11.0  # the smallest letter of a picture on a phone, in CSS pixels


def _phone_text_px(png: Path, shown_px: float) -> float | None:
    """The smallest letter of a chart's phone variant as shown ``shown_px`` wide, in CSS pixels,
    from what examples/phone_figures.py recorded in it (its width in inches, its smallest text in points)."""
    from PIL import Image

    with Image.open(png) as im:
        found = im.info.get("gyrochain-phone")
    if found is None:
        return None
    rec = dict(kv.split("=") for kv in found.split())
    return float(rec["smallest_pt"]) / 72.0 * shown_px / float(rec["width_in"])


def test_the_pages_on_a_phone(site, browser):
    """At 390 × 844 (a phone): no page wider than the screen; every chart shown as its phone
    variant, whose smallest letter is at least 11 px there, and every other picture (drawn by
    animate, with 11 px letters) at its own size, not shrunk; every picture a link to itself (a tap
    opens it at full size); no cue to scroll a table that hides no column."""
    ctx, page, _left, _errors = _offline(browser, viewport=(390, 844))
    wide, small, unlinked, empty_cue = {}, {}, {}, {}
    try:
        for html_page in sorted(p for p in site.rglob("*.html") if "assets" not in p.parts and p.name != "404.html"):
            page.goto(html_page.as_uri())
            name = str(html_page.relative_to(site))
            width = page.evaluate("() => document.documentElement.scrollWidth")
            wide[name] = [width] if width > 390 else []
            found = page.evaluate("""() => [...document.querySelectorAll('article figure img')].map(i => [
                i.currentSrc, i.getBoundingClientRect().width, i.naturalWidth, !!i.closest('a.gc-enlarge')])""")
            small[name] = []
            for src, shown, natural, _ in found:
                path = Path(src.removeprefix("file://"))
                if path.name in PRINTED_PAGES:
                    continue
                px = _phone_text_px(path, shown) if path.name.endswith(".phone.png") else None
                if px is not None:
                    if px < SMALLEST_PX:
                        small[name].append(f"{path.name}: letters of {px:.1f} px")
                elif path.suffix == ".png" and path.parent.name != "gallery" or shown < natural - 0.5:
                    small[name].append(f"{path.name}: {shown:.0f} px of its {natural}, no phone variant")
            unlinked[name] = [src for src, _, _, linked in found if not linked]
            empty_cue[name] = page.evaluate("() => [...document.querySelectorAll('.gc-scroll-hint')]"
                                            ".map(h => h.textContent).filter(t => / 0 more column/.test(t))")
    finally:
        ctx.close()
    for what in (wide, small, unlinked, empty_cue):
        assert not {k: v for k, v in what.items() if v}, what
