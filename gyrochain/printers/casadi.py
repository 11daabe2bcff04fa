"""The CasADi target (``generate --casadi``): NAME_casadi.c, the model as CasADi external functions
(CasADi's C API for ``casadi.external``), with the exact Jacobians of the emitted derivatives:

- ``NAME_f(x, u, p) -> xdot`` the continuous dynamics (NAME_rhs), and ``jac_NAME_f`` its Jacobian
  with respect to x and u, with the true sparsity (the entries the forward-mode derivative
  leaves structurally zero, as a cyclic coordinate's column, are not stored);
- ``NAME_F(x, u, p, h) -> xnext`` one classical RK4 step of the control held over it (NAME_step),
  and ``jac_NAME_F`` its Jacobian with respect to x, u and h (NAME_step_jacobian: the chain rule
  through the four stages);
- ``NAME_M(q, p) -> M`` the mass matrix and ``NAME_E(x, p) -> E`` the energy (23), without
  derivatives.

The parameters p (the spec's symbolic parameters, in their order) are an input like the others:
the p blocks of jac_NAME_f and jac_NAME_F are exact (NAME_param_derivatives,
NAME_step_param_derivatives).  The second derivatives in p are not emitted: those blocks of
jac_adj1_ are NaN (never zeros that would say the dynamics do not depend on a mass), and M and E,
which have no derivatives, CasADi refuses to differentiate.  The target is
written for autonomous models with a control, up to CASADI_MAX_N joints, in double (``check``)."""
from __future__ import annotations

from ..chainspec.errors import SpecError
from ..derive import derivatives
from ..derive.assemble import VARIATIONAL_MAX_N

CASADI_MAX_N = VARIATIONAL_MAX_N  # jac_NAME_F is NAME_step_jacobian, which NAME.c has up to this n


def structure(model) -> list[list[bool]]:
    """``nz[k][j]``: whether ∂φ̈ᵏ⁺¹/∂(direction j) can be nonzero (directions φ, φ̇, u): the
    forward-mode derivative's structural zeros, or every entry where the derivative has another
    form (the world form or one generic tangent: a superset of the true pattern)."""
    spec = model.spec
    ndir = 2 * spec.n + len(spec.controls)
    if isinstance(model.der, derivatives.Derivatives):
        return [[not e.is_zero() for e in row] for row in model.der.dqdd]
    return [[True] * ndir for _ in range(spec.n)]


def jacobian_of_f(model) -> dict:
    """The CCS pattern of ∂f/∂x and ∂f/∂u (f = (φ̇, φ̈)) and, in the same order, the C expression
    of each stored entry (in the blocks Dq, Dv, Du of NAME_qdd_derivatives)."""
    n, nu = model.spec.n, len(model.spec.controls)
    nz = structure(model)
    blocks = {}
    for key, ncol, entry in (("x", 2 * n, lambda k, j: (f"Dq[{k * n + j}]" if j < n else f"Dv[{k * n + j - n}]")),
                             ("u", nu, lambda k, j: f"Du[{k * nu + j}]")):
        colind, rows, values = [0], [], []
        for j in range(ncol):
            if key == "x" and j >= n:  # d(phidot)/d(phidot): the identity
                rows.append(j - n)
                values.append("1.0")
            for k in range(n):
                if nz[k][j if key == "x" else 2 * n + j]:
                    rows.append(n + k)
                    values.append(entry(k, j))
            colind.append(len(rows))
        blocks[key] = dict(sparsity=[2 * n, ncol, *colind, *rows], values=values)
    return blocks


def check(spec, real: str = "double", time_dependent: bool = False) -> None:
    """SpecError where the CasADi target cannot be written for ``spec``."""
    if not spec.controls:
        raise SpecError("--casadi", "the spec has no control torque (a [[body]] with control = true): an optimal "
                                    "control problem needs one")
    if spec.n > CASADI_MAX_N:
        raise SpecError("--casadi", f"is written up to n = {CASADI_MAX_N} joints (n = {spec.n})")
    if real != "double":
        raise SpecError("--casadi", "CasADi computes in double: leave out --real float")
    if time_dependent:
        raise SpecError("--casadi", "the model depends on t (a moving platform or a time-varying load): its "
                                    "external functions are written for autonomous models")


class CasadiTarget:
    """Lays out NAME_casadi.c (the template holds the C; the patterns and entries are decided here)."""

    suffixes = ("_casadi.c",)

    def files(self, model, context: dict, env) -> dict[str, str]:
        name = model.spec.name
        check(model.spec, context["real"], context["time_dependent"])
        n, nu = model.spec.n, len(model.spec.controls)
        data = dict(context, jac_f=jacobian_of_f(model), casadi=signatures(model), np=len(model.spec.params), nu=nu,
                    second_order=model.hess is not None)
        return {f"{name}_casadi.c": env.get_template("model_casadi.c.jinja").render(data)}


def _dense(nrow: int, ncol: int) -> list[int]:
    return [nrow, ncol, 1]


def _empty(nrow: int, ncol: int) -> list[int]:
    return [nrow, ncol, *([0] * (ncol + 1))]


def signatures(model) -> dict:
    """Every external function's inputs and outputs: name, sparsity (CasADi's compressed form) and
    whether CasADi may differentiate with respect to it (x, u, h and p; an output's seed is not an
    input to differentiate)."""
    n, nu, np_ = model.spec.n, len(model.spec.controls), len(model.spec.params)
    d = 2 * n
    arg = lambda name, sp, diff=1: dict(name=name, sparsity=sp, diff=diff)  # noqa: E731
    f_in = [arg("x", _dense(d, 1)), arg("u", _dense(nu, 1)), arg("p", _dense(np_, 1))]
    F_in = [*f_in, arg("h", _dense(1, 1))]
    jac = jacobian_of_f(model)
    out = dict(
        f_in=f_in, f_out=[arg("xdot", _dense(d, 1))],
        jac_f_in=[*f_in, arg("out_xdot", _empty(d, 1), 0)],
        jac_f_out=[arg("jac_xdot_x", jac["x"]["sparsity"]), arg("jac_xdot_u", jac["u"]["sparsity"]),
                   arg("jac_xdot_p", _dense(d, np_))],
        F_in=F_in, F_out=[arg("xnext", _dense(d, 1))],
        jac_F_in=[*F_in, arg("out_xnext", _empty(d, 1), 0)],
        jac_F_out=[arg("jac_xnext_x", _dense(d, d)), arg("jac_xnext_u", _dense(d, nu)),
                   arg("jac_xnext_p", _dense(d, np_)), arg("jac_xnext_h", _dense(d, 1))],
        M_in=[arg("q", _dense(n, 1)), arg("p", _dense(np_, 1))], M_out=[arg("M", _dense(n, n))],
        E_in=[arg("x", _dense(d, 1)), arg("p", _dense(np_, 1))], E_out=[arg("E", _dense(1, 1))],
    )
    if model.hess is not None:
        out.update(second_order(n, nu, np_, "f", f_in, "xdot"))
        out.update(second_order(n, nu, np_, "F", F_in, "xnext"))
    return out


def second_order(n: int, nu: int, np_: int, fname: str, ins: list, res: str) -> dict:
    """The reverse-mode function adj1_NAME_<fname> (λ ↦ λ·∂<fname>/∂(inputs)) and its Jacobian
    jac_adj1_NAME_<fname>, which CasADi asks for the second derivatives of λ·<fname> (IPOPT's
    exact Hessian): each output of jac_adj1 is one block, and how the template fills it
    (``fill``): "hess" a block of the Hessian of λ·<fname> in w = (x, u[, h]) (its rows r0…,
    columns c0…), "jacT" a block of the Jacobian's transpose (∂adj/∂λ), "nan" a derivative in p
    (second derivatives in p are not emitted), "empty" a structural zero (the derivative in an
    output's value); adj1's outputs: "adj" λ·(a block of the Jacobian), "adjp" λ·∂/∂p."""
    d = 2 * n
    arg = lambda name, sp, diff=1, **kw: dict(name=name, sparsity=sp, diff=diff, **kw)  # noqa: E731
    sizes = {"x": d, "u": nu, "p": np_, "h": 1}
    offset = {"x": 0, "u": d, "h": d + nu}  # where each input sits in w
    names = [a["name"] for a in ins]
    adj_in = [*ins, arg(f"out_{res}", _empty(d, 1), 0), arg(f"adj_{res}", _dense(d, 1))]
    adj_out = [arg(f"adj_{i}", _dense(sizes[i], 1), fill=("adjp" if i == "p" else "adj", offset.get(i, 0), sizes[i]))
               for i in names]
    blocks = []
    for o in names:
        for i in [*names, f"out_{res}", f"adj_{res}"]:
            rows, cols = sizes[o], sizes.get(i, d)
            if i == f"out_{res}" or rows * cols == 0:
                kind = ("empty",)
            elif "p" in (o, i):
                kind = ("nan", rows * cols)
            elif i == f"adj_{res}":
                kind = ("jacT", offset[o], rows, cols)
            else:
                kind = ("hess", offset[o], offset[i], rows, cols)
            sparsity = _empty(rows, cols) if kind[0] == "empty" else _dense(rows, cols)
            blocks.append(arg(f"jac_adj_{o}_{i}", sparsity, fill=kind))
    jac_in = [*adj_in, *(arg(f"out_adj_{i}", _empty(sizes[i], 1), 0) for i in names)]
    return {f"adj1_{fname}_in": adj_in, f"adj1_{fname}_out": adj_out, f"jac_adj1_{fname}_in": jac_in,
            f"jac_adj1_{fname}_out": blocks}
