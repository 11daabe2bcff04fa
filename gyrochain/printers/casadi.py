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
which have no derivatives, CasADi refuses to differentiate.

A model that reads t (a moving platform, a rotor spun up, a load of t) takes t as one more input,
the last, of f and F: ``NAME_f(x, u, p, t)`` and ``NAME_F(x, u, p, h, t)`` (the step from t to t + h),
with exact derivatives in t too (NAME_time_derivative, and the step's through its stages' times),
first and second.  A spec's disturbance torques (a [[body]] with disturbance = true: an input of
the C's u that no controller sets) are CasADi's ``u_dist``, the last input of f and F, apart from
the controls u; their derivatives are the C's in those entries of u.  The target is written for
models with a control, up to CASADI_MAX_N joints, in double (``check``)."""
from __future__ import annotations

from ..chainspec.errors import SpecError
from ..derive import derivatives
from ..derive.assemble import VARIATIONAL_MAX_N

CASADI_MAX_N = VARIATIONAL_MAX_N  # jac_NAME_F is NAME_step_jacobian, which NAME.c has up to this n


def slots(spec) -> tuple[list[int], list[int]]:
    """The entries of the C's u (every input torque, in chain order) that CasADi's u and u_dist
    fill: (the controls', the disturbances')."""
    dist = set(spec.disturbances)
    return ([i for i, k in enumerate(spec.controls) if k not in dist],
            [i for i, k in enumerate(spec.controls) if k in dist])


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
    """The CCS pattern of ∂f/∂x, ∂f/∂u, ∂f/∂u_dist and ∂f/∂t (f = (φ̇, φ̈)) and, in the same order,
    the C expression of each stored entry (in the blocks Dq, Dv, Du of NAME_qdd_derivatives and Dt
    of NAME_time_derivative)."""
    n, nu = model.spec.n, len(model.spec.controls)
    ctrl, dist = slots(model.spec)
    nz = structure(model)
    blocks = {}
    for key, cols, entry in (("x", list(range(2 * n)), lambda k, j: f"Dq[{k * n + j}]" if j < n else f"Dv[{k * n + j - n}]"),
                             ("u", ctrl, lambda k, j: f"Du[{k * nu + j}]"), ("u_dist", dist, lambda k, j: f"Du[{k * nu + j}]"),
                             ("t", [0] if model.tder else [], lambda k, j: f"Dt[{k}]")):
        colind, rows, values = [0], [], []
        for j in cols:
            if key == "x" and j >= n:  # d(phidot)/d(phidot): the identity
                rows.append(j - n)
                values.append("1.0")
            for k in range(n):
                if not model.tder[k].is_zero() if key == "t" else nz[k][j if key == "x" else 2 * n + j]:
                    rows.append(n + k)
                    values.append(entry(k, j))
            colind.append(len(rows))
        blocks[key] = dict(sparsity=[2 * n, len(cols), *colind, *rows], values=values)
    return blocks


def check(spec, real: str = "double") -> None:
    """SpecError where the CasADi target cannot be written for ``spec``."""
    if not slots(spec)[0]:
        raise SpecError("--casadi", "the spec has no control torque (a [[body]] with control = true): an optimal "
                                    "control problem needs one")
    if spec.n > CASADI_MAX_N:
        raise SpecError("--casadi", f"is written up to n = {CASADI_MAX_N} joints (n = {spec.n})")
    if real != "double":
        raise SpecError("--casadi", "CasADi computes in double: leave out --real float")


class CasadiTarget:
    """Lays out NAME_casadi.c (the template holds the C; the patterns and entries are decided here)."""

    suffixes = ("_casadi.c",)

    def files(self, model, context: dict, env) -> dict[str, str]:
        name = model.spec.name
        check(model.spec, context["real"])
        ctrl, dist = slots(model.spec)
        data = dict(context, jac_f=jacobian_of_f(model), casadi=signatures(model), np=len(model.spec.params),
                    nu=len(model.spec.controls), timed=bool(model.tder), ctrl_slots=ctrl, dist_slots=dist,
                    second_order=model.hess is not None,
                    # the columns of the C's Jacobians in (x, u[, t]) and (x, u, h[, t]) (u every input torque)
                    fcols=2 * model.spec.n + len(model.spec.controls) + bool(model.tder),
                    Fcols=2 * model.spec.n + len(model.spec.controls) + 1 + bool(model.tder))
        return {f"{name}_casadi.c": env.get_template("model_casadi.c.jinja").render(data)}


def _dense(nrow: int, ncol: int) -> list[int]:
    return [nrow, ncol, 1]


def _empty(nrow: int, ncol: int) -> list[int]:
    return [nrow, ncol, *([0] * (ncol + 1))]


def positions(model, step: bool) -> dict:
    """Where each differentiable input of f (or, with ``step``, of F) sits in the C's variables
    w = (x, u, h, t) of NAME_rhs_hessian / NAME_step_hessian and of the Jacobians (h only in F's,
    t only in a model that reads t): a list of indices per input (p has none: its derivatives are
    NAME_param_derivatives')."""
    n, nu = model.spec.n, len(model.spec.controls)
    ctrl, dist = slots(model.spec)
    d = 2 * n
    out = {"x": list(range(d)), "u": [d + s for s in ctrl], "p": None}
    if step:
        out["h"] = [d + nu]
    if model.tder:
        out["t"] = [d + nu + int(step)]
    if dist:
        out["u_dist"] = [d + s for s in dist]
    return out


def signatures(model) -> dict:
    """Every external function's inputs and outputs: name, sparsity (CasADi's compressed form) and
    whether CasADi may differentiate with respect to it (x, u, h, p, t and u_dist; an output's seed
    is not an input to differentiate); t and u_dist, the last inputs of f and F, only in a model
    that reads t or has disturbance torques.  A Jacobian's output of F says which columns of the
    C's J = ∂xn/∂w it is (``cols``)."""
    n, np_ = model.spec.n, len(model.spec.params)
    d = 2 * n
    arg = lambda name, sp, diff=1, **kw: dict(name=name, sparsity=sp, diff=diff, **kw)  # noqa: E731
    pos_f, pos_F = positions(model, False), positions(model, True)
    size = lambda name: np_ if name == "p" else len(pos_F[name])  # noqa: E731
    f_in = [arg(k, _dense(size(k), 1)) for k in pos_f]
    F_in = [arg(k, _dense(size(k), 1)) for k in pos_F]
    jac = jacobian_of_f(model)
    t_in = [arg("t", _dense(1, 1))] if model.tder else []
    out = dict(
        f_in=f_in, f_out=[arg("xdot", _dense(d, 1))],
        jac_f_in=[*f_in, arg("out_xdot", _empty(d, 1), 0)],
        jac_f_out=[arg(f"jac_xdot_{k}", _dense(d, np_) if k == "p" else jac[k]["sparsity"], block=k) for k in pos_f],
        F_in=F_in, F_out=[arg("xnext", _dense(d, 1))],
        jac_F_in=[*F_in, arg("out_xnext", _empty(d, 1), 0)],
        jac_F_out=[arg(f"jac_xnext_{k}", _dense(d, size(k)), cols=pos_F[k] or None) for k in pos_F],
        M_in=[arg("q", _dense(n, 1)), arg("p", _dense(np_, 1))], M_out=[arg("M", _dense(n, n))],
        E_in=[arg("x", _dense(d, 1)), arg("p", _dense(np_, 1)), *t_in], E_out=[arg("E", _dense(1, 1))],
    )
    if model.hess is not None:
        out.update(second_order(d, np_, "f", f_in, "xdot", pos_f))
        out.update(second_order(d, np_, "F", F_in, "xnext", pos_F))
    return out


def second_order(d: int, np_: int, fname: str, ins: list, res: str, pos: dict) -> dict:
    """The reverse-mode function adj1_NAME_<fname> (λ ↦ λ·∂<fname>/∂(inputs)) and its Jacobian
    jac_adj1_NAME_<fname>, which CasADi asks for the second derivatives of λ·<fname> (IPOPT's
    exact Hessian): each output of jac_adj1 is one block, and how the template fills it
    (``fill``): "hess" a block of the Hessian of λ·<fname> in the C's w (its rows and columns
    there, ``pos``), "jacT" a block of the Jacobian's transpose (∂adj/∂λ), "nan" a derivative in
    p (second derivatives in p are not emitted), "empty" a structural zero (the derivative in an
    output's value); adj1's outputs: "adj" λ·(columns of the Jacobian), "adjp" λ·∂/∂p."""
    arg = lambda name, sp, diff=1, **kw: dict(name=name, sparsity=sp, diff=diff, **kw)  # noqa: E731
    size = lambda i: np_ if i == "p" else d if i == f"adj_{res}" else len(pos[i])  # noqa: E731
    names = [a["name"] for a in ins]
    adj_in = [*ins, arg(f"out_{res}", _empty(d, 1), 0), arg(f"adj_{res}", _dense(d, 1))]
    adj_out = [arg(f"adj_{i}", _dense(size(i), 1), fill=("adjp", np_) if i == "p" else ("adj", pos[i])) for i in names]
    blocks = []
    for o in names:
        for i in [*names, f"out_{res}", f"adj_{res}"]:
            rows, cols = size(o), (d if i == f"out_{res}" else size(i))
            if i == f"out_{res}" or rows * cols == 0:
                kind = ("empty",)
            elif "p" in (o, i):
                kind = ("nan", rows * cols)
            elif i == f"adj_{res}":
                kind = ("jacT", pos[o], d)
            else:
                kind = ("hess", pos[o], pos[i])
            sparsity = _empty(rows, cols) if kind[0] == "empty" else _dense(rows, cols)
            blocks.append(arg(f"jac_adj_{o}_{i}", sparsity, fill=kind))
    jac_in = [*adj_in, *(arg(f"out_adj_{i}", _empty(size(i), 1), 0) for i in names)]
    return {f"adj1_{fname}_in": adj_in, f"adj1_{fname}_out": adj_out, f"jac_adj1_{fname}_in": jac_in,
            f"jac_adj1_{fname}_out": blocks}
