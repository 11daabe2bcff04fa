"""The generator scales: a 12-body spatial gyrostat chain is generated, compiled and agrees with
the reference model; reduced scenes get smaller models; the op counts in the files are those of
the code."""
from __future__ import annotations

import numpy as np
import pytest

from gyrochain import assemble, dynamics, integrals, kinematics, reference
from gyrochain.randspec import random_spec_text
from gyrochain.spec import parse_spec

from conftest import code_op_count, stated_op_counts


def test_n12_chain_matches_reference(make_model):
    rng = np.random.default_rng(12)
    model = make_model(random_spec_text(rng, 12, name="chain12", controls=(3, 12)))
    n = 12
    for _ in range(6):
        x = np.concatenate([rng.uniform(-np.pi, np.pi, n), rng.normal(size=n) * 2.0])
        u = rng.normal(size=2)
        ref = reference.qdd(model.ref, x, u)
        scale = np.max(np.abs(ref))
        for impl in (model.c, model.py):
            assert np.max(np.abs(impl.qdd(x, u) - ref)) <= 1e-10 * scale
        assert np.allclose(model.c.mass_matrix(x[:n]), reference.mass_matrix(model.ref, x[:n]), rtol=1e-11, atol=1e-12)
        assert abs(model.c.energy(x) - reference.energy(model.ref, x)) <= 1e-11 * max(1.0, abs(reference.energy(model.ref, x)))


def _counts(text: str) -> dict:
    spec = parse_spec(text)
    kin = kinematics.derive(spec)
    dyn = dynamics.derive(spec, kin.prog, kin)
    return assemble.op_counts(assemble.build_model(spec, kin.prog, kin, dyn, integrals.derive(spec, kin.prog, kin, dyn)))


@pytest.mark.parametrize("n", [2, 5])
def test_reduced_scenes_get_smaller_models(n):
    """The same random draws, with the scene reduced: every function shrinks."""
    def text(**kw):
        return random_spec_text(np.random.default_rng(50 + n), n, name="s", **kw)

    general = _counts(text())
    zero_c = "\n".join("c = [0.0, 0.0, 0.0]" if ln.startswith("c = ") else ln for ln in text().splitlines())
    for label, counts in (("planar", _counts(text(planar=True))), ("no rotors", _counts(text(gyro=False))),
                          ("zero offsets", _counts(zero_c))):
        assert counts["forces"] < general["forces"], label
        assert counts["qdd"] < general["qdd"], label
        assert counts["mass_matrix"] <= general["mass_matrix"], label


def test_op_counts_in_header_are_the_codes(make_model):
    """The header's op counts are computed from the emitted straight-line code: count the
    operators of the C function body and compare (the LDLᵀ part is added to qdd)."""
    model = make_model(random_spec_text(np.random.default_rng(3), 3, name="opc"))
    stated = stated_op_counts((model.folder / "opc.h").read_text())
    body = (model.folder / "opc.c").read_text().split("int opc_mass_matrix(")[1].split("opc_symmetrize_(M);")[0]
    assert code_op_count(body, r"M\[\d+\]") == stated["mass_matrix"]


@pytest.mark.parametrize("base", ["fixed", "turning"])
def test_loop_form_agrees_with_the_straight_line_form(make_model, base):
    """The loop form of long chains (loopform.py) forced on a short chain: every function it
    changes (mass matrix, energy, momentum, momenta, velocities, pdot) agrees with the straight-line
    form of the same spec to 1e-12, C and Python; the other functions are the same code."""
    rng = np.random.default_rng(77)
    text = random_spec_text(rng, 6, name="loops6", controls=(2,) if base == "fixed" else (), theta1=0.0)
    if base == "turning":  # a platform turning uniformly about the vertical: energy, Jacobi's integral
        text = text.replace("g = 9.81\n", 'g = 9.81\n\n[base]\nrotation = [{axis = [1, 0, 0], angle = "0.7*t"}]\n', 1)
    straight = make_model(text, loops="straight")
    loops = make_model(text, loops="loops")
    assert "loopform" in (loops.folder / "loops6.c").read_text() and "loopform" not in (straight.folder / "loops6.c").read_text()
    n = 6
    for _ in range(5):
        x = np.concatenate([rng.uniform(-np.pi, np.pi, n), rng.normal(size=n) * 2.0])
        q = x[:n]
        for a, b in ((straight.c, loops.c), (straight.py, loops.py)):
            M = a.mass_matrix(q)
            assert np.max(np.abs(b.mass_matrix(q) - M)) <= 1e-12 * np.max(np.abs(M))
            t = (0.3,) if getattr(straight.py, "TIME_DEPENDENT", False) else ()
            fns = [("energy", (*t, x))] + ([("jacobi", (x,))] if base == "turning" else [])
            if base == "fixed":
                fns += [("momentum", (x,)), ("momenta", (x,)), ("pdot", (x, [0.4])), ("velocities", (q, x[n:]))]
            for fn, args in fns:
                va, vb = np.asarray(getattr(a, fn)(*args)), np.asarray(getattr(b, fn)(*args))
                assert np.max(np.abs(vb - va)) <= 1e-12 * max(1.0, np.max(np.abs(va))), fn
