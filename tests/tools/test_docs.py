"""The README and the docs: every code block runs (tests/docrun.py says how), every link resolves,
and the site builds with warnings as errors."""
from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import ROOT

sys.path.insert(0, str(ROOT / "tests"))
import docrun  # noqa: E402

PAGES = docrun.pages()


@pytest.mark.parametrize("page", PAGES, ids=[str(p.relative_to(ROOT)) for p in PAGES])
def test_every_block_of_the_page_runs(page, tmp_path):
    counts = docrun.run_page(page, tmp_path / "work")
    assert sum(counts[k] for k in docrun.KINDS) + counts["skipped"] + counts["installed"] == len(docrun.blocks(page))


def test_what_the_pages_hold():
    """Every block is of a kind the runner knows, and only a cluster's recipe is not run."""
    kinds, skips = {}, []
    for page in PAGES:
        for b in docrun.blocks(page):
            assert b.kind in docrun.KINDS, f"{b.where}: {b.kind!r}"
            kinds[b.kind] = kinds.get(b.kind, 0) + 1
            if b.skip:
                skips.append(f"{b.where} ({b.skip})")
    print(f"\ndocs: {sum(kinds.values())} blocks {kinds}; not run: {skips}")
    assert kinds.get("console", 0) >= 10 and len(skips) <= 1, (kinds, skips)


LINK = re.compile(r"\]\((?!https?://|#|mailto:)([^)\s]+?)(?:#[^)]*)?\)")


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
    assert tour and tour[0].kind == "console" and "$ pip install gyrochain" in tour[0].text


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
    "a spec field that is gone": "```toml\nname = \"x\"\ng = 9.81\n[[body]]\ntheta = 0\nmass = 1\n```\n",
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
            "```toml\nname = \"x\"\ng = 9.81\n[[body]]\ntheta = 0\nm = 1\nc = [0, 0, 0.1]\n"
            "I_c = [0.01, 0.01, 0.01, 0, 0, 0]\n```\n")
    counts = docrun.run_page(page, tmp_path / "work", text=text)
    assert counts["commands"] == 3 and counts["c"] == counts["python"] == counts["toml"] == 1


def test_output_patterns():
    assert docrun.matches(["a ... b", "...", "end"], "a 1.5 b\nx\ny\nend\n")
    assert docrun.matches(["a ... b", "...", "end"], "a  b\nend\n")
    assert not docrun.matches(["a ... b", "end"], "a 1 c\nend\n")
    assert not docrun.matches(["a"], "a\nb\n")


# --------------------------------------------------------------------------- the site
def test_the_site_builds_with_warnings_as_errors(tmp_path):
    pytest.importorskip("mkdocs", reason="the docs extra (make docs installs it)")
    pytest.importorskip("mkdocstrings", reason="the docs extra (make docs installs it)")
    r = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "-q", "-d", str(tmp_path / "site")],
                       cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stdout + r.stderr
    site = tmp_path / "site"
    assert (site / "index.html").exists() and (site / "reference" / "api" / "index.html").exists()
    api = (site / "reference" / "api" / "index.html").read_text()
    assert "derive_and_render" in api and "load_spec" in api  # the docstrings made it in
