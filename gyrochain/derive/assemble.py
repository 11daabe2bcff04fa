"""Model assembly: the derivation stages' outputs → the straight-line code of every emitted
function, with the forms of φ̈ and of its derivatives chosen by the cost model (op counts).

It reads the stages (kinematics, dynamics, integrals, aba, derivatives, world, quadratures) and
prints nothing: the printers (``printers/``) take the ``Model`` it returns.
"""
from __future__ import annotations

from dataclasses import dataclass

from . import aba, baseparams, derivatives, hessian, quadratures, regressor, world
from .algebra import Poly
from .dynamics import Dynamics
from .integrals import Integrals
from .kinematics import Kinematics, appends_to
from .program import Program
from ..chainspec.spec import T as TIME, ChainSpec
from .straightline import StraightLine, straight_line


def ldlt_op_count(n: int) -> int:
    """Floating-point operations of the emitted LDLᵀ factorization and solve (unrolled: one
    reciprocal per pivot, products and differences as written)."""
    factor = sum(2 * j + 1 + (n - 1 - j) * (2 * j + 1) for j in range(n))
    solve = 2 * sum(2 * j for j in range(n)) + n
    return factor + solve


@dataclass(frozen=True)
class Stages:
    """The three derivation stages of one spec: kinematics, dynamics, integrals."""

    kin: Kinematics
    dyn: Dynamics
    ints: Integrals
    kin_defs: int | None = None  # how many of the program's definitions the kinematics made


@dataclass(frozen=True)
class Model:
    """Everything the generator derived for one spec: inputs of all printers."""

    spec: ChainSpec
    kin: Kinematics
    dyn: Dynamics
    integrals: Integrals
    lines: dict  # name → StraightLine (mass_matrix, forces, qdd, energy, momentum)
    qdd_form: str  # "composite" (M and f, then LDLᵀ) or "articulated" (aba.py: φ̈ and pivots)
    quad: quadratures.TwoBody | None = None  # the integrable two-body case (28)–(30), when it applies
    der: derivatives.Derivatives | derivatives.Tangent | world.World | None = None  # ∂φ̈/∂(φ, φ̇, u)
    der_store: tuple = ()  # the recursion's quantities the columns of ∂φ̈ read (C: the array b)
    der_form: str = "specialised"  # "specialised", "generic" (forward mode) or "world" (world.py)
    # the world form's products with M⁻¹: "solve" (LDLᵀ applied to every column of ∂ID) or "inverse"
    # (M⁻¹ formed, its products with ∂ID's low-rank pairs by prefix sums); "" in the other forms
    world_columns: str = ""
    # the general case's stages again with ω⁰, ε⁰, v̇₀, γ⁰ as symbols (the LaTeX states (8)–(10)
    # with the platform's terms apart); None for a fixed base without loads or when not asked for
    symbolic: Stages | None = None
    # the regressor u = Y π + τ₀ and the base parameters (generate --regressor), else None
    reg: regressor.Regressor | None = None
    base: baseparams.BaseParameters | None = None
    # the weighted second derivatives ∇²(μ·φ̈) (generate --hessian, --casadi), else None (not asked
    # for, or longer than HESSIAN_MAX_OPS)
    hess: hessian.Hessian | None = None
    hess_skipped: str = ""  # why the second derivatives asked for were not emitted ("" when they were, or not asked)
    # ∂φ̈/∂p in the spec's symbolic parameters (NAME_param_derivatives), None without parameters
    pder: derivatives.ParamDerivatives | None = None
    # ∂φ̈/∂t of a model that reads t (NAME_time_derivative: the step's derivatives in h and t), else ()
    tder: tuple = ()


class FormNotApplicable(ValueError):
    """A forced form that this spec cannot have."""


QDD_FORMS = ("auto", "composite", "articulated")
# NAME_qdd_derivatives: forward mode, or world.py's inverse dynamics (its products with M⁻¹ chosen by
# op count, or forced: "world-solve", "world-inverse")
DER_FORMS = ("auto", "forward", "world", "world-solve", "world-inverse")


def build_model(spec: ChainSpec, prog: Program, kin: Kinematics, dyn: Dynamics, ints: Integrals, progress=None,
                qdd_form: str = "auto", der_form: str = "auto", with_regressor: bool = False,
                with_hessian: bool = False) -> Model:
    """The straight-line code of every function, from the program ``prog`` the stages appended
    to (the articulated recursion, the derivatives and Hamilton's variables are appended here).  φ̈ is emitted in whichever form costs fewer
    operations for this spec (``qdd_form="auto"``): composite bodies + LDLᵀ (short chains) or
    articulated bodies (long ones); ties go to the composite form.  Its derivatives likewise
    (``der_form="auto"``): the forward mode of the articulated recursion, or the inverse dynamics
    in frame 0 (world.py) where that applies and costs less."""
    if qdd_form not in QDD_FORMS:
        raise ValueError(f"qdd_form must be one of {', '.join(QDD_FORMS)}, not {qdd_form!r}")
    if der_form not in DER_FORMS:
        raise ValueError(f"der_form must be one of {', '.join(DER_FORMS)}, not {der_form!r}")
    if der_form.startswith("world") and not world.applies(spec, kin, dyn):
        raise FormNotApplicable("the world form needs a fixed base, constant rotors, no body loads and no armature; this spec has "
                                + ("a moving platform" if kin.platform is not None else "rotors that change" if dyn.Lamdot
                                   else "body loads" if dyn.Phi else "motor armature"))
    n = spec.n
    say = progress or (lambda msg: None)
    loops = dyn.loops is not None
    # a long chain's n² entries (and its composite form: O(n²) straight line, O(n³) LDLᵀ) only when asked for
    straight_M = not loops or qdd_form == "composite"
    lower = [dyn.M[i][j] for i in range(n) for j in range(i + 1)] if straight_M else None
    lines = {}
    say("straight-line code: mass matrix, forces, qdd, integrals")
    appends_to(prog, kin)
    P = prog
    # the loop form (loopform.py): S and z1 per joint, the pairs and the LDLᵀ are the template's loops
    axes = [x for v in (dyn.loops.S + dyn.loops.z1 if loops else ()) for x in v]
    lines["mass_matrix"] = straight_line(P, axes if loops else lower)
    lines["forces"] = straight_line(P, dyn.f)
    composite = straight_line(P, lower + list(dyn.f)) if straight_M else None
    art = aba.derive(spec, P, kin, dyn)
    articulated = straight_line(P, list(art.qdd) + list(art.pivots))
    cheaper = composite is None or articulated.op_count() < composite.op_count() + ldlt_op_count(n)
    if qdd_form == "articulated" or (qdd_form == "auto" and cheaper):
        lines["qdd"], form = articulated, "articulated"
    else:
        lines["qdd"], form = composite, "composite"
    say(f"qdd: {form} form ({articulated.op_count()} ops articulated"
        + (f", {composite.op_count() + ldlt_op_count(n)} composite + LDL^T)" if composite is not None else ")"))
    lines["energy"] = straight_line(P, [ints.energy])
    if ints.momentum is not None:
        lines["momentum"] = straight_line(P, [ints.momentum])
    if ints.jacobi is not None:
        lines["jacobi"] = straight_line(P, [ints.jacobi])
    quad = quadratures.derive(spec, kin, dyn, ints)
    if quad is not None:
        lines["quad_terms"] = straight_line(P, quad.terms)
    # last, so that the names of everything above do not depend on it; the world form after all
    # the rest (where it applies and is not chosen, the other names stay what they were)
    say("straight-line code: derivatives of qdd")
    use_world = der_form != "forward" and world.applies(spec, kin, dyn)
    forward = None if der_form.startswith("world") else _forward(spec, P, kin, art, articulated, skip_generic=use_world)
    if forward is not None:
        der_lines = forward[2]
        lines.update(der_lines)
    if canonical_applies(spec, kin, dyn, lines):
        say("straight-line code: momenta p = dL/dphidot and their rate (the symplectic GAUSS2)")
        can = derivatives.canonical(spec, P, kin, dyn, ints.subchain)
        lines["momenta"] = straight_line(P, list(can.p))
        # the loop form's velocities take M from the mass matrix's S and z1 (the C's mass_pairs_)
        lines["velocity_terms"] = straight_line(P, ([] if loops else lower) + list(can.k))
        lines["pdot"] = straight_line(P, list(can.pdot))
    chosen, columns = forward, ""
    if use_world:
        chosen, columns = _choose_world(spec, P, kin, dyn, der_form, forward, lines, say)
    der, store, _, form_d = chosen
    say(f"derivatives: {form_d} form")
    # the regressor after everything else: no other quantity's name depends on it
    reg, base = _regressor(spec, P, kin, dyn, ints, lines, say) if with_regressor else (None, None)
    timed = reads_time_any(lines)
    hess, skipped = _hessian(spec, P, kin, art, articulated, lines, say, timed) if with_hessian else (None, "")
    tder, pder = _seeded(spec, P, kin, art, lines, say, timed)
    return Model(spec, kin, dyn, ints, lines, form, quad, der, store, der_form=form_d, reg=reg, base=base,
                 world_columns=columns if form_d == "world" else "", hess=hess, hess_skipped=skipped, pder=pder,
                 tder=tder)


def _seeded(spec, P: Program, kin, art, lines: dict, say, timed: bool) -> tuple:
    """(∂φ̈/∂t of a model that reads t, else (); ∂φ̈/∂p with symbolic parameters, else None), with
    their straight lines in ``lines``, after the rest: no other quantity's name depends on them."""
    tder: tuple = ()
    if timed:
        say("straight-line code: the derivative of qdd in t")
        tder = derivatives.derive_time(spec, P, kin, art)
        lines["time_derivative"] = straight_line(P, list(art.qdd) + list(art.pivots) + list(tder), prefix="wt")
    pder = None
    if spec.params:
        say("straight-line code: derivatives of qdd in the symbolic parameters")
        pder = derivatives.derive_params(spec, P, kin, art)
        lines["param_derivatives"] = straight_line(P, list(art.qdd) + list(art.pivots) + [d for row in pder.dqdd for d in row],
                                                   prefix="wp")
    return tder, pder


# Past this many operations NAME_rhs_hessian is not emitted (gcc's time; the Panda's is 103k): an
# optimiser then differences the exact Jacobian for its second derivatives
HESSIAN_MAX_OPS = 150000


# The weighted Hessian's operations are about this fraction of (the recursion's) × ndir² (UR5 0.14,
# Panda 0.13): past twice the budget by that estimate it is not derived at all (minutes of Python)
HESSIAN_OPS_PER_RECURSION_DIR2 = 0.14


def _hessian(spec, P: Program, kin, art, articulated: StraightLine, lines: dict, say, timed: bool) -> tuple:
    """(the weighted Hessian of φ̈, "") with its straight line (the recursion, then the pairs i ≤ j)
    in ``lines``, last of all: no other quantity's name depends on it.  (None, why) past
    HESSIAN_MAX_OPS, or past twice it by estimate (not derived).  ``timed``: t is a direction too."""
    ndir = 2 * spec.n + len(spec.controls) + int(timed)
    guess = int(HESSIAN_OPS_PER_RECURSION_DIR2 * articulated.op_count() * ndir * ndir)
    if guess > 2 * HESSIAN_MAX_OPS or spec.n > VARIATIONAL_MAX_N:
        why = f"about {guess:,} operations at n = {spec.n}, past {HESSIAN_MAX_OPS:,}"
        say(f"second derivatives: {why}: not emitted")
        return None, why
    say("second derivatives: the Hessian of mu . qdd, forward mode over forward mode")
    hess = hessian.derive(spec, P, kin, art, timed)
    pairs = [hess.upper[k] for k in sorted(hess.upper)]
    line = straight_line(P, list(art.qdd) + list(art.pivots) + pairs, prefix="wh")
    if line.op_count() > HESSIAN_MAX_OPS:
        why = f"{line.op_count():,} operations, past {HESSIAN_MAX_OPS:,}"
        say(f"second derivatives: {why}: not emitted")
        return None, why
    lines["rhs_hessian"] = line
    return hess, ""


def _choose_world(spec, P: Program, kin, dyn, der_form: str, forward, lines: dict, say) -> tuple:
    """The world form and its products with M⁻¹ ("solve" or "inverse", by op count unless
    forced), in place of ``forward`` in ``lines`` where it costs less or is forced; (chosen, columns)."""
    n = spec.n
    w = _world(spec, P, kin, dyn)
    line_ops = w[2]["qdd_derivatives"].op_count()
    w_counts = world_op_counts(n, 2 * n + len(spec.controls), line_ops, len(w[0].ext))
    columns = der_form[len("world-"):] if der_form in ("world-solve", "world-inverse") else min(w_counts, key=w_counts.get)
    w_count = w_counts[columns]
    f_count = sum(line.op_count() for line in forward[2].values()) if forward is not None else None
    say(f"derivatives: world form {w_count} ops (M^-1 by {columns}: solve {w_counts['solve']}, inverse {w_counts['inverse']})"
        + (f", forward mode {f_count}" if f_count is not None else ""))
    if f_count is not None and line_ops + WORLD_LOOP_WEIGHT * (w_count - line_ops) >= f_count:
        return forward, columns
    for key in forward[2] if forward is not None else ():
        del lines[key]
    lines.update(w[2])
    return w, columns


def _regressor(spec, P: Program, kin, dyn, ints, lines: dict, say) -> tuple:
    """The regressor stage, its base parameters and its three straight lines."""
    say("regressor: Y(phi, phidot, phidd) of the standard parameters, the energy's, the base parameters")
    reg = regressor.derive(spec, P, kin, dyn, ints)
    base = baseparams.find(spec, reg.params)
    n = spec.n
    lines["regressor"] = straight_line(P, [y for row in reg.Y for y in row] + list(reg.tau0), prefix="wr")
    lines["base_regressor"] = straight_line(P, [reg.Y[i][j] for i in range(n) for j in base.columns] + list(reg.tau0),
                                            prefix="wb")
    lines["energy_regressor"] = straight_line(P, list(reg.h) + [reg.e0], prefix="we")
    lines["standard_parameters"] = straight_line(P, [P.from_sympy(p.value) for p in reg.params], prefix="ws")
    return reg, base


def _forward(spec, P: Program, kin, art, articulated: StraightLine, skip_generic: bool) -> tuple:
    """(der, store, lines, form) of the forward mode: one specialised function per column, or past
    SPECIALISED_MAX_OPS one generic tangent called per column (not derived when
    ``skip_generic``: the world form will be used).  None when nothing was derived."""
    n = spec.n
    lines: dict = {"qdd_derivatives": articulated}
    ndir = 2 * n + len(spec.controls)
    base = [a for a, _ in P.needed(list(art.qdd) + list(art.pivots))]
    have = frozenset(base)
    # the specialised columns cost about 0.1–0.6 of the recursion per direction: past 4× the budget
    # by that estimate they are not derived at all (n = 32 would take minutes of Python)
    if articulated.op_count() * ndir <= 4 * SPECIALISED_MAX_OPS:
        used: set = set()
        der = derivatives.derive(spec, P, kin, art)
        for j, label in enumerate(der.labels):
            line = straight_line(P, [der.dqdd[k][j] for k in range(n)], prefix=f"w{label}_", have=have)
            lines[f"d_{label}"] = line
            used |= _reads(P, line) & have
        if sum(lines[f"d_{lab}"].op_count() for lab in der.labels) <= SPECIALISED_MAX_OPS:
            return der, tuple(a for a in base if a in used), lines, "specialised"
    if skip_generic:
        return None
    der = derivatives.derive_tangent(spec, P, kin, art)
    lines = {"qdd_derivatives": articulated, "d_jvp": straight_line(P, list(der.jvp), prefix="wt", have=have)}
    used = _reads(P, lines["d_jvp"]) & have
    return der, tuple(a for a in base if a in used), lines, "generic"


def _world(spec, P: Program, kin, dyn) -> tuple:
    """(der, store, lines, form) of the world form: M φ̈'s right side and world.py's per-joint
    vectors in one straight line; the pairs, the solves and φ̈'s share of β and G are loops of the
    template."""
    der = world.derive(spec, P, kin, dyn)
    outs = [c for name in world.VECTORS for v in der.vec[name] for c in v] + [c for v in der.ic for c in v]
    return der, (), {"qdd_derivatives": straight_line(P, list(der.rhs) + outs + [d for _, _, d in der.ext])}, "world"


# An operation of the world form's loops (6-dots of arrays, the LDLᵀ solve) costs about twice one of
# straight-line code (measured with gcc -O2: arm7 4.3 µs world vs 4.0 µs forward mode at op counts
# 10.6k vs 13.6k; random spatial chain n = 8 5.5 µs vs 9.1 µs); the choice weighs them so.
WORLD_LOOP_WEIGHT = 2


# The template's world_accel_ per joint: the prefix and suffix sums (24), S × A (30), Iᶜ applied
# twice (2 × 42), Z added to Iᶜ A (6), S ×* (30) and the updates of β and G (18)
WORLD_ACCEL_OPS = 192


# world_products_ per pair (j, r), both blocks: the sums P_j (a, b) for φ (23) and φ̇ (24), P's update
# (24), Q's update (12) and Q_j c for φ and φ̇ (2 × 12)
WORLD_PRODUCT_OPS = 107


def minv_op_count(n: int) -> int:
    """Operations of the template's minv_: the reciprocals of D, W = L⁻¹ and M⁻¹ = Wᵀ D⁻¹ W."""
    w = sum(2 * k for r in range(1, n) for k in range(1, r))
    return n + w + sum(a + (n - 1 - a) * (1 + 2 * (a + 1)) for a in range(n))


def world_op_counts(n: int, ndir: int, line_ops: int, n_ext: int) -> dict[str, int]:
    """Operations of the world form with either product with M⁻¹: its straight line, then in loops
    the 6-dots of M's lower triangle, the LDLᵀ factorization, the solve for φ̈ and φ̈'s share of β
    and G; then "solve": the 6-dots of ∂ID (two per pair below the diagonal, one on and above it,
    for φ and φ̇) and the solve with every column; "inverse": M⁻¹ formed, its products with ∂ID's
    pairs by prefix sums and one column of M⁻¹ per entry of ∂τ/∂x."""
    below, upper = n * (n - 1) // 2, n * (n + 1) // 2
    factor = sum(2 * j * (n - j) + 2 * j for j in range(n))
    one_solve = 2 * n * (n - 1) + n
    common = line_ops + 11 * upper + factor + one_solve + WORLD_ACCEL_OPS * n
    return {"solve": common + 2 * (24 * below + 11 * upper) + ndir * one_solve,
            "inverse": common + minv_op_count(n) + WORLD_PRODUCT_OPS * n * n + 2 * n * n_ext}


def canonical_applies(spec: ChainSpec, kin: Kinematics, dyn: Dynamics, lines: dict) -> bool:
    """Whether the model gets Hamilton's variables (NAME_momenta, NAME_velocities, NAME_pdot and
    NAME_GAUSS2_SYMPLECTIC): a fixed base, every λ constant and nothing that reads t, so that
    p = M φ̇ + k(φ) and the flow in (φ, p) is autonomous."""
    return kin.platform is None and not dyn.Lamdot and not any(reads_time(lines[k]) for k in ("forces", "qdd"))


# Above this many operations in all the specialised columns of ∂φ̈ together (about n = 10 for a
# spatial gyrostat chain), NAME_qdd_derivatives uses one generic tangent function called per column
# instead: exact all the same, ~2n times less code to compile, at most a few times the run time.
SPECIALISED_MAX_OPS = 60000


def _reads(P, line: StraightLine) -> set:
    """The program quantities a straight-line section reads."""
    out: set = set()
    for _, rhs in line.temporaries:
        if isinstance(rhs, Poly):
            out.update(rhs.atoms())
        else:
            out.update(a for a in (P.quantity(s) for s in rhs.free_symbols) if a is not None)
    for o in line.outputs:
        out.update(o.atoms())
    return out


GAUSS2_NEWTON_MAX_N = 16  # GAUSS2's Newton matrix is 2n × 2n on the stack: 8 KB at n = 16
# NAME_integrate_variational carries the 2n × 2n fundamental matrix through DOP853's 16 stages on the
# stack: 28 (2n)(2n + 1) doubles, 236 KB at n = 16; longer chains are not emitted one
VARIATIONAL_MAX_N = 16


def variational_stack_bytes(n: int) -> int:
    """The stack NAME_integrate_variational's arrays take: DOP853's 16 stages, 5 work vectors and 7
    dense-output rows of the system (x, Φ), and the wrapper's two rows of it."""
    return 8 * (28 + 2) * 2 * n * (2 * n + 1)


def step_jacobian_stack_bytes(n: int, nu: int) -> int:
    """The stack NAME_step_jacobian's arrays take: dy, dk, ds and J, 2n x (2n + nu + 1) each."""
    return 8 * 4 * 2 * n * (2 * n + nu + 1)


def step_hessian_stack_bytes(n: int, nu: int) -> int:
    """The stack NAME_step_hessian's arrays take: per stage y, k, dy/dw, dk/dw and the Jacobian's
    blocks; the stage's Hessian and its product with dy/dw (w = (x, u, h))."""
    d, m, z = 2 * n, 2 * n + nu + 1, 2 * n + nu
    return 8 * (4 * (2 * d + 2 * d * m + 2 * n * n + n * max(nu, 1)) + 5 * d + z * z + z * m + m)


def newton_sweeps(n: int, counts: dict) -> int:
    """A simplified Newton solve of GAUSS2's stages in fixed-point sweeps (2 rhs each): the
    Jacobian, the LU of the 2n × 2n matrix (⅔(2n)³ flops) and ~3 iterations of 2 rhs."""
    rhs = max(1, counts["qdd"])
    setup = (counts.get("qdd_derivatives", 0) + 2 * (2 * n) ** 3 // 3) / rhs
    return int(round(setup / 2 + 3))


def newton_sweeps_canonical(n: int, counts: dict) -> int:
    """The same for GAUSS2_SYMPLECTIC: 2n + 1 canonical evaluations for the Jacobian by differences,
    the LU of the 4n × 4n matrix and ~4 iterations, in sweeps of 2 canonical evaluations."""
    g = max(1, counts.get("velocities", 0) + counts.get("pdot", 0))
    setup = ((2 * n + 1) * g + 2 * (4 * n) ** 3 // 3) / g
    return int(round(setup / 2 + 4))


# NAME_qdd_derivatives: φ̈ by the articulated recursion (line "qdd_derivatives"), then one column of
# ∂φ̈ per direction (lines "d_q1" …), each its own static C function reading the recursion's values
# it needs from an array: a Jacobian of a long chain is too big for one function (gcc's time grows
# faster than its length); a block whose output is NULL is not computed.

def reads_time(line: StraightLine) -> bool:
    """Whether a straight-line program reads t (a prescribed motion, λ(t), a load of t)."""
    for _, rhs in line.temporaries:
        if isinstance(rhs, Poly):
            if any(a.sym == TIME for a in rhs.atoms()):
                return True
        elif rhs.has(TIME):
            return True
    return any(a.sym == TIME for o in line.outputs for a in o.atoms())


def step_hessian_applies(model: Model) -> bool:
    """Whether NAME_step_hessian is emitted beside NAME_rhs_hessian: a model with
    NAME_step_jacobian (n ≤ VARIATIONAL_MAX_N)."""
    return model.hess is not None and model.spec.n <= VARIATIONAL_MAX_N


def reads_time_any(lines: dict) -> bool:
    """Whether any of the straight lines of the state's functions reads t."""
    return any(reads_time(lines[k]) for k in ("forces", "qdd", "energy", "momentum") if k in lines)


def time_dependent(model: Model) -> bool:
    """Whether any emitted function of the state needs t (then all of them but NAME_mass_matrix
    and NAME_jacobi take it, first; the header says so with NAME_TIME_DEPENDENT 1)."""
    return reads_time_any(model.lines)



def op_counts(model: Model) -> dict[str, int]:
    """Op count of each emitted function (multiplications, additions and function calls of the
    straight-line code; the qdd and rhs counts include the unrolled LDLᵀ solve)."""
    n = model.spec.n
    blocks = ["qdd_derivatives", "d_jvp"] + ([f"d_{lab}" for lab in model.der.labels] if model.der else [])
    counts = {name: line.op_count() for name, line in model.lines.items() if name not in blocks}
    if model.qdd_form == "composite":
        counts["qdd"] += ldlt_op_count(n)
    counts["rhs"] = counts["qdd"]
    if model.dyn.loops is not None:  # the loop form: S and z1, then a 6-dot (11 ops) per pair
        counts["mass_matrix"] += 11 * n * (n + 1) // 2
        if "velocity_terms" in counts:  # M as mass_matrix forms it, then k
            counts["velocity_terms"] += counts["mass_matrix"]
    if "velocity_terms" in counts:  # M and k, then φ̇ = M⁻¹(p − k) by LDLᵀ
        counts["velocities"] = counts.pop("velocity_terms") + ldlt_op_count(n) + n
    if model.der is not None:
        # φ̈ by the articulated recursion, then every block of derivatives
        if model.der_form == "world":  # the straight line, then the loops
            ndir = 2 * n + len(model.spec.controls)
            counts["qdd_derivatives"] = world_op_counts(n, ndir, model.lines["qdd_derivatives"].op_count(),
                                                        len(model.der.ext))[model.world_columns]
        elif "d_jvp" in model.lines:  # run-time count: the tangent once per column
            cols = len(model.der.labels) * model.lines["d_jvp"].op_count()
            counts["qdd_derivatives"] = model.lines["qdd_derivatives"].op_count() + cols
        else:
            counts["qdd_derivatives"] = sum(model.lines[b].op_count() for b in blocks if b in model.lines)
        counts["linearize"] = counts["qdd_derivatives"]
    return counts


