"""Printers by target: a derived model (assemble.Model) → {file name: text}.  Writes nothing.

One target a module, as SymForce keeps its backends: ``c`` (header, source, cffi cdef),
``python`` (the pure-Python mirror), ``latex`` (the document a reviewer reads).  Python makes
every decision here; the jinja2 templates in ``templates/`` only lay out strings that are already
printed and loop over them.
"""
from __future__ import annotations

import hashlib
import json
import shlex
from pathlib import Path

import sympy as sp

from .. import __version__
from ..chainspec.tables import spec_limits
from ..derive import integrals, loopform, world
from ..derive.assemble import (GAUSS2_NEWTON_MAX_N, VARIATIONAL_MAX_N, Model, newton_sweeps, newton_sweeps_canonical, op_counts,
                        step_hessian_applies, step_hessian_stack_bytes, step_jacobian_stack_bytes, time_dependent,
                        variational_stack_bytes)
from .c import CTarget
from .casadi import CasadiTarget
from .cuda import CudaTarget
from .common import c_comment, environment, py_docstring
from .latex import LatexTarget
from .python import PythonTarget
from .real import single_precision

# in the order they are printed; "cuda" (generate --gpu) and "casadi" (generate --casadi) only when asked
TARGETS = {"c": CTarget, "cuda": CudaTarget, "casadi": CasadiTarget, "python": PythonTarget, "latex": LatexTarget}
REALS = ("double", "float")  # generate --real: the floating type of the C
ALL = ("c", "python", "latex")  # what generate writes by default


def regenerate_command(spec_label: str, options=(), real: str = "double") -> str:
    """The command that writes these files again, as every file's first lines state it: the spec's
    file name and the generate options that made them (``options``: e.g. ("--qdd-form",
    "composite")), shell-quoted."""
    words = [spec_label, *options, *(("--real", real) if real != "double" else ())]
    return "gyrochain generate " + " ".join(shlex.quote(w) for w in words)


def code_context(model: Model, spec_label: str, counts: dict, regenerate: str | None = None, real: str = "double") -> dict:
    """The facts the C and Python templates lay out (names, sizes, which functions exist)."""
    spec, ints = model.spec, model.integrals
    name, n = spec.name, spec.n
    regenerate = regenerate or regenerate_command(spec_label)
    return dict(
        name=name,
        NAME=name.upper(),
        n=n,
        nn=n * n,
        version=__version__,
        spec_sha=hashlib.sha256(spec.source.encode("utf-8")).hexdigest()[:16],
        regenerate=c_comment(regenerate),
        regenerate_py=py_docstring(regenerate),
        spec_label=c_comment(spec_label),
        description=c_comment(spec.description),
        spec_label_py=py_docstring(spec_label),
        description_py=py_docstring(spec.description),
        params=[str(p) for p in spec.params],
        controls=list(enumerate(spec.controls)),
        disturbances=list(spec.disturbances),  # the joints among them whose input is a disturbance torque
        has_params=bool(spec.params),
        has_controls=bool(spec.controls),
        has_momentum="momentum" in model.lines,
        general=spec.general,
        time_dependent=time_dependent(model),
        has_jacobi="jacobi" in model.lines,
        canonical="momenta" in model.lines,
        articulated=model.qdd_form == "articulated",
        loops=model.dyn.loops is not None,  # a long chain: M from S and z1 by the template's loops (loopform.py)
        ldlt_by_columns=n >= loopform.LDLT_COLUMNS_MIN_N,
        has_energy_integral=int(ints.has_energy_integral),
        energy_verdict=c_comment(integrals.energy_verdict(spec, ints)),
        momentum_verdict=c_comment(integrals.momentum_verdict(ints)),
        has_momentum_integral=int(ints.has_momentum_integral),
        momentum_condition=ints.momentum_condition and c_comment(ints.momentum_condition).replace('"', "'"),
        quad=model.quad is not None,
        limits=spec_limits(spec),
        der_store=[a.name for a in model.der_store],
        der_dirs=[(lab, lab[0], int(lab[1:]) - 1, j) for j, lab in enumerate(model.der.labels)] if model.der else [],
        der_generic="d_jvp" in model.lines,
        der_world=model.der_form == "world",
        world_inverse=model.world_columns == "inverse",
        factor_by_columns=n >= world.FACTOR_COLUMNS_MIN_N,
        world_vectors=world.VECTORS,
        ic_parts=world.IC_PARTS,
        world_ext=[(k, c, i) for i, (k, c, _) in enumerate(model.der.ext)] if model.der_form == "world" else [],
        newton=n <= GAUSS2_NEWTON_MAX_N,
        variational=n <= VARIATIONAL_MAX_N,
        variational_stack_kb=(variational_stack_bytes(n) + 1023) // 1024,
        step_jacobian_stack_kb=(step_jacobian_stack_bytes(n, len(spec.controls) + bool(model.tder)) + 1023) // 1024,
        newton_sweeps=newton_sweeps(n, counts),
        newton_sweeps_canonical=newton_sweeps_canonical(n, counts),
        counts=counts,
        counts_text=", ".join(f"{k} {v}" for k, v in sorted(counts.items())),
        # the time argument of the functions that read t (NAME_TIME_DEPENDENT), as each place spells it
        t_param="double t, " if time_dependent(model) else "",
        t_arg="t, " if time_dependent(model) else "",
        label=spec_label,
        real=real,
        **regressor_context(model),
        **hessian_context(model),
        # NAME_param_derivatives (a model with symbolic parameters), and the step's with NAME_step_jacobian
        param_derivatives=model.pder is not None,
        step_param_derivatives=model.pder is not None and n <= VARIATIONAL_MAX_N,
        time_derivative=bool(model.tder),  # NAME_time_derivative: ∂φ̈/∂t of a model that reads t
        seeded_derivatives=model.pder is not None or bool(model.tder),  # either of them (model_params.c.jinja)
        gyrochain_version=__version__,
        sympy_version=sp.__version__,
    )


def _linear(row, array: str) -> str:
    """Σ c·array[j] as C and Python alike: unit coefficients without a factor."""
    from .common import literal, signed_sum

    return signed_sum(row, lambda j, c: f"{array}[{j}]" if float(c) == 1.0 else f"{literal(float(c))} * {array}[{j}]")


def regressor_context(model: Model) -> dict:
    """The regressor's facts (generate --regressor): π's and β's names, β = K π's rows."""
    if model.reg is None:
        return dict(regressor=False)
    names = [p.name for p in model.reg.params]
    base = model.base
    return dict(
        regressor=True,
        npi=len(names),
        nbase=base.count,
        pi_names=names,
        base_names=[names[j] for j in base.columns],
        base_rows=[_linear(row, "pi") for row in base.K],
        base_numerical=any(base.numerical),
    )


def hessian_context(model: Model) -> dict:
    """The second derivatives' facts (generate --hessian, --casadi): ∇²(μ·φ̈)'s stored pairs i ≤ j
    (i, j, their slot), the size 2n + nu of z = (x, u) (and t, the last, in a model that reads t),
    and whether NAME_step_hessian is emitted (with NAME_step_jacobian)."""
    n = model.spec.n
    if model.hess is None:
        return dict(hessian=False, step_hessian=False)
    pairs = sorted(model.hess.upper)
    return dict(hessian=True, hessian_pairs=[(i, j, k) for k, (i, j) in enumerate(pairs)], npairs=len(pairs),
                zdim=2 * n + len(model.spec.controls) + bool(model.tder), step_hessian=step_hessian_applies(model),
                step_hessian_stack_kb=(step_hessian_stack_bytes(n, len(model.spec.controls) + bool(model.tder)) + 1023) // 1024)


def _limits_json(spec) -> list:
    """Per joint its limits as the spec gives them (MANIFEST.json's "limits"; not enforced by the model)."""
    return [{"joint": k, **dict(b.limits)} for k, b in enumerate(spec.bodies, start=1)]


def render(model: Model, spec_label: str, targets=ALL, on_c=None, real: str = "double", options=(),
           compiled: Path | None = None, paper: str = "a4") -> dict[str, str]:
    """The emitted files of the asked targets, by file name.  With every target, also
    MANIFEST.json (the spec's hash, the versions, the op counts and every file's hash).
    ``options``: the generate options besides ``real`` that made the files (their headers say how
    to regenerate them).
    ``on_c``, if given, is called with the C target's files as soon as they are printed (the
    build can start while the Python and the LaTeX are printed).  ``real``: "float" retypes the C to
    single precision (printers/real.py).  ``compiled``: where compiled templates are kept between
    processes (``common.environment``).  ``paper``: the LaTeX's page, "a4" or "letter"."""
    unknown = [t for t in targets if t not in TARGETS]
    if unknown:
        raise ValueError(f"unknown target {unknown[0]!r} (one of {', '.join(TARGETS)})")
    counts = op_counts(model)
    context = code_context(model, spec_label, counts, regenerate_command(spec_label, options, real), real)
    context["paper"] = paper
    env = environment(compiled)
    files: dict[str, str] = {}
    for key in TARGETS:  # in one order, whatever the order asked
        if key in targets:
            files.update(TARGETS[key]().files(model, context, env))
            if key == "c" and real == "float":
                files = single_precision(files, model.spec.name)
            if key == "c" and on_c is not None:
                on_c(dict(files))
    if set(ALL) <= set(targets):
        spec = model.spec
        manifest = dict(
            spec=spec_label,
            spec_sha256=hashlib.sha256(spec.source.encode("utf-8")).hexdigest(),
            gyrochain=__version__,
            **({"real": real} if real != "double" else {}),
            sympy=sp.__version__,
            op_counts=counts,
            **({"limits": _limits_json(spec)} if spec_limits(spec) else {}),
            files={k: hashlib.sha256(v.encode("utf-8")).hexdigest() for k, v in sorted(files.items())},
        )
        files["MANIFEST.json"] = json.dumps(manifest, indent=2, sort_keys=True) + "\n"
    return files
