"""Runs the code blocks of the README and the docs, so that a stale example fails the suite.

Every fenced block must carry one of these info strings (anything else is an error):

- ``console``: ``$ command`` lines, each followed by the output it shows.  ``gyrochain …`` runs
  in this process (``gyrochain.cli.main``, stdout and stderr in one stream as a terminal shows
  them), in the page's scratch folder (``specs/`` and ``examples/`` linked in).  ``make TARGET``
  runs for real in a scratch copy of the Makefile for ``generate``; for the targets that run
  the suite, benchmarks, TeX or long jobs (``make test`` inside ``make test`` would recurse)
  it is dry-run (``make -n``), which still fails on a target that does not exist.  The shown
  output is compared line by line: ``...`` inside a line matches anything, a line that is only
  ``...`` matches any number of lines; a block that shows ``error:`` expects exit status 2, any
  other exit 0.  A command with no output shown is checked for its exit status alone.
- ``python``: executed in order, one namespace per page, in the page's scratch folder.
- ``toml``: parsed; a whole spec (``name`` and ``[[body]]``) is also checked by ``gyrochain check``.
- ``c``: compiled against a generated header (the model named in a ``/* model: NAME */`` comment,
  default the gimbal): declarations with ``-fsyntax-only`` (a prototype that disagrees with the
  header is an error), a program with ``main`` compiled with the model's C and run.
- ``text``: shown output, a file tree or a formula; never run, and it may not hold a ``$`` command.
  After ``<!-- docs-test: from PATH -->`` it quotes that file of the repository, and every line of
  it must be found there.

A console block right after ``<!-- docs-test: numbers within TOL -->`` (``2%``, ``1e-6``) compares
every number of its shown output with the number printed in its place: they agree when they differ
by at most TOL of the shown number, or by half a unit of its last shown digit (a shown ``0.0030``
stands for 0.00295 to 0.00305), so that figures which move with the machine (an estimate from noisy
data, a condition number) are shown in full and still checked.

A block right after ``<!-- docs-test: save NAME -->`` (a spec the page asks the reader to save) is
also written to the page's folder as NAME, for the commands after it.

A block right after ``<!-- docs-test: skip (reason) -->`` is not run (a cluster that needs other
machines); the skips are counted and reported.  A block right after ``<!-- docs-test: installed
(reason) -->`` is what a user types after ``pip install gyrochain``, from an empty folder: it is not
run here but by tests/tools/test_install.py, with the built wheel in a fresh virtual environment
(every ``$`` line through the shell, ``pip install gyrochain`` installing the wheel).

The pages a newcomer follows (``USER_PAGES``: the README, the index's page, Getting started and
the tutorial) are run whole by tests/tools/test_install.py as well, every block in order from an
empty folder on the documented install, but a block right after ``<!-- docs-test: clone (reason)
-->``: a checkout's make targets, which that install does not have (run here all the same).
"""
from __future__ import annotations

import contextlib
import io
import os
import re
import shlex
import shutil
import subprocess
import sys
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
KINDS = ("console", "python", "toml", "c", "text")
DRY_MAKE = {"test", "test-fast", "test-install", "fuzz", "bench", "bench-speed", "bench-setup", "docs", "plot", "animations",
            "generate-all", "setup", "clean", "all", "pdf", "gallery"}
SKIP = re.compile(r"<!--\s*docs-test:\s*skip\s*\((.+?)\)\s*-->")
FROM = re.compile(r"<!--\s*docs-test:\s*from\s+(\S+)\s*-->")
INSTALLED = re.compile(r"<!--\s*docs-test:\s*installed\s*\((.+?)\)\s*-->")
CLONE = re.compile(r"<!--\s*docs-test:\s*clone\s*\((.+?)\)\s*-->")
USER_PAGES = ("README.md", "README-pypi.md", "docs/getting-started.md", "docs/tutorial.md")
SAVE = re.compile(r"<!--\s*docs-test:\s*save\s+([\w.-]+)\s*-->")
WITHIN = re.compile(r"<!--\s*docs-test:\s*numbers within\s+([0-9.e+-]+)(%?)\s*-->")
NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
FENCE = re.compile(r"^(?P<indent>[ \t]*)(?P<fence>`{3,})(?P<info>[^`\n]*)$")


@dataclass
class Block:
    path: Path
    line: int  # 1-based line of the opening fence
    kind: str
    text: str
    skip: str = ""  # the reason, when marked not to run
    source: str = ""  # a text block quoting a file of the repository: every line must be in it
    installed: bool = False  # run by tests/tools/test_install.py in a fresh virtual environment
    clone: bool = False  # a checkout's block (make targets): not run on an installed package
    within: float | None = None  # a console block's numbers compared within this relative tolerance
    save: str = ""  # written to the page's folder under this name before it runs

    @property
    def where(self) -> str:
        return f"{self.path.relative_to(ROOT) if self.path.is_relative_to(ROOT) else self.path}:{self.line}"


def blocks(path: Path, text: str | None = None) -> list[Block]:
    """The fenced blocks of a Markdown file, in order (an indented fence in a list item too)."""
    lines = (path.read_text() if text is None else text).splitlines()
    found, i = [], 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        indent, fence, info = m["indent"], m["fence"], m["info"].strip()
        body, j = [], i + 1
        while j < len(lines) and not lines[j].strip().startswith(fence):
            body.append(lines[j][len(indent):] if lines[j].startswith(indent) else lines[j].lstrip())
            j += 1
        skip = source = ""
        installed = False
        k = i - 1
        while k >= 0 and not lines[k].strip():
            k -= 1
        if k >= 0 and (s := SKIP.search(lines[k])):
            skip = s[1]
        if k >= 0 and (s := FROM.search(lines[k])):
            source = s[1]
        if k >= 0 and INSTALLED.search(lines[k]):
            installed = True
        clone = k >= 0 and bool(CLONE.search(lines[k]))
        within, save = None, ""
        if k >= 0 and (s := WITHIN.search(lines[k])):
            within = float(s[1]) / (100 if s[2] else 1)
        if k >= 0 and (s := SAVE.search(lines[k])):
            save = s[1]
        found.append(Block(path, i + 1, info.split()[0] if info else "", "\n".join(body) + "\n", skip, source, installed,
                           clone=clone, within=within, save=save))
        i = j + 1
    return found


# --------------------------------------------------------------------------- console
@dataclass
class Command:
    line: str
    shown: list[str] = field(default_factory=list)


def commands(text: str) -> list[Command]:
    """``$ `` lines (a trailing backslash continues a line) and the output each shows."""
    out: list[Command] = []
    pending = ""
    for raw in text.splitlines():
        if pending:
            pending += " " + raw.strip()
        elif raw.startswith("$ "):
            pending = raw[2:].strip()
        else:
            if not out:
                if raw.strip():
                    raise AssertionError(f"output before the first $ command: {raw!r}")
                continue
            out[-1].shown.append(raw.rstrip())
            continue
        if pending.endswith("\\"):
            pending = pending[:-1].rstrip()
            continue
        out.append(Command(pending))
        pending = ""
    while out and out[-1].shown and not out[-1].shown[-1]:
        out[-1].shown.pop()
    return out


def _literal(text: str, numbers: list[str] | None) -> str:
    """A piece of a shown line as a pattern: itself, or (``numbers``) with each number a group."""
    if numbers is None:
        return re.escape(text)
    out, at = [], 0
    for m in re.finditer(r"(?<![\w.])" + NUMBER + r"(?![\w.])", text):
        out += [_spaced(text[at:m.start()]), f"({NUMBER})"]
        numbers.append(m.group(0))
        at = m.end()
    return "".join(out) + _spaced(text[at:])


def _spaced(text: str) -> str:
    """A piece of text between numbers as a pattern: its words exact, each run of spaces one or
    more (a column of numbers is aligned by the width of the numbers printed in it)."""
    return re.sub(r"(?:\\ )+", lambda m: "[ \t]+", re.escape(text))


def _pattern(shown: list[str], numbers: list[str] | None = None) -> re.Pattern:
    parts = []
    for ln in shown:
        if ln.strip() == "...":
            parts.append(r"(?:[^\n]*\n)*?")
        else:
            parts.append(".*?".join(_literal(p, numbers) for p in ln.rstrip().split("...")) + r"[ \t]*\n")
    return re.compile("".join(parts) + r"\Z", re.S)


def close(shown: str, printed: str, within: float) -> bool:
    """A printed number is the shown one, within ``within`` of it or half a unit of its last digit."""
    mantissa, _, exponent = shown.lower().partition("e")
    digits = len(mantissa.split(".")[1]) if "." in mantissa else 0
    half_unit = 0.5 * 10.0 ** (int(exponent or 0) - digits)
    s, p = float(shown), float(printed)
    return abs(p - s) <= max(within * abs(s), half_unit * (1 + 1e-9))


def matches(shown: list[str], actual: str, within: float | None = None) -> bool:
    """The output as shown: ``...`` matches anything; with ``within``, numbers match within it."""
    actual = "\n".join(ln.rstrip() for ln in actual.rstrip("\n").splitlines()) + "\n"
    while shown and not shown[-1].strip():
        shown = shown[:-1]
    if within is None:
        return bool(_pattern(shown).match(actual))
    numbers: list[str] = []
    m = _pattern(shown, numbers).match(actual)
    return bool(m) and all(close(s, p, within) for s, p in zip(numbers, m.groups()))


def scratch(folder: Path) -> Path:
    """A page's working folder, with the examples linked in and a copy of the Makefile."""
    folder.mkdir(parents=True, exist_ok=True)
    for name in ("specs", "examples"):
        if not (folder / name).exists():
            (folder / name).symlink_to(ROOT / name)
    shutil.copy2(ROOT / "Makefile", folder / "Makefile")
    return folder


def run_gyrochain(argv: list[str]) -> tuple[int, str]:
    from gyrochain.cli import main

    buf = io.StringIO()
    argv0, columns = sys.argv[0], os.environ.get("COLUMNS")
    sys.argv[0], os.environ["COLUMNS"] = "gyrochain", "100"  # the console script, in a 100-column terminal
    try:
        with contextlib.redirect_stdout(buf), contextlib.redirect_stderr(buf):
            try:
                code = main(argv)
            except SystemExit as exc:  # argparse's --help and --version
                code = exc.code if isinstance(exc.code, int) else 2
    finally:
        sys.argv[0] = argv0
        if columns is None:
            del os.environ["COLUMNS"]
        else:
            os.environ["COLUMNS"] = columns
    return code, buf.getvalue()


def run_make(words: list[str], env: dict, folder: Path) -> tuple[int, str]:
    targets = [w for w in words if "=" not in w and not w.startswith("-")]
    dry = any(t in DRY_MAKE for t in targets) or not targets
    # this interpreter's environment stands for the Makefile's .venv, taken as set up
    venv = Path(sys.prefix)
    argv = ["make", "-s", *(["-n"] if dry else []), f"VENV={venv}", "-o", f"{venv}/.installed", *words]
    # one stream, unbuffered: the lines in the order a terminal shows them
    r = subprocess.run(argv, cwd=folder if not dry else ROOT, env={**os.environ, "PYTHONUNBUFFERED": "1", **env},
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=600)
    return r.returncode, "" if dry else r.stdout


def run_console(block: Block, folder: Path) -> int:
    ran = 0
    for cmd in commands(block.text):
        words = shlex.split(cmd.line, comments=True)
        env = {}
        while words and re.fullmatch(r"[A-Z_]+=\S*", words[0]):
            k, v = words.pop(0).split("=", 1)
            env[k] = v
        cwd = os.getcwd()
        os.chdir(folder)
        try:
            if words[:1] == ["gyrochain"]:
                if "--pdf" in words and shutil.which("lualatex") is None:
                    import pytest

                    pytest.skip(f"{block.where}: `{cmd.line}` needs LuaLaTeX (apt-get install texlive-luatex; .ci/run installs it)")
                if env:
                    raise AssertionError(f"{block.where}: environment variables before gyrochain are not run: {cmd.line}")
                code, out = run_gyrochain(words[1:])
            elif words[:1] == ["make"]:
                code, out = run_make(words[1:], env, folder)
            else:
                raise AssertionError(f"{block.where}: only gyrochain and make commands run here: {cmd.line}")
        finally:
            os.chdir(cwd)
        want = 2 if any(ln.startswith("error:") for ln in cmd.shown) else 0
        assert code == want, f"{block.where}: `{cmd.line}` exited {code}, expected {want}:\n{out}"
        if cmd.shown:
            assert matches(cmd.shown, out, block.within), (
                f"{block.where}: `{cmd.line}` printed\n{out}\nwhere the docs show"
                + (f" (numbers within {block.within:g})" if block.within is not None else "") + "\n" + "\n".join(cmd.shown))
        ran += 1
    return ran


# --------------------------------------------------------------------------- the other kinds
def run_python(block: Block, folder: Path, namespace: dict) -> None:
    cwd = os.getcwd()
    os.chdir(folder)
    try:
        with contextlib.redirect_stdout(io.StringIO()):
            exec(compile(block.text, block.where, "exec"), namespace)
    except Exception as exc:
        raise AssertionError(f"{block.where}: {type(exc).__name__}: {exc}") from exc
    finally:
        os.chdir(cwd)


def run_toml(block: Block, folder: Path) -> None:
    try:
        data = tomllib.loads(block.text)
    except tomllib.TOMLDecodeError as exc:
        raise AssertionError(f"{block.where}: not TOML: {exc}") from None
    if "name" in data and "body" in data:
        spec = folder / f"docs_block_{block.line}.toml"
        spec.write_text(block.text)
        code, out = run_gyrochain(["check", str(spec)])
        assert code == 0, f"{block.where}: the spec does not check: {out}"


def run_c(block: Block, folder: Path) -> None:
    m = re.search(r"/\*\s*model:\s*(\w+)\s*\*/", block.text)
    model = m[1] if m else "gimbal"
    gen = ROOT / "generated" / model
    src = folder / f"docs_block_{block.line}.c"
    text = re.sub(r"\bNAME_(?=[A-Z0-9]+\b|[A-Z0-9]+_[A-Z0-9_]*\b)", f"{model.upper()}_", block.text)  # macros
    text = re.sub(r"\bNAME_", f"{model}_", text)
    cc = os.environ.get("CC", "cc")
    flags = ["-std=c99", "-Wall", "-Wextra", "-Werror", "-Wno-unused-parameter", "-I", str(gen)]
    if re.search(r"\bint\s+main\s*\(", text):
        src.write_text(text)
        exe = folder / f"docs_block_{block.line}"
        r = subprocess.run([cc, *flags, str(src), str(gen / f"{model}.c"), "-lm", "-o", str(exe)], capture_output=True,
                           text=True, timeout=300)
        assert r.returncode == 0, f"{block.where}: does not compile:\n{r.stderr}"
        r = subprocess.run([str(exe)], capture_output=True, text=True, timeout=60, cwd=folder)
        assert r.returncode == 0, f"{block.where}: the program exited {r.returncode}:\n{r.stdout}{r.stderr}"
    else:
        src.write_text(f'#include "{model}.h"\n' + text)
        r = subprocess.run([cc, *flags, "-fsyntax-only", str(src)], capture_output=True, text=True, timeout=120)
        assert r.returncode == 0, f"{block.where}: does not agree with {model}.h:\n{r.stderr}"


def check_text(block: Block) -> None:
    for ln in block.text.splitlines():
        assert not ln.startswith("$ "), f"{block.where}: a command in a text block is never run: {ln}"
    if block.source:
        quoted = (ROOT / block.source).read_text()
        for ln in filter(str.strip, block.text.splitlines()):
            assert ln.strip() in quoted, f"{block.where}: not in {block.source}: {ln}"


def run_page(path: Path, folder: Path, text: str | None = None) -> dict:
    """Every block of one page, in order; returns how many of each kind ran (and the skips)."""
    folder = scratch(folder)
    namespace: dict = {"__name__": f"docs:{path.name}"}
    counts = {k: 0 for k in KINDS} | {"commands": 0, "skipped": 0, "installed": 0}
    for block in blocks(path, text):
        assert block.kind in KINDS, f"{block.where}: a code block needs one of {', '.join(KINDS)}, got {block.kind!r}"
        if block.skip:
            counts["skipped"] += 1
            continue
        if block.installed:  # tests/tools/test_install.py runs it
            assert block.kind in ("console", "python"), f"{block.where}: an installed block is console or python"
            counts["installed"] += 1
            continue
        if block.save:
            (folder / block.save).write_text(block.text)
        if block.kind == "console":
            counts["commands"] += run_console(block, folder)
        elif block.kind == "python":
            run_python(block, folder, namespace)
        elif block.kind == "toml":
            run_toml(block, folder)
        elif block.kind == "c":
            run_c(block, folder)
        else:
            check_text(block)
        counts[block.kind] += 1
    return counts


def pages() -> list[Path]:
    """The README, the package index's page (README-pypi.md) and the docs."""
    return [ROOT / "README.md", ROOT / "README-pypi.md", *sorted((ROOT / "docs").rglob("*.md"))]


def installed_blocks() -> list[Block]:
    """The blocks a user types after ``pip install gyrochain``, in page order."""
    return [b for page in pages() for b in blocks(page) if b.installed]


def user_pages() -> list[Path]:
    """The pages a newcomer follows from the install on (USER_PAGES)."""
    return [ROOT / p for p in USER_PAGES]
