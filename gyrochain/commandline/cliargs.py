"""The command line's small parsers, shared by the commands in cli.py: comma-separated numbers,
name=value options, an option given once, sizes, and argparse's words turned into the form of every
other error (``<what>: <why>``); the heartbeat of a long command on a terminal."""
from __future__ import annotations

import argparse
import math
import re
import sys
import time

from ..chainspec.errors import did_you_mean
from ..chainspec.spec import SpecError


def floats(text: str, what: str, count: int) -> list[float]:
    try:
        vals = [float(v) for v in text.split(",")] if text else [0.0] * count
    except ValueError:
        raise SpecError(what, f"expected {count} comma-separated numbers") from None
    if len(vals) != count:
        raise SpecError(what, f"expected {count} comma-separated numbers, got {len(vals)}")
    return finite(vals, what)


def float_list(text: str, what: str) -> list[float] | None:
    """Comma-separated numbers, or None when the option was not given (its count is checked
    where the spec is known)."""
    if not text:
        return None
    try:
        vals = [float(v) for v in text.split(",")]
    except ValueError:
        raise SpecError(what, "expected comma-separated numbers") from None
    return finite(vals, what)


def finite(vals: list[float], what: str) -> list[float]:
    if not all(math.isfinite(v) for v in vals):
        raise SpecError(what, "expected finite numbers, got " + ",".join(f"{v:g}" for v in vals))
    return vals


def at_phi(text: str, n: int) -> list[float]:
    """``--at phi=A`` (one angle for every joint) or ``phi=A1,..,An`` (or the list alone)."""
    name, eq, rest = text.partition("=")
    if eq and name.strip() != "phi":
        raise SpecError("--at", f"{text!r}: expected phi=A (every joint) or phi=A1,..,A{n}")
    vals = float_list(rest if eq else text, "--at") or []
    if len(vals) == 1:
        return vals * n
    if len(vals) != n:
        raise SpecError("--at", f"expected one angle or {n}, got {len(vals)}")
    return vals


def one(what: str, given: list | None, why: str) -> None:
    """An option that may be given once: a second one is refused, not silently taken for the first."""
    if given and len(given) > 1:
        raise SpecError(what, f"given {len(given)} times ({', '.join(given)}); {why}")


def params_of(items, what: str = "--param") -> dict:
    """name=number options (--param) as a dict (the names and values are checked against the
    spec by physical.run_values)."""
    params = {}
    for item in items or []:
        key, eq, val = item.partition("=")
        key = key.strip()
        if key in params:
            raise SpecError(f"{what} {key}", "given twice")
        try:
            if not (eq and key):
                raise ValueError
            params[key] = float(val)
        except ValueError:
            raise SpecError(f"{what} {item}", "expected name=number") from None
    return params


def size(text: str) -> tuple[int, int]:
    w, x, h = text.lower().partition("x")
    try:
        size = (int(w), int(h)) if x else (0, 0)
    except ValueError:
        size = (0, 0)
    if not (64 <= size[0] <= 4096 and 64 <= size[1] <= 4096) or size[0] % 2 or size[1] % 2:
        raise SpecError("--size", f"{text!r}: expected WIDTHxHEIGHT, even numbers of pixels from 64 to 4096")
    return size


def unrecognized(extra: list[str], parser: argparse.ArgumentParser) -> str:
    """The first word a command does not know, and the option of the command nearest to it."""
    word = extra[0].split("=", 1)[0]
    if not word.startswith("-"):
        return f"{word}: unexpected argument"
    hint = did_you_mean(word, [o for a in parser._actions for o in a.option_strings])
    return f"{word}: no such option of {parser.prog}" + (f"; {hint.strip()}" if hint else "")


_CHOICE = re.compile(r"^argument (?P<what>[^:]+): invalid choice: '(?P<got>[^']*)' \(choose from (?P<among>.*)\)$")


def plain(message: str) -> str:
    """argparse's words in the form of every other error, ``<what>: <why>``: "argument --t1:
    invalid float value: 'x'" → "--t1: invalid float value: 'x'", and a mistyped choice answered
    with the nearest one ("command: no such command 'chek'; did you mean check? ...")."""
    m = _CHOICE.match(message)
    if m:
        among = [c.strip(" '") for c in m["among"].split(",")]
        what = {"cmd": "command", "COMMAND": "command", "ACTION": "action"}.get(m["what"], m["what"])
        hint = did_you_mean(m["got"], among)
        return f"{what}: no such {'command' if what == 'command' else 'choice'} '{m['got']}'; {hint}one of {', '.join(among)}"
    return message.removeprefix("argument ")


_NEGATIVE = re.compile(r"^-(\.?\d|inf|nan)", re.IGNORECASE)


def join_negative(argv: list[str], valued: set) -> list[str]:
    """``--phi -1,0`` → ``--phi=-1,0`` for every option that takes a value (argparse takes "-1,0",
    "-1e3" or "-inf" for an option)."""
    out, i = [], 0
    while i < len(argv):
        a = argv[i]
        if a in valued and i + 1 < len(argv) and _NEGATIVE.match(argv[i + 1]):
            out.append(f"{a}={argv[i + 1]}")
            i += 2
            continue
        out.append(a)
        i += 1
    return out


def valued_options(parser: argparse.ArgumentParser) -> set:
    """The option strings of ``parser`` and its subcommands that take a value."""
    out = set()
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for sub in action.choices.values():
                out |= valued_options(sub)
        elif action.option_strings and action.nargs != 0:
            out |= {o for o in action.option_strings if o.startswith("--")}
    return out


class ClearsFirst:
    """stdout that stops the heartbeat (and clears its line) before the command's first output."""

    def __init__(self, stream, beat):
        self._stream, self._beat = stream, beat

    def write(self, text):
        self._beat.stop()
        return self._stream.write(text)

    def __getattr__(self, name):
        return getattr(self._stream, name)


class Heartbeat:
    """On a terminal, a command that runs longer than two seconds says so on stderr, once a second,
    on one line it rewrites ("steady: working, 12 s; Ctrl-C stops it"), and clears the line when
    it ends: a long run is never silent.  Not on a pipe or a file (scripts and tests see nothing)."""

    def __init__(self, name: str, after: float = 2.0):
        import threading

        self.name, self.after, self.t0 = name, after, time.perf_counter()
        self.done, self.shown, self.lock = threading.Event(), False, threading.Lock()
        self.running = sys.stderr.isatty()
        self.status = ""  # where the work is (``say``), shown after the time
        Heartbeat.current = self
        if self.running:
            threading.Thread(target=self._run, name="gyrochain-heartbeat", daemon=True).start()

    def _run(self) -> None:
        if self.done.wait(self.after):
            return
        while True:
            with self.lock:
                if self.done.is_set():
                    return
                where = f"; {self.status}" if self.status else ""
                sys.stderr.write(f"\r\033[K{self.name}: working, {time.perf_counter() - self.t0:.0f} s{where}; Ctrl-C stops it ")
                sys.stderr.flush()
                self.shown = True
            self.done.wait(1.0)

    current = None  # the running command's heartbeat

    @classmethod
    def say(cls, status: str) -> None:
        """Where the running command's work is, for its heartbeat's line (nothing off a terminal)."""
        if cls.current is not None:
            cls.current.status = status

    def stop(self) -> None:
        with self.lock:
            self.done.set()
            if self.shown:
                sys.stderr.write("\r\033[K")
                sys.stderr.flush()
                self.shown = False
