"""gyrochain: closed-form equations of compound spatial pendulums → C, Python and LaTeX.

The data flow, one module a stage: spec → the derivation stages (kinematics → dynamics →
integrals, aba, derivatives, world, quadratures) → assemble (the Model, forms chosen by op count)
→ printers (c, python, latex; the kernels) and build → pipeline (derive, render, compile: the one
route) → the commands (generate, simulate, steady, sweep, animate, plot) → cli.  No module imports
a layer above its own ([tool.importlinter] in pyproject.toml).

The notation is the paper's ("The compound spatial pendulum", with Kharlamov's equations of
motion of a system of rigid bodies): k is the body index (0 the base), phi/phidot are φᵏ/φ̇ᵏ,
alpha are the direction cosines; equation numbers in comments are the paper's.
"""
__version__ = "0.3.0"  # the one place of the version (pyproject.toml reads it; --version prints it)
DISTRIBUTION = "gyrochain"  # the name on the package index, of the import package and of the console command

import os as _os  # (os, sys and the built-in _signal are loaded with the interpreter: free)
import sys as _sys

import _signal  # not signal.py, whose enums take a while to load: the handler goes in first

INTERRUPT = {"requested": False}  # set by the console script's Ctrl-C handlers (below, and __main__.py)


def _sigint_noted(signum, frame):
    """Ctrl-C while the command line's package itself loads, before __main__'s handler is in
    place: noted, and the command then ends as interrupted (__main__.run), without a traceback."""
    INTERRUPT["requested"] = True


def _started_as_the_command() -> bool:
    """``python -m gyrochain ...`` or the ``gyrochain`` console script, not a program importing us."""
    argv = list(getattr(_sys, "orig_argv", []))
    m = argv.index("-m") if "-m" in argv else len(argv)
    return argv[m + 1:m + 2] == [DISTRIBUTION] or _os.path.basename(_sys.argv[0] if _sys.argv else "") == DISTRIBUTION


if _started_as_the_command() and _signal.getsignal(_signal.SIGINT) is _signal.default_int_handler:
    _signal.signal(_signal.SIGINT, _sigint_noted)  # before the imports below

from pathlib import Path as _Path  # noqa: E402

# the package data, found beside the code whether it runs from a checkout or a wheel
TEMPLATES = _Path(__file__).resolve().parent / "templates"   # jinja2 layouts of the emitted files and the viewer
KERNELS = _Path(__file__).resolve().parent / "kernels"       # the fixed numerical kernels (printers/kernels.py)
EXAMPLES = _Path(__file__).resolve().parent / "examples"     # the example specs (`gyrochain examples`)



def caused_by_interrupt(exc: BaseException) -> bool:
    """Whether a Ctrl-C is behind ``exc``: a KeyboardInterrupt in its chain (Python 3.11 turns one
    raised in a descriptor's ``__set_name__``, a dataclass field while a module loads, into a
    RuntimeError caused by it), or any error after the user pressed Ctrl-C (a C extension that
    loads a module, as numpy loads datetime, reports the interrupt as its own ImportError).
    The command line (``__main__``, ``cli``) then ends as interrupted, not with an internal error."""
    if INTERRUPT["requested"]:
        return True
    seen = set()
    while exc is not None and id(exc) not in seen:
        if isinstance(exc, KeyboardInterrupt):
            return True
        seen.add(id(exc))
        exc = exc.__cause__ or exc.__context__
    return False
