"""The compiled equations are the Lagrange equations of ℒ = Σ[T_k + λᵏ·ωᵏ] + U, checked
numerically for n = 3, 4 (tests/unit/test_lagrange_symbolic.py proves them for n = 2)."""
from __future__ import annotations

import numpy as np
import pytest

from gyrochain.randspec import random_spec_text
from gyrochain.spec import parse_spec
from lagrange import lagrange_terms_np


@pytest.mark.parametrize("n", [3, 4])
def test_numeric_chain_equals_lagrange(n, make_model):
    rng = np.random.default_rng(100 + n)
    spec = parse_spec(random_spec_text(rng, n, name=f"lag{n}", controls=(n,)))
    model = make_model(spec)
    for _ in range(6):
        x = rng.normal(size=2 * n) * 1.5
        u = rng.normal(size=1)
        Href, b = lagrange_terms_np(model.ref, x[:n], x[n:])
        fref = -b
        fref[n - 1] += u[0]
        for impl in (model.py, model.c):
            M = impl.mass_matrix(x[:n])
            f = impl.forces(x, u)
            assert np.max(np.abs(M - Href)) <= 1e-12 * np.max(np.abs(Href))
            assert np.max(np.abs(f - fref)) <= 1e-12 * np.max(np.abs(fref))


def test_negative_control_ocr_sign_of_alpha13_is_detected(make_model):
    """The literal OCR reading α₁₃ = +sin θ of (15) gives other equations; the check sees it."""
    rng = np.random.default_rng(103)
    n = 3
    model = make_model(parse_spec(random_spec_text(rng, n, name="lag3", controls=(n,))))
    x = rng.normal(size=2 * n)
    H_bad, b_bad = lagrange_terms_np(model.ref, x[:n], x[n:], sign13=+1.0)
    M = model.c.mass_matrix(x[:n])
    f = model.c.forces(x, [0.0])
    err = max(np.max(np.abs(M - H_bad)) / np.max(np.abs(M)), np.max(np.abs(f + b_bad)) / np.max(np.abs(f)))
    assert err > 1e-3
