"""`gyrochain fmu` (FMI 2.0, model exchange and co-simulation) read by FMPy, a client no one here
wrote: its validator finds nothing; its CVode on the model-exchange FMU and its driver of the
co-simulation FMU follow the trajectory of the generated C; the directional derivatives are the
exact Jacobian; a saved, serialised and restored state steps to bit-identical results; what FMI
cannot hold is one line."""
from __future__ import annotations

import shutil
import zipfile

import numpy as np
import pytest

from gyrochain import fmu, pipeline
from gyrochain.cli import main
from gyrochain.spec import load_spec, parse_spec
from conftest import ROOT, example_params

fmpy = pytest.importorskip("fmpy", reason="FMPy (pip install fmpy; make test installs it) reads the FMUs")
from fmpy import read_model_description  # noqa: E402
from fmpy.fmi2 import FMU2Model, FMU2Slave  # noqa: E402
from fmpy.validation import validate_fmu  # noqa: E402

pytestmark = pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler to build the FMU's binary")
CASES = ["gimbal", "furuta", "furuta_sym", "kapitza"]
T1 = 5.0


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    out = {}
    d = tmp_path_factory.mktemp("fmu")
    for name in CASES:
        spec = load_spec(ROOT / "specs" / f"{name}.toml")
        values = {**(spec.values or {}), **(example_params(name) or {})}
        data, _ = fmu.make(spec, f"{name}.toml", values)
        path = d / f"{name}.fmu"
        path.write_bytes(data)
        unzipped = d / name
        with zipfile.ZipFile(path) as z:
            z.extractall(unzipped)
        cm, _ = pipeline.compiled(spec)
        out[name] = (spec, values, path, unzipped, cm)
    return out


def _x0(spec):
    ini = spec.initial or {}
    return np.array(list(ini.get("phi") or [0.0] * spec.n) + list(ini.get("phidot") or [0.0] * spec.n), float)


def _u(spec):
    return [0.3 * (-1) ** j for j in range(len(spec.controls))]


def _reference(spec, values, cm):
    """The generated C's DOP853 at tight tolerances: what `gyrochain simulate` integrates."""
    X = cm.integrate([0.0, T1], _x0(spec), method="dop853", rtol=1e-13, atol=1e-13, u=_u(spec) or None, params=values or None)
    return X[-1]


@pytest.mark.parametrize("name", CASES)
def test_fmpy_validates_the_fmu(name, built):
    assert validate_fmu(str(built[name][2])) == []


@pytest.mark.parametrize("name", CASES)
def test_co_simulation_and_model_exchange_follow_the_c(name, built):
    spec, values, path, _, cm = built[name]
    ref = _reference(spec, values, cm)
    names = [f"phi{k}" for k in range(1, spec.n + 1)] + [f"phidot{k}" for k in range(1, spec.n + 1)]
    inputs = None
    if spec.controls:
        dtype = [("time", float)] + [(f"u{j + 1}", float) for j in range(len(spec.controls))]
        inputs = np.array([(0.0, *_u(spec)), (T1, *_u(spec))], dtype=dtype)
    cs = fmpy.simulate_fmu(str(path), fmi_type="CoSimulation", stop_time=T1, output_interval=0.5, input=inputs,
                           start_values={"solver.rtol": 1e-12, "solver.atol": 1e-12}, output=names)
    me = fmpy.simulate_fmu(str(path), fmi_type="ModelExchange", stop_time=T1, output_interval=0.005, relative_tolerance=1e-10,
                           input=inputs, output=names)
    got_cs = np.array([cs[-1][k] for k in names])
    got_me = np.array([me[-1][k] for k in names])
    scale = max(1.0, np.max(np.abs(ref)))
    print(f"{name}: CS {np.max(np.abs(got_cs - ref)) / scale:.1e}, ME (CVode) {np.max(np.abs(got_me - ref)) / scale:.1e}")
    assert np.max(np.abs(got_cs - ref)) <= 1e-9 * scale
    assert np.max(np.abs(got_me - ref)) <= 1e-6 * scale


def _instance(cls, unzipped, md, kind):
    inst = cls(guid=md.guid, unzipDirectory=str(unzipped), modelIdentifier=getattr(md, kind).modelIdentifier, instanceName="t")
    inst.instantiate()
    inst.setupExperiment(startTime=0.0)
    inst.enterInitializationMode()
    inst.exitInitializationMode()
    return inst


@pytest.mark.parametrize("name", CASES)
def test_directional_derivatives_are_the_exact_jacobian(name, built):
    spec, values, _, unzipped, cm = built[name]
    md = read_model_description(str(unzipped / "modelDescription.xml"))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    n, nu = spec.n, len(spec.controls)
    states = [vr[f"phi{k}"] for k in range(1, n + 1)] + [vr[f"phidot{k}"] for k in range(1, n + 1)]
    ders = [vr[f"der(phi{k})"] for k in range(1, n + 1)] + [vr[f"der(phidot{k})"] for k in range(1, n + 1)]
    inputs = [vr[f"u{j}"] for j in range(1, nu + 1)]
    model = _instance(FMU2Model, unzipped, md, "modelExchange")
    rng = np.random.default_rng(3)
    x, u, t = np.concatenate([rng.uniform(-2, 2, n), rng.normal(size=n)]), rng.normal(size=nu), 0.37
    model.setTime(t)
    model.setReal(states + inputs, list(x) + list(u))
    A, B = cm.linearize(x, u if nu else None, values or None, t=t)
    for j, known in enumerate(states + inputs):
        column = np.array(model.getDirectionalDerivative(ders, [known], [1.0]))
        want = A[:, j] if j < 2 * n else B[:, j - 2 * n]
        assert np.max(np.abs(column - want)) <= 1e-12 * max(1.0, np.max(np.abs(A))), (known, column, want)
    model.terminate()
    model.freeInstance()


@pytest.mark.parametrize("name", ["gimbal", "kapitza"])
def test_a_restored_state_steps_to_the_same_bits(name, built):
    spec, values, _, unzipped, _ = built[name]
    md = read_model_description(str(unzipped / "modelDescription.xml"))
    vr = [v.valueReference for v in md.modelVariables if v.name.startswith("phi")]
    slave = _instance(FMU2Slave, unzipped, md, "coSimulation")
    slave.doStep(0.0, 0.7)
    state = slave.getFMUState()
    saved = slave.serializeFMUState(state)
    slave.freeFMUState(state)
    slave.doStep(0.7, 0.6)
    first = slave.getReal(vr)
    slave.doStep(1.3, 2.0)  # elsewhere
    state = slave.deserializeFMUState(saved)
    slave.setFMUState(state)
    slave.doStep(0.7, 0.6)
    assert slave.getReal(vr) == first  # bit for bit
    slave.freeFMUState(state)
    slave.terminate()
    slave.freeInstance()


def test_the_same_spec_gives_the_same_fmu(built, tmp_path):
    spec, values, path, _, _ = built["furuta"]
    again, _ = fmu.make(spec, "furuta.toml", values)
    assert again == path.read_bytes()


@pytest.mark.parametrize("args, words", [
    (["--real", "float"], "--real: FMI's variables are double precision"),
    (["--kind", "hybrid"], "--kind: expected me, cs or me,cs"),
    (["-o", "-"], "-o -: a binary file is not printed"),
])
def test_what_fmi_cannot_hold_is_one_line(args, words, capsys, tmp_path):
    code = main(["fmu", str(ROOT / "specs" / "gimbal.toml"), *args] + ([] if "-o" in args else ["-o", str(tmp_path / "g.fmu")]))
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and words in err, err
    assert not list(tmp_path.iterdir())


def test_a_random_eight_link_chain_validates():
    from gyrochain.randspec import random_spec_text

    spec = parse_spec(random_spec_text(np.random.default_rng(46), 8, name="chain8", controls=(1, 8)))
    data, lines = fmu.make(spec, "chain8.toml", {})
    assert "16 states, inputs u1, u2" in lines[0]
    import tempfile
    from pathlib import Path

    with tempfile.TemporaryDirectory() as d:
        (Path(d) / "c.fmu").write_bytes(data)
        assert validate_fmu(str(Path(d) / "c.fmu")) == []
