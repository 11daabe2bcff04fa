"""How a kernel file becomes a model's code (printers/kernels.py): the preamble dropped, the
name put in, the flags' sections kept or dropped, the generated parts filled in."""
from __future__ import annotations

import ast

import pytest

from codegen.printers import kernels
from conftest import ROOT


def test_a_c_kernel_specialised():
    body = kernels.specialise("quad.c", "arm", {"HAS_PARAMS": False}, {"quad_terms": "    out[0] = 1.0;\n"})
    assert "model_stub" not in body and "@kernel" not in body and "#if" not in body
    assert "static void arm_quad_terms_(double phi, const arm_params *p, double *out)" in body
    assert "    out[0] = 1.0;\n" in body and "@generated" not in body
    assert "model_" not in body and "MODEL_" not in body and "ARM_NO_PARAMS" not in body
    with_params = kernels.specialise("quad.c", "arm", {"HAS_PARAMS": True}, {"quad_terms": ""})
    assert with_params.count("return ARM_NO_PARAMS;") == 2


def test_a_python_kernel_is_python_and_specialised():
    ast.parse((ROOT / "codegen" / "kernels" / "quad.py").read_text())
    body = kernels.specialise("quad.py", "arm", {}, {"prologue": "    p_m = 1.0\n", "quad_terms": "    out[0] = phi\n"})
    assert "{model}" not in body and "arm.c" in body and "model_stub" not in body
    assert "    p_m = 1.0\n" in body and "    out[0] = phi\n" in body


def test_an_unknown_flag_or_part_is_an_error():
    with pytest.raises(KeyError):
        kernels.specialise("quad.c", "arm", {}, {"quad_terms": ""})
    with pytest.raises(KeyError):
        kernels.specialise("quad.c", "arm", {"HAS_PARAMS": True}, {})
