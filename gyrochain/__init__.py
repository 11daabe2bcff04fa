"""gyrochain: closed-form equations of compound spatial pendulums → C, Python and LaTeX.

The data flow, one subpackage a stage: chainspec (the spec file and its checks) → derive (the
derivation stages, kinematics → dynamics → integrals, aba, derivatives, world, quadratures →
assemble: the Model, its forms chosen by op count) → printers (c, python, latex; the kernels) →
models (pipeline: derive, render, compile, the one route; build, generate, typeset) → the
capabilities (analysis, ensembles, robots, fmi, identification) → view → commandline.  No module
imports a layer above its own ([tool.importlinter] in pyproject.toml); the names of the modules
before this layout still import them (MOVED, below).

The notation is the paper's ("The compound spatial pendulum", with Kharlamov's equations of
motion of a system of rigid bodies): k is the body index (0 the base), phi/phidot are φᵏ/φ̇ᵏ,
alpha are the direction cosines; equation numbers in comments are the paper's.
"""
__version__ = "0.4.0"  # the one place of the version (pyproject.toml reads it; --version prints it)
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


# The package is laid out by capability, gyrochain/<capability>/<module>.py (docs/reference/layout.md);
# the names scripts used before that layout (gyrochain.spec, gyrochain.pipeline, gyrochain.build, ...)
# import the same modules: `import gyrochain.pipeline` is gyrochain.models.pipeline itself.
MOVED = {
    "aba": "derive.aba",
    "algebra": "derive.algebra",
    "animate": "view.animate",
    "assemble": "derive.assemble",
    "baseparams": "derive.baseparams",
    "build": "models.build",
    "cli": "commandline.cli",
    "cliargs": "commandline.cliargs",
    "codes": "printers.codes",
    "consistency": "identification.consistency",
    "derivatives": "derive.derivatives",
    "dynamics": "derive.dynamics",
    "errors": "chainspec.errors",
    "exact": "derive.exact",
    "exchange": "robots.exchange",
    "excite": "identification.excite",
    "files": "models.files",
    "floquet": "analysis.floquet",
    "fmu": "fmi.fmu",
    "generate": "models.generate",
    "identify": "identification.identify",
    "integrals": "derive.integrals",
    "kinematics": "derive.kinematics",
    "loopform": "derive.loopform",
    "measured": "identification.measured",
    "measures": "ensembles.measures",
    "mjcf": "robots.mjcf",
    "names": "chainspec.names",
    "orbits": "analysis.orbits",
    "parsers": "commandline.parsers",
    "physical": "chainspec.physical",
    "pipeline": "models.pipeline",
    "platform": "derive.platform",
    "plot": "view.plot",
    "program": "derive.program",
    "quadratures": "derive.quadratures",
    "randspec": "chainspec.randspec",
    "raster": "view.raster",
    "reference": "derive.reference",
    "regressor": "derive.regressor",
    "robot": "robots.robot",
    "robotspec": "robots.robotspec",
    "scene": "view.scene",
    "simulate": "analysis.simulate",
    "spec": "chainspec.spec",
    "starter": "commandline.starter",
    "steady": "analysis.steady",
    "store": "ensembles.store",
    "straightline": "derive.straightline",
    "sweep": "ensembles.sweep",
    "trigform": "derive.trigform",
    "typeset": "models.typeset",
    "urdf": "robots.urdf",
    "vec3": "derive.vec3",
    "world": "derive.world"
}


class _MovedLoader:
    """Loads an old name as the module it became.  The import system gives the module it returns
    the old name's spec; exec_module gives it its own back, so that a relative import inside it
    resolves by its own package (where __package__ and __spec__.parent differ, Python 3.12 warns
    and a later Python takes the spec's)."""

    def __init__(self, target: str):
        self.target = target
        self.own_spec = None

    def create_module(self, spec):
        import importlib

        module = importlib.import_module(self.target)
        self.own_spec = module.__spec__
        return module

    def exec_module(self, module) -> None:
        module.__spec__ = self.own_spec


class _MovedFinder:
    """Finds ``gyrochain.<old name>`` as the module it became (MOVED)."""

    @staticmethod
    def find_spec(fullname: str, path=None, target=None):
        head, _, name = fullname.partition(".")
        if head != DISTRIBUTION or name not in MOVED:
            return None
        import importlib.util

        return importlib.util.spec_from_loader(fullname, _MovedLoader(f"{DISTRIBUTION}.{MOVED[name]}"))


_sys.meta_path.insert(0, _MovedFinder)  # first: an old name is always the module it became



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
