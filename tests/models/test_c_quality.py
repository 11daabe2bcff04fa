"""The generated C is code other people ship: strict C99 and C++ compiles, sanitizers, error
codes instead of silent NaN, and a plain-cc embedding example."""
from __future__ import annotations

import math
import re
import shutil
import subprocess

import numpy as np
import pytest

from gyrochain import reference
from gyrochain.build import ModelError
from gyrochain.spec import load_spec
from conftest import (EXAMPLES, ONE_ARM, QUICK_EXAMPLES, tiered, ROOT, SHORT_EXAMPLES, STRICT_COMPILERS, example_params, printer_setting,
                      strict_compile)

GEN = ROOT / "generated"
STRICT = ["-Wall", "-Wextra", "-Wpedantic", "-Werror"]
COMPILERS = STRICT_COMPILERS


def _run(cmd, **kw):
    return subprocess.run(cmd, capture_output=True, text=True, **kw)


@pytest.fixture(scope="module")
def objects(tmp_path_factory):
    """gcc's -O2 objects of the examples, kept for test_only_libm_and_no_globals (compiled once)."""
    return tmp_path_factory.mktemp("objects")


@pytest.mark.parametrize("cc,flags", COMPILERS, ids=[c for c, _ in COMPILERS])
@pytest.mark.parametrize("name", tiered(EXAMPLES, QUICK_EXAMPLES))
def test_compiles_warning_free(name, cc, flags, objects, tmp_path):
    if not shutil.which(cc):
        pytest.skip(f"{cc} is not installed")
    obj = objects / f"{name}.o" if cc == "gcc" else tmp_path / "m.o"
    res = strict_compile(cc, flags, STRICT, GEN / name / f"{name}.c", obj)
    assert res.returncode == 0 and not res.stderr, res.stderr


@pytest.mark.parametrize("name", tiered(EXAMPLES, QUICK_EXAMPLES))
def test_only_libm_and_no_globals(objects, name):
    """Each example's C includes its header and math.h only, allocates nothing, keeps no mutable
    static and calls libm only (its -O2 object's symbols)."""
    src = (GEN / name / f"{name}.c").read_text()
    # math.h, and float.h (a freestanding header, no library: FLT_EVAL_METHOD) where RK4 has lanes
    assert set(re.findall(r"#include\s*[<\"]([^>\"]+)", src)) - {"float.h"} == {f"{name}.h", "math.h"}
    assert ("float.h" in src) == (f"{name}_rk4_lanes_(" in src)
    assert "malloc" not in src
    # no mutable static variables (function-local static const tables are read-only data)
    assert not re.search(r"^\s*static\s+(?!const\b)[\w ]+\b\w+\s*(\[[^\]]*\])?\s*(=|;)", src, re.M)
    obj = objects / f"{name}.o"
    if not obj.exists():  # the strict compile did not run (a -k selection)
        assert _run(["gcc", "-std=c99", "-O2", "-c", str(GEN / name / f"{name}.c"), "-o", str(obj)]).returncode == 0
    syms = _run(["nm", str(obj)]).stdout
    data = [ln for ln in syms.splitlines() if re.search(r"\s[BbDdCc]\s", ln)]
    assert not data, f"{name} has data symbols: {data}"
    undefined = {ln.split()[-1] for ln in syms.splitlines() if " U " in ln}
    assert undefined <= {"sin", "cos", "sincos", "sqrt", "fabs", "pow", "asin", "floor", "sinh", "cosh", "asinh", "ceil", "fmin", "fmax", "log"}, undefined  # libm only


DRIVER = r"""
#include <math.h>
#include <stdio.h>
#include "{name}.h"

static double rnd(unsigned long *s) {{ *s = *s * 6364136223846793005UL + 1442695040888963407UL; return (double)(*s >> 11) / 9007199254740992.0 * 2.0 - 1.0; }}

int main(void)
{{
    double x[2 * {NAME}_N], xdot[2 * {NAME}_N], qdd[{NAME}_N], M[{NAME}_N * {NAME}_N], f[{NAME}_N];
    double u[{NAME}_NU + 1];
    {name}_params params = {{ {init} }};
    const {name}_params *p = {NAME}_NPARAMS ? &params : NULL;
    unsigned long seed = 12345UL;
    int i, k, bad = 0;
    for (k = 0; k < 200; ++k) {{
        for (i = 0; i < 2 * {NAME}_N; ++i) x[i] = 3.0 * rnd(&seed);
        for (i = 0; i <= {NAME}_NU; ++i) u[i] = rnd(&seed);
        bad |= {name}_mass_matrix(x, p, M);
        bad |= {name}_forces({T}x, u, p, f);
        bad |= {name}_forces({T}x, NULL, p, f);
        bad |= {name}_qdd({T}x, u, p, qdd);
        bad |= {name}_rhs(0.0, x, NULL, p, xdot);
        {{
            /* the derivatives: all blocks, then only some (NULL blocks are not written) */
            double dq[{NAME}_N * {NAME}_N], dv[{NAME}_N * {NAME}_N], du[{NAME}_N * {NAME}_NU + 1];
            double A[4 * {NAME}_N * {NAME}_N], B[2 * {NAME}_N * {NAME}_NU + 1];
            bad |= {name}_qdd_derivatives({T}x, u, p, qdd, dq, dv, du);
            bad |= {name}_qdd_derivatives({T}x, NULL, p, NULL, dq, NULL, NULL);
            bad |= {name}_qdd_derivatives({T}x, u, p, NULL, NULL, NULL, du);
            bad |= {name}_linearize(0.7, x, u, p, A, B);
            bad |= {name}_linearize(0.7, x, NULL, p, A, NULL);
        }}
        if (!isfinite({name}_energy({T}x, p))) bad |= 8;
{momentum}
{quad}
        if (k % 20 == 0) {{
            /* every integrator, a short run from a random state: any documented code is allowed */
            double x1[2 * {NAME}_N], tt[3] = {{0.0, 0.02, 0.05}}, X[3 * 2 * {NAME}_N];
            long nrhs;
            int m, rc;
            {name}_integrate_stats st;
            for (m = {NAME}_RK4; m <= {NAME}_GAUSS2_SYMPLECTIC; ++m) {{
                rc = {name}_integrate(m, 0.0, 0.05, 0.01, 1e-8, 1e-8, x, u, p, x1, &nrhs);
                rc |= {name}_integrate_grid(m, 3, tt, 0.0125, 1e-6, 1e-6, 1000, x, NULL, p, X, &st);
                if (rc < 0 || rc > 15) bad |= 128;
            }}
            {{
                /* the batch: two trajectories (the second from a NaN state), one u for both */
                double X0[2 * 2 * {NAME}_N], XB[2 * 3 * 2 * {NAME}_N];
                int codes[2], i;
                for (i = 0; i < 2 * {NAME}_N; ++i) {{
                    X0[i] = x[i];
                    X0[2 * {NAME}_N + i] = i == 0 ? NAN : x[i];
                }}
                rc = {name}_integrate_batch({NAME}_DOP853, 2, 3, tt, 0.0, 1e-6, 1e-6, 1000, X0, u, 0, p, 0, XB, codes);
                if (rc != (codes[0] != 0) + (codes[1] != 0) || codes[1] != {NAME}_NONFINITE) bad |= 256;
                if ({name}_integrate_batch({NAME}_RK4, -1, 3, tt, 0.01, 0.0, 0.0, 0, X0, u, 0, p, 0, XB, codes) != -{NAME}_BAD_ARGUMENT) bad |= 256;
            }}
        }}
    }}
    x[0] = NAN;
    if ({name}_qdd({T}x, u, p, qdd) != {NAME}_NONFINITE) bad |= 16;
    {{
        double A[4 * {NAME}_N * {NAME}_N];
        if ({name}_linearize(0.0, x, u, p, A, NULL) != {NAME}_NONFINITE) bad |= 16;
    }}
    printf("%d\n", bad);
    return bad;
}}
"""


# a 64-link cable took 150 s under the sanitizers; the loop form and the functions in parts are
# checked on the loop_models and cut_models below
@pytest.mark.extended  # (the sanitizers: make test-all, with the static analysers)
@pytest.mark.parametrize("name", [e for e in SHORT_EXAMPLES if e in ONE_ARM])
def test_sanitizers_clean(name, tmp_path):
    _sanitized_driver(GEN / name, load_spec(ROOT / "specs" / f"{name}.toml"), example_params(name), tmp_path)


@pytest.fixture(scope="module")
def world_model(make_model):
    """spatial3 with NAME_qdd_derivatives in the world form (gyrochain/derive/world.py), which the examples
    do not choose: its loops, LDLᵀ and block handling go through the same checks."""
    text = (ROOT / "specs" / "spatial3.toml").read_text().replace('name = "spatial3"', 'name = "spatial3w"')
    return make_model(text, der_form="world")


@pytest.fixture(scope="module")
def world_inverse_model(make_model):
    """spatial3 with the world form's products with M⁻¹ by M⁻¹ formed (long chains choose it)."""
    text = (ROOT / "specs" / "spatial3.toml").read_text().replace('name = "spatial3"', 'name = "spatial3i"')
    return make_model(text, der_form="world-inverse")


@pytest.fixture(scope="module")
def loop_models(make_model):
    """The loop form of long chains (gyrochain/derive/loopform.py) forced on spatial3 (fixed base: Hamilton's
    variables too) and on ship_gimbal (a moving platform: no canonical functions), with the world
    form of the derivatives where it applies: the loops' helpers go through the same checks."""
    text = (ROOT / "specs" / "spatial3.toml").read_text().replace('name = "spatial3"', 'name = "spatial3l"')
    ship = (ROOT / "specs" / "ship_gimbal.toml").read_text().replace('name = "ship_gimbal"', 'name = "ship_gimball"')
    return [make_model(text, der_form="world", loops="loops"),
            make_model(ship, example_params("ship_gimbal"), loops="loops")]


@pytest.mark.parametrize("cc,flags", COMPILERS, ids=[c for c, _ in COMPILERS])
@pytest.mark.parametrize("form", ["world", "world-inverse", "loops", "loops, moving base"])
def test_world_and_loop_forms_compile_warning_free(world_model, world_inverse_model, loop_models, form, cc, flags, tmp_path):
    if not shutil.which(cc):
        pytest.skip(f"{cc} is not installed")
    model = {"world": world_model, "world-inverse": world_inverse_model, "loops": loop_models[0],
             "loops, moving base": loop_models[1]}[form]
    src = model.folder / f"{model.spec.name}.c"
    assert {"world": "ldlt_columns_", "world-inverse": "world_products_"}.get(form, "ldlt_checked_") in src.read_text()
    res = strict_compile(cc, flags, STRICT, src, tmp_path / "m.o")
    assert res.returncode == 0 and not res.stderr, res.stderr


@pytest.mark.extended  # (the sanitizers: make test-all, with the static analysers)
@pytest.mark.parametrize("form", ["world", "world-inverse", "loops", "loops, moving base"])
def test_world_and_loop_forms_sanitizers_clean(world_model, world_inverse_model, loop_models, form, tmp_path):
    model = {"world": world_model, "world-inverse": world_inverse_model, "loops": loop_models[0],
             "loops, moving base": loop_models[1]}[form]
    _sanitized_driver(model.folder, model.spec, model.params, tmp_path)


def _sanitized_driver(folder, spec, params, tmp_path):
    """DRIVER on the model in ``folder`` under ASan and UBSan: exit 0, nothing printed."""
    name = spec.name
    init = ", ".join(repr(params[str(p)]) for p in spec.params) if params else "0"
    header = (folder / f"{name}.h").read_text()
    T = "0.7, " if f"{name.upper()}_TIME_DEPENDENT 1" in header else ""
    mom = f"        if (!isfinite({name}_momentum({T}x, p))) bad |= 32;" if f"{name}_momentum(" in header else ""
    if f"{name}_jacobi(" in header:
        mom += f"\n        if (!isfinite({name}_jacobi(x, p))) bad |= 32;"
    if f"{name}_momenta(" in header:
        # Hamilton's variables: any documented code is allowed (a random state may be singular)
        mom += (f"\n        {{ double pm[{name.upper()}_N], qd[{name.upper()}_N], pd[{name.upper()}_N];\n"
                f"          int rc = {name}_momenta(x, p, pm) | {name}_velocities(x, pm, p, qd) | {name}_pdot(x, u, p, pd);\n"
                f"          if (rc < 0 || rc > 3) bad |= 256; }}")
    if f"{name.upper()}_HAS_VARIATIONAL 1" in header:
        # the state with its fundamental matrix: any documented code is allowed
        mom += (f"\n        if (k % 20 == 0) {{ double x1[2 * {name.upper()}_N], Phi[4 * {name.upper()}_N * {name.upper()}_N];\n"
                f"          int rc;\n"
                f"          for (i = 0; i < 4 * {name.upper()}_N * {name.upper()}_N; ++i) Phi[i] = (i % (2 * {name.upper()}_N + 1)) == 0;\n"
                f"          rc = {name}_integrate_variational(0.0, 0.05, 0.0, 1e-6, 1e-6, x, u, p, x1, Phi, NULL);\n"
                f"          rc |= {name}_integrate_variational(0.0, 0.05, 0.0, 1e-6, 1e-6, x, NULL, p, x1, NULL, NULL);\n"
                f"          if (rc < 0 || rc > 15) bad |= 512; }}")
    quad = ""
    if "_quad_state" in (folder / f"{name}.h").read_text():
        # every quadrature entry point on random states: any documented code is allowed, the
        # sanitizers watch the memory and the arithmetic
        quad = (f"        {{ double y[4], T, fo[6]; {name}_quad_info qi; int rc = {name}_quad_motion(x, p, &qi);\n"
                f"          rc |= {name}_quad_period(x, p, &T) | {name}_quad_state(3.7 * rnd(&seed), x, p, y)\n"
                f"             | {name}_quad_functions(x[1], x, p, fo);\n"
                f"          if (rc < 0 || rc > 7) bad |= 64; }}")
    (tmp_path / "driver.c").write_text(DRIVER.format(name=name, NAME=name.upper(), init=init, momentum=mom, quad=quad, T=T))
    exe = tmp_path / "driver"
    res = _run(["gcc", "-std=c99", "-g1", "-O1", "-fsanitize=address,undefined", "-fno-sanitize-recover=all",
                "-fno-omit-frame-pointer", *STRICT, "-I", str(folder), str(tmp_path / "driver.c"),
                str(folder / f"{name}.c"), "-lm", "-o", str(exe)])
    assert res.returncode == 0, res.stderr
    run = _run([str(exe)], env={"ASAN_OPTIONS": "detect_leaks=1", "UBSAN_OPTIONS": "print_stacktrace=1"})
    assert run.returncode == 0 and run.stdout.strip() == "0" and not run.stderr, (run.stdout, run.stderr)


@pytest.mark.extended  # (the sanitizers: make test-all, with the static analysers)
def test_both_loop_ldlt_forms_give_the_same_bits_under_the_sanitizers(tmp_path):
    """The loop form's LDLᵀ in velocities one sum per entry (short chains, and mass_matrix's pivot
    test always) or by columns (from loopform.LDLT_COLUMNS_MIN_N joints on): the
    same random 12-joint chain emitted in both (columns 4 to 11 take the four-k steps and the
    rest), compiled with ASan and UBSan, gives the same bits for M, its pivot
    verdict and φ̇ from the momenta at random states."""
    from gyrochain import loopform, pipeline
    from gyrochain.randspec import random_spec_text
    from gyrochain.spec import parse_spec

    spec = parse_spec(random_spec_text(np.random.default_rng(1212), 12, name="ldl12", planar=False, gyro=True, controls=()))
    outs = {}
    for label, threshold in (("entries", 10**6), ("columns", 12)):
        with printer_setting(loopform, "LDLT_COLUMNS_MIN_N", threshold):
            files, model = pipeline.derive_and_render(spec, targets=("c",), loops="loops")
        assert model.dyn.loops is not None
        src = files["ldl12.c"]
        assert ("L transposed above it" in src) == (label == "columns")
        d = tmp_path / label
        d.mkdir()
        for k in ("ldl12.c", "ldl12.h"):
            (d / k).write_text(files[k])
        (d / "main.c").write_text("""#include <stdio.h>
#include <stdlib.h>
#include "ldl12.h"
int main(void)
{
    double q[12], pm[12], qd[12], M[144];
    int s, i, c1, c2;
    srand(7);
    for (s = 0; s < 40; ++s) {
        for (i = 0; i < 12; ++i) {
            q[i] = 6.0 * rand() / RAND_MAX - 3.0;
            pm[i] = 2.0 * rand() / RAND_MAX - 1.0;
        }
        c1 = ldl12_mass_matrix(q, 0, M);
        c2 = ldl12_velocities(q, pm, 0, qd);
        printf("%d %d", c1, c2);
        for (i = 0; i < 144; ++i) printf(" %a", M[i]);
        for (i = 0; i < 12; ++i) printf(" %a", qd[i]);
        printf("\\n");
    }
    return 0;
}
""")
        exe = d / "main"
        res = _run(["gcc", "-std=c99", "-O0", "-fsanitize=address,undefined", "-fno-sanitize-recover=all",
                    "-fno-omit-frame-pointer", *STRICT, "-I", str(d), str(d / "main.c"), str(d / "ldl12.c"), "-lm", "-o", str(exe)])
        assert res.returncode == 0, res.stderr
        run = _run([str(exe)], env={"ASAN_OPTIONS": "detect_leaks=1", "UBSAN_OPTIONS": "print_stacktrace=1"})
        assert run.returncode == 0 and not run.stderr, run.stderr
        outs[label] = run.stdout
    assert outs["entries"].count("\n") == 40 and outs["entries"] == outs["columns"]


def test_error_codes_instead_of_nan(example):
    m = example("furuta_sym")
    x = np.array([0.1, 0.2, 0.3, 0.4])
    # p NULL with symbolic parameters
    with pytest.raises(ModelError) as err:
        m.c.qdd(x)
    assert err.value.code == 3
    assert math.isnan(m.c.energy(x))
    # all-zero parameters: M = 0 is not positive definite
    zero = {k: 0.0 for k in m.params}
    for call in (lambda: m.c.qdd(x, None, zero), lambda: m.c.mass_matrix(x[:2], zero)):
        with pytest.raises(ModelError) as err:
            call()
        assert err.value.code == 1
    with pytest.raises(m.py.SingularMassMatrix):
        m.py.qdd(x, None, zero)
    # a NaN in the state
    bad = x.copy()
    bad[1] = np.nan
    with pytest.raises(ModelError) as err:
        m.c.qdd(bad, None, m.params)
    assert err.value.code == 2
    with pytest.raises(m.py.NonFiniteResult):
        m.py.qdd(bad, None, m.params)
    # and the good call works, C and Python alike
    assert np.allclose(m.c.qdd(x, [0.1], m.params), m.py.qdd(x, [0.1], m.params), rtol=1e-13)


def test_symbolic_example_matches_reference(example, rng):
    m = example("furuta_sym")
    num = example("furuta")  # the same pendulum with numbers folded in
    for _ in range(5):
        x = rng.normal(size=4)
        u = rng.normal(size=1)
        ref = reference.qdd(m.ref, x, u)
        assert np.allclose(m.c.qdd(x, u, m.params), ref, rtol=1e-10, atol=1e-12)
        assert np.allclose(m.py.qdd(x, u, m.params), ref, rtol=1e-10, atol=1e-12)
    assert num.spec.n == m.spec.n


def test_embedding_example_builds_with_plain_cc_and_runs(tmp_path):
    exe = tmp_path / "embed"
    res = _run(["cc", "-std=c99", "-O2", *STRICT, "-I", str(GEN / "gimbal"), str(ROOT / "examples" / "embed_gimbal.c"),
                str(GEN / "gimbal" / "gimbal.c"), "-lm", "-o", str(exe)])
    assert res.returncode == 0, res.stderr
    out = _run([str(exe)])
    assert out.returncode == 0, out.stderr
    psi, phi = map(float, re.search(r"psi = (\S+)\s+phi = (\S+)", out.stdout).groups())
    e_drift, k_drift = map(float, re.search(r"energy drift (\S+)\s+momentum drift (\S+)", out.stdout).groups())
    ch = reference.numeric(load_spec(ROOT / "specs" / "gimbal.toml"))
    ref = reference.simulate(ch, [0.0, 0.5235987755982988, 1.0, 0.5], [0.0, 2.0])[-1]
    assert abs(psi - ref[0]) < 1e-8 and abs(phi - ref[1]) < 1e-8
    assert e_drift < 1e-9 and k_drift < 1e-9
    psi_a, phi_a = map(float, re.search(r"DOP853: psi = (\S+)\s+phi = (\S+)", out.stdout).groups())
    assert abs(psi_a - ref[0]) < 1e-8 and abs(phi_a - ref[1]) < 1e-8


@pytest.fixture(scope="module")
def cut_models(tmp_path_factory):
    """A 4-link gyrostat chain with a control torque in the loop form, with every long function
    cut into parts of 25 temporaries (printers/chunks.py; a real model is cut at 150 from 3 parts
    on), and the same spec whole."""
    from gyrochain import pipeline
    from gyrochain.printers import chunks
    from gyrochain.randspec import random_spec_text
    from gyrochain.spec import parse_spec

    spec = parse_spec(random_spec_text(np.random.default_rng(5), 4, name="cut4", controls=(2,)))
    whole_files, _ = pipeline.derive_and_render(spec, targets=("c",), loops="loops", der_form="world")
    with printer_setting(chunks, "PART_TEMPORARIES", 25):
        cut_files, _ = pipeline.derive_and_render(spec, targets=("c",), loops="loops", der_form="world")
    folder = tmp_path_factory.mktemp("cut") / "cut4"
    pipeline.write_tree(cut_files, folder, build_it=False, name="cut4")
    return spec, folder, pipeline.compile(whole_files, "cut4"), pipeline.compile(cut_files, "cut4"), cut_files


def test_parts_are_the_same_computation(cut_models, rng):
    """Cut into parts, every function gives the same doubles, bit for bit (the values cross the
    parts through memory, unrounded)."""
    spec, _folder, whole, cut, files = cut_models
    text = files["cut4.c"]
    assert text.count("_part") > 20 and "CUT4_PART_" in text  # it was cut, in many parts
    n = spec.n
    for _ in range(5):
        x = np.concatenate([rng.uniform(-np.pi, np.pi, n), rng.normal(size=n)])
        u = rng.normal(size=1)
        for fn, args in (("mass_matrix", (x[:n],)), ("qdd", (x, u)), ("energy", (x,)), ("momenta", (x,)),
                         ("velocities", (x[:n], x[n:])), ("pdot", (x, u)), ("forces", (x, u))):
            assert np.array_equal(getattr(whole, fn)(*args), getattr(cut, fn)(*args)), fn
        for a, b in zip(whole.qdd_derivatives(x, u), cut.qdd_derivatives(x, u)):
            assert np.array_equal(a, b)


def test_parts_of_the_other_forms_are_the_same_computation(rng):
    """The composite qdd (its parts write the function's own M and f) and the forward-mode
    derivatives (acc and piv), cut into parts of 25 temporaries: the same doubles, bit for bit."""
    from gyrochain import pipeline
    from gyrochain.printers import chunks
    from gyrochain.randspec import random_spec_text
    from gyrochain.spec import parse_spec

    spec = parse_spec(random_spec_text(np.random.default_rng(6), 3, name="cut3", controls=(1,)))
    forms = dict(targets=("c",), qdd_form="composite", der_form="forward")
    whole_files, _ = pipeline.derive_and_render(spec, **forms)
    with printer_setting(chunks, "PART_TEMPORARIES", 25):
        cut_files, _ = pipeline.derive_and_render(spec, **forms)
    assert cut_files["cut3.c"].count("cut3_qdd_part") > 6 and "cut3_qdd_derivatives_part" in cut_files["cut3.c"]
    whole, cut = pipeline.compile(whole_files, "cut3"), pipeline.compile(cut_files, "cut3")
    for _ in range(5):
        x = np.concatenate([rng.uniform(-np.pi, np.pi, 3), rng.normal(size=3)])
        u = rng.normal(size=1)
        assert np.array_equal(whole.qdd(x, u), cut.qdd(x, u))
        for a, b in zip(whole.qdd_derivatives(x, u), cut.qdd_derivatives(x, u)):
            assert np.array_equal(a, b)


@pytest.mark.parametrize("cc,flags", COMPILERS, ids=[c for c, _ in COMPILERS])
def test_parts_compile_warning_free(cut_models, cc, flags, tmp_path):
    if not shutil.which(cc):
        pytest.skip(f"{cc} is not installed")
    _spec, folder, *_ = cut_models
    res = strict_compile(cc, flags, STRICT, folder / "cut4.c", tmp_path / "m.o")
    assert res.returncode == 0 and not res.stderr, res.stderr


@pytest.mark.extended  # (the sanitizers: make test-all, with the static analysers)
def test_parts_sanitizers_clean(cut_models, tmp_path):
    spec, folder, *_ = cut_models
    _sanitized_driver(folder, spec, None, tmp_path)


@pytest.mark.parametrize("cc,flags", COMPILERS, ids=[c for c, _ in COMPILERS])
def test_a_uniformly_moving_platform_compiles_warning_free(make_model, cc, flags, tmp_path):
    """A platform moving at constant velocity: the energy reads t, the equations of motion do not
    (NAME_TIME_DEPENDENT 1 all the same): their unused t is no warning."""
    if not shutil.which(cc):
        pytest.skip(f"{cc} is not installed")
    text = (ROOT / "specs" / "kapitza.toml").read_text().replace('position = ["a*cos(w*t)", 0, 0]', 'position = ["a*w*t", 0, 0]')
    model = make_model(text.replace('name = "kapitza"', 'name = "drift"'), example_params("kapitza"))
    src = model.folder / "drift.c"
    assert "DRIFT_TIME_DEPENDENT 1" in (model.folder / "drift.h").read_text()
    res = strict_compile(cc, flags, STRICT, src, tmp_path / "m.o")
    assert res.returncode == 0 and not res.stderr, res.stderr
