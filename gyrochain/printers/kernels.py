"""The fixed numerical kernels (gyrochain/kernels/): real C and Python source files that every
model shares, specialised to one model when printed.

A kernel file is a preamble for compilers and linters, the line ``/* @kernel */`` (C) or
``# @kernel`` (Python), and the body.
Printing the body: ``#if MODEL_<FLAG>`` … [``#else`` …] ``#endif`` sections are kept or dropped
by the model's facts, each line holding ``@generated <part>`` is replaced by that part of the
model's printed code, ``MODEL_V_<KEY>`` by the model's number (a size, an op count),
``MODEL_T(args)`` by the time arguments of a time-dependent model (nothing otherwise) and
``MODEL_T_OR(a, b)`` by a or b likewise, and ``model_``/``MODEL_`` (C) or ``{model}`` (Python) by
the model's name.  The kernel's C compiles as it stands with ``model_stub.h``, which defines
these macros the same way.

A C kernel may print another one more than once, as a C++ template is instantiated: the lines
``#define SYS_<X> <name>`` or ``#define sys_<x> <name>`` before ``#include "<kernel>.c"`` name the
instance (DOP853 over the state, and over the state with its fundamental matrix), and the
printer puts that kernel's body there with those names spelled out (the ``#define`` and
``#undef`` lines are dropped).  A compiler does the same with the preprocessor.
"""
from __future__ import annotations

import re
from functools import lru_cache

from .. import KERNELS

_IF = re.compile(r"#if MODEL_(\w+)\n")
_GENERATED = re.compile(r"[^\n]*@generated (\w+)[^\n]*\n")
_VALUE = re.compile(r"\bMODEL_V_(\w+)\b")
_TIME = re.compile(r" ?MODEL_T\(((?:[^()]|\([^()]*\))*)\)")  # (a space before it goes with it: "x MODEL_T(, y)")
_TIME_OR = re.compile(r"MODEL_T_OR\(([^,()]*), ([^,()]*)\)")
_INSTANCE_NAME = re.compile(r"#define ((?:SYS|sys)_\w+) (\w+)\n")
_INSTANCE_UNDEF = re.compile(r"#undef (?:SYS|sys)_\w+\n")
_INCLUDE = re.compile(r'#include "(\w+\.c)"\n')


@lru_cache(maxsize=None)
def _body(filename: str) -> str:
    lines = (KERNELS / filename).read_text(encoding="utf-8").splitlines(keepends=True)
    starts = [i for i, line in enumerate(lines) if line.strip() in ("/* @kernel */", "# @kernel")]
    if len(starts) != 1:
        raise ValueError(f"kernel {filename}: expected one @kernel line, found {len(starts)}")
    return _instances(lines[starts[0] + 1:])


def _instances(lines: list[str]) -> str:
    """The body with every ``#include "<kernel>.c"`` replaced by that kernel's body, its
    ``SYS_``/``sys_`` names spelled as the ``#define`` lines before it say."""
    out, names = [], {}
    for line in lines:
        m = _INSTANCE_NAME.fullmatch(line)
        if m:
            names[m.group(1)] = m.group(2)
            continue
        if _INSTANCE_UNDEF.fullmatch(line):
            continue
        m = _INCLUDE.fullmatch(line)
        if m:
            if not names:
                raise ValueError(f"#include \"{m.group(1)}\" without the #define lines that name its instance")
            pattern = re.compile(r"\b(" + "|".join(map(re.escape, names)) + r")\b")
            out.append(pattern.sub(lambda w: names[w.group(1)], _body(m.group(1))))
            names = {}
            continue
        out.append(line)
    return "".join(out)


def specialise(filename: str, name: str, flags: dict[str, bool], parts: dict[str, str],
               values: dict[str, int] | None = None, time_dependent: bool = False) -> str:
    """The body of a kernel file for the model ``name``: its flags' sections kept or dropped,
    its ``@generated`` parts, values and time arguments filled in."""
    lines, keep, out = _body(filename).splitlines(keepends=True), [], []
    for line in lines:
        m = _IF.fullmatch(line)
        if m:
            keep.append(bool(flags[m.group(1)]))
        elif line == "#else\n" and keep:
            keep[-1] = not keep[-1]
        elif line == "#endif\n" and keep:
            keep.pop()
        elif all(keep):
            out.append(line)
    text = _GENERATED.sub(lambda m: parts[m.group(1)], "".join(out))
    if not filename.endswith(".c"):
        return text.replace("{model}", name)
    text = _VALUE.sub(lambda m: str(values[m.group(1)]), text)
    text = _TIME.sub(lambda m: m.group(1) if time_dependent else "", text)
    text = _TIME_OR.sub(lambda m: m.group(1) if time_dependent else m.group(2), text)
    return text.replace("MODEL_", f"{name.upper()}_").replace("model_", f"{name}_")
