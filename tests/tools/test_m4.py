"""A run on a microcontroller-class target: the float Furuta pendulum and its LQR loop at 1 kHz with
the emitted RK4, cross-compiled for the Cortex-M4F (arm-none-eabi-gcc, newlib) and run in QEMU's MPS2
AN386 board, against the same program built for the host; QEMU's instruction count calibrated, the
code size, the stack and the instructions per NAME_qdd call (bench/embedded.py's helpers)."""
from __future__ import annotations

import importlib.util
import re
import subprocess
import sys

import numpy as np
import pytest

from gyrochain import pipeline
from gyrochain.spec import load_spec
from conftest import ROOT, example_script


def _embedded():
    spec = importlib.util.spec_from_file_location("bench_embedded", ROOT / "bench" / "embedded.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


E = _embedded()
pytestmark = pytest.mark.skipif(bool(E.available()), reason=f"needs {E.available()} (apt-get install gcc-arm-none-eabi "
                                                            "libnewlib-arm-none-eabi qemu-system-arm)")
M4 = ROOT / "examples" / "embed" / "m4"
LINE = re.compile(r"^t ([\d.]+) x (\S+) (\S+) (\S+) (\S+) u (\S+)$")


@pytest.fixture(scope="module")
def furuta(tmp_path_factory):
    """The float Furuta pendulum's files and the LQR gain of examples/furuta_lqr.py, in a work folder."""
    work = tmp_path_factory.mktemp("m4")
    spec = load_spec(ROOT / "specs" / "furuta.toml")
    # as examples/embed/m4/README.md says
    subprocess.run([sys.executable, "-m", "gyrochain", "generate", "specs/furuta.toml", "--real", "float", "-o", str(work),
                    "--no-build", "-q"], cwd=ROOT, check=True, capture_output=True)
    K = example_script("furuta_lqr").gain(pipeline.compiled(spec)[0])[0]
    (work / "lqr_gain.h").write_text("#define FURUTA_K {" + ", ".join(f"{float(k)!r}f" for k in K) + "}\n")
    return work


def _states(out: str) -> np.ndarray:
    rows = [LINE.match(line) for line in out.splitlines()]
    assert rows and all(rows), out
    return np.array([[float(v) for v in m.groups()] for m in rows])


def test_the_lqr_loop_balances_on_the_m4_as_on_the_host(furuta):
    elf = E.build([M4 / "furuta_lqr.c", furuta / "furuta.c"], furuta / "furuta_lqr.elf", include=(furuta,))
    code, out = E.run(elf)
    assert code == 0, out
    m4 = _states(out)
    host = furuta / "furuta_lqr_host"
    subprocess.run(["cc", "-std=c99", "-O2", "-Wall", "-Wextra", "-Wdouble-promotion", "-Wfloat-conversion", "-Werror",
                    f"-I{furuta}", str(M4 / "furuta_lqr.c"), str(furuta / "furuta.c"), "-lm", "-o", str(host)], check=True)
    ref = _states(subprocess.run([str(host)], capture_output=True, text=True, check=True).stdout)
    assert m4.shape == ref.shape == (8, 6)
    # the same float arithmetic but newlib's sinf/cosf against glibc's: the stable loop keeps them together
    assert np.max(np.abs(m4 - ref)) < 1e-4, np.max(np.abs(m4 - ref))
    assert abs(m4[-1, 2] - np.pi) < 1e-3 and abs(m4[-1, 4]) < 1e-2  # upright and at rest after 4 s
    assert abs(m4[0, 2] - np.pi) > abs(m4[-1, 2] - np.pi)


def test_qemu_counts_instructions(tmp_path):
    """One call of a function of 1000 nops counts 1000 + the call and the return."""
    assert E.calibrate(tmp_path) == pytest.approx(1002, abs=3)


def test_size_stack_and_instructions_of_qdd(furuta, tmp_path):
    obj, ci = E.model_object(furuta, "furuta", tmp_path)
    sz = E.sizes(obj, "furuta")
    assert 100 < sz["qdd"] < 4000 and sum(sz.values()) > sz["qdd"]
    assert 0 < E.stack(ci, "furuta_qdd") < 1024 and E.stack(ci, "furuta_integrate") > E.stack(ci, "furuta_qdd")
    ins = E.per_call(E.qdd_program("furuta", 2, 1, None, False), (furuta,), tmp_path, objects=(furuta / "furuta.c",))
    assert 100 < ins < 2000, ins
