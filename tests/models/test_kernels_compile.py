"""The fixed numerical kernels are real C: a compiler reads gyrochain/kernels/*.c as they stand
(with model_stub.h, for both values of every #if flag), strict and warning-free."""
from __future__ import annotations

import shutil
import subprocess

import pytest

from conftest import ROOT

KERNELS = sorted((ROOT / "gyrochain" / "kernels").glob("*.c"))
STRICT = ["-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-Wno-unused-function", "-fsyntax-only"]


# the flags a model sets (printers/c.py); Hamilton's variables exist only for an autonomous model
# (RK4's lanes on and off in turn, so that each value meets both of every other flag's)
FLAGS = [dict(HAS_PARAMS=hp, TIME_DEPENDENT=td, CANONICAL=c, NEWTON=nw, VARIATIONAL=v, LANES=(hp + td + c + nw + v) % 2)
         for hp in (0, 1) for td in (0, 1) for c in (0, 1) for nw in (0, 1) for v in (0, 1) if not (td and c)]


@pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler (apt-get install gcc)")
@pytest.mark.parametrize("kernel", KERNELS, ids=[k.name for k in KERNELS])
def test_kernel_compiles_as_it_stands(kernel):
    for flags in FLAGS:
        defines = [f"-DMODEL_{k}={v}" for k, v in flags.items()]
        res = subprocess.run(["cc", *STRICT, *defines, str(kernel)], capture_output=True, text=True)
        assert res.returncode == 0, (flags, res.stderr)


def test_a_broken_kernel_is_caught(tmp_path):
    """The check can fail: a kernel with a type error does not compile."""
    if shutil.which("cc") is None:
        pytest.skip("no C compiler")
    bad = tmp_path / "bad.c"
    bad.write_text((KERNELS[0].parent / "quad.c").read_text().replace("double a, b;", "dooble a, b;"))
    res = subprocess.run(["cc", *STRICT, f"-I{KERNELS[0].parent}", str(bad)], capture_output=True, text=True)
    assert res.returncode != 0
