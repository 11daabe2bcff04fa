"""The numbers the emitted C and its callers share, in one table: the return codes of the int
functions, the integrators' method numbers and the kinds of a two-body motion.  The C header
(printers/c.py lays them out as #defines) and the cffi wrapper (build.py) both read them here."""
from __future__ import annotations

# return codes (NAME_OK ... NAME_BAD_ARGUMENT); 4–6 only in models with the quadratures (30)
STATUS = {
    "OK": 0, "SINGULAR": 1, "NONFINITE": 2, "NO_PARAMS": 3, "SEPARATRIX": 4, "NO_PERIOD": 5, "QUAD_FAILED": 6,
    "STEP_UNDERFLOW": 7, "NO_CONVERGENCE": 8, "TOO_MANY_STEPS": 9, "BAD_ARGUMENT": 10,
}
STATUS_MEANING = {"SINGULAR": "M is not positive definite", "NO_PERIOD": "steady motion"}
QUAD_STATUS = ("SEPARATRIX", "NO_PERIOD", "QUAD_FAILED")

# NAME_integrate*'s method argument
METHODS = {"rk4": 1, "dop853": 2, "gauss2": 3, "gauss2_fixed": 4, "gauss2_symplectic": 5, "rk4_lanes": 6}

# NAME_quad_info.kind
MOTIONS = {"libration": 1, "rotation": 2, "steady": 3}


def status_text(code: int) -> str:
    """SINGULAR (M is not positive definite), NONFINITE, …, or "unknown code"."""
    for name, value in STATUS.items():
        if value == code:
            return f"{name} ({STATUS_MEANING[name]})" if name in STATUS_MEANING else name
    return "unknown code"
