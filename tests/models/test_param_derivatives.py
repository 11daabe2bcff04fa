"""Derivatives in the symbolic parameters: NAME_param_derivatives (∂φ̈/∂p), its Python mirror and
NAME_step_param_derivatives (∂xn/∂p of the RK4 step) against central differences of the emitted
φ̈ and step in each parameter, for every parameter of furuta_sym (masses, lengths, inertias,
gravity) and of a random spatial chain whose inertias, masses, rotor momenta, springs and dampers
are all symbols; a planted error fails; a model without parameters has none."""
from __future__ import annotations

import numpy as np
import pytest

from gyrochain.build import ModelError
from gyrochain.spec import load_spec
from conftest import ROOT, FURUTA_SYM_PARAMS, richardson

TOL = 1e-7


def symbolic_chain(rng, n: int = 3) -> tuple[str, dict]:
    """A spatial chain of n gyrostats with every inertia entry, mass, offset of the centre of mass,
    rotor momentum, spring and damper a symbol, and its [values] (a random chain)."""
    lines, values = ['name = "symchain"', 'description = "a spatial chain with symbolic inertias"', "g = 9.81", ""], {}
    for k in range(1, n + 1):
        m, c = rng.uniform(0.5, 2.0), rng.uniform(-0.3, 0.3, 3)
        pm = np.sort(rng.uniform(0.02, 0.1, 3))
        pm[2] = min(pm[2], 0.9 * (pm[0] + pm[1]))  # the triangle inequality of a body's principal moments
        Q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        A = Q @ np.diag(pm) @ Q.T + m * (c @ c * np.eye(3) - np.outer(c, c))
        names = [[f"inert{k}_{min(i, j) + 1}{max(i, j) + 1}" for j in range(3)] for i in range(3)]
        for i in range(3):
            for j in range(i, 3):
                values[names[i][j]] = A[i, j]
        values.update({f"mass{k}": m, f"zc{k}": c[2], f"rotor{k}": rng.uniform(-0.3, 0.3), f"kspring{k}": rng.uniform(0.2, 2.0),
                       f"bdamp{k}": rng.uniform(0.01, 0.1)})
        values = {key: float(v) for key, v in values.items()}
        lines += ["[[body]]", f'theta = "{str(rng.choice(["0", "pi/2", "pi", "-pi/2", "0.7"]))}"',
                  f'm = "mass{k}"', f'c = [{c[0]:.4f}, {c[1]:.4f}, "zc{k}"]',
                  "A = [" + ", ".join("[" + ", ".join(f'"{v}"' for v in row) + "]" for row in names) + "]",
                  f'lambda = [0, "rotor{k}", 0]', f'spring = "kspring{k}"', f'damping = "bdamp{k}"']
        if k < n:
            lines.append("s = [0.1, -0.05, 0.2]")
        if k == 1:
            lines.append("control = true")
        lines.append("")
    lines += ["[values]"] + [f"{key} = {v!r}" for key, v in values.items()]
    return "\n".join(lines) + "\n", values


def _check(m, params, rng, points: int) -> float:
    n, nu = m.spec.n, m.c.nu
    names = [str(p) for p in m.spec.params]
    worst = 0.0
    for _ in range(points):
        x = np.concatenate([rng.uniform(-np.pi, np.pi, n), rng.normal(size=n)])
        u = rng.normal(size=nu) if nu else None
        qdd, D = m.c.param_derivatives(x, u, params)
        qdd_py, D_py = m.py.param_derivatives(x, u, params)
        assert np.allclose(qdd, m.c.qdd(x, u, params), rtol=1e-12, atol=1e-12)
        assert np.allclose(D_py, D, rtol=1e-12, atol=1e-12 * np.max(np.abs(D)))
        h = 0.01
        xn, Dx = m.c.step_param_derivatives(x, h, u, params)
        assert np.allclose(xn, m.c.step(x, h, u, params), rtol=1e-13, atol=1e-13)

        def at(j, s):
            return {**params, names[j]: params[names[j]] * (1.0 + s)}
        want = np.array([richardson(lambda s: m.c.qdd(x, u, at(j, s)), 1e-3) / params[names[j]] for j in range(len(names))]).T
        want_step = np.array([richardson(lambda s: m.c.step(x, h, u, at(j, s)), 1e-3) / params[names[j]]
                              for j in range(len(names))]).T
        worst = max(worst, np.max(np.abs(D - want)) / np.max(np.abs(want)), np.max(np.abs(Dx - want_step)) / np.max(np.abs(want_step)))
    return worst


def test_every_parameter_of_the_symbolic_furuta_pendulum(example, rng):
    m = example("furuta_sym")
    worst = _check(m, FURUTA_SYM_PARAMS, rng, 20)
    print(f"\nfuruta_sym: d qdd/dp, d xn/dp against differences: {worst:.1e}")
    assert worst <= TOL


def test_a_random_chain_with_symbolic_inertias_rotors_springs_and_dampers(make_model, rng):
    text, values = symbolic_chain(rng)
    m = make_model(text, values)
    assert len(m.spec.params) == 3 * 11
    worst = _check(m, values, rng, 5)
    print(f"\nsymbolic chain: d qdd/dp, d xn/dp against differences: {worst:.1e}")
    assert worst <= TOL


def test_a_planted_error_fails_and_the_edges(example, rng, tmp_path):
    from gyrochain import build

    m = example("furuta_sym")
    src = (m.folder / "furuta_sym.c").read_text()
    old = "        dqdd_dp[i] = dp[i];"
    assert src.count(old) == 1
    folder = tmp_path / "planted"
    folder.mkdir()
    (folder / "furuta_sym.c").write_text(src.replace(old, "        dqdd_dp[i] = dp[i] * (i == 5 ? 1.00001 : 1.0);"))
    for ext in (".h", ".cdef"):
        (folder / f"furuta_sym{ext}").write_text((m.folder / f"furuta_sym{ext}").read_text())
    bad = build.CModel(build.compile_model(folder, "furuta_sym"), "furuta_sym")
    names, worst = [str(p) for p in m.spec.params], 0.0
    for _ in range(3):
        x, u = np.concatenate([rng.uniform(-np.pi, np.pi, 2), rng.normal(size=2)]), rng.normal(size=1)
        _, D = bad.param_derivatives(x, u, FURUTA_SYM_PARAMS)
        want = np.array([richardson(lambda s: bad.qdd(x, u, {**FURUTA_SYM_PARAMS, k: FURUTA_SYM_PARAMS[k] * (1 + s)}), 1e-3)
                         / FURUTA_SYM_PARAMS[k] for k in names]).T
        worst = max(worst, np.max(np.abs(D - want)) / np.max(np.abs(want)))
    assert worst > TOL
    with pytest.raises(ModelError):
        m.c.param_derivatives(np.zeros(4), None, None)  # no parameters: NO_PARAMS
    out = m.c.ffi.new("double[8]")
    assert m.c.lib.furuta_sym_param_derivatives(m.c.ffi.NULL, m.c.ffi.NULL, m.c._p(FURUTA_SYM_PARAMS), m.c.ffi.NULL, out) \
        == m.c.lib.FURUTA_SYM_BAD_ARGUMENT
    assert not hasattr(example("furuta").c.lib, "furuta_param_derivatives")  # a model of numbers has none
    assert "furuta_sym_param_derivatives" in (ROOT / "generated" / "furuta_sym" / "furuta_sym.h").read_text()
    assert load_spec(ROOT / "specs" / "furuta_sym.toml").params
