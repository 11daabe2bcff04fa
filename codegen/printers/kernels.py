"""The fixed numerical kernels (codegen/kernels/): real C and Python source files that every
model shares, specialised to one model when printed.

A kernel file is a preamble for compilers and linters, the line ``/* @kernel */`` (C) or
``# @kernel`` (Python), and the body.
Printing the body: ``model_``/``MODEL_`` (C) or ``{model}`` (Python) become the model's name,
``#if MODEL_<FLAG>`` … ``#endif`` sections are kept or dropped by the model's facts, and each line
holding ``@generated <part>`` is replaced by that part of the model's printed code.
"""
from __future__ import annotations

import re
from functools import lru_cache
from pathlib import Path

KERNELS = Path(__file__).resolve().parent.parent / "kernels"
_IF = re.compile(r"#if MODEL_(\w+)\n")
_GENERATED = re.compile(r"[^\n]*@generated (\w+)[^\n]*\n")


@lru_cache(maxsize=None)
def _body(filename: str) -> str:
    lines = (KERNELS / filename).read_text(encoding="utf-8").splitlines(keepends=True)
    starts = [i for i, line in enumerate(lines) if line.strip() in ("/* @kernel */", "# @kernel")]
    if len(starts) != 1:
        raise ValueError(f"kernel {filename}: expected one @kernel line, found {len(starts)}")
    return "".join(lines[starts[0] + 1:])


def specialise(filename: str, name: str, flags: dict[str, bool], parts: dict[str, str]) -> str:
    """The body of a kernel file for the model ``name``: its flags' sections kept or dropped,
    its ``@generated`` parts filled in."""
    lines, keep, out = _body(filename).splitlines(keepends=True), [], []
    for line in lines:
        m = _IF.fullmatch(line)
        if m:
            keep.append(bool(flags[m.group(1)]))
        elif line == "#endif\n" and keep:
            keep.pop()
        elif all(keep):
            out.append(line)
    text = "".join(out)
    text = _GENERATED.sub(lambda m: parts[m.group(1)], text)
    if filename.endswith(".c"):
        return text.replace("MODEL_", f"{name.upper()}_").replace("model_", f"{name}_")
    return text.replace("{model}", name)
