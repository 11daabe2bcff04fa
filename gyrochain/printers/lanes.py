"""RK4's lanes (kernels/rk4_lanes.c): NAME_qdd's body printed for L trajectories side by side.

Component i of lane l's state is X[i L + l]; every statement of the body is the scalar one for
lane l, inside a loop over the lanes that a compiler vectorises.  The sines and cosines are read
from tables that NAME_sincos_ (kernels/trig.c) fills, one entry per distinct argument and lane.
In the composite form M's LDLᵀ and the solve follow in the same loop, statement for statement
the scalar ones (printers/c.py's ldlt_factor_lines and ldlt_solve_lines), each entry of the
factors its own name.  A lane is checked without a branch (ok_[l] > 0: every input and result
finite and every pivot above its tolerance), and only a lane that fails is looked at again, for
the code NAME_rhs would return.
"""
from __future__ import annotations

from .common import function_of, spellings

# a batch's lanes (a single trajectory has one), and the longest φ̈ they are printed for
# (temporaries of NAME_qdd): past it the arithmetic, not libm's sin and cos, is the cost
LANES = 8
LANES_MAX_TEMPORARIES = 400


def lane_printer(printer_cls, names: dict, lanes: int):
    """A printer of printer_cls that spells the state lane by lane and reads sin a / cos a from
    S_ / C_ at k L + l, k the index of a among the distinct arguments (``args``, in the order
    first printed)."""

    class LanePrinter(printer_cls):
        def _trig(self, table: str, expr) -> str:
            arg = expr.args[0]
            if arg not in self.args:
                self.args.append(arg)
            return f"{table}_[{at(self.args.index(arg), lanes)}]"

        def _print_sin(self, expr):
            return self._trig("S", expr)

        def _print_cos(self, expr):
            return self._trig("C", expr)

    pr = LanePrinter({s: _spelling(v, lanes) for s, v in names.items()})
    pr.args = []
    return pr


def at(i: int, lanes: int) -> str:
    """The index of entry i of lane l in an array of L lanes side by side."""
    return f"{i * lanes} + l" if i else "l"


def _spelling(spelling: str, lanes: int) -> str:
    """x[i] → X[i L + l]; every other spelling (t, p->name, tau_k) is shared by the lanes."""
    if spelling.startswith("x["):
        return f"X[{at(int(spelling[2:-1]), lanes)}]"
    return spelling


def ldlt_lane_lines(n: int, L: int, NAME: str) -> tuple[list[str], list[str]]:
    """M's LDLᵀ and L D Lᵀ φ̈ = f for lane l, the scalar code's operations in its order (the lower
    triangle read from M_, the factors named L<i>_<k>_ and d<j>_: a temporary's name never ends
    in _), and the results: φ̈ into XD, the pivots into piv_ and their tolerance into tol_."""
    M = lambda i, j: f"M_[{at(i * n + j, L)}]"  # noqa: E731
    out = ["double tl_ = 0.0;"]
    out += [f"tl_ = fabs({M(i, i)}) > tl_ ? fabs({M(i, i)}) : tl_;" for i in range(n)]
    out.append(f"tol_[l] = tl_ * {NAME}_PIVOT_TOL;")
    for j in range(n):
        out += [f"const double v{j}_{k}_ = L{j}_{k}_ * d{k}_;" for k in range(j)]
        out.append(f"const double d{j}_ = {M(j, j)}" + "".join(f" - L{j}_{k}_ * v{j}_{k}_" for k in range(j)) + ";")
        if j < n - 1:
            out.append(f"const double r{j}_ = 1.0 / d{j}_;")
        out += [f"const double L{i}_{j}_ = ({M(i, j)}" + "".join(f" - L{i}_{k}_ * v{j}_{k}_" for k in range(j)) + f") * r{j}_;"
                for i in range(j + 1, n)]
    out += [f"piv_[{at(j, L)}] = d{j}_;" for j in range(n)]
    out.append(f"const double y0_ = f_[{at(0, L)}];")
    out += [f"const double y{i}_ = f_[{at(i, L)}] - (" + " + ".join(f"L{i}_{k}_ * y{k}_" for k in range(i)) + ");" for i in range(1, n)]
    out += [f"const double z{i}_ = y{i}_ / d{i}_;" for i in range(n)]
    out.append(f"const double w{n - 1}_ = z{n - 1}_;")
    out += [f"const double w{i}_ = z{i}_ - (" + " + ".join(f"L{k}_{i}_ * w{k}_" for k in range(i + 1, n)) + ");"
            for i in range(n - 2, -1, -1)]
    results = [f"XD[{at(n + i, L)}]" for i in range(n)]
    out += [f"{r} = w{i}_;" for i, r in enumerate(results)]
    return out, results


def lane_functions(model, fn_qdd, real: str, printer_cls) -> dict:
    """What the template prints of RK4's lanes, or {} where they do not apply; per lane count:
    NAME_qdd's body (and the composite form's solve), the arguments of its sines and cosines,
    the tables' length and the branch-free check.  They apply to
    a double model whose φ̈ is one straight-line function not longer than LANES_MAX_TEMPORARIES
    (not the loop form of long chains), whose sines and cosines are of the state, t and the
    parameters alone."""
    if real != "double" or model.dyn.loops is not None or fn_qdd.pre or len(fn_qdd.temporaries) > LANES_MAX_TEMPORARIES:
        return {}
    n, names, NAME = model.spec.n, spellings(model, "c"), model.spec.name.upper()
    articulated = model.qdd_form == "articulated"
    out = {}
    for L in (1, LANES):
        pr = lane_printer(printer_cls, names, L)
        piv = [f"piv_[{at(k, L)}]" for k in range(n)]
        if articulated:
            results = [f"XD[{at(n + k, L)}]" for k in range(n)]
            fn = function_of("qdd", model.lines["qdd"], results + piv, pr)
            solve, inputs = [], []
        else:
            lower = [f"M_[{at(i * n + j, L)}]" for i in range(n) for j in range(i + 1)]
            f = [f"f_[{at(k, L)}]" for k in range(n)]
            fn = function_of("qdd", model.lines["qdd"], lower + f, pr)
            solve, results = ldlt_lane_lines(n, L, NAME)
            inputs = [f"M_[{at(i * (n + 1), L)}]" for i in range(n)] + f
        if any(not a.free_symbols <= set(names) for a in pr.args):
            return {}
        assert not any(t.endswith("_") for t, _ in fn.temporaries), "a temporary named as the lanes' own"
        args = [(f"A_[{at(k, L)}]", printer_cls(pr.names).doprint(a)) for k, a in enumerate(pr.args)]
        finite = [f"X[{at(i, L)}]" for i in range(2 * n)] + inputs + results + piv
        # fin is 0 when all these are finite, NaN otherwise; the smallest pivot above the tolerance
        check = ["const double fin = " + " + ".join(f"({v} - {v})" for v in finite) + ";", f"double lo = {piv[0]};"]
        check += [f"lo = {v} < lo ? {v} : lo;" for v in piv[1:]]
        if articulated:  # NAME_pivots_'s tolerance: PIVOT_TOL times the largest |pivot|
            check.append(f"double hi = fabs({piv[0]});")
            check += [f"hi = fabs({v}) > hi ? fabs({v}) : hi;" for v in piv[1:]]
            check.append(f"ok_[l] = (lo - hi * {NAME}_PIVOT_TOL) + fin;")
        else:
            check.append("ok_[l] = (lo - tol_[l]) + fin;")
        out[L] = dict(fn=fn, solve=solve, args=args, size=len(pr.args) * L, check=check)
    return out
