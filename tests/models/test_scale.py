"""The generator scales: a 12-body spatial gyrostat chain is generated, compiled and agrees with
the reference model; reduced scenes get smaller models; the op counts in the files are those of
the code."""
from __future__ import annotations

import numpy as np
import pytest

from codegen import assemble, dynamics, integrals, kinematics, reference
from codegen.randspec import random_spec_text
from codegen.spec import parse_spec

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
