"""The Python target: ``NAME.py``, the same functions as the C in pure Python (the quadratures'
functions of φ on numpy arrays)."""
from __future__ import annotations

from sympy.printing.pycode import PythonCodePrinter

from . import kernels
from .common import NumbersAsDoubles, functions


class PyPrinter(NumbersAsDoubles, PythonCodePrinter):
    def __init__(self, names: dict):
        super().__init__({"fully_qualified_modules": True})
        self.names = names

    def _print_Pow(self, expr, rational=False):
        return self._pow(expr, "math.sqrt", "1.0") or super()._print_Pow(expr, rational)


class NumpyPrinter(PyPrinter):
    """Python on numpy arrays: the functions of φ that the quadratures evaluate at many nodes."""

    def _np(self, expr):
        return f"np.{type(expr).__name__}({self._print(expr.args[0])})"

    _print_sin = _print_cos = _print_tan = _np

    def _print_Pow(self, expr, rational=False):
        return self._pow(expr, "np.sqrt", "1.0") or super()._print_Pow(expr, rational)


class PythonTarget:
    suffixes = (".py",)

    def files(self, model, context: dict, env) -> dict[str, str]:
        ctx = dict(context, py=functions(model, PyPrinter, "py", array_printer_cls=NumpyPrinter))
        ctx["py_bool"] = {k: repr(bool(ctx[k])) for k in ("has_energy_integral", "has_momentum_integral", "quad", "canonical",
                                                          "has_jacobi", "time_dependent")}
        ctx["limits_py"] = repr({k: [None if v is None else float(v) for v in vs] for k, vs in ctx["limits"].items()})
        ctx["momentum_condition_py"] = f'"{ctx["momentum_condition"]}"' if ctx["momentum_condition"] else "None"
        if ctx["quad"]:
            part = env.from_string('{% from "_py.jinja" import prologue, straight with context %}{{ prologue(False) }}\n'
                                   '|{{ straight(f) }}\n')
            prologue, straight = part.render(ctx, f=ctx["py"]["quad_terms"]).split("|", 1)
            ctx["quad_py"] = kernels.specialise("quad.py", model.spec.name, {}, {"prologue": prologue, "quad_terms": straight})
        return {f"{model.spec.name}.py": env.get_template("model.py.jinja").render(ctx)}
