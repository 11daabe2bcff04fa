"""`gyrochain fmu`: the model as a Functional Mock-up Unit (FMI 2.0, model exchange and
co-simulation in one binary) for Modelica tools, Simulink and FMPy.

    path, lines = fmu.write(spec, "gimbal.toml", Path("gimbal.fmu"), values={})

The FMU holds ``modelDescription.xml``, ``sources/`` (the generated C, the FMI wrapper
NAME_fmi2.c and the FMI headers, so it rebuilds with a plain C compiler) and
``binaries/linux64/NAME.so`` compiled here.  Its variables, in this order (value references
1, 2, … in the same order):

- the states phi1..phin (rad) and phidot1..phidotn (rad/s), their start values the spec's
  [initial], and their derivatives der(phik) = phidotk and der(phidotk) = φ̈ᵏ;
- an input per control torque (u1.., N·m);
- a fixed parameter per symbolic parameter, its start value the spec's [values] (or --param);
- the outputs energy (T − U) and, where the model emits them, the momentum integral (27) and
  the Jacobi integral;
- for co-simulation, the integrator (the method of NAME_integrate, rtol, atol, its step h).

The dependencies of the ModelStructure are the true ones: the sparsity of the exact Jacobian of
the derivatives (NAME_linearize) at random states.  The wrapper's logic is in the template
fmi2.c.jinja; every fact it lays out is decided here.
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

from . import KERNELS, __version__, pipeline
from .errors import SpecError
from .printers.common import environment

PLATFORM = "linux64"
HEADERS = ("fmi2Functions.h", "fmi2FunctionTypes.h", "fmi2TypesPlatform.h")
CFLAGS = ("-std=c99", "-O2", "-fPIC", "-shared", "-g0")
METHODS = {"rk4": 1, "dop853": 2, "gauss2": 3}
UNITS = {"rad": (("rad", 1),), "rad/s": (("rad", 1), ("s", -1)), "rad/s2": (("rad", 1), ("s", -2)),
         "N.m": (("kg", 1), ("m", 2), ("s", -2)), "J": (("kg", 1), ("m", 2), ("s", -2)), "kg.m2/s": (("kg", 1), ("m", 2), ("s", -1)),
         "s": (("s", 1),)}
ZIP_TIME = (2026, 1, 1, 0, 0, 0)  # every entry's date: the same spec gives the same bytes


@dataclass
class Var:
    name: str
    vr: int
    causality: str
    variability: str
    description: str
    c: str = ""  # the C lvalue in the instance's data (m->d....)
    get_c: str = ""  # the C expression of its value
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


def check(spec, real: str, kinds) -> None:
    """What FMI cannot hold, one line each."""
    if real != "double":
        raise SpecError("--real", "FMI's variables are double precision: the float model cannot be an FMU")
    bad = [k for k in kinds if k not in ("me", "cs")]
    if bad or not kinds:
        raise SpecError("--kind", f"expected me, cs or me,cs, got {','.join(kinds) or 'nothing'}")


def variables(spec, model, values: dict, kinds) -> list[Var]:
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
                description=f"{what} of joint {k} (the spec's {group}{k})", c=f"m->d.x[{i}]", get_c=f"m->d.x[{i}]",
                unit=unit, start=repr(start), start_c=repr(start), settable=True, state_index=i)
    for k in range(1, 2 * n + 1):
        state = out[k - 1]
        add(name=f"der({state.name})", causality="local", variability="continuous", description=f"the rate of {state.name}",
            unit="rad/s" if k <= n else "rad/s2", derivative_of=k, derivative_index=k - 1)
    for j, k in enumerate(spec.controls):
        add(name=f"u{j + 1}", causality="input", variability="continuous", description=f"control torque in joint {k}",
            c=f"m->d.u[{j}]", get_c=f"m->d.u[{j}]", unit="N.m", start="0.0", start_c="0.0", settable=True, input_index=j)
    for p in spec.params:
        v = float(values[str(p)])
        add(name=str(p), causality="parameter", variability="fixed", initial="exact", description=f"the spec's parameter {p}",
            c=f"m->d.p.{p}", get_c=f"m->d.p.{p}", start=repr(v), start_c=repr(v), settable=True)
    t_arg = "m->d.t, " if spec_time_dependent(model) else ""
    for key, unit, what in (("energy", "J", "T - U, the energy (23)"), ("momentum", "kg.m2/s", "the momentum (27) about the axis l1"),
                            ("jacobi", "J", "the Jacobi integral")):
        if key in model.lines:
            add(name=key, causality="output", variability="continuous", initial="calculated", description=what, unit=unit,
                get_c=f"{spec.name}_{key}({t_arg}m->d.x, &m->d.p)")
    if "cs" in kinds:
        add(name="solver.method", type="Integer", causality="parameter", variability="fixed", initial="exact",
            description="co-simulation: 1 RK4 (fixed step h), 2 DOP853 (adaptive, rtol and atol), 3 Gauss (implicit, 4th order, step h)",
            c="m->d.method", start="2", start_c="2", settable=True, min=1, max=3)
        for name, start, what in (("solver.rtol", 1e-10, "co-simulation: DOP853's relative tolerance"),
                                  ("solver.atol", 1e-10, "co-simulation: DOP853's absolute tolerance"),
                                  ("solver.h", 0.0, "co-simulation: the fixed step of RK4 and Gauss (0: the communication step)")):
            add(name=name, causality="parameter", variability="fixed", initial="exact", description=what,
                c=f"m->d.{name.split('.')[1]}", get_c=f"m->d.{name.split('.')[1]}", unit="s" if name.endswith(".h") else "",
                start=repr(start), start_c=repr(start), settable=True)
    return out


def spec_time_dependent(model) -> bool:
    from .assemble import time_dependent

    return time_dependent(model)


def structure(spec, cm, variables_: list[Var], values: dict) -> dict:
    """The ModelStructure's (index, dependencies) lists: the sparsity of the exact A and B at three
    random states (a structural zero is exactly zero at every one of them)."""
    n, nu = spec.n, len(spec.controls)
    index = {v.vr: i + 1 for i, v in enumerate(variables_)}
    states = [index[v.vr] for v in variables_ if v.state_index is not None]
    inputs = [index[v.vr] for v in variables_ if v.input_index is not None]
    rng = np.random.default_rng(0)
    A_seen, B_seen = np.zeros((2 * n, 2 * n), bool), np.zeros((2 * n, max(nu, 1)), bool)
    for _ in range(3):
        x = np.concatenate([rng.uniform(-3, 3, n), rng.normal(size=n)])
        A, B = cm.linearize(x, rng.normal(size=nu) if nu else None, values or None, t=rng.uniform(0, 1))
        A_seen |= A != 0
        if nu:
            B_seen[:, :nu] |= B != 0
    derivs = []
    for v in variables_:
        if v.derivative_index is not None:
            r = v.derivative_index
            deps = [states[c] for c in range(2 * n) if A_seen[r, c]] + [inputs[c] for c in range(nu) if B_seen[r, c]]
            derivs.append((index[v.vr], deps))
    outputs = [(index[v.vr], states) for v in variables_ if v.causality == "output"]
    initial = [(index[v.vr], []) for v in variables_ if v.causality == "output" or v.derivative_index is not None]
    return dict(derivatives=derivs, outputs=outputs, initial_unknowns=initial)


def render(spec, spec_label: str, values: dict, kinds=("me", "cs")) -> tuple[dict, object, list]:
    """{path in the FMU: text}, the compiled model (for the dependencies) and the variables."""
    model = pipeline.derive(spec, latex=False)
    files = pipeline.render(model, spec_label, targets=("c",))
    cm = pipeline.compile(files, spec.name)
    vs = variables(spec, model, values, kinds)
    st = structure(spec, cm, vs, values)
    name = spec.name
    sources = [f"{name}.c", f"{name}_fmi2.c"]
    facts = dict(name=name, NAME=name.upper(), n=spec.n, nu=len(spec.controls), version=__version__,
                 spec_label=Path(spec_label).name, spec_sha=hashlib.sha256(spec.source.encode("utf-8")).hexdigest()[:16],
                 regenerate=f"gyrochain fmu {Path(spec_label).name}", variables=vs, sources=sources,
                 description=_xml(spec.description or name), me="me" in kinds, cs="cs" in kinds, stop_time="5",
                 units=[dict(name=u, base=[(k, v) for k, v in UNITS[u]]) for u in sorted({v.unit for v in vs if v.unit})], **st)
    env = environment()
    c_text = {f"sources/{name}.c": files[f"{name}.c"], f"sources/{name}.h": files[f"{name}.h"]}
    guid = "{" + str(_uuid(c_text, env.get_template("fmi2_model_description.xml.jinja").render(**facts, guid=""))) + "}"
    out = {**c_text, f"sources/{name}_fmi2.c": env.get_template("fmi2.c.jinja").render(**facts, guid=guid),
           "modelDescription.xml": env.get_template("fmi2_model_description.xml.jinja").render(**facts, guid=guid)}
    for h in HEADERS:
        out[f"sources/{h}"] = (KERNELS / "fmi" / h).read_text()
    return out, cm, vs


def _uuid(*parts) -> str:
    import uuid

    digest = hashlib.sha256(repr(parts).encode("utf-8")).hexdigest()
    return str(uuid.UUID(digest[:32]))


def _xml(text: str) -> str:
    return (text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;").replace('"', "&quot;")
            .replace("\n", " "))


def build(files: dict, name: str) -> bytes:
    """The shared library from the FMU's sources, with the system's C compiler."""
    cc = shutil.which(os.environ.get("CC", "cc")) or shutil.which("gcc")
    if cc is None:
        raise SpecError("fmu", "no C compiler (cc) to build the FMU's binary")
    with tempfile.TemporaryDirectory() as tmp:
        d = Path(tmp)
        for path, text in files.items():
            if path.startswith("sources/"):
                (d / Path(path).name).write_text(text)
        lib = d / f"{name}.so"
        r = subprocess.run([cc, *CFLAGS, f"-I{d}", str(d / f"{name}.c"), str(d / f"{name}_fmi2.c"), "-lm", "-o", str(lib)],
                           capture_output=True, text=True)
        if r.returncode != 0:
            raise RuntimeError(f"the FMU's C did not compile: {r.stderr.strip()[:2000]}")
        return lib.read_bytes()


def pack(files: dict, binary: bytes, name: str) -> bytes:
    """The .fmu (a zip), entries in a fixed order with a fixed date."""
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as z:
        entries = {**files, f"binaries/{PLATFORM}/{name}.so": binary}
        for path in sorted(entries):
            info = zipfile.ZipInfo(path, ZIP_TIME)
            info.compress_type = zipfile.ZIP_DEFLATED
            info.external_attr = 0o644 << 16
            data = entries[path]
            z.writestr(info, data if isinstance(data, bytes) else data.encode("utf-8"))
    return buf.getvalue()


def make(spec, spec_label: str, values: dict, kinds=("me", "cs"), fmi: str = "2", real: str = "double") -> tuple[bytes, list[str]]:
    """The .fmu's bytes and lines that say what it holds."""
    check(spec, real, kinds)
    if fmi != "2":
        raise SpecError("--fmi", "FMI 3.0 is not written yet: --fmi 2 writes FMI 2.0, which the tools that read 3.0 read too")
    files, _, vs = render(spec, spec_label, values, kinds)
    binary = build(files, spec.name)
    data = pack(files, binary, spec.name)
    said = {c: [v.name for v in vs if v.causality == c] for c in ("input", "parameter", "output")}
    lines = [f"FMI 2.0 {' and '.join({'me': 'model exchange', 'cs': 'co-simulation'}[k] for k in kinds)} FMU of {spec.name}: "
             f"{2 * spec.n} states, inputs {', '.join(said['input']) or 'none'}, outputs {', '.join(said['output']) or 'none'}, "
             f"parameters {', '.join(said['parameter']) or 'none'}; {len(data) // 1024} KiB ({PLATFORM} binary and the C sources)"]
    return data, lines
