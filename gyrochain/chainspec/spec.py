"""Spec files: TOML → ChainSpec (frozen), with every check a user needs.

Every number of a spec may be a string: a parameter name or an arithmetic
expression of names, numbers, ``pi`` and sqrt/sin/cos/tan.  The string is
parsed with Python's ``ast`` parser (a parser only: nothing is evaluated),
then walked against a whitelist and turned into a sympy expression.
Plain numbers become exact rationals of the decimal the user wrote, so that
zeros vanish exactly and the printers fold the rest into double literals.
"""
from __future__ import annotations

import ast
import math
import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import sympy as sp

from .errors import SpecError, did_you_mean
from .names import (C_KEYWORDS, GENERATED_NAMES, GENERATED_PATTERN, RESERVED_NAMES, RESERVED_PATTERN,  # noqa: F401
                    model_name_clash)
from .tables import parse_initial, parse_limits, parse_values
from .physical import check_physical, check_values

__all__ = ["SpecError", "BodySpec", "ChainSpec", "BaseSpec", "LoadSpec", "load_spec", "parse_spec", "parse_expression",
           "T", "phi_symbol", "phidot_symbol"]

FUNCTIONS = {"sqrt": sp.sqrt, "sin": sp.sin, "cos": sp.cos, "tan": sp.tan}
IDENT = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")
MAX_EXPR_LEN = 200


# The time and the state as they appear in spec expressions (``t``, ``phi1``, ``phidot1``): the
# same sympy symbols the derivation uses (kinematics.state_symbols), so they never become parameters.
T = sp.Symbol("t", real=True)


def phi_symbol(k: int) -> sp.Symbol:
    return sp.Symbol(f"phi_{k}", real=True)


def phidot_symbol(k: int) -> sp.Symbol:
    return sp.Symbol(f"phidot_{k}", real=True)


@dataclass(frozen=True)
class LoadSpec:
    """An external force F^k (at ``point``, from O^k in body axes) or a pure moment M^k of the
    paper's (2)–(4).  ``frame``: "body" (components turn with the body: a follower load) or
    "fixed" (components in the fixed frame ê⁰)."""

    vec: tuple[sp.Expr, sp.Expr, sp.Expr]
    frame: str
    point: tuple[sp.Expr, sp.Expr, sp.Expr] | None = None  # None for a moment

    @property
    def is_force(self) -> bool:
        return self.point is not None


@dataclass(frozen=True)
class BaseSpec:
    """The platform's prescribed motion: O¹ at ``position`` r₀(t) (fixed frame), attitude the
    product of rotations about platform-fixed unit ``axes`` by ``angles`` (intrinsic, in order)."""

    position: tuple[sp.Expr, sp.Expr, sp.Expr]
    axes: tuple[tuple[sp.Expr, sp.Expr, sp.Expr], ...]
    angles: tuple[sp.Expr, ...]

    @property
    def moves(self) -> bool:
        """Whether the platform moves at all (a constant position and no rotation is a fixed base)."""
        return any(e.has(T) for e in self.position) or any(a.has(T) for a in self.angles)


@dataclass(frozen=True)
class BodySpec:
    """Gyrostat S^k.  ``A`` is the inertia tensor about O^k (not the centre of mass)."""

    theta: sp.Expr
    m: sp.Expr
    c: tuple[sp.Expr, sp.Expr, sp.Expr]
    A: tuple[tuple[sp.Expr, ...], ...]
    s: tuple[sp.Expr, sp.Expr, sp.Expr]  # zero for the last body (unused)
    lam: tuple[sp.Expr, sp.Expr, sp.Expr]  # gyrostatic moment lambda^k, body axes (may depend on t)
    control: bool  # the joint takes an input torque, an entry of u: a motor's, or a disturbance's
    spring: sp.Expr | None = None  # joint stiffness: torque -spring (phi - rest)
    rest: sp.Expr = sp.Integer(0)
    damping: sp.Expr | None = None  # viscous joint friction: torque -damping phidot
    torque: sp.Expr | None = None  # any other joint torque, of t, the state and parameters
    forces: tuple[LoadSpec, ...] = ()
    moments: tuple[LoadSpec, ...] = ()
    offset: sp.Expr = sp.Integer(0)  # the joint's zero: the paper's φᵏ is the spec's joint angle + offset
    armature: sp.Expr = sp.Integer(0)  # the joint's reflected motor inertia, added to M_kk (MuJoCo's armature)
    limits: tuple = ()  # ((key, value), …) of limits.KEYS: data for the optimiser, not enforced by the model
    disturbance: bool = False  # the input is a disturbance torque, which no controller sets (CasADi's u_dist)

    @property
    def lam_dot(self) -> tuple:
        """The star derivative of λᵏ (its components' rate in the body frame), eq. (7)."""
        return tuple(sp.diff(x, T) for x in self.lam)

    @property
    def loaded(self) -> bool:
        """Whether the body has any of the general case's fields."""
        return (self.spring is not None or self.damping is not None or self.torque is not None
                or bool(self.forces) or bool(self.moments) or any(x.has(T) for x in self.lam))


@dataclass(frozen=True)
class ChainSpec:
    name: str
    description: str
    g: sp.Expr
    bodies: tuple[BodySpec, ...]
    params: tuple[sp.Symbol, ...]  # symbolic parameters, in order of first appearance
    initial: dict | None = field(default=None, compare=False)
    values: dict = field(default_factory=dict, compare=False)  # [values]: default values of symbolic parameters
    source: str = ""  # the spec text (for provenance and the LaTeX table)
    base: BaseSpec | None = None  # None: a fixed base

    @property
    def general(self) -> bool:
        """Whether the spec uses any field of the general equations (8)–(10)."""
        return self.base is not None or any(b.loaded for b in self.bodies)

    @property
    def n(self) -> int:
        return len(self.bodies)

    @property
    def controls(self) -> tuple[int, ...]:
        """Joints k (1-based) with a control torque, in chain order."""
        return tuple(k for k, b in enumerate(self.bodies, start=1) if b.control)

    @property
    def disturbances(self) -> tuple[int, ...]:
        """Joints k (1-based) whose input is a disturbance torque (among ``controls``, in chain order)."""
        return tuple(k for k, b in enumerate(self.bodies, start=1) if b.disturbance)

    @property
    def is_numeric(self) -> bool:
        return not self.params


# --------------------------------------------------------------------------- expressions
class _ExprBuilder:
    """Turns a whitelisted Python AST into a sympy expression; records names in order."""

    def __init__(self, where: str, names: dict[str, sp.Symbol], state: dict | None = None):
        self.where = where
        self.names = names
        self.state = state or {}

    def fail(self, why: str):
        raise SpecError(self.where, why)

    def build(self, node: ast.AST) -> sp.Expr:
        if isinstance(node, ast.Expression):
            return self.build(node.body)
        if isinstance(node, ast.Constant):
            if isinstance(node.value, bool) or not isinstance(node.value, (int, float)):
                self.fail(f"{node.value!r} is not a number")
            return _number(node.value, self)
        if isinstance(node, ast.Name):
            if node.id == "pi":
                return sp.pi
            return self.name(node.id)
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
            v = self.build(node.operand)
            return -v if isinstance(node.op, ast.USub) else v
        if isinstance(node, ast.BinOp):
            a, b = self.build(node.left), self.build(node.right)
            op = node.op
            if isinstance(op, ast.Add):
                return a + b
            if isinstance(op, ast.Sub):
                return a - b
            if isinstance(op, ast.Mult):
                return a * b
            if isinstance(op, ast.Div):
                if b == 0:
                    self.fail("division by zero")
                return a / b
            if isinstance(op, ast.Pow):
                if not b.is_number or abs(float(b)) > 16:
                    self.fail("an exponent must be a number between -16 and 16")
                if a == 0 and float(b) <= 0:
                    self.fail("0 raised to a non-positive power")
                return a**b
            if isinstance(op, ast.BitXor):
                self.fail("'^' is not a power here; write '**'")
            self.fail(f"operator {type(op).__name__} is not allowed")
        if isinstance(node, ast.Call):
            if (
                isinstance(node.func, ast.Name)
                and node.func.id in FUNCTIONS
                and len(node.args) == 1
                and not node.keywords
            ):
                arg = self.build(node.args[0])
                if node.func.id == "sqrt" and arg.is_number and arg.is_negative:
                    self.fail("sqrt of a negative number")
                return FUNCTIONS[node.func.id](arg)
            self.fail("only sqrt(x), sin(x), cos(x), tan(x) may be called")
        self.fail(f"'{type(node).__name__}' is not allowed in an expression")

    def name(self, ident: str) -> sp.Symbol:
        if ident in self.state:
            sym = self.state[ident]
            if sym is None:
                self.fail(f"unknown symbol {ident!r}: there is no such body")
            if isinstance(sym, str):
                self.fail(sym)
            return sym
        check_param_name(ident, self.where)
        if ident not in self.names:
            self.names[ident] = sp.Symbol(ident, real=True)
        return self.names[ident]


def check_param_name(ident: str, where: str) -> None:
    if not IDENT.match(ident):
        raise SpecError(where, f"parameter name {ident!r} is not an identifier")
    if ident in C_KEYWORDS:
        raise SpecError(where, f"parameter name {ident!r} is a C/C++ keyword")
    if ident in GENERATED_NAMES or GENERATED_PATTERN.match(ident):
        raise SpecError(where, f"parameter name {ident!r} collides with a name of the generated code")
    if ident in FUNCTIONS:
        raise SpecError(where, f"parameter name {ident!r} is a function name")
    if ident in RESERVED_NAMES or RESERVED_PATTERN.match(ident):
        raise SpecError(where, f"parameter name {ident!r} is reserved (sympy, Python or C give it a meaning)")


def _number(value, builder: _ExprBuilder) -> sp.Expr:
    if isinstance(value, float) and not math.isfinite(value):
        builder.fail(f"{value} is not a finite number")
    if isinstance(value, int):
        return sp.Integer(value)
    # The decimal the user wrote (repr round-trips), as an exact rational.
    return sp.Rational(repr(value))


def parse_expression(text: str, where: str, names: dict[str, sp.Symbol] | None = None, state: dict | None = None) -> sp.Expr:
    """Parse one spec string (never evaluated as code) into a sympy expression.  ``state`` maps the
    names an expression of this field may use besides parameters (t, phi1, …) to their symbols
    (or to the message that says why not)."""
    names = {} if names is None else names
    if len(text) > MAX_EXPR_LEN:
        raise SpecError(where, f"expression longer than {MAX_EXPR_LEN} characters")
    if not text.strip():
        raise SpecError(where, "empty expression")
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except SyntaxError:
        raise SpecError(where, f"expression {text!r} does not parse") from None
    expr = _ExprBuilder(where, names, state).build(tree)
    if expr.has(sp.nan, sp.zoo, sp.oo, -sp.oo):
        raise SpecError(where, f"expression {text!r} is not finite")
    return expr


def _scalar(value, where: str, names: dict, state: dict | None = None) -> sp.Expr:
    if isinstance(value, bool):
        raise SpecError(where, "expected a number or an expression string, got a boolean")
    if isinstance(value, (int, float)):
        return _number(value, _ExprBuilder(where, names))
    if isinstance(value, str):
        return parse_expression(value, where, names, state)
    raise SpecError(where, f"expected a number or an expression string, got {type(value).__name__}")


def _vector(value, where: str, names: dict, state: dict | None = None) -> tuple:
    if not isinstance(value, list) or len(value) != 3:
        raise SpecError(where, "expected a vector of 3 entries")
    return tuple(_scalar(v, f"{where}[{i + 1}]", names, state) for i, v in enumerate(value))


def _state_names(n: int, kind: str) -> dict:
    """What the names t, phi1…, phidot1… mean in a field: ``kind`` "const" (numbers and
    parameters only), "time" (t too: prescribed motions) or "state" (t and the state)."""
    out: dict = {}
    pattern_max = max(n, 9)
    for k in range(1, pattern_max + 1):
        for nm, sym in ((f"phi{k}", phi_symbol(k)), (f"phidot{k}", phidot_symbol(k))):
            if k > n:
                out[nm] = None
            elif kind == "state":
                out[nm] = sym
            else:
                out[nm] = (f"{nm!r} is not allowed here: " + ("this field is prescribed, a function of t and parameters only"
                           if kind == "time" else "this field is a constant (numbers and parameters only)"))
    out["t"] = T if kind in ("time", "state") else "'t' is not allowed here: this field is a constant (numbers and parameters only)"
    return out


def _matrix(value, where: str, names: dict, state: dict | None = None) -> tuple:
    if not isinstance(value, list) or len(value) != 3 or not all(isinstance(r, list) and len(r) == 3 for r in value):
        raise SpecError(where, "expected a 3×3 matrix (three rows of three entries)")
    return tuple(
        tuple(_scalar(v, f"{where}[{i + 1}][{j + 1}]", names, state) for j, v in enumerate(row)) for i, row in enumerate(value)
    )


# --------------------------------------------------------------------------- the spec
TOP_FIELDS = {"name", "description", "g", "body", "initial", "base", "values"}
BODY_FIELDS = {"theta", "m", "c", "A", "I_c", "s", "lambda", "rotor", "control", "disturbance", "spring", "rest", "damping", "torque", "force",
               "moment", "offset", "armature", "limits"}
BODY_REQUIRED = ("theta", "m", "c")
ROTOR_FIELDS = ("axis", "inertia", "speed")
SYMMETRY_TOL = 1e-12  # a 3×3 tensor whose A_ij, A_ji differ by at most this × its largest entry is symmetrised
ZERO3 = (sp.Integer(0),) * 3


def _fields(raw: dict, at: str, allowed, required, expected: str) -> None:
    """Every key of a table known and every required one present, else the field named (``at`` "": the top)."""
    name = (lambda key: f"{at}.{key}") if at else (lambda key: key)
    for key in raw:
        if key not in allowed:
            raise SpecError(name(key), f"unknown field ({did_you_mean(key, allowed)}expected {expected})")
    for key in required:
        if key not in raw:
            raise SpecError(name(key), "missing field")


MAX_SPEC_BYTES = 1 << 20  # a spec is text a person writes; the 64-link cable is 9 KB


def load_spec(path: str | Path) -> ChainSpec:
    """A spec file: a regular file (or a pipe) of at most MAX_SPEC_BYTES, parsed.  A device such as
    /dev/zero, a folder or a larger file is one line, at once."""
    import os
    import stat

    path = Path(path)
    try:
        mode = os.stat(path).st_mode
        if stat.S_ISDIR(mode):
            raise SpecError(str(path), "is a folder, not a spec file")
        if stat.S_ISCHR(mode) or stat.S_ISBLK(mode) or stat.S_ISSOCK(mode):
            raise SpecError(str(path), "is a device, not a spec file")
        with open(path, "rb") as fh:
            data = fh.read(MAX_SPEC_BYTES + 1)
        if len(data) > MAX_SPEC_BYTES:
            raise SpecError(str(path), f"larger than {MAX_SPEC_BYTES >> 20} MB: not a spec file")
        text = data.decode("utf-8")
    except FileNotFoundError:
        raise SpecError(str(path), "no such file") from None
    except UnicodeDecodeError as exc:
        raise SpecError(str(path), f"cannot read: not UTF-8 text (byte {exc.start})") from None
    except OSError as exc:
        raise SpecError(str(path), f"cannot read: {exc.strerror or exc}") from None
    if text.lstrip("\ufeff \t\r\n").startswith("<"):  # XML: a URDF or MJCF file given where a spec goes
        raise SpecError(str(path), f"is a robot description (XML), not a spec: `gyrochain import {path.name} -o "
                                   f"{path.stem}.toml` makes a spec of it")
    return parse_spec(text)


def parse_spec(text: str) -> ChainSpec:
    """A spec from its TOML text (as a file holds it): checked field by field, the numbers exact,
    the names parameters; a mistake is a SpecError naming the field."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SpecError("spec", f"not valid TOML: {exc}") from None
    _fields(data, "", TOP_FIELDS, ("name", "g", "body"), "one of " + ", ".join(sorted(TOP_FIELDS)))

    name = data["name"]
    if not isinstance(name, str) or not re.match(r"^[A-Za-z][A-Za-z0-9_]*$", name):
        raise SpecError("name", f"{name!r} is not a C identifier (letters, digits, '_'; starting with a letter)")
    if name in C_KEYWORDS:
        raise SpecError("name", f"{name!r} is a C/C++ keyword")
    clash = model_name_clash(name)
    if clash:
        raise SpecError("name", f"{name!r} would {clash}; choose another name (e.g. {name}_model)")
    if len(name) > 48:
        raise SpecError("name", "longer than 48 characters")
    description = data.get("description", "")
    if not isinstance(description, str):
        raise SpecError("description", "expected a string")

    names: dict[str, sp.Symbol] = {}
    raw_bodies = data["body"]
    n_guess = len(raw_bodies) if isinstance(raw_bodies, list) else 0
    g = _scalar(data["g"], "g", names, _state_names(n_guess, "const"))
    base = _base(data["base"], names, n_guess) if "base" in data else None
    if g.is_number and g < 0:
        raise SpecError("g", "gravity magnitude must not be negative (it acts along ê⁰₁, 'down')")

    if not isinstance(raw_bodies, list) or not all(isinstance(b, dict) for b in raw_bodies):
        raise SpecError("body", "expected [[body]] tables")
    if not raw_bodies:
        raise SpecError("body", "a chain needs at least one body (n = 0)")
    n = len(raw_bodies)
    bodies = []
    for k, raw in enumerate(raw_bodies, start=1):
        bodies.append(_body(raw, k, n, names))

    initial = data.get("initial")
    if initial is not None:
        initial = parse_initial(initial, n, lambda v, at: _scalar(v, at, {}))
    params = tuple(names.values())
    number = lambda v, at: _scalar(v, at, {}, _state_names(0, "const"))  # noqa: E731
    values = parse_values(data["values"], params, number) if "values" in data else {}

    spec = ChainSpec(
        name=name,
        description=description,
        g=g,
        bodies=tuple(bodies),
        params=params,
        initial=initial,
        values=values,
        source=text,
        base=base,
    )
    if len(values) == len(params) and params:
        check_values(spec, values, " with the spec's [values]")
    return spec


def _base(raw, names: dict, n: int) -> BaseSpec:
    if not isinstance(raw, dict):
        raise SpecError("base", "expected a table with position and/or rotation")
    _fields(raw, "base", ("position", "rotation"), (), "position, rotation")
    state = _state_names(n, "time")
    const = _state_names(n, "const")
    position = _vector(raw["position"], "base.position", names, state) if "position" in raw else ZERO3
    rotation = raw.get("rotation", [])
    if not isinstance(rotation, list) or not all(isinstance(r, dict) for r in rotation):
        raise SpecError("base.rotation", "expected a list of tables {axis = [..], angle = ..}")
    axes, angles = [], []
    for i, r in enumerate(rotation, start=1):
        at = f"base.rotation[{i}]"
        _fields(r, at, ("axis", "angle"), ("axis", "angle"), "axis, angle")
        axis = _vector(r["axis"], f"{at}.axis", names, const)
        norm2 = sp.expand(sum(a * a for a in axis))
        if norm2 == 0 or (norm2.is_number and float(norm2) < 1e-24):
            raise SpecError(f"{at}.axis", "an axis of zero length")
        axes.append(axis)
        angles.append(_scalar(r["angle"], f"{at}.angle", names, state))
    return BaseSpec(position=position, axes=tuple(axes), angles=tuple(angles))


def _load(raw, at: str, names: dict, n: int, force: bool) -> LoadSpec:
    if not isinstance(raw, dict):
        raise SpecError(at, "expected a table")
    key_vec = "F" if force else "M"
    allowed = ("point", "F", "frame") if force else ("M", "frame")
    _fields(raw, at, allowed, allowed, ", ".join(allowed))
    frame = raw["frame"]
    if frame not in ("body", "fixed"):
        raise SpecError(f"{at}.frame", f"expected \"body\" or \"fixed\", got {frame!r}")
    point = _vector(raw["point"], f"{at}.point", names, _state_names(n, "const")) if force else None
    vec = _vector(raw[key_vec], f"{at}.{key_vec}", names, _state_names(n, "state"))
    return LoadSpec(vec=vec, frame=frame, point=point)


def _body(raw: dict, k: int, n: int, names: dict) -> BodySpec:
    at = f"body[{k}]"
    _fields(raw, at, BODY_FIELDS, BODY_REQUIRED, "one of " + ", ".join(sorted(BODY_FIELDS)))
    if ("A" in raw) == ("I_c" in raw):
        raise SpecError(f"{at}.A", "give the inertia once: A (about O^k) or I_c (about the centre of mass)"
                        if "A" in raw else "missing field (the inertia: A about O^k, or I_c about the centre of mass)")
    if "lambda" in raw and "rotor" in raw:
        raise SpecError(f"{at}.rotor", "give the rotor once: lambda (its angular momentum) or rotor = {axis, inertia, speed}")
    if k < n and "s" not in raw:
        raise SpecError(f"{at}.s", "missing field (the vector O^k → O^(k+1), needed for every body but the last)")
    if k == n and "s" in raw:
        raise SpecError(f"{at}.s", "the last body has no next joint; leave s out")
    # Read in the file's order so that parameters are numbered by first appearance.
    vals = {}
    const, time, state = (_state_names(n, kind) for kind in ("const", "time", "state"))
    for key, value in raw.items():
        where = f"{at}.{key}"
        if key in ("theta", "offset", "m", "spring", "rest", "damping", "armature"):
            vals[key] = _scalar(value, where, names, const)
        elif key in ("c", "s"):
            vals[key] = _vector(value, where, names, const)
        elif key == "lambda":
            vals[key] = _vector(value, where, names, time)
        elif key == "torque":
            vals[key] = _scalar(value, where, names, state)
        elif key in ("A", "I_c"):
            vals[key] = _tensor(value, where, names, const)
        elif key == "rotor":
            vals["lambda"] = _rotor(value, where, names, const, time)
        elif key == "limits":
            vals[key] = parse_limits(value, where, lambda v, at: _scalar(v, at, {}, const))
        elif key in ("control", "disturbance"):
            if not isinstance(value, bool):
                raise SpecError(where, "expected true or false")
            vals[key] = value
        elif key in ("force", "moment"):
            if not isinstance(value, list) or not all(isinstance(v, dict) for v in value):
                raise SpecError(where, f"expected [[{at.split('[')[0]}.{key}]] tables")
            vals[key] = tuple(_load(v, f"{where}[{i}]", names, n, key == "force") for i, v in enumerate(value, start=1))
    if vals.get("control") and vals.get("disturbance"):
        raise SpecError(f"{at}.disturbance", "the joint has a control torque: a disturbance on it adds to u (give one of "
                                             "control = true or disturbance = true)")
    if "rest" in vals and "spring" not in vals:
        raise SpecError(f"{at}.rest", "a rest angle without a spring (give spring = k too)")
    for key, what in (("spring", "stiffness"), ("damping", "damping coefficient")):
        v = vals.get(key)
        if v is not None and v.is_number and v < 0:
            raise SpecError(f"{at}.{key}", f"a negative {what} ({float(v):g}) would feed energy into the joint")
    if (arm := vals.get("armature", sp.Integer(0))).is_number and arm < 0:
        raise SpecError(f"{at}.armature", f"a motor's reflected inertia is not negative, got {float(arm):g}")
    m, c = vals["m"], vals["c"]
    if m.is_number and m < 0:
        raise SpecError(f"{at}.m", f"mass must be positive, got {float(m):g} (or 0: a massless frame between two joints)")
    if "I_c" in vals:  # the parallel-axis theorem: A = I_c + m(|c|²1 − c cᵀ)
        Ic, cc = vals["I_c"], sum(x * x for x in c)
        A = tuple(tuple(Ic[i][j] + m * ((cc if i == j else 0) - c[i] * c[j]) for j in range(3)) for i in range(3))
    else:
        A = vals["A"]
    check_physical(f"{at}.{'I_c' if 'I_c' in vals else 'A'}", m, c, A)
    return BodySpec(
        theta=vals["theta"],
        m=m,
        c=c,
        A=A,
        s=vals.get("s", ZERO3),
        lam=vals.get("lambda", ZERO3),
        control=vals.get("control", False) or vals.get("disturbance", False),
        disturbance=vals.get("disturbance", False),
        spring=vals.get("spring"),
        rest=vals.get("rest", sp.Integer(0)),
        damping=vals.get("damping"),
        torque=vals.get("torque"),
        forces=vals.get("force", ()),
        moments=vals.get("moment", ()),
        offset=vals.get("offset", sp.Integer(0)),
        armature=arm,
        limits=vals.get("limits", ()),
    )


def _tensor(value, where: str, names: dict, state: dict) -> tuple:
    """An inertia tensor as a 3×3 matrix or six numbers [Ixx, Iyy, Izz, Ixy, Ixz, Iyz] (the
    order of URDF's and MuJoCo's fullinertia), as a symmetric 3×3.  A 3×3 matrix must be
    symmetric; numeric entries that differ by round-off (at most SYMMETRY_TOL of the largest
    entry, as a rotated principal tensor gives) are replaced by their mean."""
    if isinstance(value, list) and len(value) == 6 and not any(isinstance(v, list) for v in value):
        xx, yy, zz, xy, xz, yz = (_scalar(v, f"{where}[{i + 1}]", names, state) for i, v in enumerate(value))
        return ((xx, xy, xz), (xy, yy, yz), (xz, yz, zz))
    if not (isinstance(value, list) and len(value) == 3 and all(isinstance(r, list) and len(r) == 3 for r in value)):
        raise SpecError(where, "expected a 3×3 matrix (three rows of three entries) or six numbers [Ixx, Iyy, Izz, Ixy, Ixz, Iyz]")
    A = [list(row) for row in _matrix(value, where, names, state)]
    big = max((abs(a) for row in A for a in row if a.is_number), default=sp.Integer(0))
    for i in range(3):
        for j in range(i + 1, 3):
            d = sp.expand(A[i][j] - A[j][i])
            if d == 0:
                continue
            if d.is_number and abs(d) <= SYMMETRY_TOL * big:
                A[i][j] = A[j][i] = (A[i][j] + A[j][i]) / 2
                continue
            how = f" (they differ by {float(abs(d)):.3g}, more than round-off: {SYMMETRY_TOL:g} of the largest entry)" if d.is_number else ""
            raise SpecError(where, f"not symmetric: [{i + 1}][{j + 1}] ≠ [{j + 1}][{i + 1}]{how}")
    return tuple(tuple(row) for row in A)


def _rotor(value, where: str, names: dict, const: dict, time: dict) -> tuple:
    """rotor = {axis, inertia, speed}: a rotor of axial moment ``inertia`` spinning at ``speed``
    relative to its carrier about ``axis`` (body axes; a direction, normalised) has the relative
    angular momentum λ = inertia · speed · axis/|axis|.  The carrier's A or I_c includes the rotor
    as a rigid part, as in the paper."""
    if not isinstance(value, dict):
        raise SpecError(where, "expected a table {axis = [x, y, z], inertia = J, speed = w}")
    _fields(value, where, ROTOR_FIELDS, ROTOR_FIELDS, "one of " + ", ".join(ROTOR_FIELDS))
    axis = _vector(value["axis"], f"{where}.axis", names, const)
    inertia = _scalar(value["inertia"], f"{where}.inertia", names, const)
    speed = _scalar(value["speed"], f"{where}.speed", names, time)
    if inertia.is_number and not inertia > 0:
        raise SpecError(f"{where}.inertia", f"the rotor's axial moment of inertia must be positive, got {float(inertia):g}")
    norm2 = sp.expand(sum(x * x for x in axis))
    if norm2.is_number and norm2 == 0:
        raise SpecError(f"{where}.axis", "a zero axis has no direction")
    norm = sp.sqrt(norm2)
    return tuple(inertia * speed * x / norm if x != 0 else sp.Integer(0) for x in axis)
