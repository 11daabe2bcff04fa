"""NAME_qdd comes in two forms (assemble.build_model): composite bodies + LDLᵀ and articulated bodies.
The generator picks the cheaper; here both are forced on the same specs and must agree with the
reference model, report a singular configuration the same way, and state their op counts."""
from __future__ import annotations

import re

import numpy as np
import pytest

from gyrochain import reference
from gyrochain.build import ModelError
from gyrochain.randspec import random_spec_text

from conftest import ROOT, code_op_count, example_params, stated_op_counts

FORMS = ("composite", "articulated")


def _renamed(text: str, name: str) -> str:
    return re.sub(r'^name = ".*"$', f'name = "{name}"', text, count=1, flags=re.M)


@pytest.mark.parametrize("form", FORMS)
@pytest.mark.parametrize("example", ["gimbal", "furuta_sym", "spatial3"])
def test_forced_form_matches_reference(make_model, example, form, rng):
    text = _renamed((ROOT / "specs" / f"{example}.toml").read_text(), f"{example}_{form[:3]}")
    model = make_model(text, example_params(example), qdd_form=form)
    n, nu = model.spec.n, len(model.spec.controls)
    for _ in range(8):
        x = np.concatenate([rng.uniform(-np.pi, np.pi, n), rng.normal(size=n) * 3.0])
        u = rng.normal(size=nu) if nu else None
        ref = reference.qdd(model.ref, x, u)
        tol = 1e-12 * max(1.0, np.max(np.abs(ref)))
        assert np.max(np.abs(model.c.qdd(x, u, model.params) - ref)) <= tol
        assert np.max(np.abs(model.py.qdd(x, u, model.params) - ref)) <= tol


@pytest.mark.parametrize("form", FORMS)
def test_forced_form_long_chain(make_model, form):
    rng = np.random.default_rng(6)
    model = make_model(random_spec_text(rng, 6, name=f"chain6_{form[:3]}", controls=(1, 4)), qdd_form=form)
    for _ in range(6):
        x = np.concatenate([rng.uniform(-np.pi, np.pi, 6), rng.normal(size=6) * 2.0])
        u = rng.normal(size=2)
        ref = reference.qdd(model.ref, x, u)
        assert np.max(np.abs(model.c.qdd(x, u) - ref)) <= 1e-11 * np.max(np.abs(ref))


SINGULAR = """
name = "{name}"
g = 9.81
[[body]]
theta = 0.3
m = 1.0
c = [0.1, 0.0, -0.2]
A = [[0.2, 0, 0], [0, 0.2, 0], [0, 0, 0.1]]
s = [0.0, 0.1, -0.4]
[[body]]
theta = 1.1
m = "m2"
c = [0.05, 0, 0.2]
A = [["a2", 0, 0], [0, "a2", 0], [0, 0, "a2"]]
lambda = [0.0, 0.0, 0.5]
"""


@pytest.mark.parametrize("form", FORMS)
def test_singular_configuration_reported(make_model, form):
    """Body 2 without mass or inertia: M₂₂ = 0, M is singular in every state.  Both forms return
    SINGULAR (C) and raise SingularMassMatrix (Python), and leave the caller's buffer alone."""
    ok = dict(m2=0.5, a2=0.05)
    model = make_model(SINGULAR.format(name=f"sing_{form[:3]}"), ok, qdd_form=form)
    x = np.array([0.3, -0.7, 0.5, 1.5])
    zero = dict(m2=0.0, a2=0.0)
    with pytest.raises(ModelError) as err:
        model.c.qdd(x, None, zero)
    assert err.value.code == 1
    name = model.spec.name
    ffi, lib = model.c.ffi, model.c.lib
    out = ffi.new("double[]", [7.0, 7.0])
    code = getattr(lib, f"{name}_qdd")(ffi.new("double[]", list(x)), ffi.NULL, ffi.new(f"{name}_params *", zero), out)
    assert code == getattr(lib, f"{name.upper()}_SINGULAR") and list(out) == [7.0, 7.0]
    with pytest.raises(model.py.SingularMassMatrix):
        model.py.qdd(x, None, zero)
    assert np.allclose(model.c.qdd(x, None, ok), reference.qdd(model.ref, x), rtol=1e-12, atol=1e-12)


def test_articulated_op_count_in_header_is_the_codes(make_model):
    """The stated qdd op count of an articulated model is the count of its emitted code."""
    model = make_model(random_spec_text(np.random.default_rng(4), 3, name="opca"), qdd_form="articulated", latex=True)
    stated = stated_op_counts((model.folder / "opca.h").read_text())
    body = (model.folder / "opca.c").read_text().split("int opca_qdd(")[1].split("for (i = 0")[0]
    assert code_op_count(body, r"(acc|piv)\[\d+\]") == stated["qdd"]
    assert "articulated" in (model.folder / "opca.tex").read_text()
