"""The regressor (generate --regressor): u = Y(φ, φ̇, φ̈) π + τ₀ against the inverse dynamics of the
generated C (M φ̈ − f at u = 0), the energy's h π + e₀ against NAME_energy, the base parameters
against the numerical rank of the stacked regressor and against Pinocchio's joint-torque
regressor, and the independent numpy regressor of reference.py against the C."""
from __future__ import annotations

import numpy as np
import pytest

from conftest import EXAMPLES, LONG_EXAMPLES, QUICK_EXAMPLES, ROOT, example_params, tiered
from gyrochain import pipeline, reference
from gyrochain.randspec import random_general_spec_text, random_spec_text
from gyrochain.spec import SpecError, load_spec, parse_spec

STATES = 100
TOL = 1e-12
# cable64: its regressor (64 × 832) is 5 MB of C and compiles in minutes; every shorter example is here
SHORT = [e for e in EXAMPLES if e not in LONG_EXAMPLES]
RANDOM = {  # random chains with platforms, loads, springs, dampers, torque expressions and rotors (constant λ)
    "rchain6": random_spec_text(np.random.default_rng(32), 6, name="rchain6", controls=(1, 3, 6), offsets=True),
    "gchain3": random_general_spec_text(np.random.default_rng(33), 3, name="gchain3", spin_up=False),
}


def _spec(name):
    return parse_spec(RANDOM[name]) if name in RANDOM else load_spec(ROOT / "specs" / f"{name}.toml")


def _params(name, spec):
    return example_params(name) if name not in RANDOM else None


def _rank(M) -> int:
    """The numerical rank of the columns scaled to unit length (a column of round-off is zero)."""
    norms = np.linalg.norm(M, axis=0)
    live = norms > 1e-12 * norms.max()
    sv = np.linalg.svd(M[:, live] / norms[live], compute_uv=False)
    return int(np.sum(sv > 1e-9 * sv[0]))


def _states(rng, n):
    for _ in range(STATES):
        yield rng.uniform(-np.pi, np.pi, n), rng.normal(size=n) * 2.0, rng.normal(size=n) * 5.0, float(rng.uniform(0, 5))


_PY: dict = {}


def _python(name):
    """The generated Python module of the spec with its regressor (executed once per process), its
    model, and the plain model's C (the one every other test compiles: no build of its own)."""
    if name not in _PY:
        import importlib.util

        spec = _spec(name)
        model = pipeline.derive(spec, regressor=True, latex=False)
        text = pipeline.render(model, targets=("python",))[f"{spec.name}.py"]
        mod = importlib.util.module_from_spec(importlib.util.spec_from_loader(spec.name, loader=None))
        exec(compile(text, f"{spec.name}.py", "exec"), mod.__dict__)
        _PY[name] = mod, model, _Plain(spec)
    return _PY[name]


class _Plain:
    """The spec's plain C model, built when first used (the Pinocchio test needs none)."""

    def __init__(self, spec):
        self.spec, self.cm = spec, None

    def __getattr__(self, what):
        if self.__dict__["cm"] is None:
            self.__dict__["cm"] = pipeline.compiled(self.__dict__["spec"])[0]
        return getattr(self.__dict__["cm"], what)


def _t(mod, t):
    return (t,) if getattr(mod, "TIME_DEPENDENT", False) else ()


@pytest.mark.parametrize("name", tiered(SHORT, QUICK_EXAMPLES) + sorted(RANDOM))
def test_regressor_is_the_inverse_dynamics_of_the_c(name):
    """The generated regressor (its Python printing here; the C is the same straight line, checked
    against it below) against the inverse dynamics of the generated C, the energy regressor
    against NAME_energy, and the independent numpy regressor; the base parameters as many as the
    stacked regressor's numerical rank, Y_B of full rank."""
    spec = _spec(name)
    p = _params(name, spec)
    mod, model, cm = _python(name)
    n = spec.n
    pi = mod.standard_parameters(p)
    beta = mod.base_parameters(pi)
    assert len(beta) == model.base.count and len(pi) == len(model.reg.params)
    worst = dict(Y=0.0, Yb=0.0, energy=0.0, reference=0.0)
    cols = [(q.kind, q.body, q.index) for q in model.reg.params]
    ch = reference.numeric(spec, p)
    stacked, stacked_b = [], []
    for i, (q, v, a, t) in enumerate(_states(np.random.default_rng(5), n)):
        x = np.concatenate([q, v])
        tau = cm.mass_matrix(q, p) @ a - cm.forces(x, None, p, t)  # the C's inverse dynamics at u = 0 elsewhere
        scale = max(1.0, np.abs(tau).max())
        Y, tau0 = mod.regressor(*_t(mod, t), q, v, a, p)
        Yb, tau0b = mod.base_regressor(*_t(mod, t), q, v, a, p)
        worst["Y"] = max(worst["Y"], np.abs(Y @ pi + tau0 - tau).max() / scale)
        worst["Yb"] = max(worst["Yb"], np.abs(Yb @ beta + tau0b - tau).max() / scale)
        h, e0 = mod.energy_regressor(*_t(mod, t), q, v, p)
        E = cm.energy(x, p, t)
        worst["energy"] = max(worst["energy"], abs(h @ pi + e0 - E) / max(1.0, abs(E)))
        if i < 10:  # the independent numpy regressor (a Python loop over the columns: ten states)
            Yr = reference.regressor(ch, cols, q, v, a, t)
            worst["reference"] = max(worst["reference"], np.abs(Yr - Y).max() / max(1.0, np.abs(Y).max()))
        stacked.append(Y)
        stacked_b.append(Yb)
    print(f"{name}: {len(pi)} standard, {len(beta)} base parameters; worst " + ", ".join(f"{k} {v:.1e}" for k, v in worst.items()))
    assert max(worst.values()) <= TOL, worst
    assert _rank(np.vstack(stacked)) == model.base.count
    assert np.linalg.matrix_rank(np.vstack(stacked_b)) == model.base.count


@pytest.mark.parametrize("seed", range(8))
def test_base_parameters_are_the_numerical_rank_on_random_chains(seed):
    """3–6-link chains, spatial or planar, with and without rotors: the count is the rank of Y
    stacked at fresh states (numpy's reference regressor), and β = K π reproduces Y π there."""
    from gyrochain import baseparams, regressor

    rng = np.random.default_rng(100 + seed)
    n = 3 + seed % 4
    spec = parse_spec(random_spec_text(rng, n, planar=seed % 3 == 2, gyro=seed % 2 == 0, theta1=0.0 if seed % 4 == 1 else None))
    params = regressor.parameters(spec)
    base = baseparams.find(spec, params)
    ch = reference.numeric(spec)
    cols = [(q.kind, q.body, q.index) for q in params]
    Y = np.vstack([reference.regressor(ch, cols, q, v, a, t) for q, v, a, t in _states(np.random.default_rng(seed), n)][:40])
    rank = _rank(Y)
    K = base.matrix(len(params))
    worst = np.abs(Y[:, list(base.columns)] @ K - Y).max() / np.abs(Y).max()
    print(f"n = {n}: {len(params)} standard, {base.count} base parameters, rank {rank}, |Y_B K - Y| {worst:.1e}")
    assert base.count == rank
    assert worst <= 1e-12


def test_a_rotor_spinning_up_has_no_constant_parameter():
    spec = parse_spec(random_general_spec_text(np.random.default_rng(3), 2, name="spin"))
    with pytest.raises(SpecError, match=r"body\[1\]\.lambda: depends on t"):
        pipeline.derive(spec, regressor=True, latex=False)


@pytest.mark.parametrize("name", ["furuta_sym", "kapitza", "gchain3"])
def test_the_c_regressor_is_the_python(name):
    """The C's regressor functions against the Python's (the same straight lines, printed twice) on
    a symbolic spec, a driven pivot and a random chain on a moving platform with loads, springs,
    dampers and rotors, and the C's Y π against its own inverse dynamics."""
    spec = _spec(name)
    p = _params(name, spec)
    mod, model, plain = _python(name)
    cm, _ = pipeline.compiled(spec, regressor=True)
    assert np.array_equal(mod.standard_parameters(p), cm.standard_parameters(p))
    pi = cm.standard_parameters(p)
    assert np.allclose(mod.base_parameters(pi), cm.base_parameters(pi), rtol=1e-15, atol=0)
    for q, v, a, t in list(_states(np.random.default_rng(8), spec.n))[:20]:
        for base in (False, True):
            Y, tau0 = (mod.base_regressor if base else mod.regressor)(*_t(mod, t), q, v, a, p)
            Yc, tau0c = cm.regressor(q, v, a, p, t, base=base)
            assert np.allclose(Y, Yc, rtol=1e-13, atol=1e-13) and np.allclose(tau0, tau0c, rtol=1e-13, atol=1e-13)
        h, e0 = mod.energy_regressor(*_t(mod, t), q, v, p)
        hc, e0c = cm.energy_regressor(q, v, p, t)
        assert np.allclose(h, hc, rtol=1e-13, atol=1e-13) and abs(e0 - e0c) <= 1e-13
        x = np.concatenate([q, v])
        tau = plain.mass_matrix(q, p) @ a - plain.forces(x, None, p, t)
        Yc, tau0c = cm.regressor(q, v, a, p, t)
        assert np.abs(Yc @ pi + tau0c - tau).max() <= TOL * max(1.0, np.abs(tau).max())


@pytest.mark.parametrize("name", ["furuta", "gimbal", "ur5", "spatial3", "kapitza"])
def test_the_latex_base_parameters_are_the_code(name):
    """Each β row of the LaTeX read back (names and coefficients) is the row of K the code uses."""
    import re
    from fractions import Fraction

    spec = _spec(name)
    model = pipeline.derive(spec, regressor=True)
    tex = pipeline.render(model, targets=("latex",))[f"{spec.name}.tex"]
    import texread

    eqs = texread.equations(tex)
    rows = [(str(i), eqs[rf"\beta_{{{i}}}"]) for i in range(1, model.base.count + 1) if rf"\beta_{{{i}}}" in eqs]
    assert len(rows) == model.base.count and rf"\beta_{{{model.base.count + 1}}}" not in eqs
    by_tex = {p.tex: j for j, p in enumerate(model.reg.params)}
    term = re.compile(r"\s*([+-])?\s*(?:(\d+(?:\.\d+)?(?:e[+-]?\d+)?|\\tfrac\{(\d+)\}\{(\d+)\})\\,)?((?:\(mc\)|[mA]|\\lambda|b)\^\{\d+\}(?:_\{\d+\})?)")
    for (i, text), row in zip(rows, model.base.K):
        found, pos = {}, 0
        while pos < len(text):
            m = term.match(text, pos)
            assert m, (name, text[pos:])
            sign = -1 if m.group(1) == "-" else 1
            c = Fraction(m.group(2)) if m.group(2) else Fraction(int(m.group(3)), int(m.group(4))) if m.group(3) else Fraction(1)
            found[by_tex[m.group(5)]] = sign * c
            pos = m.end()
        assert set(found) == {j for j, _ in row}, (name, i, text)
        for j, c in row:  # exact coefficients exactly; a numerical one to the 15 digits printed
            assert found[j] == Fraction(int(c.p), int(c.q)) if c.is_Rational else abs(float(found[j]) - float(c)) <= 1e-14 * abs(float(c)), (name, i, j, text)


# --------------------------------------------------------------------------- Pinocchio
@pytest.mark.parametrize("name", ["double_pendulum", "furuta", "ur5", "panda", "arm4", "arm5"])
def test_base_parameters_match_pinocchio(name, tmp_path):
    """Fixed-base chains without rotors, exported to URDF: the rank of Pinocchio's
    computeJointTorqueRegressor stacked at random states is our number of base parameters (with
    the joints' damping, which Pinocchio's regressor does not have, left out), and Y π (ours)
    equals Y π (Pinocchio's, its inertias in its link frames)."""
    from gyrochain import exchange

    pin = pytest.importorskip("pinocchio", reason="Pinocchio (pip install pin; make test installs it) checks the base parameters")
    texts = {"arm4": random_spec_text(np.random.default_rng(41), 4, name="arm4", gyro=False, controls=(1, 2, 3, 4)),
             "arm5": random_spec_text(np.random.default_rng(42), 5, name="arm5", gyro=False, offsets=True)}
    if name in texts:
        RANDOM.setdefault(name, texts[name])
    mod, model, _ = _python(name)
    spec = model.spec
    text, _ = exchange.export_text(spec, f"{name}.toml", "urdf", {})
    (tmp_path / "m.urdf").write_text(text)
    pm = pin.buildModelFromUrdf(str(tmp_path / "m.urdf"))
    pm.gravity.linear[:] = [0.0, 0.0, -float(spec.g)]
    data = pm.createData()
    n = spec.n
    joints = [pm.joints[pm.getJointId(f"joint{k}")] for k in range(1, n + 1)]
    pi_pin = np.concatenate([pm.inertias[i].toDynamicParameters() for i in range(1, pm.njoints)])
    pi = mod.standard_parameters()
    inertial = [j for j, q in enumerate(model.reg.params) if q.kind != "b"]
    damped = [j for j, q in enumerate(model.reg.params) if q.kind == "b"]
    ours, theirs, worst = [], [], 0.0
    for q, v, a, _t in list(_states(np.random.default_rng(9), n))[:40]:
        qp = pin.neutral(pm)
        vp, ap = np.zeros(pm.nv), np.zeros(pm.nv)
        for k, j in enumerate(joints):
            if j.nq == 2:
                qp[j.idx_q:j.idx_q + 2] = np.cos(q[k]), np.sin(q[k])
            else:
                qp[j.idx_q] = q[k]
            vp[j.idx_v], ap[j.idx_v] = v[k], a[k]
        Yp = pin.computeJointTorqueRegressor(pm, data, qp, vp, ap)
        rows = [j.idx_v for j in joints]
        Y, tau0 = mod.regressor(q, v, a)
        tau_ours = Y[:, inertial] @ pi[inertial] + tau0
        tau_pin = (Yp @ pi_pin)[rows]
        worst = max(worst, np.abs(tau_ours - tau_pin).max() / max(1.0, np.abs(tau_pin).max()))
        ours.append(Y[:, inertial])
        theirs.append(Yp[rows])
    r_pin, r_ours = _rank(np.vstack(theirs)), _rank(np.vstack(ours))
    print(f"{name}: base parameters {model.base.count} ({len(damped)} dampers), rank ours {r_ours}, Pinocchio's {r_pin}; "
          f"|Y pi - Y_pin pi_pin| {worst:.1e}")
    assert model.base.count - len(damped) == r_ours == r_pin
    assert worst <= 1e-10


@pytest.mark.extended  # (the sanitizers: make test-all, with the static analysers)
def test_the_regressor_c_is_strict_and_clean_under_the_sanitizers(tmp_path):
    """Kapitza's pendulum (t first, symbolic parameters) with --regressor: warning-free under the
    strict flags, and every new function, with tau0 and e0 NULL and the error codes, clean under
    ASan and UBSan."""
    import shutil
    import subprocess

    if shutil.which("gcc") is None:
        pytest.skip("no gcc")
    spec = _spec("kapitza")
    files = pipeline.render(pipeline.derive(spec, regressor=True, latex=False), targets=("c",))
    for k, v in files.items():
        (tmp_path / k).write_text(v)
    (tmp_path / "drv.c").write_text("""
#include <math.h>
#include "kapitza.h"
int main(void) {
    double phi[KAPITZA_N] = {0.3}, phidot[KAPITZA_N] = {1.0}, phidd[KAPITZA_N] = {-2.0};
    double Y[KAPITZA_N * KAPITZA_NPI], Yb[KAPITZA_N * KAPITZA_NBASE], tau0[KAPITZA_N], h[KAPITZA_NPI], e0;
    double pi[KAPITZA_NPI], beta[KAPITZA_NBASE];
    kapitza_params p;
    int c = 0;
    p.a = 0.01;
    p.w = 200.0;
    c |= kapitza_regressor(0.1, phi, phidot, phidd, &p, Y, tau0);
    c |= kapitza_regressor(0.1, phi, phidot, phidd, &p, Y, 0);
    c |= kapitza_base_regressor(0.1, phi, phidot, phidd, &p, Yb, tau0);
    c |= kapitza_energy_regressor(0.1, phi, phidot, &p, h, &e0);
    c |= kapitza_energy_regressor(0.1, phi, phidot, &p, h, 0);
    c |= kapitza_standard_parameters(&p, pi);
    c |= kapitza_base_parameters(pi, beta);
    if (c) return 2;
    if (kapitza_regressor(0.1, phi, phidot, phidd, 0, Y, tau0) != KAPITZA_NO_PARAMS) return 3;
    if (kapitza_regressor(0.1, 0, phidot, phidd, &p, Y, tau0) != KAPITZA_BAD_ARGUMENT) return 4;
    if (kapitza_base_parameters(pi, 0) != KAPITZA_BAD_ARGUMENT) return 5;
    phi[0] = NAN;
    if (kapitza_regressor(0.1, phi, phidot, phidd, &p, Y, tau0) != KAPITZA_NONFINITE) return 6;
    return 0;
}
""")
    strict = ["gcc", "-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror"]
    res = subprocess.run(strict + ["-c", "kapitza.c", "-o", "k.o"], cwd=tmp_path, capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    san = ["-g1", "-fsanitize=address,undefined", "-fno-sanitize-recover=all", "-fno-omit-frame-pointer"]
    res = subprocess.run(strict + san + ["drv.c", "kapitza.c", "-lm", "-o", "drv"], cwd=tmp_path, capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    run = subprocess.run(["./drv"], cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0 and run.stderr == "", (run.returncode, run.stderr[-2000:])
