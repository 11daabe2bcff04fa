"""The command reference (docs/reference/commands.md) from the parsers themselves: a table of the
commands, and per command (and per action of ``examples``) what it does and a table of its
arguments and options (name, argument, default, meaning), so that the page cannot drift from the
program.  The page's prose stays the page's: only the regions between ``<!-- reference: KEY -->``
and ``<!-- end reference -->`` are written here (``python -m gyrochain.commandline.reference
docs/reference/commands.md`` rewrites them; a test holds the committed page to it).
"""
from __future__ import annotations

import argparse
import re
import sys

from . import parsers
from .starter import KINDS

REGION = re.compile(r"(<!-- reference: ([\w ]+) -->\n)(.*?)(<!-- end reference -->)", re.S)
# "(default: X)", or "(other words; default: X)", which keeps "(other words)"
_DEFAULT = re.compile(r"\s*\(([^()]*?)(?:;\s*)?default:? ([^()]*(?:\([^()]*\)[^()]*)*)\)")


def parser() -> argparse.ArgumentParser:
    return parsers.build("gyrochain", "", "0", KINDS)


def _subparsers(ap: argparse.ArgumentParser) -> argparse._SubParsersAction | None:
    return next((a for a in ap._actions if isinstance(a, argparse._SubParsersAction)), None)


def commands(ap: argparse.ArgumentParser | None = None) -> dict[str, argparse.ArgumentParser]:
    """Every command and every action of a command ("examples copy"), in the parsers' order."""
    ap = ap or parser()
    out = {}
    for name, sub in _subparsers(ap).choices.items():
        out[name] = sub
        inner = _subparsers(sub)
        for action, p in (inner.choices.items() if inner else ()):
            out[f"{name} {action}"] = p
    return out


def _cell(text: str) -> str:
    """One table cell: on one line, its | escaped, a terminal's maths (M^-1, LDL^T) as code."""
    text = re.sub(r"(?<![`\w/])([\w./+-]*\^[\w.+-]+)", r"`\1`", " ".join(text.split()))
    return text.replace("|", "\\|")


def rows(p: argparse.ArgumentParser) -> list[tuple[str, str, str, str]]:
    """(name, argument, default, meaning) of each positional argument and option but --help: the
    default as the help text says it, else argparse's where it is a value."""
    out = []
    for a in p._actions:
        if isinstance(a, (argparse._HelpAction, argparse._SubParsersAction)) or a.help == argparse.SUPPRESS:
            continue
        meaning = (a.help or "") % {"default": a.default} if a.help else ""
        said = _DEFAULT.search(meaning)
        default = said[2] if said else ""
        meaning = _DEFAULT.sub(lambda m: f" ({m[1].strip()})" if m[1].strip() else "", meaning).strip()
        if not default and a.option_strings and a.default not in (None, False, argparse.SUPPRESS) and a.nargs != 0:
            default = str(a.default)
        if a.option_strings:
            name = ", ".join(f"`{o}`" for o in a.option_strings)
            arg = "" if a.nargs == 0 else (f"`{{{','.join(a.choices)}}}`" if a.choices and not a.metavar
                                            else f"`{a.metavar or a.dest.upper()}`")
        else:
            name, arg = f"`{a.metavar or a.dest}`", ""
        out.append((name, arg, _cell(default), _cell(meaning)))
    return out


def table(p: argparse.ArgumentParser) -> str:
    found = rows(p)
    if not found:  # a command whose words are its actions (examples): their sections follow
        return "No options of its own: its actions follow.\n"
    lines = ["| name | argument | default | meaning |", "|---|---|---|---|"]
    lines += [f"| {n} | {a} | {d} | {m} |" for n, a, d, m in found]
    return "\n".join(lines) + "\n"


def section(key: str, ap: argparse.ArgumentParser | None = None) -> str:
    """A region's text: ``commands`` the table of commands, else one command's usage, description and table."""
    ap = ap or parser()
    if key == "commands":
        found = _subparsers(ap)
        helps = {a.dest: a.help for a in found._choices_actions}
        return ("| command | what it does |\n|---|---|\n"
                + "".join(f"| [`{name}`](#{name}) | {_cell(helps[name])} |\n" for name in found.choices))
    p = commands(ap)[key]
    usage = " ".join(p.format_usage().split()).removeprefix("usage: ")
    text = f"```text\n{usage}\n```\n\n"  # a block: a usage line is never broken at its options' hyphens
    if p.description:
        text += _cell(p.description) + "\n\n"
    return text + table(p)


def render(page: str) -> str:
    """The page with every region rewritten from the parsers."""
    ap = parser()
    return REGION.sub(lambda m: m[1] + section(m[2], ap) + m[4], page)


def main(argv: list[str]) -> int:
    from pathlib import Path

    path = Path(argv[0] if argv else "docs/reference/commands.md")
    path.write_text(render(path.read_text(encoding="utf-8")), encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
