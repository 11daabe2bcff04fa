"""The fixed numerical kernels are real C: a compiler reads codegen/kernels/*.c as they stand
(with model_stub.h, for both values of every #if flag), strict and warning-free."""
from __future__ import annotations

import shutil
import subprocess

import pytest

from conftest import ROOT

KERNELS = sorted((ROOT / "codegen" / "kernels").glob("*.c"))
STRICT = ["-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-Wno-unused-function", "-fsyntax-only"]


@pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler (apt-get install gcc)")
@pytest.mark.parametrize("kernel", KERNELS, ids=[k.name for k in KERNELS])
@pytest.mark.parametrize("has_params", [0, 1])
def test_kernel_compiles_as_it_stands(kernel, has_params):
    res = subprocess.run(["cc", *STRICT, f"-DMODEL_HAS_PARAMS={has_params}", str(kernel)], capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
