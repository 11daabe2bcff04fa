"""Joint offsets (``offset``, the joint's zero as imported robots have it): the paper's φᵏ is the
spec's joint angle plus the offset, in the direction cosines only.  The generated C and Python
agree with the reference model and with an independent Lagrangian that both add the offset
themselves; the exact derivatives agree with differences; an offset of a quarter or half turn,
which sympy folds into sin and cos, gives the same numbers as the spec turned by hand."""
from __future__ import annotations

import numpy as np
import pytest

from gyrochain import reference
from gyrochain.randspec import random_spec_text
from gyrochain.spec import parse_spec
from conftest import check_derivatives
from lagrange import lagrange_terms_np

CASES = {"n3-tilt-u3": (3, None, (3,)), "n4-vert-u1": (4, 0.0, (1,))}


@pytest.fixture(params=list(CASES), scope="module")
def offset_model(request, make_model):
    n, theta1, controls = CASES[request.param]
    rng = np.random.default_rng(sum(map(ord, request.param)))
    text = random_spec_text(rng, n, name=f"off{n}", theta1=theta1, controls=controls, offsets=True)
    assert text.count("offset = ") == n
    return make_model(text), rng


def test_offsets_change_the_motion_and_match_the_reference(offset_model):
    model, rng = offset_model
    n = model.spec.n
    plain = reference.NumericChain(**{**model.ref.__dict__, "offset": np.zeros(n)})
    for _ in range(5):
        x = np.concatenate([rng.uniform(-np.pi, np.pi, n), rng.normal(size=n) * 2.0])
        u = rng.normal(size=len(model.spec.controls))
        ref = reference.qdd(model.ref, x, u)
        assert np.max(np.abs(ref - reference.qdd(plain, x, u))) > 1e-3 * np.max(np.abs(ref))  # the offset matters
        for impl in (model.c, model.py):
            assert np.max(np.abs(impl.qdd(x, u) - ref)) <= 1e-10 * np.max(np.abs(ref))


def test_offsets_match_the_lagrangian(offset_model):
    model, rng = offset_model
    n = model.spec.n
    for _ in range(4):
        x = rng.normal(size=2 * n) * 1.5
        H, b = lagrange_terms_np(model.ref, x[:n], x[n:])
        M = model.c.mass_matrix(x[:n])
        f = model.c.forces(x, np.zeros(len(model.spec.controls)))
        assert np.max(np.abs(M - H)) <= 1e-12 * np.max(np.abs(H))
        assert np.max(np.abs(f + b)) <= 1e-12 * np.max(np.abs(b))


def test_offsets_derivatives_match_differences(offset_model):
    model, rng = offset_model
    n = model.spec.n
    x = np.concatenate([rng.uniform(-np.pi, np.pi, n), rng.normal(size=n)])
    check_derivatives(model, x, rng.normal(size=len(model.spec.controls)))


GIMBAL_LIKE = """
name = "{name}"
g = 9.81
[[body]]
theta = "pi/2"
m = 1.0
c = [0.1, 0.2, 0.3]
I_c = [0.05, 0.04, 0.03, 0.001, 0.002, 0.003]
s = [0.0, 0.1, 0.4]
{offset}
[[body]]
theta = 0.7
m = 0.5
c = [0.0, 0.0, 0.3]
I_c = [0.02, 0.02, 0.01, 0, 0, 0]
"""


@pytest.mark.parametrize("turn", ["pi/2", "pi", "-pi/2"])
def test_an_exact_offset_folds_and_equals_the_shifted_angle(turn, make_model):
    """offset = pi/2 makes cos φ into −sin φ exactly; the model equals the plain one at φ¹ + δ."""
    shifted = make_model(GIMBAL_LIKE.format(name="exact_off", offset=f'offset = "{turn}"'))
    plain = make_model(GIMBAL_LIKE.format(name="plain_off", offset=""))
    delta = {"pi/2": np.pi / 2, "pi": np.pi, "-pi/2": -np.pi / 2}[turn]
    rng = np.random.default_rng(7)
    for _ in range(4):
        x = rng.normal(size=4)
        moved = x.copy()
        moved[0] += delta
        assert np.allclose(shifted.c.qdd(x), plain.c.qdd(moved), rtol=1e-13, atol=1e-13)
    assert not np.allclose(shifted.c.qdd(x), plain.c.qdd(x))  # (the offset is not ignored)


def test_an_offset_is_checked_like_an_angle():
    from gyrochain.spec import SpecError

    with pytest.raises(SpecError, match=r"body\[1\]\.offset"):
        parse_spec(GIMBAL_LIKE.format(name="bad", offset='offset = "phi2"'))
    with pytest.raises(SpecError, match=r"body\[1\]\.offset"):
        parse_spec(GIMBAL_LIKE.format(name="bad", offset='offset = [1, 2]'))


def test_the_latex_states_the_offsets_it_uses(make_model):
    """The body table is followed by δᵏ where some joint has one, and the direction cosines read
    cos(φᵏ + δᵏ) there and only there."""
    model = make_model(GIMBAL_LIKE.format(name="tex_off", offset="offset = 0.25"), latex=True)
    tex = (model.folder / "tex_off.tex").read_text()
    assert r"$\delta^{1} = 0.25$; the other joints have $\delta^k = 0$." in tex
    assert r"\cos\left(\varphi^{1} + \delta^{1}\right)" in tex and r"\delta^{2}" not in tex
    plain = make_model(GIMBAL_LIKE.format(name="tex_plain", offset=""), latex=True)
    assert "Joint offsets" not in (plain.folder / "tex_plain.tex").read_text()
    assert r"\delta^{" not in (plain.folder / "tex_plain.tex").read_text()
