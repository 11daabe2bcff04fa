"""``generate``: a spec → a folder of C, Python and LaTeX (and the compiled extension), and the
report of what was derived: sizes, op counts, forms, which integrals exist and why.

    result = generate.run(spec, Path("generated/gimbal"), "gimbal.toml")
    print("\\n".join(generate.report(result)))

Outputs go to a temporary folder beside the target and move into it a rename a file at the end
(pipeline.write_tree): a failure leaves the old files as they were, and nothing gyrochain did not
write is touched.
"""
from __future__ import annotations

import shutil
import sys
from dataclasses import dataclass
from pathlib import Path

from . import files, pipeline, typeset
from ..derive.assemble import Model, op_counts, step_hessian_applies, time_dependent
from ..derive.integrals import energy_verdict, momentum_verdict
from ..chainspec.spec import SpecError

DERIVATIVE_FORMS = {
    "specialised": "forward mode over the articulated recursion, one function per column",
    "generic": "forward mode over the articulated recursion, one tangent called per column",
    "world": "inverse dynamics differentiated in frame 0, O(n^2) pairs",
}
WORLD_COLUMNS = {  # the world form's products with M^-1 (assemble.world_op_counts chooses)
    "solve": "M^-1 applied by LDL^T to every column",
    "inverse": "M^-1 formed from LDL^T, its products by prefix sums",
}


@dataclass(frozen=True)
class Result:
    spec: object
    model: Model
    target: Path
    files: tuple  # the file names written
    build: str | None  # "compiled", "reused" or None (--no-build)
    pdf: tuple | None = None  # (the PDF, its pages) with --pdf
    checked: str | None = None  # what the self-check compared (``verify``), None without it


def run(spec, target: Path, label: str, build: bool = True, force: bool = False, qdd_form: str = "auto",
        der_form: str = "auto", progress=None, real: str = "double", source: Path | None = None,
        regressor: bool = False, paper: str = "a4", pdf: bool = False, gpu: bool = False, casadi: bool = False,
        check_model: bool = True, hessian: bool = False) -> Result:
    """Derive, print and write ``spec`` into ``target`` (built unless ``build`` is False).  A
    folder this generator did not write is written into only with ``force``, and its other files
    are kept; a folder that holds ``source``, the spec file, never.  ``pdf``: the LaTeX typeset too.
    ``check_model``: the emitted model held to the independent one before anything is written
    (``verify``)."""
    target = Path(target)
    check(spec, target, force, source, der_form, pdf)
    say = progress or (lambda msg: None)
    ahead = pipeline.BuildAhead(target, spec.name) if build else None
    try:
        try:
            files, model = pipeline.derive_and_render(spec, label, say, qdd_form=qdd_form, der_form=der_form, on_c=ahead,
                                                      real=real, regressor=regressor, paper=paper, gpu=gpu,
                                                      casadi=casadi, hessian=hessian)
        except pipeline.FormNotApplicable as exc:
            raise SpecError("--derivative-form", str(exc)) from None
        if build:
            say("the cffi extension: the folder's if built from the same C and flags, else the model cache's (compiled if new)")
        checked = []
        how = pipeline.write_tree(files, target, build, spec.name, ahead, verify=None if not check_model else
                                  lambda folder: checked.append(verify(spec, model, files, folder, build, say)))
    finally:
        if ahead is not None:
            ahead.close()
    made = None
    if pdf:
        say("the PDF: LuaLaTeX, two passes")
        made = typeset.pdf(target / f"{spec.name}.tex")
    return Result(spec, model, target, tuple(sorted(files)), how, made, checked[0] if checked else None)


def verify(spec, model: Model, files: dict, folder: Path, built: bool, say=None) -> str:
    """The emitted model in ``folder`` held to the independent model (selfcheck.py): the compiled C
    when it was ``built``, and the Python mirror; an EmittedModelError if they differ, else the
    line ``generate`` reports."""
    from . import build as builder
    from . import selfcheck

    (say or (lambda msg: None))(f"the self-check: the emitted {'C and ' if built else ''}Python against the "
                                f"independent model at {selfcheck.STATES} random states")
    functions = {}
    try:
        if built:
            c = pipeline.load_built(folder, files, spec.name)
            functions.update(dict.fromkeys(pipeline.self_check(spec, c)))
        module = builder.load_python(folder, spec.name)
        try:
            functions.update(dict.fromkeys(selfcheck.check(spec, selfcheck.PythonMirror(module, time_dependent(model)),
                                                           "Python")))
        finally:
            sys.modules.pop(module.__name__, None)  # a module of a temporary folder: nothing imports it again
            shutil.rmtree(folder / "__pycache__", ignore_errors=True)  # only the emitted files move into place
    except selfcheck.EmittedModelError as exc:
        raise selfcheck.EmittedModelError(f"{exc}; nothing was written") from None
    single = built and c.real == "float"
    tol, dtol = (f"{v:.0e}".replace("e-0", "e-") for v in selfcheck.tolerances(single))
    return (f"self-check: the emitted {'C and ' if built else ''}Python equal the independent model at {selfcheck.STATES} "
            f"random states ({', '.join(functions)}; relative tolerance {tol}{' for the C, 1e-9 for the Python' if single else ''}, "
            f"{dtol} against its differences and integrations)")


def check(spec, target: Path, force: bool = False, source: Path | None = None, der_form: str = "auto",
          pdf: bool = False) -> None:
    """What must hold before anything is derived: the target is a folder we may write into (one
    gyrochain wrote, a new or empty one, or with ``force`` any folder: its other files are kept),
    it does not hold the spec file ``source`` itself, and the chain's mass matrix is not singular
    everywhere; with ``pdf``, LuaLaTeX is installed."""
    target = Path(target)
    if pdf:
        typeset.available()
    if target.exists() and not target.is_dir():
        raise SpecError("-o", f"{target} is a file, not a folder")
    if source is not None:
        where = target.resolve()
        if Path(source).resolve().parent.is_relative_to(where):
            raise SpecError("-o", f"{target} holds the spec {source} itself; choose another folder")
    if not pipeline.is_ours(target) and not force:
        raise SpecError("-o", f"{target} exists and was not written by gyrochain; choose another folder or pass --force "
                              "(its other files are kept)")
    files.writable(target / "x" if target.is_dir() else target)  # the folder it writes in (or makes)
    pipeline.check_mass_matrix(spec)
    if der_form.startswith("world"):  # said before the first progress line, from the spec (assemble checks it again)
        why = ("a moving platform" if spec.base is not None and spec.base.moves
               else "rotors that change" if any(any(c != 0 for c in b.lam_dot) for b in spec.bodies)
               else "body loads" if any(b.loaded for b in spec.bodies)
               else "motor armature" if any(b.armature != 0 for b in spec.bodies) else "")
        if why:
            raise SpecError("--derivative-form", f"the world form needs a fixed base, constant rotors, no body loads and no armature; "
                                                 f"this spec has {why}")


def report(result: Result) -> list[str]:
    """What ``generate`` prints: the model's size and forms, the integrals, the quadratures, the
    motion of the spec's [initial] state, and what was written."""
    spec, model = result.spec, result.model
    counts = op_counts(model)
    out = [f"{spec.name}: n = {spec.n}, {len(spec.params)} symbolic parameters, {len(spec.controls)} control torques"
           + (", moving platform" if spec.base is not None and spec.base.moves else ""),
           "op counts: " + ", ".join(f"{spec.name}_{k} {v}" for k, v in counts.items()),
           f"qdd form: {model.qdd_form}" + (" (composite bodies + LDL^T)" if model.qdd_form == "composite" else " (articulated bodies, O(n))"),
           f"derivative form: {model.der_form} (" + DERIVATIVE_FORMS[model.der_form]
           + (", " + WORLD_COLUMNS[model.world_columns] if model.world_columns else "") + ")"]
    out += integral_lines(spec, model)
    if model.reg is not None:
        out.append(regressor_line(model))
    if model.hess is not None:
        out.append(f"second derivatives: {spec.name}_rhs_hessian ({counts['rhs_hessian']} ops)"
                   + (f" and {spec.name}_step_hessian" if step_hessian_applies(model) else
                      " (no step Hessian: emitted up to n = 16)")
                   + (", in (x, u, t): the model reads t" if model.tder else ""))
    elif model.hess_skipped:
        out.append(f"second derivatives: not emitted ({model.hess_skipped}); an optimiser differences the exact "
                   "Jacobian instead")
    if model.quad is not None and spec.initial is not None:
        out.append(motion_line(spec, result.target))
    built = {None: "", "compiled": " + cffi extension",
             "reused": " + cffi extension (not recompiled: the C, the header and the compiler flags are those it was built from)"}[result.build]
    if result.checked is not None:
        out.append(result.checked)
    out.append(f"wrote {result.target}/: " + ", ".join(result.files) + built)
    if result.pdf is not None:
        out.append(f"typeset {result.pdf[0]}: {result.pdf[1]} pages")
    return out


def regressor_line(model: Model) -> str:
    """The regressor's size: standard and base parameters, and which coefficients are numerical."""
    base = model.base
    approx = sum(base.numerical)
    return (f"regressor: {len(model.reg.params)} standard parameters, {base.count} base parameters (identifiable "
            f"combinations; their formulas in the LaTeX" + (f", {approx} with numerical coefficients" if approx else "") + ")")


def integral_lines(spec, model: Model) -> list[str]:
    """What ``generate`` says about the integrals and the quadratures of a spec."""
    from ..derive.quadratures import why_not

    ints = model.integrals
    reason = why_not(spec)
    quad = ("quadratures (30): emitted (" + ("Nikolai's balanced gyroscope, " if model.quad.nikolai else "")
            + "NAME_quad_period, NAME_quad_state)" if reason is None else f"quadratures (30): not emitted: {reason}")
    out = ["integrals: " + energy_verdict(spec, ints), "           " + momentum_verdict(ints)]
    if spec.general and spec.base is not None and spec.base.moves:
        out.append("           Jacobi integral T2 - T0 - U - sum lambda.omega0: " + (
            "conserved (the platform turns uniformly, gravity fixed in it; NAME_jacobi)" if ints.jacobi is not None
            else "none (the platform's motion or a load makes the Lagrangian depend on t)"))
    if spec.general:
        out.append("time: " + ("the equations depend on t (NAME_TIME_DEPENDENT 1: forces, qdd, energy, momentum take t)"
                               if time_dependent(model) else "autonomous (NAME_TIME_DEPENDENT 0)"))
    return [line.replace("NAME_T", f"{spec.name.upper()}_T").replace("NAME", spec.name) for line in out] + [quad.replace("NAME", spec.name)]


def motion_line(spec, target: Path) -> str:
    """The kind of motion of the spec's [initial] state, by the generated Python module itself."""
    from .build import load_python

    if spec.params:
        return "motion of [initial]: needs values of the parameters (" + ", ".join(map(str, spec.params)) + ")"
    mod = load_python(target, spec.name)
    x0 = [*spec.initial["phi"], *spec.initial["phidot"]]
    try:
        m = mod.quad_motion(x0)
    except ArithmeticError as exc:
        return f"motion of [initial]: {exc}"
    if m["kind"] == "libration":
        return (f"motion of [initial]: libration of phi2 between {m['phi_min']:.9g} and {m['phi_max']:.9g} rad, "
                f"period {m['period']:.12g} s, psi gains {m['psi_advance']:.9g} rad per period")
    if m["kind"] == "rotation":
        return (f"motion of [initial]: rotation (phi2 runs round), period {m['period']:.12g} s per turn, "
                f"psi gains {m['psi_advance']:.9g} rad per turn")
    return "motion of [initial]: steady (phi2 stays constant, psi turns uniformly)"
