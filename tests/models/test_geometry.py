"""Chains of the geometry users write, through every emitted target.

A derivation that takes a shortcut on an exact value (a zero sine, a unit cosine, a zero offset or
mass, a diagonal tensor, a rotor along an axis) is right on the comfortable middle and wrong on
exactly what users write: θ = π, which ``import`` writes for every flipped axis, once gave O(1)
errors in the articulated φ̈.  The chains here are drawn from the exact values
(gyrochain/chainspec/randspec.py: θ from 0, ±π/2, ±π, ±π/4, 3π/4 and numbers of either sign; exact
zeros in c and s; full, diagonal, axial, point-mass and rod tensors and massless frames; rotors
along the axis or anywhere; offsets 0, a number or π; springs, dampers, controls; gravity or none;
a fixed or moving platform with loads), and every target is held to the independent model
(gyrochain/derive/reference.py) or to the C that is:

- the C in double and in float and the Python mirror: M, f, φ̈, its derivatives, the energy, the
  momentum, an RK4 step, the quadratures (gyrochain/models/selfcheck.py, at more states than
  ``generate``'s own check and at others); the C strict C99 (gcc -std=c99 -Wpedantic -Werror);
- the integrators (DOP853, RK4, the symmetric and the symplectic GAUSS2) against the independent
  model under scipy, and the variational equations against differences of the C's trajectories;
- the LaTeX read back (tests/models/test_latex_roundtrip.py) and compared with the C;
- the GPU kernels' host form, thread by thread the C's batch, bit for bit;
- the CasADi functions f, F, M, E and the Jacobians of f and F;
- the FMU (FMI 3.0 and 2.0 through FMPy): its derivatives and its tip output.

``make test`` runs FIXED, a set of chains that between them take every shortcut (SHORTCUTS says
which case covers which), and the strategy itself on a few fixed-seed draws; ``make fuzz`` draws
fresh chains for FUZZ_SECONDS, every target on each.
"""
from __future__ import annotations

import os
import shutil
import subprocess
import tempfile
import time
import zipfile
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from gyrochain import pipeline, reference
from gyrochain.chainspec import randspec
from gyrochain.chainspec.randspec import BodyPlan, ChainPlan
from gyrochain.derive.assemble import time_dependent
from gyrochain.models import build, selfcheck
from gyrochain.spec import SpecError, parse_spec

hypothesis = pytest.importorskip("hypothesis", reason="the test extra (hypothesis) is not installed")
from hypothesis import HealthCheck, Phase, assume, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

LONG = float(os.environ.get("FUZZ_SECONDS", "0"))  # > 0: make fuzz
STATES = 6  # states per target (generate's own check takes 3)
SEED = 79  # not the self-check's: these states are others
TARGETS = ("c", "integrators", "latex", "gpu", "casadi", "fmu")

# ---------------------------------------------------------------------------- the strategy


def body_plans():
    return st.builds(BodyPlan, theta=st.sampled_from(randspec.THETAS), inertia=st.sampled_from(randspec.INERTIAS),
                     zero_c=st.tuples(st.booleans(), st.booleans(), st.booleans()),
                     zero_s=st.tuples(st.booleans(), st.booleans(), st.booleans()),
                     rotor=st.sampled_from(randspec.ROTORS), offset=st.sampled_from(randspec.OFFSETS),
                     spring=st.booleans(), damping=st.booleans(), control=st.booleans(), torque=st.booleans())


def chain_plans(max_n: int = 5, long: bool = True):
    """ChainPlans of one to ``max_n`` bodies (and with ``long``, one draw in ten, a long chain of the
    loop form)."""
    short = st.lists(body_plans(), min_size=1, max_size=max_n)
    sizes = [short] * 9 + ([st.lists(body_plans(), min_size=12, max_size=13)] if long else [])
    return st.builds(ChainPlan, bodies=st.one_of(*sizes).map(tuple),
                     seed=st.integers(0, 2**31 - 1), base=st.sampled_from(randspec.BASES), loads=st.booleans(),
                     gravity=st.booleans())


FORMS = st.tuples(st.sampled_from(["composite", "articulated"]), st.sampled_from(["auto", "forward", "world-solve", "world-inverse"]))


# ---------------------------------------------------------------------------- the targets
def _spec(plan: ChainPlan, name: str):
    return parse_spec(randspec.geometry_spec_text(plan, name))


def _states(spec, rng, count=4):
    n, nu = spec.n, len(spec.controls)
    return [(np.concatenate([rng.uniform(-np.pi, np.pi, n), rng.normal(size=n)]),
             rng.normal(size=nu) if nu else None, float(rng.uniform(0.0, 3.0))) for _ in range(count)]


def _der_form(spec, der_form):
    """The derivative form asked, or the automatic one where it does not apply to the spec (the
    world form needs a fixed base, constant rotors and no loads)."""
    if der_form.startswith("world") and (spec.base is not None and spec.base.moves or any(b.loaded for b in spec.bodies)
                                         or any(c != 0 for b in spec.bodies for c in b.lam_dot)):
        return "auto"
    return der_form


def strict_c99(files: dict, name: str) -> None:
    """gcc's front end on the C as C99 with every warning an error (an identifier that is not C99's,
    as M_PI, fails)."""
    with tempfile.TemporaryDirectory() as d:
        for k in (f"{name}.c", f"{name}.h"):
            (Path(d) / k).write_text(files[k])
        run = subprocess.run(["gcc", "-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-fsyntax-only",
                              str(Path(d) / f"{name}.c")], capture_output=True, text=True)
    assert run.returncode == 0 and not run.stderr, run.stderr[:2000]


def check_c_and_python(spec, qdd_form="auto", der_form="auto"):
    """The C in double, the Python mirror and the C in float against the independent model; the C
    strict C99."""
    der_form = _der_form(spec, der_form)
    files, model = pipeline.derive_and_render(spec, targets=("c", "python"), qdd_form=qdd_form, der_form=der_form)
    if shutil.which("gcc"):
        strict_c99(files, spec.name)
    cm = pipeline.compile(files, spec.name)
    selfcheck.check(spec, cm, "C", count=STATES, seed=SEED)
    with tempfile.TemporaryDirectory() as d:
        (Path(d) / f"{spec.name}.py").write_text(files[f"{spec.name}.py"])
        selfcheck.check(spec, selfcheck.PythonMirror(build.load_python(d, spec.name), time_dependent(model)), "Python",
                        count=STATES, seed=SEED)
    single, _ = pipeline.derive_and_render(spec, targets=("c",), qdd_form=qdd_form, der_form=der_form, real="float")
    selfcheck.check(spec, pipeline.compile(single, spec.name), "C", count=STATES, seed=SEED)
    return files, model, cm


def check_integrators(spec, cm, rng):
    """DOP853 against the independent model under scipy over 0.4 s (less for a stiff chain); RK4 and
    GAUSS2 (and its symplectic form where the model has Hamilton's variables) on it to rounding or
    converging to it; the fundamental matrix of the variational equations against central
    differences of the C's DOP853 trajectories."""
    params = selfcheck.parameters(spec)
    ch = reference.numeric(spec, params)
    n = spec.n
    x0 = np.concatenate([rng.uniform(-1.0, 1.0, n), 0.5 * rng.normal(size=n)])
    u = rng.normal(size=len(spec.controls)) if spec.controls else None
    # 0.4 s, or as much of it as DOP853 covers in 1,000 steps (a stiff chain: a point mass on a light
    # frame oscillates fast, and scipy's explicit DOP853 would take minutes)
    t1 = 0.4
    while True:
        try:
            _, stats = cm.integrate([0.0, t1], x0, "dop853", u=u, params=params, rtol=1e-12, atol=1e-12, full_output=True,
                                    max_steps=20000)
            break
        except build.IntegrationError as exc:  # the motion runs into a singular configuration (M not invertible), or
            if exc.t <= 1e-4:  # is too stiff for 20,000 steps: nothing an integrator can follow from this state
                return
            t1 = exc.t / 2
    if stats["n_steps"] > 1000:
        t1 *= 1000 / stats["n_steps"]
    t = np.linspace(0.0, t1, 5)
    ref = reference.simulate(ch, x0, t, u=u)
    scale = max(1.0, float(np.max(np.abs(ref))))
    X = cm.integrate(t, x0, "dop853", u=u, params=params, rtol=1e-12, atol=1e-12)
    err = float(np.max(np.abs(X - ref))) / scale
    assert err <= 1e-8, (spec.name, "dop853", err)
    # the fixed-step methods of order 4: on the solution to rounding, or converging to it faster than
    # order 2 (halving h divides the error by 16 in the limit; a stiff chain's fast modes are not there
    # yet, and a wrong stage or weight gives order 1 or none); h from t1 / 400, within RK4's stability
    for method in ("rk4", "gauss2") + (("gauss2_symplectic",) if cm.has_canonical else ()):
        steps = max(400, 2 * min(stats["n_steps"], 1000))
        for _ in range(3):
            try:
                errs = [float(np.max(np.abs(cm.integrate(t, x0, method, u=u, params=params, h=t1 / k) - ref))) / scale
                        for k in (steps, 2 * steps)]
                break
            except build.IntegrationError:  # GAUSS2's iteration does not converge at this step (it says so): shorter
                assert method != "rk4", (spec.name, method, "an explicit step within its stability failed")
                steps *= 4
        else:
            raise AssertionError((spec.name, method, "no step converges"))
        assert errs[1] <= 1e-9 or errs[1] <= errs[0] / 4, (spec.name, method, errs)
    if cm.has_variational:
        tv = min(0.2, t1)
        x1, Phi = cm.integrate_variational(0.0, tv, x0, u=u, params=params, rtol=1e-12, atol=1e-12)
        end = lambda y: cm.integrate([0.0, tv], y, "dop853", rtol=1e-13, atol=1e-13, u=u, params=params)[-1]  # noqa: E731
        fd = np.column_stack([_richardson(lambda s, e=e: end(x0 + s * e), 1e-4) for e in np.eye(2 * n)])
        err = float(np.max(np.abs(Phi - fd))) / max(1.0, float(np.max(np.abs(fd))))
        assert err <= 1e-6, (spec.name, "integrate_variational", err)


def check_latex(spec, qdd_form, der_form, cm):
    """The LaTeX document read back and compared with the C (the formulas, the scene's angles and
    vectors, the inputs' values)."""
    from test_latex_roundtrip import Doc, mismatches

    files, _ = pipeline.derive_and_render(spec, targets=("c", "latex"), qdd_form=qdd_form, der_form=_der_form(spec, der_form))
    params = selfcheck.parameters(spec)
    doc = Doc(files[f"{spec.name}.tex"], spec.n, params)
    assert mismatches(doc, SimpleNamespace(c=cm, spec=spec), params, np.random.default_rng(SEED), points=6) == []


def check_gpu(spec, qdd_form, der_form, cm, rng):
    """The kernels' host form (g++): each thread the C batch's trajectory, bit for bit."""
    from gyrochain import gpu

    files, _ = pipeline.derive_and_render(spec, targets=("c",), qdd_form=qdd_form, der_form=_der_form(spec, der_form), gpu=True)
    gm = gpu.GpuModel(cm, files, host=True)
    params = selfcheck.parameters(spec)
    X0 = rng.uniform(-1.0, 1.0, (3, 2 * spec.n))
    U = rng.normal(size=(3, len(spec.controls))) if spec.controls else None
    t = np.linspace(0.0, 0.2, 3)
    for method, h in (("rk4", 0.01), ("dop853", 0.0)):
        X, codes = gm.integrate_batch(t, X0, method=method, h=h, u=U, params=params, max_steps=20000)
        Xc, cc = cm.integrate_batch(t, X0, method=method, h=h, u=U, params=params, max_steps=20000)
        assert list(codes) == list(cc) and np.array_equal(X, Xc, equal_nan=True), (spec.name, method)


def casadi_applies(spec, model) -> bool:
    return bool(spec.controls) and spec.n <= 16 and not time_dependent(model)


def check_casadi(spec, rng):
    """f, the RK4 step F, M, E and the Jacobian of f against the C they are built on (the model of
    the same spec that ``pipeline.compiled`` holds to the independent model), to rounding; the
    Jacobian of F against central differences of F."""
    casadi = pytest.importorskip("casadi", reason="CasADi is not installed (make test installs it)")
    from gyrochain import casadi as gc

    params = selfcheck.parameters(spec)
    m = gc.functions(spec, params)
    cm, _ = pipeline.compiled(spec)  # the same C (the default forms), checked against the independent model
    jac_f, jac_F = m.f.jacobian(), m.F.jacobian()
    close = lambda a, b, what, tol=1e-12: _close(spec.name, what, a, b, tol)  # noqa: E731
    for x, u, _ in _states(spec, rng, 3):
        xdot = np.asarray(m.f(x, u, m.p0)).ravel()
        k1 = cm.rhs(0.0, x, u, params)
        close(xdot, k1, "f")
        h = min(0.01, 1e-3 * max(1.0, np.max(np.abs(x))) / np.max(np.abs(k1)))  # a step that moves the state a little
        k2 = cm.rhs(0.0, x + h / 2 * k1, u, params)
        k3 = cm.rhs(0.0, x + h / 2 * k2, u, params)
        k4 = cm.rhs(0.0, x + h * k3, u, params)
        xn = np.asarray(m.F(x, u, m.p0, h)).ravel()
        close(xn - x, h / 6 * (k1 + 2 * k2 + 2 * k3 + k4), "F (its increment)", 1e-10)
        close(np.asarray(m.M(x[: spec.n], m.p0).full()), cm.mass_matrix(x[: spec.n], params), "M")
        close(float(m.E(x, m.p0)), cm.energy(x, params), "E")
        A, B = cm.linearize(x, u, params)
        Jx, Ju = (np.asarray(casadi.DM(b).full()) for b in jac_f(x, u, m.p0, xdot)[:2])
        close(np.hstack([Jx, Ju]), np.hstack([A, B]), "jac_f")
        d, e = rng.normal(size=2 * spec.n), rng.normal(size=len(u))
        Fx, Fu, _, Fh = (np.asarray(casadi.DM(b).full()) for b in jac_F(x, u, m.p0, h, xn))
        fd = _richardson(lambda s: np.asarray(m.F(x + s * d, u + s * e, m.p0, h + s * h)).ravel(), 1e-4)
        close(Fx @ d + Fu @ e + h * Fh[:, 0], fd, "jac_F (along a random direction)", 1e-6)


def _close(name, what, got, want, tol):
    got, want = np.asarray(got, float), np.asarray(want, float)
    err = float(np.max(np.abs(got - want))) / max(float(np.max(np.abs(want))), 1e-300)
    assert err <= tol, (name, what, err)


def _richardson(f, h=1e-3):
    d1 = (np.asarray(f(h)) - np.asarray(f(-h))) / (2 * h)
    d2 = (np.asarray(f(h / 2)) - np.asarray(f(-h / 2))) / h
    return (4 * d2 - d1) / 3


def check_fmu(spec, rng, fmi="3"):
    """The FMU (model exchange, with the tip output) through FMPy: the state's derivatives against
    the C it is built on (held to the independent model), the tip against the independent model."""
    pytest.importorskip("fmpy", reason="FMPy is not installed (make test installs it)")
    from fmpy import read_model_description
    from fmpy.fmi2 import FMU2Model
    from fmpy.fmi3 import FMU3Model

    from gyrochain import fmu

    params = selfcheck.parameters(spec) or {}
    data, _ = fmu.make(spec, f"{spec.name}.toml", params, kinds=("me",), fmi=fmi, outputs=("tip",))
    ch = reference.numeric(spec, params or None)
    cm, _ = pipeline.compiled(spec)  # the C the FMU is built on, checked against the independent model
    n, nu = spec.n, len(spec.controls)
    with tempfile.TemporaryDirectory() as d:
        with zipfile.ZipFile(__import__("io").BytesIO(data)) as z:
            z.extractall(d)
        md = read_model_description(str(Path(d) / "modelDescription.xml"))
        cls = FMU3Model if fmi == "3" else FMU2Model
        inst = cls(guid=md.guid, unzipDirectory=d, modelIdentifier=md.modelExchange.modelIdentifier, instanceName="g")
        inst.instantiate()
        try:
            if fmi == "2":
                inst.setupExperiment(startTime=0.0)
                inst.enterInitializationMode()
            else:
                inst.enterInitializationMode(startTime=0.0)
            inst.exitInitializationMode()
            if fmi == "3":
                inst.enterContinuousTimeMode()
            vr = {v.name: v.valueReference for v in md.modelVariables}
            get, put = (inst.getReal, inst.setReal) if fmi == "2" else (inst.getFloat64, inst.setFloat64)
            states = [vr[f"phi{k}"] for k in range(1, n + 1)] + [vr[f"phidot{k}"] for k in range(1, n + 1)]
            ders = [vr[f"der(phi{k})"] for k in range(1, n + 1)] + [vr[f"der(phidot{k})"] for k in range(1, n + 1)]
            inputs = [vr[f"u{j}"] for j in range(1, nu + 1)]
            tip = [vr[f"tip.{a}"] for a in "xyz"]
            for x, u, t in _states(spec, rng, 3):
                inst.setTime(t)
                put(states + inputs, list(x) + (list(u) if nu else []))
                _close(spec.name, f"FMI {fmi} derivatives", np.array(get(ders)), cm.rhs(t, x, u if nu else None, params or None),
                       1e-12)
                got, want = np.array(get(tip)), fmu.tip_position(ch, x[:n])
                assert np.max(np.abs(got - want)) <= 1e-12 * max(1.0, np.max(np.abs(want))), (spec.name, fmi, "tip")
            inst.terminate()
        finally:
            inst.freeInstance()


def check_all(spec, qdd_form="auto", der_form="auto", targets=TARGETS, fmi=("3",)):
    rng = np.random.default_rng(SEED)
    files, model, cm = check_c_and_python(spec, qdd_form, der_form)
    if "integrators" in targets:
        check_integrators(spec, cm, rng)
    if "latex" in targets:
        check_latex(spec, qdd_form, der_form, cm)
    if "gpu" in targets and shutil.which("g++"):
        check_gpu(spec, qdd_form, der_form, cm, rng)
    if "casadi" in targets and casadi_applies(spec, model):
        check_casadi(spec, rng)
    if "fmu" in targets and shutil.which("cc"):
        for version in fmi:
            check_fmu(spec, rng, version)


# ---------------------------------------------------------------------------- the fixed set (make test)
B = BodyPlan
FIXED = {
    # anti-parallel consecutive axes (θ = ±π: R₂ is diag(−1, 1, −1), not the identity) in the articulated
    # form that turned the tensors wrong, full tensors and rotors, offsets; every target
    "antiparallel": (ChainPlan((B("number", "full", rotor="full", control=True), B("pi", "full", offset="number", control=True),
                                B("-pi", "full", rotor="full", offset="number", damping=True)), seed=11),
                     "articulated", "forward", TARGETS),
    # quarter and eighth turns (cos θ = 0, sin θ = ±1, √2/2), diagonal and axial tensors, exact zeros in c
    # and s, a rotor along the joint axis; the composite form
    "quarter_turns": (ChainPlan((B("pi/2", "diagonal", zero_c=(True, False, True), zero_s=(True, True, False), control=True),
                                 B("-pi/2", "axial", zero_c=(False, True, False), rotor="axis"),
                                 B("pi/4", "diagonal", zero_s=(False, True, True), spring=True),
                                 B("3*pi/4", "full", zero_c=(True, True, False), control=True)), seed=12),
                      "composite", "forward", ("c", "integrators", "latex", "casadi", "fmu")),
    # point masses and slender rods (a tensor with zero moments), a flipped axis, negative angles; the
    # world form of the derivatives
    "point_masses": (ChainPlan((B("-pi/4", "rod"), B("pi", "point", zero_c=(False, True, False)), B("number", "rod", offset="pi"),
                                B("-pi/2", "point")), seed=13), "composite", "world-solve", ("c", "integrators")),
    # massless frames between joints (a ball joint of three revolute joints), then a body
    "massless_frames": (ChainPlan((B("0", "full"), B("pi/2", "massless", zero_s=(True, True, True)),
                                   B("pi/2", "massless", zero_s=(True, True, True), control=True),
                                   B("-pi/2", "full", rotor="full")), seed=14), "articulated", "world-inverse", ("c", "integrators")),
    # a planar chain with flipped axes (θ ∈ {0, π, −π}), springs and dampers, no gravity
    "planar_flipped": (ChainPlan((B("0", "axial", rotor="axis", spring=True), B("pi", "diagonal", damping=True, spring=True),
                                  B("-pi", "full", offset="pi", control=True), B("pi", "point")), seed=15, gravity=False),
                       "articulated", "auto", ("c", "integrators", "casadi")),
    # a moving, turning platform with loads on the bodies, flipped axes and quarter turns; every target
    # but CasADi (a model of t)
    "moving_base": (ChainPlan((B("pi", "full", rotor="full", spring=True), B("-pi/2", "point", damping=True, control=True, torque=True),
                               B("-pi", "full", rotor="spin", offset="number")), seed=16, base="both", loads=True),
                    "articulated", "auto", TARGETS),
    # the first axis vertical and pointing up (θ¹ = π): the momentum (27) and the quadratures (30)
    "vertical_up": (ChainPlan((B("pi", "axial", zero_c=(True, True, True), zero_s=(True, True, True)),
                               B("-pi/2", "full", rotor="full")), seed=17), "articulated", "auto", ("c", "integrators", "latex")),
    # a long chain of the special angles: the loop form (n ≥ 12)
    "long_chain": (ChainPlan(tuple(B(th, kind, rotor="full" if i % 3 == 0 else "none", control=i == 5)
                                   for i, (th, kind) in enumerate(zip(["pi", "-pi", "pi/2", "0", "-pi/2", "pi", "pi/4", "-pi", "number",
                                                                       "pi", "3*pi/4", "-pi/4"],
                                                                      ["full", "diagonal", "point", "full", "rod", "axial", "full",
                                                                       "massless", "full", "diagonal", "full", "point"]))), seed=18),
                   "articulated", "auto", ("c",)),
    # motor armature (a term on M's diagonal alone): the articulated form's pivots, flipped axes and rotors;
    # every target
    "armature": (ChainPlan((B("pi", "full", armature=True, control=True), B("pi/2", "diagonal", armature=True, damping=True),
                            B("-pi/2", "full", rotor="full", armature=True, control=True)), seed=19),
                 "articulated", "forward", TARGETS),
    # armature on a moving platform (the energy from absolute velocities, the momentum), the composite form
    "armature_platform": (ChainPlan((B("0", "full", armature=True), B("pi/2", "point", zero_c=(False, True, False), armature=True,
                                                                     control=True)), seed=20, base="both"),
                          "composite", "auto", ("c", "integrators", "latex")),
    # a long chain with armature: the straight-line forms at n >= 12 (the loop form has no diagonal term)
    "armature_long": (ChainPlan(tuple(B(th, "full", armature=i % 2 == 0, control=i == 3)
                                      for i, th in enumerate(["pi", "pi/2", "0", "-pi/2", "number", "pi", "pi/4", "-pi", "pi/2",
                                                              "0", "number", "pi", "-pi/2"])), seed=5),
                      "auto", "auto", ("c",)),
}
# the shortcuts of the derivation and the printers (or the exact values they met) and the fixed case
# that exercises each; the note of this change lists them with their places in the code
SHORTCUTS = {
    "armature on M's diagonal alone; the articulated pivot D = U1 + a (W1 != 1, row 1 of the inertia passed on kept); "
    "the loop and world forms not taken": "armature, armature_platform, armature_long",
    "R2(theta) skipped where theta = 0 (kinematics.Joint.is_planar): theta = +-pi": "antiparallel, planar_flipped, long_chain",
    "cos theta = 0, sin theta = +-1, sqrt(2)/2 folded exactly (exact.py)": "quarter_turns, point_masses",
    "a zero offset delta^k left out of the angle (kinematics.derive)": "every case but antiparallel's first body",
    "zero components of c, s, A, lambda dropped (algebra.Poly)": "quarter_turns, vertical_up, massless_frames",
    "a massless body's terms vanish (m = 0)": "massless_frames, long_chain",
    "a point mass's and a rod's central tensor (zero moments)": "point_masses, long_chain",
    "the world form's zero tangents skipped (world._torque_tangents)": "point_masses, massless_frames",
    "no spring, damper or torque expression: joint = () (dynamics.derive)": "antiparallel, quarter_turns",
    "no loads / constant lambda: the Phi and Lamdot recursions left out": "moving_base against the rest",
    "sin theta1 = 0: the axis l1 vertical, momentum (27) and quadratures (30) emitted": "vertical_up",
    "g = 0: no gravity terms": "planar_flipped",
    "pi in an expression (an offset, the platform's motion, a torque): printed as M_PI, M_PI_4 (not C99)": "moving_base, point_masses",
    "lambda(t) and a torque expression of t and the state": "moving_base",
    "the loop form of long chains (loopform.py)": "long_chain",
}


@pytest.mark.parametrize("case", sorted(FIXED))
def test_a_chain_of_the_geometry_users_write_is_the_independent_model_in_every_target(case):
    plan, qdd_form, der_form, targets = FIXED[case]
    spec = _spec(plan, f"geo_{case}")
    check_all(spec, qdd_form, der_form, targets, fmi=("3", "2"))


def test_every_shortcut_has_a_case():
    cases = set(FIXED)
    for where in SHORTCUTS.values():
        named = {w.strip().split(" ")[0].split("'")[0] for w in where.replace(" against the rest", "").split(",")}
        assert named <= cases | {"every"}, named - cases
    assert {th for plan, *_ in FIXED.values() for th in (b.theta for b in plan.bodies)} == set(randspec.THETAS)
    assert {b.inertia for plan, *_ in FIXED.values() for b in plan.bodies} == set(randspec.INERTIAS)


# a draw costs seconds (a build of C each): a failing one is reported as drawn, not shrunk
NO_SHRINK = (Phase.explicit, Phase.generate)


def _derandomized(examples: int):
    return settings(max_examples=examples, derandomize=True, deadline=None, database=None, phases=NO_SHRINK,
                    suppress_health_check=list(HealthCheck))


def _property(plan, forms, targets, count):
    spec = _spec(plan, f"fz{count}")
    try:
        pipeline.check_mass_matrix(spec)
    except SpecError:  # a joint that moves no mass (a point mass on its own axis): refused, not a model
        assume(False)
    check_all(spec, *forms, targets=targets, fmi=("3", "2"))


def test_the_strategy_draws_chains_every_target_takes():
    """A few fixed-seed draws of the strategy (the same on every run) through the C, the Python
    mirror, the float C and the integrators."""
    count = iter(range(10**9))
    given(chain_plans(4, long=False), FORMS)(_derandomized(3)(lambda plan, forms: _property(plan, forms, ("c", "integrators"), next(count))))()


@pytest.mark.skipif(LONG <= 0, reason="make fuzz (FUZZ_SECONDS) draws fresh chains for that long")
def test_geometry_fuzz_for_a_while():
    """Fresh chains for FUZZ_SECONDS, every target on each; prints how many."""
    t_end, tried = time.monotonic() + LONG, [0]
    rounds = settings(max_examples=5, derandomize=False, deadline=None, database=None, phases=NO_SHRINK,
                      suppress_health_check=list(HealthCheck))

    def one(plan, forms):
        tried[0] += 1
        _property(plan, forms, TARGETS, tried[0])

    search = given(chain_plans(5), FORMS)(rounds(one))
    while time.monotonic() < t_end:
        search()
        print(f"geometry fuzz: {tried[0]} chains, every target, no failure", flush=True)
    print(f"\ngeometry fuzz: {tried[0]} chains in {LONG:.0f} s, every target, no failure")
