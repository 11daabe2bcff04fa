"""How a kernel file becomes a model's code (printers/kernels.py): the preamble dropped, the
name put in, the flags' sections kept or dropped, the generated parts filled in."""
from __future__ import annotations

import ast

import pytest

from gyrochain.printers import kernels
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
    ast.parse((ROOT / "gyrochain" / "kernels" / "quad.py").read_text())
    body = kernels.specialise("quad.py", "arm", {}, {"prologue": "    p_m = 1.0\n", "quad_terms": "    out[0] = phi\n"})
    assert "{model}" not in body and "arm.c" in body and "model_stub" not in body
    assert "    p_m = 1.0\n" in body and "    out[0] = phi\n" in body


def test_an_unknown_flag_or_part_is_an_error():
    with pytest.raises(KeyError):
        kernels.specialise("quad.c", "arm", {}, {"quad_terms": ""})
    with pytest.raises(KeyError):
        kernels.specialise("quad.c", "arm", {"HAS_PARAMS": True}, {})


def _integrators(time_dependent: bool, canonical: bool, variational: bool = True, lanes: bool = False) -> str:
    values = dict(N=3, DIM=6, NN=9, NU=1, NNU1=3, HCOL=7, COLS=8 + time_dependent, ZDIM=7 + time_dependent, NP=2, NNP=6, DIM2=36, VDIM=42, OPS_QDD=11, OPS_QDD_DERIVATIVES=12, OPS_VELOCITIES=13, OPS_PDOT=14,
                  OPS_CANONICAL=27, NEWTON_SWEEPS=5, NEWTON_SWEEPS_CANONICAL=6, LANES=8, **{"2DIM": 12, "4DIM2": 144})
    flags = dict(NEWTON=True, CANONICAL=canonical, CANONICAL_NEWTON=canonical, TIME_DEPENDENT=time_dependent, HAS_PARAMS=False,
                 VARIATIONAL=variational, LANES=lanes, HESSIAN=variational,
                 PARAM_DERIVATIVES=variational)
    return kernels.specialise("integrate.c", "arm", flags, {}, values, time_dependent)


def test_the_integrators_take_the_models_numbers_and_time():
    auto, timed = _integrators(False, True), _integrators(True, False)
    for body in (auto, timed):
        assert "MODEL_" not in body and "model_" not in body and "#if " not in body and "#else" not in body
        assert "double x[6], cmp[6], dx[6], F[2][6]" in body
    assert "static inline int arm_rk4_step_(const double *x, double h," in auto
    assert "static inline int arm_rk4_step_(double t0, const double *x, double h," in timed
    assert "arm_eval_canonical_" in auto and "arm_eval_canonical_" not in timed
    assert "27 ops against GAUSS2's 11." in auto
    # a model that reads t: the step's derivatives in w = (x, u, h, t) take its stages' times' derivatives
    assert "double *xn_h, double *xn_t)" in timed and "double *xn_h)" in auto
    assert "arm_time_derivative(t, y, u, p, 0, Dt)" in timed and "arm_time_derivative" not in auto


def test_dop853_is_printed_once_per_system():
    """kernels/dop853.c is instantiated for the state (6 components) and, where the model has the
    variational equations, for the state with its fundamental matrix (6 + 36 = 42), its names and
    dimension spelled out: no SYS_/sys_ name and no #include is left (the defines that named them are gone)."""
    both, one = _integrators(True, False), _integrators(False, True, variational=False)
    for body in (both, one):
        assert "SYS_" not in body and "sys_" not in body and "#include" not in body
        assert "static int arm_dop853_(int nt," in body and "double k[][6]" in body
    assert "static int arm_dop853_variational_(int nt," in both and "double k[][42]" in both
    assert "arm_eval_variational_(t, y, u, p, k[0], st)" not in both  # the stage calls read t + c h
    assert "arm_eval_variational_(t, x, u, p, k[0], st)" in both
    assert "variational" not in one
    with pytest.raises(ValueError):
        kernels._instances(['#include "dop853.c"\n'])


def test_rk4_lanes_are_printed_for_one_lane_and_for_a_batch():
    """kernels/rk4_lanes.c is instantiated twice where the model has RK4's lanes: LANES of them (a
    batch) and one (a single RK4_LANES call), each reading the right side printed for its count;
    without lanes neither is printed and RK4_LANES is RK4's scalar step."""
    with_lanes, without = _integrators(True, False, lanes=True), _integrators(True, False)
    assert "static void arm_rk4_lane_(int own, int nt," in with_lanes and "static void arm_rk4_lanes_(int own, int nt," in with_lanes
    assert "double x[6 * 1]" in with_lanes and "double x[6 * 8]" in with_lanes
    assert "arm_rhs_lane_(tk, own, x, u, p, k[0], fail);" in with_lanes and "arm_rhs_lanes_(tk, own, x, u, p, k[0], fail);" in with_lanes
    assert "arm_rk4_lanes_(own, nt, t, h, budget, u, p, Xl, 0, lc);" in with_lanes
    assert "arm_fixed_(method == ARM_RK4_LANES ? ARM_RK4 : method," in without
    assert "SYS_" not in with_lanes and "sys_" not in with_lanes and "#include" not in with_lanes
    assert "arm_rk4_lane" not in without and "arm_rhs_lane" not in without
