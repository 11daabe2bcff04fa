"""Names a model or a parameter may not take: C and C++ keywords, the names of the generated
code, what sympy, Python or <math.h> give a meaning, and model names whose files would shadow a
system header or a Python module.  Used by spec.py (and nothing here imports the package)."""
from __future__ import annotations

import re

C_KEYWORDS = frozenset(
    """auto break case char const continue default do double else enum extern float for goto if
    inline int long register restrict return short signed sizeof static struct switch typedef union
    unsigned void volatile while _Bool _Complex _Imaginary
    alignas alignof and and_eq asm bitand bitor bool catch class compl const_cast constexpr
    decltype delete dynamic_cast explicit export false friend mutable namespace new noexcept not
    not_eq nullptr operator or or_eq private protected public reinterpret_cast static_assert
    static_cast template this thread_local throw true try typeid typename using virtual wchar_t
    xor xor_eq""".split()
)
# Names the generated code itself uses (arguments, states, math functions, Python builtins
# the generated module needs).  A parameter may not take one of them.
GENERATED_NAMES = frozenset(
    {"pi", "t", "q", "x", "u", "p", "M", "f", "qdd", "xdot", "np", "math", "numpy", "N"}
    | {"sqrt", "sin", "cos", "tan"} | {"exp", "log", "pow", "fabs", "isfinite", "abs", "None", "True", "False"}
)
# Names sympy, Python or C's <math.h> give a meaning (a constant, infinity, NaN, a macro): a parameter
# called nan or E would not stay a parameter everywhere it is printed.
RESERVED_NAMES = frozenset({"E", "I", "S", "O", "Q", "oo", "zoo", "EulerGamma", "GoldenRatio", "Catalan", "TribonacciConstant",
                            "NULL", "EOF", "errno", "HUGE_VAL", "HUGE_VALF", "HUGE_VALL", "INFINITY", "NAN"})
RESERVED_PATTERN = re.compile(r"^(?i:nan|inf|infinity)$|^M_[A-Z0-9_]+$|^FP_[A-Z_]+$|^MATH_ERR")
GENERATED_PATTERN = re.compile(r"^(w\d+|phi_?\d+|phidot_?\d+|phiddot_?\d+|L_?\d+|tau_?\d+)$")


# The files a model writes are NAME.h, NAME.c and NAME.py beside each other, and its folder is on
# the include path of its own build and on sys.path of whoever imports NAME.py: a name that is a
# system header (math.h, stdint.h, Python.h; compared without case, as macOS's file system does)
# or a Python module the model or its callers import would be found in its place.
# <unistd.h>'s access modes R_OK, W_OK, X_OK, F_OK: a model named w would define W_OK (its return code
# NAME_OK) and the cffi build, which includes Python.h and so unistd.h, warns that it is redefined.
ACCESS_MODES = frozenset({"R", "W", "X", "F"})
C_HEADERS = frozenset(
    """assert complex ctype errno fenv float inttypes iso646 limits locale math setjmp signal stdalign stdarg
    stdatomic stdbool stddef stdint stdio stdlib stdnoreturn string tgmath threads time uchar wchar wctype
    unistd fcntl pthread sched alloca malloc memory strings features endian dlfcn termios poll
    python pyconfig structmember ffi""".split()
)


def _shipped_sources() -> dict:
    """{stem, lower case: the file} of the C sources and headers the package ships and writes
    beside a model (the FMI headers, the integrators' kernels): a model of that name would
    collide with them, on a case-insensitive file system too."""
    from pathlib import Path

    kernels = Path(__file__).resolve().parent.parent / "kernels"
    return {p.stem.lower(): p.name for p in sorted(kernels.rglob("*")) if p.suffix in (".h", ".c")}


def model_name_clash(name: str) -> str:
    """Why a model may not be called ``name`` ("" if it may): its NAME.h or NAME.py would shadow
    a system header or a Python module, or NAME.py could not be imported (a Python keyword)."""
    import keyword
    import sys

    low = name.lower()
    shipped = _shipped_sources().get(low)
    if shipped:
        return f"make its {name}.h or {name}.c collide with {shipped}, which the product writes beside it (FMUs, builds)"
    if low in C_HEADERS:
        return f"make its {name}.h shadow the system header <{low if low != 'python' else 'Python'}.h>"
    if name.upper() in ACCESS_MODES:
        return f"make its header's {name.upper()}_OK the macro {name.upper()}_OK of <unistd.h> (access modes)"
    if keyword.iskeyword(name):
        return f"make {name}.py impossible to import ({name} is a Python keyword)"
    if low in {m.lower() for m in sys.stdlib_module_names} | {"numpy", "scipy", "cffi", "sympy", "jinja2", "gyrochain",
                                                             "codegen", "setuptools", "np", "matplotlib", "zarr", "dask"}:
        return f"make its {name}.py shadow the Python module {name}"
    return ""
