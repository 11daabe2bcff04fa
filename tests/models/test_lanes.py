"""RK4's lanes (issue 50): NAME_integrate_batch advances LANES trajectories in lock-step with the
model's right side printed for lanes: RK4 with libm's sines and cosines, RK4_LANES with the lanes'
own (kernels/trig.c), whose single call is the one-lane instance.  A batch's trajectory is the
single call's bit for bit with either method, failures included; the lane right side is NAME_rhs's
bit for bit once both take the same sin and cos (the scalar statements, the composite form's LDLᵀ
included, are the same operations in the same order)."""
from __future__ import annotations

import shutil
import subprocess
import sys

import numpy as np
import pytest

from conftest import QUICK_EXAMPLES, ROOT, tiered
from gyrochain.build import IntegrationError
from gyrochain.printers import lanes

pytestmark = pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler (apt-get install gcc)")

# articulated, composite with controls and parameters, composite with three bodies, time-dependent
# (a parameter), time-dependent (a moving platform), six bodies with six controls
MODELS = ["double_pendulum", "furuta_sym", "spatial3", "kapitza", "ship_gimbal", "ur5"]


def _text(model) -> str:
    return (model.folder / f"{model.spec.name}.c").read_text()


def _states(rng, n: int, count: int) -> np.ndarray:
    X0 = np.hstack([rng.uniform(-3.0, 3.0, (count, n)), rng.normal(size=(count, n))])
    X0[3, 0] = np.nan          # fails at once
    X0[11, n] = 1e200          # fails in the first step where φ̈ reads φ̇² (it overflows)
    return X0


@pytest.mark.parametrize("method", ["rk4", "rk4_lanes"])
@pytest.mark.parametrize("name", MODELS)
def test_batch_is_the_single_calls_bit_for_bit(example, name, method, rng):
    m = example(name)
    assert f"{name}_rk4_lanes_(" in _text(m)
    n, nu = m.c.n, m.c.nu
    X0 = _states(rng, n, 2 * lanes.LANES + 3)  # two groups of lanes and three alone
    u = rng.normal(size=nu) if nu else None
    t = np.linspace(0.0, 0.3, 4)
    X, codes = m.c.integrate_batch(t, X0, method=method, h=0.01, u=u, params=m.params)
    assert codes[3] == 2 and (np.delete(codes, [3, 11]) == 0).all()
    for b in range(len(X0)):
        try:
            single = m.c.integrate(t, X0[b], method, h=0.01, u=u, params=m.params)
            code = 0
        except IntegrationError as e:  # the rows past the failure NaN
            single, code = e.X, e.code
        assert code == codes[b]
        if b != 3:  # (a state that is not finite fills no row)
            assert np.array_equal(X[b], single, equal_nan=True), b


@pytest.mark.parametrize("method", ["rk4", "rk4_lanes"])
def test_a_step_budget_ends_every_lane_as_it_ends_one(example, method, rng):
    m = example("double_pendulum")
    X0 = rng.uniform(-1.0, 1.0, (lanes.LANES + 1, 4))
    t = np.array([0.0, 0.05, 0.1])
    X, codes = m.c.integrate_batch(t, X0, method=method, h=0.01, max_steps=7)
    assert (codes == 9).all()  # TOO_MANY_STEPS
    assert np.array_equal(X[:, 1], m.c.integrate_batch(t[:2], X0, method=method, h=0.01)[0][:, 1])
    assert np.array_equal(X[0, 1], m.c.integrate(t[:2], X0[0], method, h=0.01)[1]) and np.isnan(X[:, 2]).all()


def test_the_two_methods_differ_only_in_the_last_places(example, rng):
    """RK4 and RK4_LANES are the same method: over 0.5 s of the double pendulum their states agree
    to round-off (their sines and cosines differ by at most 1 ulp)."""
    m = example("double_pendulum")
    X0 = np.hstack([rng.uniform(-3.0, 3.0, (20, 2)), np.zeros((20, 2))])
    a = m.c.integrate_batch([0.0, 0.5], X0, method="rk4", h=1e-3)[0]
    b = m.c.integrate_batch([0.0, 0.5], X0, method="rk4_lanes", h=1e-3)[0]
    assert np.max(np.abs(a - b)) < 1e-11


def test_own_controls_or_parameters_take_the_single_path(example):
    """Per-trajectory u or parameters cannot share lanes: each trajectory is the single call."""
    m = example("furuta_sym")
    P = [dict(m.params, m2=m.params["m2"] * (1 + 0.1 * b)) for b in range(3)]
    X0 = np.tile([0.1, 2.9, 0.0, 0.3], (3, 1))
    t = np.linspace(0, 0.5, 4)
    for method in ("rk4", "rk4_lanes"):
        X, codes = m.c.integrate_batch(t, X0, method=method, h=0.01, u=np.zeros(1), params=P)
        assert not codes.any()
        for b in range(3):
            assert np.array_equal(X[b], m.c.integrate(t, X0[b], method, h=0.01, u=np.zeros(1), params=P[b]))


DRIVER = r"""
#include <math.h>
#include <stdio.h>
#include <string.h>
#define OWN {own}
#if OWN
static double k_sin_(double a);
static double k_cos_(double a);
#define sin(a) k_sin_(a)
#define cos(a) k_cos_(a)
#endif
#include "{name}.c"
#if OWN
#undef sin
#undef cos
/* NAME_rhs with the lanes' sine and cosine; (sin)(a) is libm's */
static double k_sin_(double a)
{{
    double v[4] = {{0.0, 0.0, 0.0, 0.0}}, s[4], c[4];
    if (!(fabs(a) < 1e6)) {{
        return (sin)(a);
    }}
    v[0] = a;
    {name}_sincos_(v, s, c, 4);
    return s[0];
}}
static double k_cos_(double a)
{{
    double v[4] = {{0.0, 0.0, 0.0, 0.0}}, s[4], c[4];
    if (!(fabs(a) < 1e6)) {{
        return (cos)(a);
    }}
    v[0] = a;
    {name}_sincos_(v, s, c, 4);
    return c[0];
}}
#endif
static unsigned long long seed = 88172645463325252ull;
static double rnd(void)
{{
    seed ^= seed << 13;
    seed ^= seed >> 7;
    seed ^= seed << 17;
    return (double)(seed >> 11) * 0x1.0p-53;
}}
#define L {lanes}
#define DIM (2 * {NAME}_N)
int main(void)
{{
    {params}
    double X[DIM * L], XD[DIM * L], x[DIM], xd[DIM], xd1[DIM], u[{NAME}_NU + 1];
    int code[L], c1, cr, i, l, k, bad = 0, failed = 0;
    for (k = 0; k < 1000; ++k) {{
        const double t = 3.0 * rnd();
        for (i = 0; i <= {NAME}_NU; ++i) {{
            u[i] = k % 97 == 5 ? NAN : 2.0 * rnd() - 1.0;
        }}
        for (i = 0; i < DIM; ++i) {{
            for (l = 0; l < L; ++l) {{
                X[i * L + l] = i < {NAME}_N ? 8.0 * rnd() - 4.0 : 4.0 * rnd() - 2.0;
            }}
        }}
        if (k % 5 == 0) X[(k / 5) % DIM * L + k % L] = (k / 5) % 2 ? NAN : HUGE_VAL;
        if (k % 7 == 0) X[({NAME}_N + k % {NAME}_N) * L + (k + 3) % L] = 1e160;
        {name}_rhs_lanes_({T}OWN, X, u, p, XD, code);
        for (l = 0; l < L; ++l) {{
            for (i = 0; i < DIM; ++i) {{
                x[i] = X[i * L + l];
            }}
            cr = {name}_rhs(t, x, u, p, xd);
            {name}_rhs_lane_({T}OWN, x, u, p, xd1, &c1);
            failed += cr != 0;
            if (code[l] != cr || c1 != cr) {{
                bad |= 1;
            }}
            for (i = 0; cr == 0 && i < DIM; ++i) {{
                if (memcmp(&XD[i * L + l], &xd[i], sizeof(double)) || memcmp(&xd1[i], &xd[i], sizeof(double))) {{
                    bad |= 2;
                }}
            }}
        }}
    }}
    printf("%d %d\n", bad, failed);
    return 0;
}}
"""


@pytest.mark.parametrize("own", [0, 1], ids=["libm", "own"])
@pytest.mark.parametrize("name", tiered(MODELS[:-1], QUICK_EXAMPLES))  # (not ur5, whose C takes 4 s to compile: the batch test has it)
def test_lane_rhs_is_the_scalar_rhs_bit_for_bit(example, name, own, tmp_path):
    """The lanes' right side (LANES lanes and one) against NAME_rhs at 8000 random states with t, u
    and parameters, with libm's sin and cos (RK4's) and with the lanes' own (RK4_LANES's; NAME_rhs
    compiled with them): the same bits wherever NAME_rhs returns OK, the same code everywhere (NaN,
    infinite and overflowing states among them, a NaN control)."""
    m = example(name)
    NAME = name.upper()
    header = (m.folder / f"{name}.h").read_text()
    T = "t, " if f"{NAME}_TIME_DEPENDENT 1" in header else ""
    if m.params:
        init = ", ".join(repr(m.params[str(p)]) for p in m.spec.params)
        params = f"const {name}_params prm = {{{init}}}, *p = &prm;"
    else:
        params = f"const {name}_params *p = 0;"
    (tmp_path / "driver.c").write_text(DRIVER.format(name=name, NAME=NAME, lanes=lanes.LANES, params=params, T=T, own=own))
    exe = tmp_path / "driver"
    build = subprocess.run(["cc", "-std=c99", "-O2", "-Wall", "-Wextra", "-Wno-unused-function", f"-I{m.folder}",
                            str(tmp_path / "driver.c"), "-o", str(exe), "-lm"], capture_output=True, text=True)
    assert build.returncode == 0, build.stderr
    bad, failed = map(int, subprocess.run([str(exe)], capture_output=True, text=True, timeout=120).stdout.split())
    assert bad == 0
    assert 200 <= failed < 800  # the 200 lanes with a NaN or an infinity among them, and few others


def test_the_bit_check_can_fail(example, tmp_path):
    """A lane body that adds its products in another order is caught by the driver."""
    m = example("spatial3")
    src = _text(m)
    start = src.index("static void spatial3_rhs_lanes_(")
    body = src[start:]
    line = next(ln for ln in body.splitlines() if " - (L1_0_ * y0_" in ln or "const double y1_ = " in ln)
    mutant = src[:start] + body.replace(line, line.replace("const double y1_ = f_[", "const double y1_ = 1e-15 + f_["), 1)
    assert mutant != src
    folder = tmp_path / "m"
    folder.mkdir()
    (folder / "spatial3.c").write_text(mutant)
    shutil.copy(m.folder / "spatial3.h", folder)
    init = ", ".join(repr(m.params[str(p)]) for p in m.spec.params) if m.params else ""
    params = f"const spatial3_params prm = {{{init}}}, *p = &prm;" if m.params else "const spatial3_params *p = 0;"
    (tmp_path / "driver.c").write_text(DRIVER.format(name="spatial3", NAME="SPATIAL3", lanes=lanes.LANES, params=params, T="", own=1))
    exe = tmp_path / "driver"
    assert subprocess.run(["cc", "-std=c99", "-O2", f"-I{folder}", str(tmp_path / "driver.c"), "-o", str(exe), "-lm"]).returncode == 0
    bad, _ = map(int, subprocess.run([str(exe)], capture_output=True, text=True, timeout=120).stdout.split())
    assert bad & 2


def test_where_the_lanes_are_not_printed(example):
    """Single precision (the kernel's constants are double's), the loop form of long chains and a
    φ̈ longer than LANES_MAX_TEMPORARIES keep the scalar RK4 step, and RK4_LANES is RK4 there."""
    from gyrochain import pipeline
    from gyrochain.printers import render
    from gyrochain.spec import load_spec

    spec = load_spec(ROOT / "specs" / "double_pendulum.toml")
    model = pipeline.derive(spec)
    c = render(model, "double_pendulum.toml", targets=("c",))["double_pendulum.c"]
    f = render(model, "double_pendulum.toml", targets=("c",), real="float")["double_pendulum.c"]
    assert "double_pendulum_rk4_lanes_(" in c and "rhs_lanes_" in c
    assert "_rk4_lane_(" not in f and "_rk4_lanes_(" not in f and "_rhs_lane" not in f and "_sincos" not in f
    for name in ("cable64", "panda"):
        text = (ROOT / "generated" / name / f"{name}.c").read_text()
        assert f"{name}_rk4_lanes_(" not in text and f"{name}_rk4_step_(" in text
    m = example("panda")
    x0 = np.zeros(14)
    x0[:7] = 0.3
    t = np.linspace(0.0, 0.1, 3)
    assert np.array_equal(m.c.integrate(t, x0, "rk4_lanes", h=0.01), m.c.integrate(t, x0, "rk4", h=0.01))


def test_a_sweep_with_rk4_lanes_is_the_batch(tmp_path):
    """`sweep --method rk4_lanes` runs the batch with the lanes' own sin and cos: its final states are
    the single RK4_LANES calls', and a typo in the method is one line naming the choices."""
    pytest.importorskip("zarr", reason="the sweep extra (zarr, dask, distributed, tqdm) is not installed")
    from gyrochain import sweep
    from gyrochain.cli import main

    store = tmp_path / "s.zarr"
    args = ["sweep", str(ROOT / "specs" / "double_pendulum.toml"), "--vary", "phi1=-2:2:5", "--t1", "0.5",
            "--method", "rk4_lanes", "--h", "0.01", "-q", "-o", str(store)]
    assert main(args) == 0
    final = sweep.read(store)["final"]
    from gyrochain import pipeline
    from gyrochain.spec import load_spec

    c, _ = pipeline.compiled(load_spec(ROOT / "specs" / "double_pendulum.toml"))
    for k, phi1 in enumerate(np.linspace(-2.0, 2.0, 5)):
        x = c.integrate([0.0, 0.5], [phi1, 0.0, 0.0, 0.0], "rk4_lanes", h=0.01)[-1]
        assert np.array_equal(final[k], x)
    typo = [a if a != "rk4_lanes" else "rk4_lane" for a in args[:-1]] + [str(tmp_path / "t.zarr")]
    bad = subprocess.run([sys.executable, "-m", "gyrochain", *typo], capture_output=True, text=True, cwd=tmp_path)
    assert bad.returncode == 2 and bad.stderr.count("\n") == 1 and "rk4_lanes" in bad.stderr, bad.stderr
    assert not (tmp_path / "t.zarr").exists()
