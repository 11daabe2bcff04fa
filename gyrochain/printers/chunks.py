"""A long C function in parts: its temporaries cut into static functions of at most
``PART_TEMPORARIES`` each, the values a later part reads passed through one array.

gcc's register allocation of one straight-line function grows faster than its length (the
LRA of a 1 MB function of a 32-link chain took most of its two minutes): thousands of values
live at once.  In parts, each value lives inside its part or in memory, and gcc's time is
linear in the length.  The parts are ``noinline`` where the compiler knows the attribute (gcc
would otherwise inline a static function called once and undo the cut); elsewhere they are
plain static functions, the same code.  Shorter functions (every example) are printed whole.
"""
from __future__ import annotations

import re
from dataclasses import replace

from ..derive.world import VECTORS
from .common import Function

PART_TEMPORARIES = 150  # temporaries per part; a function is cut from 3 parts on
MIN_PARTS = 3

# (how the function names φ's array, whether it reads u, whether it takes t when the model is
# time dependent): the arguments its parts take, as the template's signature of the function
SIGNATURES = {
    "mass_matrix": ("q", False, False), "forces": ("x", True, True), "qdd": ("x", True, True),
    "qdd_derivatives": ("x", True, True), "energy": ("x", False, True), "momentum": ("x", False, True),
    "jacobi": ("x", False, False), "momenta": ("x", False, False), "velocity_terms": ("q", False, False),
    "pdot": ("x", True, False), "rhs_hessian": ("x", True, True), "param_derivatives": ("x", True, True),
    "time_derivative": ("x", True, True),
}
# the inputs a function reads besides its state, controls and parameters, passed on to its parts
EXTRA_INPUTS = {"rhs_hessian": ("lam",)}

# the arrays a function's outputs fill that are locals of the template's C function, declared
# before its parts are called (templates/model.c.jinja): the parts write them directly.  Others
# (the caller's M, f, pm, ... which might overlap the inputs) are copied from s_ at the end.
LOCAL_OUTPUTS = {
    "qdd": {"acc", "piv", "M", "f"},
    "mass_matrix": {"S_", "z1_"},  # only the loop form's per-joint axes (NAME_mass_pairs_)
    "qdd_derivatives": {"acc", "piv", "ext", "IC_"} | {f"{v}_" for v in VECTORS},
    "rhs_hessian": {"acc", "piv", "hv"},
    "param_derivatives": {"acc", "piv", "dp"},
    "time_derivative": {"acc", "piv", "dp"},
}

NOINLINE = """#if defined(__GNUC__)
#define {NAME}_PART_ {NAME}_FN static __attribute__((noinline)) void
#else
#define {NAME}_PART_ {NAME}_FN static void
#endif
"""


def cut(key: str, fn: Function, ctx: dict) -> tuple[Function, list[str]]:
    """(the function with its temporaries moved into parts, the parts' C text); a function too
    short to cut, or one of no known signature, comes back as it is, with no parts."""
    temps = fn.temporaries
    if key not in SIGNATURES or len(temps) < MIN_PARTS * PART_TEMPORARIES or not fn.reads:
        return fn, []
    xname, with_u, with_t = SIGNATURES[key]
    with_t = with_t and ctx["time_dependent"]
    # the outputs too are computed in the parts (as temporaries out<k>_, each to its slot) and the
    # function only copies them: thousands of output expressions in one function made gcc's dead
    # store elimination, PRE and SLP passes grow as the square of their number (n = 128: the
    # function's 630 KB of outputs cost more than all its parts).  Each output is computed right
    # after the last temporary it reads, so that it reads the values of its own part; an output
    # into one of the template's own arrays (LOCAL_OUTPUTS) is written there directly.
    local = LOCAL_OUTPUTS.get(key, set())
    direct = [lhs.split("[")[0] in local and re.fullmatch(r"\w+\[\d+\]", lhs) is not None for lhs, _ in fn.outputs]
    arrays = sorted({lhs.split("[")[0] for (lhs, _), d in zip(fn.outputs, direct) if d})
    outs = [(lhs if d else f"out{k}_", code) for k, ((lhs, code), d) in enumerate(zip(fn.outputs, direct))]
    assert not {lhs for lhs, _ in temps} & {lhs for lhs, _ in outs}, "a temporary named out<k>_"
    index = {lhs: i for i, (lhs, _) in enumerate(temps)}
    order = [(i, ("t", i)) for i in range(len(temps))]
    order += [(max((index[r] for r in reads), default=-1) + 0.5, ("o", k)) for k, reads in enumerate(fn.out_reads)]
    order = [w for _, w in sorted(order, key=lambda e: e[0])]  # stable: the outputs keep their order
    temps, all_reads = (tuple(temps[i] if kind == "t" else outs[i] for kind, i in order),
                        tuple(fn.reads[i] if kind == "t" else fn.out_reads[i] for kind, i in order))
    bounds = list(range(0, len(temps), PART_TEMPORARIES)) + [len(temps)]
    spans = list(zip(bounds, bounds[1:]))
    part_of = {lhs: c for c, (a, b) in enumerate(spans) for lhs, _ in temps[a:b] if "[" not in lhs}
    # the template also stores, by name, the recursion's values the columns read (b[])
    named = sorted(set(ctx["der_store"]) & set(part_of)) if key == "qdd_derivatives" else []
    # a slot in s_ for every value read outside the part that computes it
    slot: dict = {}
    for c, (a, b) in enumerate(spans):
        for reads in all_reads[a:b]:
            for r in reads:
                if part_of[r] != c and r not in slot:
                    slot[r] = len(slot)
    for r in [lhs for lhs, _ in outs if "[" not in lhs] + sorted(named):
        slot.setdefault(r, len(slot))
    name, NAME = ctx["name"], ctx["NAME"]
    # restrict (C99; __restrict__ where the file is compiled as C++): a part writes only s_ and the
    # template's own arrays, distinct objects the caller's inputs cannot overlap; without it gcc
    # reloads inputs after every store (n = 32: qdd and the Jacobian 2-4 % slower)
    r = f"*{NAME}_RESTRICT_ "
    extra = EXTRA_INPUTS.get(key, ())
    params = (("double t, " if with_t else "") + f"const double {r}{xname}, " + (f"const double {r}u, " if with_u else "")
              + "".join(f"const double {r}{e}, " for e in extra)
              + f"const {name}_params {r}p, double {r}s_" + "".join(f", double {r}{a}" for a in arrays))
    args = (("t, " if with_t else "") + f"{xname}, " + ("u, " if with_u else "") + "".join(f"{e}, " for e in extra) + "p, s_"
            + "".join(f", {a}" for a in arrays))
    parts = []
    for c, (a, b) in enumerate(spans):
        lines = [f"/* {name}_{fn.name}, part {c + 1} of {len(spans)} (gyrochain/printers/chunks.py) */",
                 f"{NAME}_PART_ {name}_{fn.name}_part{c + 1}_({params})", "{"]
        lines += [f"    (void){v};" for v in (["t"] if with_t else []) + [xname] + (["u"] if with_u else []) + list(extra)
                  + ["p", "s_"] + arrays]
        if with_u:
            for i, k in ctx["controls"]:
                lines += [f"    const double tau_{k} = u ? u[{i}] : 0.0;", f"    (void)tau_{k};"]
        needed = sorted({r for reads in all_reads[a:b] for r in reads if part_of[r] != c}, key=slot.get)
        lines += [f"    const double {r} = s_[{slot[r]}];" for r in needed]
        lines += [f"    {lhs} = {rhs};" if "[" in lhs else f"    const double {lhs} = {rhs};" for lhs, rhs in temps[a:b]]
        lines += [f"    s_[{slot[lhs]}] = {lhs};" for lhs, _ in temps[a:b] if lhs in slot]
        parts.append("\n".join(lines + ["}", ""]))
    pre = [f"double s_[{max(1, len(slot))}];"] + [f"{name}_{fn.name}_part{c + 1}_({args});" for c in range(len(spans))]
    if with_u:  # the function's own tau_k may now be read by its parts alone
        pre += [f"(void)tau_{k};" for _, k in ctx["controls"]]
    # the values the template reads by name are imported
    outputs = tuple((lhs, f"s_[{slot[out]}]") for (lhs, _), (out, _), d in zip(fn.outputs, outs, direct) if not d)
    imports = tuple((r, f"s_[{slot[r]}]") for r in named)
    return replace(fn, temporaries=imports, outputs=outputs, pre=tuple(pre), reads=(), out_reads=()), parts


def cut_all(fns: dict, ctx: dict) -> tuple[dict, str]:
    """Every function of ``fns`` cut where it is long; the parts' C text (with the attribute's
    #define), empty when nothing was cut."""
    out, parts = {}, []
    for key, fn in fns.items():
        out[key], p = cut(key, fn, ctx)
        parts += p
    if not parts:
        return out, ""
    return out, NOINLINE.format(NAME=ctx["NAME"]) + "\n" + "\n".join(parts)
