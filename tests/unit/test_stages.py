"""The derivation stages alone, against independent numbers: the kinematics' γᵏ (the fixed
"down" ê⁰₁ in frame k, eq. (14)) and ωᵏ (eq. (1)) against reference.py's direction cosines, and
the rendered Python model (no compiler) against the independent Lagrangian of tests/lagrange.py."""
from __future__ import annotations

import types

import numpy as np
import pytest
import sympy as sp

from gyrochain import kinematics, pipeline, reference
from gyrochain.randspec import random_spec_text
from gyrochain.spec import parse_spec
from lagrange import lagrange_terms_np


def _values(kin, polys, x):
    """Program polynomials at the state x (φ, φ̇), by their closed forms."""
    n = kin.n
    exprs = kin.prog.inline(polys)
    subs = {kin.phi[k]: x[k - 1] for k in range(1, n + 1)} | {kin.phidot[k]: x[n + k - 1] for k in range(1, n + 1)}
    return np.array([float(sp.N(e.xreplace(subs))) for e in exprs])


@pytest.mark.parametrize("planar", [False, True])
def test_kinematics_against_the_direction_cosines(planar):
    rng = np.random.default_rng(7 + planar)
    spec = parse_spec(random_spec_text(rng, 3, name="kin3", planar=planar))
    kin = kinematics.derive(spec)
    ch = reference.numeric(spec)
    for _ in range(3):
        x = rng.uniform(-2, 2, 6)
        R = reference.frames(ch, x[:3])  # R[k-1]: rows êᵏᵢ in the fixed frame
        omega_fixed = np.zeros(3)
        for k in range(1, 4):
            e1 = R[k - 1][0]
            omega_fixed = omega_fixed + x[3 + k - 1] * e1  # ωᵏ = ωᵏ⁻¹ + φ̇ᵏ eᵏ (eq. (1)), fixed frame
            assert np.allclose(_values(kin, kin.gamma[k], x), R[k - 1][:, 0], atol=1e-13), k  # ê⁰₁ in frame k
            assert np.allclose(_values(kin, kin.omega[k], x), R[k - 1] @ omega_fixed, atol=1e-13), k


def _python_model(spec):
    """The rendered Python target as a module, without writing or compiling anything."""
    files = pipeline.render(pipeline.derive(spec, latex=False), targets=("python",))
    mod = types.ModuleType(f"unit_{spec.name}")
    exec(compile(files[f"{spec.name}.py"], f"{spec.name}.py", "exec"), mod.__dict__)  # noqa: S102  (our own output)
    return mod


@pytest.mark.parametrize("n", [2, 3])
def test_rendered_python_equals_the_lagrangian(n):
    rng = np.random.default_rng(200 + n)
    spec = parse_spec(random_spec_text(rng, n, name=f"ulag{n}", controls=(n,)))
    py, ch = _python_model(spec), reference.numeric(spec)
    for _ in range(4):
        x, u = rng.normal(size=2 * n) * 1.5, rng.normal(size=1)
        H, b = lagrange_terms_np(ch, x[:n], x[n:])
        f = -b
        f[n - 1] += u[0]
        assert np.max(np.abs(py.mass_matrix(x[:n]) - H)) <= 1e-12 * np.max(np.abs(H))
        assert np.max(np.abs(py.forces(x, u) - f)) <= 1e-12 * np.max(np.abs(f))
