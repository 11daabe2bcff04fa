"""NAME_qdd_derivatives and NAME_linearize: exact derivatives of the emitted φ̈ (forward mode over
the articulated recursion, or world.py's inverse dynamics in frame 0).  The random chains of
test_models.py and test_general.py check them against differences of the reference model; here:
every example, the API's NULL blocks and codes, the structure of A and B, a mutation check (a
perturbed derivative is caught), and the two forms against each other."""
from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from gyrochain import build
from gyrochain.build import ModelError
from conftest import FURUTA_SYM_PARAMS, ROOT, SHORT_EXAMPLES, check_derivatives, example_script, printer_setting, tiered


def _state(rng, n):
    return np.concatenate([rng.uniform(-np.pi, np.pi, n), rng.normal(size=n)])


# not the cable: its mass matrix has a condition number ~1e6 at random states, so the reference's
# round-off, differenced, is ~1e-7 (the emitted derivatives agree with differences of the emitted
# φ̈ to 5e-12 there); tests/physics/test_cable.py checks them at the hanging equilibrium
@pytest.mark.parametrize("name", SHORT_EXAMPLES)
def test_examples_derivatives(example, name, rng):
    m = example(name)
    nu = len(m.spec.controls)
    for _ in range(3):
        x = _state(rng, m.spec.n)
        check_derivatives(m, x, rng.normal(size=nu) if nu else None, t=rng.uniform(0.0, 1.0) if m.c.time_dependent else None)


def test_null_blocks_and_linearize(example, rng):
    m = example("furuta")  # a control torque: all three blocks exist
    c, ffi, n, nu = m.c, m.c.ffi, m.spec.n, m.c.nu
    x, u = _state(rng, n), rng.normal(size=nu)
    q, dq, dv, du = c.qdd_derivatives(x, u)
    assert np.allclose(q, c.qdd(x, u), rtol=1e-13, atol=1e-13)  # the articulated and the model's form agree
    # only the φ̇ block asked for: the others stay untouched
    out = np.full((n, n), 7.0)
    xp = ffi.cast("double *", ffi.from_buffer(np.ascontiguousarray(x)))
    up = ffi.cast("double *", ffi.from_buffer(np.ascontiguousarray(u)))
    assert c.lib.furuta_qdd_derivatives(xp, up, ffi.NULL, ffi.NULL, ffi.NULL, ffi.cast("double *", ffi.from_buffer(out)), ffi.NULL) == 0
    assert np.array_equal(out, dv)
    A, B = c.linearize(x, u)
    assert np.array_equal(A[:n, :n], np.zeros((n, n))) and np.array_equal(A[:n, n:], np.eye(n))
    assert np.array_equal(A[n:, :n], dq) and np.array_equal(A[n:, n:], dv)
    assert np.array_equal(B[:n], np.zeros((n, nu))) and np.array_equal(B[n:], du)
    Ap, Bp = m.py.linearize(0.0, x, u)
    assert np.allclose(Ap, A, rtol=1e-13, atol=1e-12) and np.allclose(Bp, B, rtol=1e-13, atol=1e-12)
    # B depends on the control only through M: the linearisation is exact in u
    dx = 1e-3 * rng.normal(size=nu)
    assert np.allclose(c.qdd(x, u + dx) - c.qdd(x, u), du @ dx, rtol=1e-9, atol=1e-14)


def test_time_dependent_linearize_reads_t(example):
    m = example("kapitza")
    x = np.array([np.pi - 0.1, 0.0])
    A0, _ = m.c.linearize(x, params=m.params, t=0.0)
    A1, _ = m.c.linearize(x, params=m.params, t=0.3 * 2 * np.pi / m.params["w"])
    assert not np.allclose(A0, A1)  # the pivot's acceleration enters ∂φ̈/∂φ
    assert np.allclose(A1, m.py.linearize(0.3 * 2 * np.pi / m.params["w"], x, None, m.params)[0], rtol=1e-13, atol=1e-12)


def test_codes(example):
    m = example("furuta_sym")
    x = np.array([0.1, 0.2, 0.3, 0.4])
    with pytest.raises(ModelError) as err:
        m.c.qdd_derivatives(x, None, {k: 0.0 for k in m.params})
    assert err.value.code == 1  # M = 0: SINGULAR, as NAME_qdd says
    with pytest.raises(ModelError) as err:
        m.c.linearize(np.array([np.nan, 0, 0, 0]), None, m.params)
    assert err.value.code == 2
    with pytest.raises(ModelError) as err:
        m.c.linearize(x)  # p NULL with symbolic parameters
    assert err.value.code == 3


def test_mutation_is_caught(example, tmp_path, rng):
    """A derivative perturbed in the emitted code by one part in 10⁶ fails the difference check:
    the check can fail (and would catch a wrong chain rule)."""
    m = example("spatial3")
    x = _state(rng, 3)
    u = rng.normal(size=len(m.spec.controls))
    check_derivatives(m, x, u)  # the original passes
    dq = m.py.qdd_derivatives(x, u)[1]
    i, j = np.unravel_index(np.argmax(np.abs(dq)), dq.shape)  # an entry that is not zero here
    lines = (m.folder / "spatial3.py").read_text().splitlines()
    target = next(k for k, ln in enumerate(lines) if ln.strip().startswith(f"dqdd_dphi[{i}, {j}] = "))
    lhs, rhs = lines[target].split(" = ", 1)
    lines[target] = f"{lhs} = (1.0 + 1e-6) * ({rhs})"
    (tmp_path / "spatial3.py").write_text("\n".join(lines) + "\n")
    mutated = build.load_python(tmp_path, "spatial3")
    with pytest.raises(AssertionError):
        check_derivatives(type(m)(m.spec, mutated, m.c, m.ref, m.params, tmp_path), x, u)


def test_furuta_lqr_example(example):
    """examples/furuta_lqr.py: the LQR gain from furuta_linearize catches the pendulum 0.2 rad off
    upright at a 1 kHz control rate; without it the pendulum falls."""
    lqr = example_script("furuta_lqr")
    m = example("furuta")
    K = lqr.gain(m.c)
    T, X, U = lqr.run(m.c, K, t1=4.0)
    assert abs(X[-1, 1] - np.pi) < 1e-4 and abs(X[-1, 0]) < 1e-3 and np.max(np.abs(X[:, 1] - np.pi)) < 0.25
    _, Xo, _ = lqr.run(m.c, None, t1=1.5)
    assert np.max(np.abs(Xo[:, 1] - np.pi)) > 1.0


# ------------------------------------------------------------------ the world form (gyrochain/derive/world.py)
# The same specs in both forms of NAME_qdd_derivatives: forward mode over the articulated recursion,
# and the inverse dynamics differentiated in frame 0 (M⁻¹(∂τ/∂x − ∂ID/∂x)).  Both are exact, so they
# agree to round-off; both against the reference's differences.
WORLD_CASES = [  # (n, planar, gyro, controls, springs/dampers/torque expression of t)
    (1, False, True, (1,), False),
    (2, True, False, (), True),
    (3, False, True, (2,), False),
    (4, False, True, (), True),
    (5, True, True, (5,), False),
    (7, False, True, (1, 7), True),
    (10, False, True, (3,), False),  # the solve's blocks of eight columns and the two left over
]


def _world_pair(make_model, n, planar, gyro, controls, springs, columns="world"):
    """The forward-mode and world-form models of one random spec (``columns``: "world", the
    products with M⁻¹ by op count, or "world-solve", "world-inverse"), and the spec's generator."""
    from gyrochain.randspec import random_general_spec_text, random_spec_text

    rng = np.random.default_rng(700 + 10 * n + len(controls))
    name = f"wf{n}{'p' if planar else 's'}{int(gyro)}{len(controls)}{int(springs)}"
    if springs:
        text = random_general_spec_text(rng, n, name=name, translate=False, rotate=False, loads=False, spin_up=False)
        blocks = text.split("[[body]]")  # control torques on the joints asked for
        text = blocks[0] + "".join("[[body]]" + ("\ncontrol = true" if k in controls else "") + b
                                   for k, b in enumerate(blocks[1:], start=1))
    else:
        text = random_spec_text(rng, n, name=name, planar=planar, gyro=gyro, controls=controls)
    fwd = make_model(text.replace(f'name = "{name}"', f'name = "{name}f"'), der_form="forward")
    suffix = {"world": "w", "world-solve": "s", "world-inverse": "i"}[columns]
    wld = make_model(text.replace(f'name = "{name}"', f'name = "{name}{suffix}"'), der_form=columns)
    return fwd, wld, rng


# make test: the planar chain without rotors, with springs and no control, and the spatial n = 10 with
# rotors and a control (the solve's blocks; its models serve the two bit tests below); make test-all: all
QUICK_WORLD = {(2, True), (10, False)}


@pytest.mark.parametrize("n, planar, gyro, controls, springs", tiered(WORLD_CASES, QUICK_WORLD, key=lambda c: c[:2], rows=True),
                         ids=[f"n{c[0]}-{'planar' if c[1] else 'spatial'}-{'gyro' if c[2] else 'nogyro'}-u{len(c[3])}"
                              + ("-springs" if c[4] else "") for c in WORLD_CASES])
def test_world_form_matches_forward_mode(make_model, n, planar, gyro, controls, springs):
    fwd, wld, rng = _world_pair(make_model, n, planar, gyro, controls, springs)
    assert "world.py" in (wld.folder / f"{wld.spec.name}.c").read_text()
    assert "world.py" not in (fwd.folder / f"{fwd.spec.name}.c").read_text()
    td = wld.c.time_dependent
    for _ in range(3):
        x = _state(rng, n)
        u = rng.normal(size=len(controls)) if controls else None
        t = rng.uniform(0.0, 2.0) if td else None
        check_derivatives(wld, x, u, t=t)
        tt = 0.0 if t is None else t
        a = np.hstack(fwd.c.qdd_derivatives(x, u, t=tt)[1:])
        scale = np.max(np.abs(a))
        for b in (np.hstack(wld.c.qdd_derivatives(x, u, t=tt)[1:]),
                  np.hstack(wld.py.qdd_derivatives(*((tt,) if td else ()), x, u)[1:])):
            assert np.max(np.abs(a - b)) <= 1e-12 * scale, np.max(np.abs(a - b)) / scale


INVERSE_CASES = [c for c in WORLD_CASES if c[0] in (1, 4, 7, 10)]


@pytest.mark.parametrize("n, planar, gyro, controls, springs",  # (make test: n = 1 and 4, springs; make test-all: 7, 10)
                         tiered(INVERSE_CASES, {1, 4}, key=lambda c: c[0], rows=True),
                         ids=[f"n{c[0]}-u{len(c[3])}" + ("-springs" if c[4] else "") for c in INVERSE_CASES])
def test_world_inverse_matches_forward_mode(make_model, n, planar, gyro, controls, springs):
    """The world form with M⁻¹ formed and its products by prefix sums (long chains choose it; forced
    here): against forward mode to round-off and the reference's differences; each block asked
    alone (the others NULL) is the full call's, bit for bit."""
    fwd, inv, rng = _world_pair(make_model, n, planar, gyro, controls, springs, columns="world-inverse")
    src = (inv.folder / f"{inv.spec.name}.c").read_text()
    assert "world_products_" in src and "ldlt_columns" not in src
    c, ffi, nu = inv.c, inv.c.ffi, len(controls)
    fn = getattr(c.lib, f"{inv.spec.name}_qdd_derivatives")
    td = inv.c.time_dependent
    for _ in range(3):
        x = _state(rng, n)
        u = rng.normal(size=nu) if controls else None
        t = rng.uniform(0.0, 2.0) if td else None
        check_derivatives(inv, x, u, t=t)
        tt = 0.0 if t is None else t
        full = inv.c.qdd_derivatives(x, u, t=tt)[1:]
        a = np.hstack(fwd.c.qdd_derivatives(x, u, t=tt)[1:])
        assert np.max(np.abs(a - np.hstack(full))) <= 1e-12 * np.max(np.abs(a))
    args = [ffi.cast("double *", ffi.from_buffer(np.ascontiguousarray(v))) for v in (x, u if controls else np.zeros(1))]
    for block, cols in enumerate((n, n, nu)):
        if not cols:
            continue
        outs = [ffi.NULL] * 3
        keep = np.full((n, cols), 7.0)
        outs[block] = ffi.cast("double *", ffi.from_buffer(keep))
        assert fn(*((tt,) if td else ()), *args, ffi.NULL, ffi.NULL, *outs) == 0
        assert np.array_equal(keep, full[block])


def test_world_columns_follow_the_op_counts():
    """The products with M⁻¹ by op count: LDLᵀ solves on short chains, M⁻¹ formed from n = 32 on
    (measured at -O3 -march=native: the same time at n = 16, 1.1-1.4x faster at 32, 1.7x at 64,
    2.3x at 128)."""
    from gyrochain.assemble import world_op_counts

    chosen = {n: min(c := world_op_counts(n, 2 * n, 0, 0), key=c.get) for n in (2, 4, 8, 16, 32, 64, 128)}
    assert chosen == {2: "solve", 4: "solve", 8: "solve", 16: "solve", 32: "inverse", 64: "inverse", 128: "inverse"}


def test_world_form_blocks_codes_and_mutation(make_model, tmp_path):
    """Blocks whose pointer is NULL are not touched and the others are the full call's; a factor
    of the pairs' formula perturbed by 1e-6 in the emitted Python fails the difference check."""
    fwd, wld, rng = _world_pair(make_model, 3, False, True, (2,), False)
    c, ffi, n = wld.c, wld.c.ffi, 3
    x, u = _state(rng, n), rng.normal(size=1)
    _, dq, dv, du = c.qdd_derivatives(x, u)
    out = np.full((n, n), 7.0)
    xp = ffi.cast("double *", ffi.from_buffer(np.ascontiguousarray(x)))
    up = ffi.cast("double *", ffi.from_buffer(np.ascontiguousarray(u)))
    fn = getattr(c.lib, f"{wld.spec.name}_qdd_derivatives")
    assert fn(xp, up, ffi.NULL, ffi.NULL, ffi.NULL, ffi.cast("double *", ffi.from_buffer(out)), ffi.NULL) == 0
    assert np.array_equal(out, dv)
    for block in (0, 2):
        outs = [ffi.NULL] * 3
        keep = np.full((n, n if block == 0 else 1), 7.0)
        outs[block] = ffi.cast("double *", ffi.from_buffer(keep))
        assert fn(xp, up, ffi.NULL, ffi.NULL, *outs) == 0
        assert np.array_equal(keep, dq if block == 0 else du)
    check_derivatives(wld, x, u)  # the original passes
    lines = (wld.folder / f"{wld.spec.name}.py").read_text().splitlines()
    target = next(k for k, ln in enumerate(lines) if "-2.0 * (z1_ @ w_.T)" in ln)
    lines[target] = lines[target].replace("-2.0 * (z1_ @ w_.T)", "-2.000002 * (z1_ @ w_.T)")
    (tmp_path / f"{wld.spec.name}.py").write_text("\n".join(lines) + "\n")
    mutated = build.load_python(tmp_path, wld.spec.name)
    with pytest.raises(AssertionError):
        check_derivatives(type(wld)(wld.spec, mutated, wld.c, wld.ref, wld.params, tmp_path), x, u)


def test_world_form_singular_and_not_applicable(make_model, tmp_path):
    text = (ROOT / "specs" / "furuta_sym.toml").read_text().replace('name = "furuta_sym"', 'name = "furuta_sym_w"')
    m = make_model(text, FURUTA_SYM_PARAMS, der_form="world")
    x = np.array([0.1, 0.2, 0.3, 0.4])
    with pytest.raises(ModelError) as err:
        m.c.qdd_derivatives(x, None, {k: 0.0 for k in m.params})
    assert err.value.code == 1
    check_derivatives(m, x, np.array([0.3]))
    # a spec the world form does not cover, in either product with M⁻¹: a one-line error naming the
    # option, nothing written
    for form in ("world", "world-inverse"):
        out = tmp_path / f"turn-{form}"
        res = subprocess.run([sys.executable, "-m", "gyrochain", "generate", str(ROOT / "specs" / "turntable.toml"), "-o", str(out),
                              "--derivative-form", form, "--no-build", "-q"], capture_output=True, text=True, cwd=ROOT)
        assert res.returncode != 0
        assert "--derivative-form" in res.stderr and "moving platform" in res.stderr
        assert "Traceback" not in res.stderr and len(res.stderr.strip().splitlines()) == 1
        assert not out.exists()


def _avx() -> bool:
    try:
        return " avx " in f" {Path('/proc/cpuinfo').read_text()} ".replace("\n", " ")
    except OSError:
        return False


def _printed_derivatives(folder, name: str, xs, exe, flags=("-O2",)) -> str:
    """Every output of NAME_qdd_derivatives of the n = 10 chain with one control (u = 0.25) at the
    states ``xs``, printed exactly (%a) by a C driver built with gcc ``flags`` as ``exe``."""
    main = exe.parent / f"{exe.name}_main.c"
    main.write_text(f'#include <stdio.h>\n#include "{name}.h"\nint main(void) {{\n'
                    f"    static const double xs[{len(xs)}][20] = {{{', '.join('{' + ', '.join(repr(float(v)) for v in x) + '}' for x in xs)}}};\n"
                    "    double u[1] = {0.25}, q[10], dq[100], dv[100], du[10];\n    int s, i;\n"
                    f"    for (s = 0; s < {len(xs)}; ++s) {{\n        printf(\"%d\", {name}_qdd_derivatives(xs[s], u, 0, q, dq, dv, du));\n"
                    "        for (i = 0; i < 100; ++i) printf(\" %a %a\", dq[i], dv[i]);\n"
                    "        for (i = 0; i < 10; ++i) printf(\" %a %a\", q[i], du[i]);\n        printf(\"\\n\");\n    }\n    return 0;\n}\n")
    subprocess.run(["gcc", "-std=c99", *flags, f"-I{folder}", str(main), str(folder / f"{name}.c"), "-lm", "-o", str(exe)],
                   check=True, capture_output=True)
    return subprocess.run([str(exe)], check=True, capture_output=True, text=True).stdout


@pytest.fixture(scope="module")
def n10_world(make_model, tmp_path_factory):
    """The n = 10 chain's world form as emitted (the factor row by row: FACTOR_COLUMNS_MIN_N is
    above 10), states (four random, and zero, where M is singular for the factor's verdict) and
    every output at them from a driver built at -O2: what the two bit tests below compare with."""
    from gyrochain import world

    if shutil.which("gcc") is None:
        pytest.skip("needs gcc")
    assert world.FACTOR_COLUMNS_MIN_N > 10
    _, wld, rng = _world_pair(make_model, 10, False, True, (3,), False)
    xs = [_state(rng, 10) for _ in range(4)] + [np.zeros(20)]
    exe = tmp_path_factory.mktemp("n10") / "plain"
    return wld, xs, _printed_derivatives(wld.folder, wld.spec.name, xs, exe)


@pytest.mark.skipif(not _avx(), reason="this CPU has no AVX to run the vector form of the column solve on")
def test_both_forms_of_the_column_solve_give_the_same_bits(n10_world, tmp_path):
    """The world form's column solve (short chains) in blocks of four rows by eight columns in
    vector registers with AVX (GNU C's vector types) and eight scalar sums without; each entry's
    products are added in the same order, so -O2 and -O2 -mavx give the same bits (n = 10: two
    blocks of four rows and two rows left over, a block of eight columns and two left over)."""
    wld, xs, plain = n10_world
    name = wld.spec.name
    assert "#if defined(__GNUC__) && defined(__AVX__)" in (wld.folder / f"{name}.c").read_text()
    avx = _printed_derivatives(wld.folder, name, xs, tmp_path / "avx", ("-O2", "-mavx"))
    assert plain.startswith("0") and plain == avx


def test_both_forms_of_the_factor_give_the_same_bits(n10_world, tmp_path):
    """The world form's LDLᵀ of M row by row (short chains) and column by column (from
    world.FACTOR_COLUMNS_MIN_N joints on: contiguous updates, four k at a time) sums each entry in
    the same order: the n = 10 chain emitted both ways gives the same bits (φ̈ and every block, the
    factor's verdict on a singular M too)."""
    from gyrochain import pipeline, world

    wld, xs, rows = n10_world
    name = wld.spec.name
    assert "four k at a time, each sum" not in (wld.folder / f"{name}.c").read_text()
    with printer_setting(world, "FACTOR_COLUMNS_MIN_N", 10):
        files, _ = pipeline.derive_and_render(wld.spec, targets=("c",), der_form="world")
    assert "four k at a time, each sum" in files[f"{name}.c"]
    for k in (f"{name}.c", f"{name}.h"):
        (tmp_path / k).write_text(files[k])
    columns = _printed_derivatives(tmp_path, name, xs, tmp_path / "main")
    assert rows.count("\n") == 5 and rows.startswith("0") and rows == columns
