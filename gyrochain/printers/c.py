"""The C target: ``NAME.h``, ``NAME.c`` and the cffi ``NAME.cdef`` of a model (C99, libm only)."""
from __future__ import annotations

from sympy.printing.c import C99CodePrinter

from .codes import METHODS, MOTIONS, QUAD_STATUS, STATUS
from .. import __version__
from . import chunks, kernels
from .common import NumbersAsDoubles, build_text, functions
from .lanes import LANES, lane_functions


class CPrinter(NumbersAsDoubles, C99CodePrinter):
    """C99 with the model's names: q[i], x[i], p->name; small integer powers multiplied out."""

    def __init__(self, names: dict):
        super().__init__()
        self.names = names

    def _print_Pow(self, expr):
        return self._pow(expr, "sqrt", "1.0") or super()._print_Pow(expr)


def defines(ctx: dict) -> list[tuple]:
    """The header's #defines NAME_<key> <value>, in the header's order: sizes, return codes and
    method numbers (codes.py), and the facts of this model (which integrals, forms and
    functions it has); an integral's define comes with generate's sentence about it."""
    status = [(k, v) for k, v in STATUS.items() if k not in QUAD_STATUS]
    out = [("N", ctx["n"]), ("NU", len(ctx["controls"])), ("NPARAMS", len(ctx["params"]))] + status[:4]
    out += [("HAS_ENERGY_INTEGRAL", ctx["has_energy_integral"], ctx["energy_verdict"]),
            ("HAS_MOMENTUM_INTEGRAL", ctx["has_momentum_integral"], ctx["momentum_verdict"]), ("HAS_QUADRATURES", int(ctx["quad"]))]
    if ctx["general"]:
        out += [("HAS_JACOBI_INTEGRAL", int(ctx["has_jacobi"])), ("TIME_DEPENDENT", int(ctx["time_dependent"]))]
    out += status[4:] + [(k.upper(), v) for k, v in METHODS.items()] + [("HAS_CANONICAL", int(ctx["canonical"]))]
    out += [("HAS_VARIATIONAL", int(ctx["variational"])), ("HAS_HESSIAN", int(ctx["hessian"])),
            ("HAS_STEP_HESSIAN", int(ctx["step_hessian"]))]
    if ctx["regressor"]:
        out += [("NPI", ctx["npi"]), ("NBASE", ctx["nbase"])]
    if ctx["quad"]:
        out += [(k, STATUS[k]) for k in QUAD_STATUS] + [(k.upper(), v) for k, v in MOTIONS.items()]
    out += limit_defines(ctx["limits"])
    return [d if len(d) == 3 else (*d, "") for d in out]


# the header's initializer of each kind of joint limit (tables.KEYS), and what stands where a joint has none
LIMIT_MACROS = {"lower": ("PHI_LOWER", "-HUGE_VAL"), "upper": ("PHI_UPPER", "HUGE_VAL"),
                "velocity": ("PHIDOT_MAX", "HUGE_VAL"), "effort": ("EFFORT_MAX", "HUGE_VAL")}


def limit_defines(limits: dict) -> list[tuple]:
    """NAME_HAS_LIMITS and, for each kind of limit some joint has, an initializer of n doubles
    (``static const double lo[NAME_N] = NAME_PHI_LOWER;``)."""
    out = [("HAS_LIMITS", int(bool(limits)), "the spec's joint limits (rad, rad/s, N m): data for an optimiser or a "
            "controller, not enforced by the model; HUGE_VAL (<math.h>) where a joint has none" if limits else "")]
    for key, (macro, none) in LIMIT_MACROS.items():
        if key in limits:
            out.append((macro, "{" + ", ".join(none if v is None else repr(float(v)) for v in limits[key]) + "}", ""))
    return out


def ldlt_factor_lines(A: str, n: int, NAME: str) -> list[str]:
    """The in-place LDLᵀ of the n × n row-major array A unrolled (after the pivot tolerance tol
    is set): L below the diagonal, D on it; a pivot not above tol returns NAME_SINGULAR."""
    out = []
    for j in range(n):
        out += [f"    v[{k}] = {A}[{j * n + k}] * {A}[{k * n + k}];" for k in range(j)]
        out.append(f"    d = {A}[{j * n + j}]" + "".join(f" - {A}[{j * n + k}] * v[{k}]" for k in range(j)) + ";")
        out += ["    if (!(d > tol)) {", f"        return {NAME}_SINGULAR;", "    }", f"    {A}[{j * n + j}] = d;"]
        if j < n - 1:
            out.append("    r = 1.0 / d;")
        out += [f"    {A}[{i * n + j}] = ({A}[{i * n + j}]" + "".join(f" - {A}[{i * n + k}] * v[{k}]" for k in range(j)) + ") * r;"
                for i in range(j + 1, n)]
    return out


def ldlt_solve_lines(A: str, b: str, n: int) -> list[str]:
    """L D Lᵀ y = b solved in place with the factors in A: forward, diagonal, backward, unrolled."""
    out = [f"    {b}[{i}] -= " + " + ".join(f"{A}[{i * n + k}] * {b}[{k}]" for k in range(i)) + ";" for i in range(1, n)]
    out += [f"    {b}[{i}] /= {A}[{i * n + i}];" for i in range(n)]
    out += [f"    {b}[{i}] -= " + " + ".join(f"{A}[{k * n + i}] * {b}[{k}]" for k in range(i + 1, n)) + ";"
            for i in range(n - 2, -1, -1)]
    return out


def integrators(ctx: dict) -> str:
    """The integrators kernel (kernels/integrate.c) for this model, without its last newline
    (the template's line ends it)."""
    n, counts = ctx["n"], ctx["counts"]
    dim = 2 * n
    nu = len(ctx["controls"])
    timed = int(bool(ctx["time_dependent"]))  # t is the last of the step's w = (x, u, h[, t]) and of z = (x, u[, t])
    values = dict(N=n, DIM=dim, NN=n * n, NU=nu, NNU1=n * max(nu, 1), HCOL=dim + nu, COLS=dim + nu + 1 + timed, ZDIM=dim + nu + timed,
                  NP=max(len(ctx["params"]), 1), NNP=n * max(len(ctx["params"]), 1), DIM2=dim * dim, **{"2DIM": 2 * dim, "4DIM2": 4 * dim * dim}, VDIM=dim * (dim + 1),
                  OPS_QDD=counts["qdd"], OPS_QDD_DERIVATIVES=counts.get("qdd_derivatives", 0),
                  OPS_VELOCITIES=counts.get("velocities", 0), OPS_PDOT=counts.get("pdot", 0),
                  OPS_CANONICAL=counts.get("velocities", 0) + counts.get("pdot", 0),
                  NEWTON_SWEEPS=ctx["newton_sweeps"], NEWTON_SWEEPS_CANONICAL=ctx["newton_sweeps_canonical"], LANES=LANES)
    flags = dict(NEWTON=ctx["newton"], CANONICAL=ctx["canonical"], CANONICAL_NEWTON=ctx["canonical"] and ctx["newton"],
                 TIME_DEPENDENT=ctx["time_dependent"], HAS_PARAMS=ctx["has_params"], VARIATIONAL=ctx["variational"],
                 LANES=bool(ctx["lanes"]), HESSIAN=ctx["step_hessian"], PARAM_DERIVATIVES=ctx["step_param_derivatives"])
    text = kernels.specialise("integrate.c", ctx["name"], flags, {}, values, ctx["time_dependent"])
    return text[:-1] if text.endswith("\n") else text


def _ext_target(col: int, n: int, nu: int) -> tuple[str, str]:
    """The block of x's column ``col`` (dqdd_dphi, _dphidot or _du) and its entry for row i."""
    if col < 2 * n:
        out = "dqdd_dphi" if col < n else "dqdd_dphidot"
        return out, f"{out}[{(col % n) * n} + i]"
    return "dqdd_du", f"dqdd_du[i * {nu} + {col - 2 * n}]"


def layout_data(ctx: dict, env) -> dict:
    """What the C templates lay out besides the printed functions, decided here: the #defines,
    the unrolled LDLᵀ, the spellings that depend on the model's facts, and the kernels."""
    name, n, NAME = ctx["name"], ctx["n"], ctx["NAME"]
    nu = len(ctx["controls"])
    out = dict(
        defines=defines(ctx),
        status=STATUS,
        column_suffix={nu: "_u", n: ""},  # NAME_ldlt_columns_ (n columns) or _u (nu columns)
        no_block_asked="!dqdd_dphi && !dqdd_dphidot" + (" && !dqdd_du" if nu else ""),
        forward_mode_how=", by one generic tangent function" if ctx["der_generic"] else "",
        du_arg="B ? du : 0" if nu else "0",
        inputs_not_finite=f"!{name}_all_finite_(x, {2 * n})" + (f" || (u && !{name}_all_finite_(u, {nu}))" if nu else ""),
        # unrolled: O(n³) text, printed only where the loop form (long chains) does not take its place
        ldlt_factor={A: ldlt_factor_lines(A, n, NAME) for A in ("LD", "M") if not ctx["loops"] or A == "M" and not ctx["articulated"]},
        ldlt_solve_code={f"M,{b}": ldlt_solve_lines("M", b, n) for b in ("f", "qd") if not ctx["loops"] or b == "f" and not ctx["articulated"]},
        # which static helpers model.c needs (each is printed only where a function calls it)
        helpers=dict(
            restrict=bool(ctx["lanes"] or ctx["parts_c"]),  # C99 restrict: the lanes' and the parts' arrays
            # the articulated recursion's pivot test
            pivots=ctx["articulated"] or not ctx["der_world"] or ctx["hessian"] or ctx["seeded_derivatives"],
            ldlt_solve=ctx["loops"] and ctx["canonical"] or ctx["der_world"],  # L D L^T y = b in place
            ldlt_columns_u=bool(nu) and nu != n,  # the world form's solve for the nu columns of dqdd_du
        ),
        rhs_lanes_name={L: f"{name}_rhs_{'lane' if L == 1 else 'lanes'}_" for L in ctx["lanes"]},
        # the world form's d tau/dx terms: the block each adds M^-1's column k times ext[e] to, and where
        world_ext_terms=[(k, *_ext_target(col, n, nu), e) for k, col, e in ctx["world_ext"]],
        integrate_c=integrators(ctx),
        trig_c=kernels.specialise("trig.c", name, {}, {}) if ctx["lanes"] else "",
    )
    if ctx["quad"]:
        body = env.from_string('{% import "_c.jinja" as c %}{{ c.body(f) }}\n{{ c.outputs(f) }}\n')
        out["quad_c"] = kernels.specialise("quad.c", name, {"HAS_PARAMS": ctx["has_params"]},
                                           {"quad_terms": body.render(f=ctx["fn"]["quad_terms"])})
    return out


class CTarget:
    """Prints every function of the model in C and lays them out by the templates."""

    suffixes = (".h", ".c", ".cdef", ".pc.in", "CMakeLists.txt")

    def files(self, model, context: dict, env) -> dict[str, str]:
        name = model.spec.name
        ctx = dict(context)
        ctx["fn"], ctx["parts_c"] = chunks.cut_all(functions(model, CPrinter, "c"), ctx)
        ctx["lanes"] = lane_functions(model, ctx["fn"]["qdd"], ctx["real"], CPrinter)
        ctx["lanes_count"] = LANES
        ctx.update(layout_data(ctx, env))
        # the prototypes: the header's carry NAME_FN (a CUDA compiler's __host__ __device__), cffi's none
        decls = env.get_template("_decls.jinja")
        ctx["decls"] = decls.render(ctx, fn=f"{ctx['NAME']}_FN ")
        # (cffi reads integer #defines only: the limits' initializers stay in the header)
        ctx["cdef_decls"] = decls.render(dict(ctx, defines=[d for d in ctx["defines"] if not str(d[1]).startswith("{")]), fn="")
        # the package files for C and C++ builds: a CMake library NAME::NAME and a pkg-config file
        package = dict(ctx, package_version=__version__, pc_description=build_text(model.spec.description or name))
        return {
            f"{name}.h": env.get_template("model.h.jinja").render(ctx),
            f"{name}.c": env.get_template("model.c.jinja").render(ctx),
            f"{name}.cdef": env.get_template("model.cdef.jinja").render(ctx),
            "CMakeLists.txt": env.get_template("CMakeLists.txt.jinja").render(package),
            f"{name}.pc.in": env.get_template("model.pc.in.jinja").render(package),
        }
