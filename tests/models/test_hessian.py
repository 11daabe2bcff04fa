"""The exact second derivatives (generate --hessian): NAME_rhs_hessian, ∇²(λ·f) in z = (x, u), and
NAME_step_hessian, ∇²(λ·xn) of the RK4 step in w = (x, u, h).  Each against central differences
of the exact first derivatives (NAME_linearize, NAME_step_jacobian) at 100 random points for the
Furuta pendulum, numbers and symbols, and at fewer for the other examples and random chains of the
geometry users write (θ = 0, ±π/2, ±π, zeros, diagonal tensors, rotors, springs, armature); the
structure (symmetric; zero where φ̈ is affine in u or a coordinate is cyclic); the API's edges;
and a planted error in one second derivative fails the check."""
from __future__ import annotations

import re

import numpy as np
import pytest

from gyrochain import build
from gyrochain.build import ModelError
from gyrochain.chainspec import randspec
from gyrochain.spec import load_spec, parse_spec
from conftest import ROOT, example_params, fd_jacobian

TOL = 1e-7  # against differences of the exact Jacobian (O(h⁴) with one Richardson step: ~1e-10 here)


def _hessian_model(make_model, name):
    return make_model(load_spec(ROOT / "specs" / f"{name}.toml"), example_params(name), hessian=True)


def _point(rng, n, nu):
    return (np.concatenate([rng.uniform(-np.pi, np.pi, n), rng.normal(size=n)]), rng.normal(size=nu),
            rng.normal(size=2 * n))


def _rhs_error(c, x, u, lam, params, t=0.0):
    """|∇²(λ·f) − differences of ∇(λ·f) = [A B]ᵀλ| relative to the largest entry."""
    d, nu = len(x), len(u)
    H = c.rhs_hessian(x, lam, u if nu else None, params, t=t)[:d + nu, :d + nu]  # (t, last, is tests/models/test_time_derivatives.py's)

    def grad(z):
        A, B = c.linearize(z[:d], z[d:] if nu else None, params, t=t)
        return np.concatenate([A.T @ lam, B.T @ lam])
    D = fd_jacobian(grad, np.concatenate([x, u]), h=1e-4)
    assert np.array_equal(H, H.T)
    return np.max(np.abs(H - D)) / max(np.max(np.abs(D)), 1e-300)


def _step_error(c, x, u, lam, params, h=0.02):
    d, nu = len(x), len(u)
    H = c.step_hessian(x, h, lam, u if nu else None, params)[:d + nu + 1, :d + nu + 1]

    def grad(w):
        _, Ad, Bd, dh = c.step_jacobian(w[:d], w[-1], w[d:d + nu] if nu else None, params)
        return np.concatenate([Ad.T @ lam, Bd.T @ lam, [dh @ lam]])
    D = fd_jacobian(grad, np.concatenate([x, u, [h]]), h=1e-4)
    assert np.array_equal(H, H.T)
    return np.max(np.abs(H - D)) / max(np.max(np.abs(D)), 1e-300)


@pytest.mark.parametrize("name", ["furuta", "furuta_sym"])
def test_the_furuta_pendulum_s_hessians_equal_differences_at_100_points(make_model, rng, name):
    m = _hessian_model(make_model, name)
    worst = [0.0, 0.0]
    for _ in range(100):
        x, u, lam = _point(rng, 2, 1)
        worst[0] = max(worst[0], _rhs_error(m.c, x, u, lam, m.params))
        worst[1] = max(worst[1], _step_error(m.c, x, u, lam, m.params, h=10.0 ** rng.uniform(-3, -1)))
    print(f"\n{name}: rhs_hessian {worst[0]:.1e}, step_hessian {worst[1]:.1e} against differences")
    assert max(worst) <= TOL, worst


@pytest.mark.parametrize("name", ["double_pendulum", "spatial3", "gyrostat2", "ur5", "kapitza"])
def test_the_examples_hessians_equal_differences(make_model, rng, name):
    m = _hessian_model(make_model, name)
    n, nu = m.spec.n, m.c.nu
    for _ in range(5):
        x, u, lam = _point(rng, n, nu)
        t = float(rng.uniform(0.0, 1.0))
        assert _rhs_error(m.c, x, u, lam, m.params, t=t) <= TOL
        assert _step_error(m.c, x, u, lam, m.params, h=1e-3 if m.c.time_dependent else 0.02) <= TOL


@pytest.mark.parametrize("seed", range(4))
def test_random_chains_of_the_geometry_users_write(make_model, seed):
    rng = np.random.default_rng(1000 + seed)
    spec = parse_spec(randspec.geometry_spec_text(randspec.random_plan(rng, int(rng.integers(2, 5))), f"hgeom{seed}"))
    m = make_model(spec, hessian=True)
    n, nu = spec.n, m.c.nu
    checked = 0
    for _ in range(6):
        x, u, lam = _point(rng, n, nu)
        try:
            err = max(_rhs_error(m.c, x, u, lam, None), _step_error(m.c, x, u, lam, None, h=0.005))
        except ModelError:  # a singular configuration of a chain with massless links
            continue
        assert err <= TOL, (spec.source, err)
        checked += 1
    assert checked >= 3


def test_the_structure_of_the_furuta_pendulum_s_hessian(make_model, rng):
    """φ̈ is affine in u: ∂²/∂u² is zero; the arm's angle φ¹ is cyclic: its row and column are zero."""
    m = _hessian_model(make_model, "furuta")
    x, u, lam = _point(rng, 2, 1)
    H = m.c.rhs_hessian(x, lam, u)
    assert H[4, 4] == 0.0 and not H[0].any() and not H[:, 0].any()
    assert np.count_nonzero(H) > 6
    # only λ's second half weighs: f's first half (φ̇) is linear
    assert np.array_equal(H, m.c.rhs_hessian(x, np.concatenate([np.zeros(2), lam[2:]]), u))
    # a model generated without --hessian has none
    header = (ROOT / "generated" / "furuta" / "furuta.h").read_text()
    assert "#define FURUTA_HAS_HESSIAN 0" in header and "furuta_rhs_hessian" not in header
    assert "#define FURUTA_HAS_HESSIAN 1" in (m.folder / "furuta.h").read_text()


def test_the_api_edges(make_model, rng):
    m = _hessian_model(make_model, "furuta_sym")
    c, ffi = m.c, m.c.ffi
    x, u, lam = _point(rng, 2, 1)
    arr = lambda v: ffi.cast("double *", ffi.from_buffer(np.ascontiguousarray(v, dtype=float)))  # noqa: E731
    H = np.zeros(25)
    p = c._p(m.params)
    assert c.lib.furuta_sym_rhs_hessian(0.0, arr(x), arr(u), p, ffi.NULL, arr(H)) == c.lib.FURUTA_SYM_BAD_ARGUMENT
    assert c.lib.furuta_sym_rhs_hessian(0.0, arr(x), arr(u), p, arr([np.nan, 0, 0, 0]), arr(H)) == c.lib.FURUTA_SYM_NONFINITE
    assert c.lib.furuta_sym_rhs_hessian(0.0, arr(x), arr(u), ffi.NULL, arr(lam), arr(H)) == c.lib.FURUTA_SYM_NO_PARAMS
    assert c.lib.furuta_sym_rhs_hessian(0.0, ffi.NULL, arr(u), p, arr(lam), arr(H)) == c.lib.FURUTA_SYM_BAD_ARGUMENT
    Hs = np.zeros(36)
    assert c.lib.furuta_sym_step_hessian(0.0, arr(x), arr(u), p, float("nan"), arr(lam), arr(Hs)) == c.lib.FURUTA_SYM_BAD_ARGUMENT
    with pytest.raises(ModelError):
        c.step_hessian(np.array([np.inf, 0, 0, 0]), 0.01, lam, u, m.params)


def test_a_planted_error_in_one_second_derivative_fails(make_model, rng, tmp_path):
    m = _hessian_model(make_model, "furuta")
    src = (m.folder / "furuta.c").read_text()
    # one part in 10⁵ on ∂²φ̈/∂(φ²)², the first entry on the diagonal
    planted, count = re.subn(r"(\n    H\[\d+\] = )(hv\[\d+\]);", r"\1\2 * 1.00001;", src, count=1)
    assert count == 1
    folder = tmp_path / "planted"
    folder.mkdir()
    (folder / "furuta.c").write_text(planted)
    for ext in (".h", ".cdef"):
        (folder / f"furuta{ext}").write_text((m.folder / f"furuta{ext}").read_text())
    bad = build.CModel(build.compile_model(folder, "furuta"), "furuta")
    x, u, lam = _point(rng, 2, 1)
    assert _rhs_error(bad, x, u, lam, None) > TOL
    assert _step_error(bad, x, u, lam, None) > TOL


def test_the_docs_prototypes_are_the_header_s(make_model, tmp_path):
    """docs/c-api.md's declarations of the second derivatives agree with a header generate
    --hessian wrote (generated/ holds none: the docs' own run cannot check them)."""
    import subprocess

    m = _hessian_model(make_model, "furuta")
    page = (ROOT / "docs" / "c-api.md").read_text()
    block = next(b for b in re.findall(r"```c\n(.*?)```", page, re.S) if "NAME_rhs_hessian" in b)
    src = tmp_path / "decls.c"
    src.write_text('#include "furuta.h"\n' + block.replace("NAME_", "furuta_"))
    res = subprocess.run(["cc", "-std=c99", "-Wall", "-Wextra", "-Werror", "-Wredundant-decls", "-Wno-error=redundant-decls",
                          "-fsyntax-only", "-I", str(m.folder), str(src)], capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    assert res.stderr.count("redundant redeclaration") == 2, res.stderr  # both are the header's, word for word


def test_generate_says_which_second_derivatives_it_wrote(tmp_path):
    """The report names the functions, or says why there are none: a model that reads t has them in
    (x, u, t); a 64-link chain's would be millions of operations and is not derived at all."""
    from conftest import cli_in_process

    res = cli_in_process("generate", "specs/kapitza.toml", "--hessian", "-q", "--no-build", "-o", str(tmp_path / "k"))
    assert res.returncode == 0, res.stdout
    assert re.search(r"second derivatives: kapitza_rhs_hessian \(\d+ ops\) and kapitza_step_hessian, in \(x, u, t\): the model "
                     r"reads t", res.stdout), res.stdout
    res = cli_in_process("generate", "specs/cable64.toml", "--hessian", "-q", "--no-build", "-o", str(tmp_path / "c"))
    assert res.returncode == 0, res.stdout
    assert re.search(r"second derivatives: not emitted \(about [\d,]+ operations at n = 64, past 150,000\)", res.stdout), res.stdout
    assert "#define CABLE64_HAS_HESSIAN 0" in (tmp_path / "c" / "cable64.h").read_text()
