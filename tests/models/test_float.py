"""`generate --real float`: every example's C in single precision compiles warning-free under
-Wdouble-promotion -Wfloat-conversion (no arithmetic promoted to double) as C99 and C++; the
precision-dependent constants get float's values; the cffi model follows NAME_REAL; φ̈ and its
derivatives agree with the double model within the bounds docs/embedding.md states."""
from __future__ import annotations

import re
import shutil
import subprocess
import sys

import numpy as np
import pytest

from gyrochain import pipeline
from gyrochain.printers import real
from gyrochain.spec import load_spec
from conftest import ONE_ARM, QUICK_EXAMPLES, ROOT, tiered, SHORT_EXAMPLES, STRICT_COMPILERS, example_params, strict_compile

STRICT = ["-Wall", "-Wextra", "-Wpedantic", "-Wdouble-promotion", "-Wfloat-conversion", "-Werror"]
# the agreement of φ̈ and of ∂φ̈/∂(φ, φ̇) with the double model over 200 random states of each short
# example, relative to the largest entry (docs/embedding.md: the median and the 99th percentile
# over all examples; bench/float_accuracy.py prints them per example)
MEDIAN, P99 = 1e-6, 1e-4


def _float_files(name: str) -> dict:
    spec = load_spec(ROOT / "specs" / f"{name}.toml")
    files, _ = pipeline.derive_and_render(spec, f"{name}.toml", targets=("c",), real="float")
    return files


@pytest.mark.parametrize("name", tiered(ONE_ARM, QUICK_EXAMPLES))
def test_float_c_compiles_without_promotion(name, tmp_path):
    files = _float_files(name)
    for fname in (f"{name}.c", f"{name}.h"):
        (tmp_path / fname).write_text(files[fname])
    src = files[f"{name}.c"]
    assert not re.search(r"\bdouble\b", re.sub(r"/\*.*?\*/", "", src, flags=re.S))  # none left outside comments
    assert f"#define {name.upper()}_REAL float" in files[f"{name}.h"]
    for cc, flags in STRICT_COMPILERS:
        if shutil.which(cc):
            res = strict_compile(cc, flags, STRICT, tmp_path / f"{name}.c", tmp_path / "m.o")
            assert res.returncode == 0 and not res.stderr, (cc, res.stderr)


def test_the_precision_constants_take_floats_values():
    files = _float_files("gimbal")
    c, h = files["gimbal.c"], files["gimbal.h"]
    assert "1.1920929e-07f" in c and "2.220446049250313e-16" not in c  # the unit round-off
    assert "1e-300" not in c and "1e-30f" in c
    assert "#define GIMBAL_GAUSS_FLOOR 1e-05f" in c and "#define GIMBAL_QUAD_TOL 1e-05f" in c
    assert "#define GIMBAL_SEPARATRIX_TOL 1e-06f" in h
    # a kernel edit that moves one of them out of the printer's sight is an error, not a silent double
    double = pipeline.derive_and_render(load_spec(ROOT / "specs" / "gimbal.toml"), "gimbal.toml", targets=("c",))[0]
    broken = dict(double, **{"gimbal.c": double["gimbal.c"].replace("#define GIMBAL_GAUSS_FLOOR 1e-12", "#define GIMBAL_GAUSS_FLOOR 1e-13")})
    with pytest.raises(ValueError, match="GAUSS2's round-off floor"):
        real.single_precision(broken, "gimbal")


def test_the_double_c_is_what_it_was():
    """--real double prints the committed files (test_fresh checks them all); retyping leaves the
    comments and strings alone."""
    spec = load_spec(ROOT / "specs" / "furuta.toml")
    files, _ = pipeline.derive_and_render(spec, "furuta.toml", targets=("c",), real="double")
    assert files["furuta.c"] == (ROOT / "generated" / "furuta" / "furuta.c").read_text()
    assert real.retype('/* 0.5 double */ double x = 0.5 * sin(y); /* 1e-8 */') == \
        "/* 0.5 double */ float x = 0.5f * sinf(y); /* 1e-8 */"
    assert real.retype("x2 = a1e2 + 3 + 2.5e-3 + 1e5 + HUGE_VAL;") == "x2 = a1e2 + 3 + 2.5e-3f + 1e5f + HUGE_VALF;"


@pytest.fixture(scope="module")
def pairs():
    """(double model, float model, parameters) of each short example, the float one built once."""
    out = {}
    for name in [e for e in SHORT_EXAMPLES if e in ONE_ARM]:
        files = _float_files(name)
        out[name] = (pipeline.compiled(load_spec(ROOT / "specs" / f"{name}.toml"))[0],
                     pipeline.compile(files, name), example_params(name))
    return out


def test_float_agrees_with_double(pairs):
    rng = np.random.default_rng(3)
    errs, jerrs = [], []
    for name, (d, f, params) in pairs.items():
        assert d.real == "double" and f.real == "float" and f.dtype == np.float32
        td = d.time_dependent
        for _ in range(200):
            x = np.concatenate([rng.uniform(-np.pi, np.pi, d.n), rng.normal(size=d.n)]).astype(np.float32)
            u = rng.normal(size=d.nu).astype(np.float32) if d.nu else None
            t = float(np.float32(rng.uniform(0, 2))) if td else 0.0
            try:
                q, dq, dv, _ = d.qdd_derivatives(x.astype(float), u, params, t=t)
            except ArithmeticError:
                continue
            qf, dqf, dvf, _ = f.qdd_derivatives(x, u, params, t=t)
            assert qf.dtype == np.float32
            errs.append(np.max(np.abs(qf - q)) / max(np.max(np.abs(q)), 1e-30))
            J, Jf = np.hstack([dq, dv]), np.hstack([dqf, dvf])
            jerrs.append(np.max(np.abs(Jf - J)) / max(np.max(np.abs(J)), 1e-30))
    for e in (np.array(errs), np.array(jerrs)):
        assert len(e) > 1000
        assert np.median(e) < MEDIAN and np.percentile(e, 99) < P99, (np.median(e), np.percentile(e, 99), e.max())


def test_float_integrators_run(pairs):
    """RK4 at 1 kHz over 1 s and DOP853 at rtol 1e-5 in float follow the double model (to 1e-4) on a
    swing of the hanging pendulum (an upright start falls, and the fall amplifies any difference:
    docs/embedding.md)."""
    d, f, _ = pairs["furuta"]
    t = np.linspace(0.0, 1.0, 11)
    x0, u = [0.0, 0.2, 0.0, 0.0], [0.01]
    for method, kw in (("rk4", dict(h=1e-3)), ("dop853", dict(rtol=1e-5, atol=1e-6))):
        Xf = f.integrate(t, x0, method, u=u, **kw)
        Xd = d.integrate(t, x0, method, u=u, **({"h": 1e-3} if method == "rk4" else dict(rtol=1e-10, atol=1e-10)))
        assert Xf.dtype == np.float32 and np.max(np.abs(Xf - Xd)) < 1e-4, (method, np.max(np.abs(Xf - Xd)))


def test_generate_real_float_writes_a_float_folder(tmp_path):
    res = subprocess.run([sys.executable, "-m", "gyrochain", "generate", "-q", "specs/gimbal.toml", "-o", str(tmp_path / "g"),
                          "--real", "float", "--no-build"], capture_output=True, text=True, cwd=ROOT)
    assert res.returncode == 0, res.stderr
    assert "#define GIMBAL_REAL float" in (tmp_path / "g" / "gimbal.h").read_text()
    assert '"real": "float"' in (tmp_path / "g" / "MANIFEST.json").read_text()
    res = subprocess.run([sys.executable, "-m", "gyrochain", "generate", "-q", "specs/gimbal.toml", "-o", str(tmp_path / "h"),
                          "--real", "single"], capture_output=True, text=True, cwd=ROOT)
    assert res.returncode == 2 and "--real" in res.stderr and len(res.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "h").exists()



def test_float_quadratures(pairs):
    """The two-body quadratures in float (their Kronrod tolerance 1e-5): the gimbal's period and
    state after 1 s within 1e-4 of the double model's, relative to the period and to the state's
    largest component (seen 2e-5 and 6e-5)."""
    d, f, _ = pairs["gimbal"]
    x0 = [0.0, 0.3, 2.0, 0.5]
    assert f.quad_period(x0) == pytest.approx(d.quad_period(x0), rel=1e-4)
    want = d.quad_state(1.0, x0)
    assert np.max(np.abs(f.quad_state(1.0, x0) - want)) < 1e-4 * np.max(np.abs(want))
