"""The 64-link hanging cable (specs/cable64.toml, written by examples/cable.py): its small
oscillations from `steady` against the discrete chain's mass and stiffness matrices assembled here
in absolute angles, independently of the generator, and against Daniel Bernoulli's continuous
hanging chain as n grows."""
from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import eigh
from scipy.special import jn_zeros

from gyrochain import pipeline
from gyrochain.spec import load_spec, parse_spec
from conftest import ROOT, example_script


cable = example_script("cable")


def discrete_chain(n: int, L: float = 2.0, mass: float = 1.0, g: float = 9.81) -> np.ndarray:
    """The angular frequencies of n uniform rods hanging from a pivot, linearised in the absolute
    angles ψ_j of the rods from the vertical: rod k's centre is at horizontal distance
    Σ_j a_kj ψ_j with a_kj = l (j < k), l/2 (j = k), so T = ½ψ̇ᵀ M ψ̇ with
    M = Σ_k m a_k a_kᵀ + (m l²/12) 1, and U = ½ ψᵀ K ψ with K = diag(Σ_k m g a_kj) (the height of
    a centre drops by a_kj ψ_j² / 2 per rod above it)."""
    l, m = L / n, mass / n
    M = np.zeros((n, n))
    K = np.zeros((n, n))
    for k in range(n):
        a = np.array([l if j < k else (l / 2 if j == k else 0.0) for j in range(n)])
        M += m * np.outer(a, a)
        K += np.diag(m * g * a)
    M += m * l * l / 12 * np.eye(n)
    return np.sqrt(eigh(K, M, eigvals_only=True))


def test_the_spec_file_is_the_examples_text():
    assert (ROOT / "specs" / "cable64.toml").read_text() == cable.spec_text(64)


@pytest.fixture(scope="module")
def cable64():
    return pipeline.compiled(load_spec(ROOT / "specs" / "cable64.toml"))


def test_cable64_frequencies_are_the_discrete_chains(cable64):
    w = cable.frequencies(*cable64)
    want = discrete_chain(64)
    assert len(w) == 64
    assert np.max(np.abs(w - want) / want) < 1e-9, np.max(np.abs(w - want) / want)


def test_the_discrete_chain_is_checked_against_a_two_rod_closed_form():
    """The assembly above, n = 2, against the double pendulum of two rods (l, m each) in closed form:
    M = m l² [[4/3, 1/2], [1/2, 1/3]], K = m g l diag(3/2, 1/2) in absolute angles."""
    l, m, g = 1.0, 0.5, 9.81
    M = m * l * l * np.array([[4 / 3, 1 / 2], [1 / 2, 1 / 3]])
    K = m * g * l * np.diag([3 / 2, 1 / 2])
    assert np.allclose(discrete_chain(2, L=2 * l, mass=2 * m, g=g), np.sqrt(eigh(K, M, eigvals_only=True)), rtol=1e-14)


def test_the_cable_tends_to_bernoulli_s_hanging_chain(cable64):
    """The lowest three frequencies approach ωᵢ = (j₀,ᵢ/2)√(g/L) at second order in 1/n: the gap
    shrinks about fourfold per doubling of n (8 → 16) and sixteenfold from 16 to 64."""
    bern = jn_zeros(0, 3) / 2 * np.sqrt(9.81 / 2.0)
    gaps = {}
    for n in (8, 16):
        gaps[n] = cable.frequencies(*pipeline.compiled(parse_spec(cable.spec_text(n))))[:3] / bern - 1
    gaps[64] = cable.frequencies(*cable64)[:3] / bern - 1
    assert np.all(gaps[8] > 0) and np.all(gaps[64] > 0)  # the discrete chain is stiffer
    assert np.all(gaps[16] / gaps[8] < 0.33) and np.all(gaps[16] / gaps[8] > 0.2), gaps
    assert np.all(gaps[64] / gaps[16] < 0.075) and np.all(gaps[64] / gaps[16] > 0.05), gaps
    assert gaps[64][0] < 1e-5
