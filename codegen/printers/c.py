"""The C target: ``NAME.h``, ``NAME.c`` and the cffi ``NAME.cdef`` of a model (C99, libm only)."""
from __future__ import annotations

from sympy.printing.c import C99CodePrinter

from ..codes import METHODS, MOTIONS, QUAD_STATUS, STATUS
from .common import NumbersAsDoubles, functions


class CPrinter(NumbersAsDoubles, C99CodePrinter):
    """C99 with the model's names: q[i], x[i], p->name; small integer powers multiplied out."""

    def __init__(self, names: dict):
        super().__init__()
        self.names = names

    def _print_Pow(self, expr):
        return self._pow(expr, "sqrt", "1.0") or super()._print_Pow(expr)


def defines(ctx: dict) -> list[tuple[str, int]]:
    """The header's #defines NAME_<key> <value>, in the header's order: sizes, return codes and
    method numbers (codes.py), and the facts of this model (which integrals, forms and
    functions it has)."""
    status = [(k, v) for k, v in STATUS.items() if k not in QUAD_STATUS]
    out = [("N", ctx["n"]), ("NU", len(ctx["controls"])), ("NPARAMS", len(ctx["params"]))] + status[:4]
    out += [("HAS_ENERGY_INTEGRAL", ctx["has_energy_integral"]), ("HAS_MOMENTUM_INTEGRAL", ctx["has_momentum_integral"]),
            ("HAS_QUADRATURES", int(ctx["quad"]))]
    if ctx["general"]:
        out += [("HAS_JACOBI_INTEGRAL", int(ctx["has_jacobi"])), ("TIME_DEPENDENT", int(ctx["time_dependent"]))]
    out += status[4:] + [(k.upper(), v) for k, v in METHODS.items()] + [("HAS_CANONICAL", int(ctx["canonical"]))]
    if ctx["quad"]:
        out += [(k, STATUS[k]) for k in QUAD_STATUS] + [(k.upper(), v) for k, v in MOTIONS.items()]
    return out


class CTarget:
    """Prints every function of the model in C and lays them out by the templates."""

    suffixes = (".h", ".c", ".cdef")

    def files(self, model, context: dict, env) -> dict[str, str]:
        name = model.spec.name
        ctx = dict(context, fn=functions(model, CPrinter, "c"))
        ctx["defines"] = defines(ctx)
        ctx["decls"] = env.get_template("_decls.jinja").render(ctx)
        return {
            f"{name}.h": env.get_template("model.h.jinja").render(ctx),
            f"{name}.c": env.get_template("model.c.jinja").render(ctx),
            f"{name}.cdef": env.get_template("model.cdef.jinja").render(ctx),
        }
