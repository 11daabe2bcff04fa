"""`gyrochain fmu`: the model as a Functional Mock-up Unit (FMI 3.0, or 2.0 with --fmi 2; model
exchange and co-simulation in one binary) for Modelica tools, Simulink and FMPy.

    data, lines = fmu.make(spec, "gimbal.toml", values={}, kinds=("me", "cs"), fmi="3", inputs=(), outputs=("tip",))

The FMU holds ``modelDescription.xml``, ``sources/`` (the generated C, the FMI wrapper
NAME_fmi3.c or NAME_fmi2.c, the FMI headers and, for FMI 3.0, buildDescription.xml, so it
rebuilds with a plain C compiler) and ``binaries/<platform>/NAME.so`` compiled here.  Its
variables, value reference 0 the time and then 1, 2, … in this order:

- the states phi1..phin (rad) and phidot1..phidotn (rad/s), their start values the spec's
  [initial], and their derivatives der(phik) = phidotk and der(phidotk) = φ̈ᵏ;
- an input per control torque (u1.., N·m);
- a fixed parameter per symbolic parameter, its start value the spec's [values] (or --param);
- the outputs energy (T − U) and, where the model emits them, the momentum integral (27) and
  the Jacobi integral;
- for co-simulation, the integrator (the method of NAME_integrate, rtol, atol, its step h).

The dependencies of the ModelStructure are the true ones, found on the compiled model (see
``structure``).  The wrappers' C is in the templates fmi3.c.jinja and fmi2.c.jinja (with what
they share in fmi_common.c.jinja); every fact they lay out is decided here.
"""
from __future__ import annotations

import hashlib
import io
import os
import shutil
import subprocess
import tempfile
import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import sympy as sp

from .. import KERNELS, __version__
from ..models import pipeline
from ..derive import reference
from ..derive.assemble import time_dependent
from ..chainspec.errors import SpecError
from ..printers.c import CPrinter
from ..printers.common import environment



@dataclass(frozen=True)
class Version:
    label: str
    prefix: str  # fmi2, fmi3: the wrapper's name and the functions' prefix
    platform: str  # the binaries' folder
    headers: tuple
    wrapper: str  # templates
    description: str
    build: str = ""


VERSIONS = {
    "2": Version("FMI 2.0", "fmi2", "linux64", ("fmi2Functions.h", "fmi2FunctionTypes.h", "fmi2TypesPlatform.h"),
                 "fmi2.c.jinja", "fmi2_model_description.xml.jinja"),
    "3": Version("FMI 3.0", "fmi3", "x86_64-linux", ("fmi3Functions.h", "fmi3FunctionTypes.h", "fmi3PlatformTypes.h"),
                 "fmi3.c.jinja", "fmi3_model_description.xml.jinja", "fmi3_build_description.xml.jinja"),
}
ABSENT_FMI3_TYPES = ("Float32", "Int8", "UInt8", "Int16", "UInt16", "UInt32", "Int64", "UInt64", "Boolean", "String")
CFLAGS = ("-std=c99", "-O2", "-fPIC", "-g0")
METHODS = {"rk4": 1, "dop853": 2, "gauss2": 3}
UNITS = {"rad": (("rad", 1),), "rad/s": (("rad", 1), ("s", -1)), "rad/s2": (("rad", 1), ("s", -2)),
         "N.m": (("kg", 1), ("m", 2), ("s", -2)), "J": (("kg", 1), ("m", 2), ("s", -2)), "kg.m2/s": (("kg", 1), ("m", 2), ("s", -1)),
         "s": (("s", 1),), "m": (("m", 1),)}
OUTPUTS = {"tip": "the last body's centre of mass Gⁿ, x, y, z in frame 0 (the base, which moves with a platform) from O¹"}
ZIP_TIME = (2026, 1, 1, 0, 0, 0)  # every entry's date: the same spec gives the same bytes


@dataclass
class Var:
    name: str
    vr: int
    causality: str
    variability: str
    description: str
    c: str = ""  # its place in the instance's data_t d (x[0], p.m1, ...)
    get_c: str = ""  # the C expression of its value if it is computed (an output), in terms of d
    type: str = "Real"
    unit: str = ""
    initial: str = ""
    start: str | None = None
    start_c: str = ""
    settable: bool = False
    derivative_of: int | None = None  # the 1-based index of the state it is the derivative of
    derivative_index: int | None = None  # its row in NAME_rhs's output
    state_index: int | None = None
    input_index: int | None = None
    min: int = 0
    max: int = 0


@dataclass(frozen=True)
class Asked:
    """What the command line asks of the FMU."""
    kinds: tuple = ("me", "cs")  # model exchange, co-simulation
    fmi: str = "3"
    real: str = "double"
    inputs: tuple = ()  # parameters made (discrete) inputs
    outputs: tuple = ()  # outputs added from OUTPUTS


def check(spec, asked: Asked) -> None:
    """What FMI cannot hold, one line each."""
    kinds, fmi, real, as_inputs, outputs = asked.kinds, asked.fmi, asked.real, asked.inputs, asked.outputs
    for name in outputs:
        if name not in OUTPUTS:
            raise SpecError("--add-output", f"no output {name!r}; the outputs that can be asked for: {', '.join(OUTPUTS)}")
    names = [str(p) for p in spec.params]
    for name in as_inputs:
        if name not in names:
            raise SpecError("--input", f"{name} is not a parameter of the spec (its parameters: {', '.join(names) or 'none'}; "
                                       "the control torques are inputs already)")
    if fmi not in VERSIONS:
        raise SpecError("--fmi", f"expected 3 (FMI 3.0) or 2 (FMI 2.0), got {fmi}")
    if real != "double":
        raise SpecError("--real", "FMI's variables are double precision: the float model cannot be an FMU")
    bad = [k for k in kinds if k not in ("me", "cs")]
    if bad or not kinds or len(set(kinds)) != len(kinds):
        raise SpecError("--kind", f"expected me, cs or me,cs, got {','.join(kinds) or 'nothing'}")
    for option, given in (("--input", as_inputs), ("--add-output", outputs)):
        twice = sorted({name for name in given if given.count(name) > 1})
        if twice:
            raise SpecError(f"{option} {twice[0]}", "given twice; give it once")


def variables(spec, model, values: dict, asked: Asked) -> list[Var]:
    n, out = spec.n, []

    def add(**kw) -> Var:
        out.append(Var(vr=len(out) + 1, **kw))
        return out[-1]

    initial = spec.initial or {}
    for group, unit, what in (("phi", "rad", "joint angle"), ("phidot", "rad/s", "joint rate")):
        for k in range(1, n + 1):
            i = (k - 1) if group == "phi" else (n + k - 1)
            start = float((initial.get(group) or [0.0] * n)[k - 1])
            add(name=f"{group}{k}", causality="local", variability="continuous", initial="exact",
                description=f"{what} of joint {k} (the spec's {group}{k})", c=f"x[{i}]",
                unit=unit, start=repr(start), start_c=repr(start), settable=True, state_index=i)
    for k in range(1, 2 * n + 1):
        state = out[k - 1]
        add(name=f"der({state.name})", causality="local", variability="continuous", description=f"the rate of {state.name}",
            unit="rad/s" if k <= n else "rad/s2", derivative_of=k, derivative_index=k - 1)
    for j, k in enumerate(spec.controls):
        add(name=f"u{j + 1}", causality="input", variability="continuous", description=f"control torque in joint {k}",
            c=f"u[{j}]", unit="N.m", start="0.0", start_c="0.0", settable=True, input_index=j)
    for p in spec.params:
        v = float(values[str(p)])
        if str(p) in asked.inputs:  # constant between events: the model has no terms in its rate
            add(name=str(p), causality="input", variability="discrete", description=f"the spec's parameter {p} as an input, "
                "piecewise constant: it changes at events (model exchange) or communication points (co-simulation)",
                c=f"p.{p}", start=repr(v), start_c=repr(v), settable=True)
        else:
            add(name=str(p), causality="parameter", variability="fixed", initial="exact", description=f"the spec's parameter {p}",
                c=f"p.{p}", start=repr(v), start_c=repr(v), settable=True)
    t_arg = "d->t, " if time_dependent(model) else ""
    for key, unit, what in (("energy", "J", "T - U, the energy (23)"), ("momentum", "kg.m2/s", "the momentum (27) about the axis l1"),
                            ("jacobi", "J", "the Jacobi integral")):
        if key in model.lines:
            add(name=key, causality="output", variability="continuous", initial="calculated", description=what, unit=unit,
                get_c=f"{spec.name}_{key}({t_arg}d->x, &d->p)")
    if "tip" in asked.outputs:
        for i, axis in enumerate("xyz"):
            add(name=f"tip.{axis}", causality="output", variability="continuous", initial="calculated", unit="m",
                description=f"the tip Gn (the last body's centre of mass), its {axis} in frame 0 (the base, moving with a platform) "
                "from O1, the first joint",
                get_c=f"tip_of(d, {i})")
    if "cs" in asked.kinds:
        add(name="solver.method", type="Integer", causality="parameter", variability="fixed", initial="exact",
            description="co-simulation: 1 RK4 (fixed step h), 2 DOP853 (adaptive, rtol and atol), 3 Gauss (implicit, 4th order, step h)",
            c="method", start="2", start_c="2", settable=True, min=1, max=3)
        for name, start, what in (("solver.rtol", 1e-10, "co-simulation: DOP853's relative tolerance"),
                                  ("solver.atol", 1e-10, "co-simulation: DOP853's absolute tolerance"),
                                  ("solver.h", 0.0, "co-simulation: the fixed step of RK4 and Gauss (0: the communication step)")):
            add(name=name, causality="parameter", variability="fixed", initial="exact", description=what,
                c=name.split('.')[1], unit="s" if name.endswith(".h") else "",
                start=repr(start), start_c=repr(start), settable=True)
    for v in out:
        v.get_c = v.get_c or (f"d->{v.c}" if v.c else "")
    return out


def structure(spec, cm, variables_: list[Var], values: dict) -> dict:
    """The ModelStructure, in value references (0 is the time): what each state's derivative and each
    output depends on, from the exact A and B and the model's own functions at three random states
    and two times.  A structural zero is exactly zero (or exactly unchanged) at every one of them."""
    n, nu = spec.n, len(spec.controls)
    states = [v.vr for v in variables_ if v.state_index is not None]
    inputs = [v.vr for v in variables_ if v.input_index is not None]
    outputs = [v for v in variables_ if v.causality == "output"]
    rng = np.random.default_rng(0)
    p = values or None
    of = _output_functions(spec, cm, values, [v.name for v in outputs])
    A_seen, B_seen = np.zeros((2 * n, 2 * n), bool), np.zeros((2 * n, max(nu, 1)), bool)
    rows_on_t, outputs_on = np.zeros(2 * n, bool), {v.name: np.zeros(2 * n + 1, bool) for v in outputs}
    for _ in range(3):
        x = np.concatenate([rng.uniform(-3, 3, n), rng.normal(size=n)])
        u = rng.normal(size=nu) if nu else None
        t = rng.uniform(0, 1)
        A, B = cm.linearize(x, u, p, t=t)
        A_seen |= A != 0
        if nu:
            B_seen[:, :nu] |= B != 0
        rows_on_t |= cm.rhs(t, x, u, p) != cm.rhs(t + 0.37, x, u, p)
        for v in outputs:
            value = of[v.name](x, t)
            for c in range(2 * n):
                dx = np.zeros(2 * n)
                dx[c] = 0.1 + 0.2 * rng.uniform()
                outputs_on[v.name][c] |= of[v.name](x + dx, t) != value
            outputs_on[v.name][2 * n] |= of[v.name](x, t + 0.37) != value
    derivs = []
    for v in variables_:
        if v.derivative_index is not None:
            r = v.derivative_index
            deps = ([0] if rows_on_t[r] else []) + [states[c] for c in range(2 * n) if A_seen[r, c]] \
                + [inputs[c] for c in range(nu) if B_seen[r, c]]
            derivs.append((v.vr, deps))
    outs = [(v.vr, ([0] if outputs_on[v.name][2 * n] else []) + [states[c] for c in range(2 * n) if outputs_on[v.name][c]])
            for v in outputs]
    initial = [v.vr for v in variables_ if v.causality == "output" or v.derivative_index is not None]
    return dict(derivatives=derivs, outputs=outs, initial_unknowns=initial)


def _output_functions(spec, cm, values: dict, names: list) -> dict:
    """{output: f(x, t)}: the integrals from the compiled model, the tip from the independent
    numeric model (reference.py)."""
    p = values or None
    fns = {"energy": lambda x, t: cm.energy(x, p, t=t), "momentum": lambda x, t: cm.momentum(x, p, t=t),
           "jacobi": lambda x, t: cm.jacobi(x, p)}
    if any(name.startswith("tip.") for name in names):
        ch = reference.numeric(spec, values)
        fns.update({f"tip.{a}": (lambda x, t, i=i: tip_position(ch, x[:spec.n])[i]) for i, a in enumerate("xyz")})
    return {name: fns[name] for name in names}


def tip_position(ch, phi) -> np.ndarray:
    """Gⁿ in frame 0: the sum over k < n of αᵏ'⁰ᵀ sᵏ, plus αⁿ'⁰ᵀ cⁿ (eq. 14: the rows of αᵏ'⁰ are
    êᵏᵢ in frame 0, and O¹ is frame 0's origin)."""
    R = reference.frames(ch, phi)
    return sum(R[k].T @ ch.s[k] for k in range(ch.n - 1)) + R[-1].T @ ch.c[-1]


def tip_joints(spec) -> list[dict]:
    """The C of the tip's recursion, joint by joint: cos θᵏ, sin θᵏ, the offset δᵏ and the vector
    added after the turn (sᵏ, and cⁿ for the last body), parameters read from the instance."""
    printer = CPrinter({p: f"d->p.{p}" for p in spec.params})
    out = []
    for k, b in enumerate(spec.bodies):
        ct, st = (printer.doprint(f(b.theta)) for f in (sp.cos, sp.sin))
        vector = b.s if k < spec.n - 1 else b.c
        angle = f"d->x[{k}]" + ("" if b.offset == 0 else f" + {printer.doprint(b.offset)}")
        out.append(dict(ct=ct, st=st, angle=angle, v=[printer.doprint(e) for e in vector]))
    return out


def _indices(st: dict, variables_: list[Var]) -> dict:
    """FMI 2.0 names variables by their place in the list, 1-based, and the time (value reference
    0) comes first: the index is the value reference + 1."""
    return dict(index={v.vr: v.vr + 1 for v in variables_},
                derivatives=[(vr + 1, [d + 1 for d in deps]) for vr, deps in st["derivatives"]],
                outputs=[(vr + 1, [d + 1 for d in deps]) for vr, deps in st["outputs"]],
                initial_unknowns=[vr + 1 for vr in st["initial_unknowns"]])


def render(spec, spec_label: str, values: dict, asked: Asked) -> tuple[dict, list]:
    """{path in the FMU: text} and the variables."""
    fmi, version = asked.fmi, VERSIONS[asked.fmi]
    model = pipeline.derive(spec, latex=False)
    files = pipeline.render(model, spec_label, targets=("c",))
    cm = pipeline.checked(spec, pipeline.compile(files, spec.name))
    vs = variables(spec, model, values, asked)
    st = structure(spec, cm, vs, values)
    name = spec.name
    sources = [f"{name}.c", f"{name}_{version.prefix}.c"]
    facts = dict(name=name, NAME=name.upper(), n=spec.n, nu=len(spec.controls), version=__version__,
                 spec_label=Path(spec_label).name, spec_sha=hashlib.sha256(spec.source.encode("utf-8")).hexdigest()[:16],
                 regenerate=_command(spec, spec_label, values, asked),
                 tip=tip_joints(spec) if "tip" in asked.outputs else [],
                 variables=vs, sources=sources, absent_types=ABSENT_FMI3_TYPES,
                 description=_xml(spec.description or name), me="me" in asked.kinds, cs="cs" in asked.kinds, stop_time="5",
                 units=[dict(name=u, base=[(k, v) for k, v in UNITS[u]]) for u in sorted({v.unit for v in vs if v.unit} | {"s"})],
                 dependency_lists=[dict(vr=vr, on=deps, c_on=", ".join(map(str, deps)) or "0")
                                   for vr, deps in st["outputs"] + st["derivatives"]],
                 **(st if fmi == "3" else _indices(st, vs)))
    env = environment(pipeline.compiled_templates())
    c_text = {f"sources/{name}.c": files[f"{name}.c"], f"sources/{name}.h": files[f"{name}.h"]}
    description = env.get_template(version.description)
    guid = "{" + str(_uuid(fmi, c_text, description.render(**facts, guid=""))) + "}"
    out = {**c_text, f"sources/{name}_{version.prefix}.c": env.get_template(version.wrapper).render(**facts, guid=guid),
           "modelDescription.xml": description.render(**facts, guid=guid)}
    if version.build:
        out["sources/buildDescription.xml"] = env.get_template(version.build).render(**facts)
    for h in version.headers:
        out[f"sources/{h}"] = (KERNELS / "fmi" / h).read_text()
    return out, vs


def _command(spec, spec_label: str, values: dict, asked: Asked) -> str:
    """The command line that makes this FMU again (the start values that differ from the spec's)."""
    import shlex

    given = {k: v for k, v in values.items() if (spec.values or {}).get(k) != v}
    return shlex.join(["gyrochain", "fmu", Path(spec_label).name, *(["--fmi", asked.fmi] if asked.fmi != "3" else []),
                       *(["--kind", ",".join(asked.kinds)] if tuple(asked.kinds) != ("me", "cs") else []),
                       *(w for a in asked.inputs for w in ("--input", a)), *(w for a in asked.outputs for w in ("--add-output", a)),
                       *(w for k in sorted(given) for w in ("--param", f"{k}={given[k]!r}"))])


def _uuid(*parts) -> str:
    import uuid

    digest = hashlib.sha256(repr(parts).encode("utf-8")).hexdigest()
    return str(uuid.UUID(digest[:32]))


def _xml(text: str) -> str:
    return (text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;").replace('"', "&quot;")
            .replace("\n", " "))


def build(files: dict, name: str, fmi: str = "3") -> bytes:
    """The shared library from the FMU's sources, with the system's C compiler.  The model's object
    (NAME.c, the most of the time) is kept in the user's private build cache under the hash of its
    sources, the flags and the compiler, so an FMU of the other version or kind only compiles its
    wrapper."""
    cc = shutil.which(os.environ.get("CC", "cc")) or shutil.which("gcc")
    if cc is None:
        raise SpecError("fmu", "no C compiler (cc) to build the FMU's binary")
    with tempfile.TemporaryDirectory() as tmp:
        d = Path(tmp)
        for path, text in files.items():
            if path.startswith("sources/"):
                (d / Path(path).name).write_text(text)
        model = _model_object(cc, d, name, files)
        lib = d / f"{name}.so"
        _cc([cc, *CFLAGS, "-shared", f"-I{d}", str(model), str(d / f"{name}_{VERSIONS[fmi].prefix}.c"), "-lm", "-o", str(lib)])
        return lib.read_bytes()


def _cc(command: list) -> None:
    r = subprocess.run(command, capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"the FMU's C did not compile: {r.stderr.strip()[:2000]}")


def _model_object(cc: str, d: Path, name: str, files: dict) -> Path:
    """NAME.o, from the cache if these sources were compiled before with this compiler and flags."""
    key = hashlib.sha256("\0".join([os.path.realpath(cc), *CFLAGS, files[f"sources/{name}.c"], files[f"sources/{name}.h"]])
                         .encode("utf-8")).hexdigest()[:24]
    cached = pipeline.cache_root() / "fmu-objects" / f"{name}-{key}.o"
    if cached.is_file():
        return cached
    obj = d / f"{name}.o"
    _cc([cc, *CFLAGS, "-c", f"-I{d}", str(d / f"{name}.c"), "-o", str(obj)])
    cached.parent.mkdir(mode=0o700, exist_ok=True)
    partial = cached.with_name(f"{cached.name}.{os.getpid()}.part")
    try:
        shutil.copyfile(obj, partial)
        os.replace(partial, cached)  # whole or not at all: another process may be writing the same one
    finally:
        partial.unlink(missing_ok=True)
    return cached


def pack(files: dict, binary: bytes, name: str, fmi: str = "3") -> bytes:
    """The .fmu (a zip), entries in a fixed order with a fixed date."""
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as z:
        entries = {**files, f"binaries/{VERSIONS[fmi].platform}/{name}.so": binary}
        for path in sorted(entries):
            info = zipfile.ZipInfo(path, ZIP_TIME)
            info.compress_type = zipfile.ZIP_DEFLATED
            info.external_attr = 0o644 << 16
            data = entries[path]
            z.writestr(info, data if isinstance(data, bytes) else data.encode("utf-8"))
    return buf.getvalue()


def make(spec, spec_label: str, values: dict, asked: Asked | None = None, **options) -> tuple[bytes, list[str]]:
    """The .fmu's bytes and lines that say what it holds; ``options`` are Asked's fields."""
    asked = asked or Asked(**{k: tuple(v) if isinstance(v, (list, tuple)) else v for k, v in options.items()})
    check(spec, asked)
    files, vs = render(spec, spec_label, values, asked)
    binary = build(files, spec.name, asked.fmi)
    data = pack(files, binary, spec.name, asked.fmi)
    said = {c: [v.name for v in vs if v.causality == c] for c in ("input", "parameter", "output")}
    version = VERSIONS[asked.fmi]
    lines = [f"{version.label} {' and '.join({'me': 'model exchange', 'cs': 'co-simulation'}[k] for k in asked.kinds)} FMU of {spec.name}: "
             f"{2 * spec.n} states, inputs {', '.join(said['input']) or 'none'}, outputs {', '.join(said['output']) or 'none'}, "
             f"parameters {', '.join(said['parameter']) or 'none'}; {len(data) // 1024} KiB ({version.platform} binary and the C sources)"]
    return data, lines
