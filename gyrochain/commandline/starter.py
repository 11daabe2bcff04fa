"""Specs to start from, for a user who installed the package and has no checkout: ``gyrochain
examples`` lists the shipped example specs and copies them into a folder; ``gyrochain new`` writes a
new, commented spec from a short description (a kind, the number of links, a rotor, motors, a
vibrating pivot).

    starter.shipped()                       # [(name, n, description)] of the example specs
    starter.copy(["gimbal"], Path("."))     # [Path("gimbal.toml")]; never overwrites without force
    text = starter.new_spec("chain", n=3)   # TOML text that load_spec accepts

The example specs are the package's data (gyrochain/examples, the repository's specs/); the new
specs' layout is the template new_spec.toml.jinja, and every number in it is decided here.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from .. import EXAMPLES
from ..chainspec.errors import SpecError, did_you_mean
from ..models.files import write_new
from ..printers.common import environment
from ..chainspec.spec import IDENT, load_spec, parse_spec

# what `gyrochain new` makes: kind -> (default number of links, a line for --help and the list)
KINDS = {
    "pendulum": (1, "one uniform rod on a horizontal hinge"),
    "double-pendulum": (2, "two uniform rods on parallel horizontal hinges"),
    "triple-pendulum": (3, "three uniform rods on parallel horizontal hinges"),
    "chain": (4, "N uniform rods on parallel horizontal hinges, a planar chain (--n)"),
    "spatial-chain": (3, "N rods, each hinge turned 90 degrees from the one before, like a robot arm (--n)"),
}
PLANAR = ("pendulum", "double-pendulum", "triple-pendulum", "chain")
MAX_NEW_LINKS = 64


def shipped() -> list[tuple[str, int, str]]:
    """The example specs that come with the package: (name, n, description), by name."""
    out = []
    for path in sorted(EXAMPLES.glob("*.toml")):
        spec = load_spec(path)
        out.append((path.stem, spec.n, spec.description))
    return out


def example_path(name: str) -> Path:
    """The shipped spec called ``name`` (with or without .toml), or robot description (NAME.urdf);
    one line naming the choices if none is."""
    if name.endswith(".urdf") and name in robot_files():
        return EXAMPLES / "robots" / name
    names = [n for n, _, _ in shipped()]
    stem = name.removesuffix(".toml")
    if stem not in names:
        raise SpecError("example", f"no example called {name!r}; {did_you_mean(stem, names + robot_files())}one of "
                        f"{', '.join(names)}, or a robot description: {', '.join(robot_files())}")
    return EXAMPLES / f"{stem}.toml"


def copy(names: list[str], folder: Path, force: bool = False) -> list[Path]:
    """Copy the named examples (all of them for ``["all"]``) into ``folder`` as NAME.toml.  A file
    already there is not replaced unless ``force``: every name is checked before anything is written."""
    folder = Path(folder)
    if not names:
        raise SpecError("examples copy", "name the examples to copy, or all")
    sources = ([EXAMPLES / f"{n}.toml" for n, _, _ in shipped()] + [EXAMPLES / "robots" / f for f in robot_files()]
               if names == ["all"] else [example_path(n) for n in names])
    if folder.exists() and not folder.is_dir():
        raise SpecError("-o", f"{folder} is not a folder")
    if not folder.is_dir() and folder.suffix.lower() in (".toml", ".urdf"):  # a file's name: one example, that file
        if len(sources) != 1:
            raise SpecError(f"-o {folder}", f"names a file, and {len(sources)} examples need a folder")
        if folder.suffix.lower() != sources[0].suffix:
            raise SpecError(f"-o {folder}", f"{sources[0].name} is a {sources[0].suffix} file (a file is what its name says)")
        targets, folder = [folder], folder.parent
    else:
        targets = [folder / src.name for src in sources]
    if not force:
        there = [str(t) for t in targets if t.exists() or t.is_symlink()]
        if there:
            raise SpecError(there[0], "exists; pass --force to replace it" + (f" (and {len(there) - 1} more)" if len(there) > 1 else ""))
    folder.mkdir(parents=True, exist_ok=True)
    for src, dst in zip(sources, targets):
        write_new(dst, src.read_text(encoding="utf-8"), force)
    return targets


def robot_files() -> list[str]:
    """The robot descriptions that come with the package, to try `gyrochain import` on."""
    return sorted(p.name for p in (EXAMPLES / "robots").glob("*.urdf"))


def examples_command(action: str | None, names, name, output: Path, force: bool, prog: str) -> int:
    """`gyrochain examples`: list them, print one (``show``), or copy some into a folder (``copy``)."""
    if action == "copy":
        written = copy(names, output, force)
        for path in written:
            print(f"wrote {path}")
        first = written[0] if names != ["all"] else next(p for p in written if p.name == "gimbal.toml")
        print(f"next: {prog} {'import' if first.suffix == '.urdf' else 'generate'} {first}")
    elif action == "show":
        print(example_path(name).read_text(encoding="utf-8"), end="")
    else:
        rows = shipped()
        width = max(len(n) for n, _, _ in rows)
        for n_, n, description in rows:
            print(f"{n_:<{width}}  n = {n:<2}  {description}")
        print(f"robot descriptions to import (URDF): {', '.join(robot_files())}")
        print(f"copy one into this folder with `{prog} examples copy NAME` (or all); print one with "
              f"`{prog} examples show NAME`")
    return 0


# --------------------------------------------------------------------------- new specs
@dataclass(frozen=True)
class Field:
    key: str
    value: str  # TOML text
    note: str = ""  # the comment after it
    active: bool = True  # False: written commented out, a suggestion to edit


@dataclass(frozen=True)
class Body:
    title: str
    fields: tuple


def new_spec(kind: str, n: int | None = None, name: str | None = None, rotor: bool = False, control: bool = False,
             driven: bool = False, mass: float = 1.0, length: float = 1.0) -> str:
    """A commented spec of ``kind`` (KINDS) with ``n`` links of uniform rods of ``mass`` kg and
    ``length`` m; ``rotor``: a spinning wheel at the last link's end; ``control``: a motor
    torque in every joint; ``driven``: the pivot vibrates vertically, a cos(w t), with a and w
    symbolic parameters.  Checked by parse_spec before it is returned."""
    if kind not in KINDS:
        raise SpecError("kind", f"no kind {kind!r}; {did_you_mean(kind, list(KINDS))}one of {', '.join(KINDS)}")
    default_n = KINDS[kind][0]
    if n is None:
        n = default_n
    elif kind in ("pendulum", "double-pendulum", "triple-pendulum") and n != default_n:
        raise SpecError("--n", f"a {kind} has {default_n} link{'s' if default_n > 1 else ''}; use the kind chain for {n}")
    if not 1 <= n <= MAX_NEW_LINKS:
        raise SpecError("--n", f"expected 1 to {MAX_NEW_LINKS} links, got {n}")
    for what, v in (("--mass", mass), ("--length", length)):
        if not (v > 0 and v < 1e6):
            raise SpecError(what, f"expected a positive number below 1e6, got {v:g}")
    name = name or (kind.replace("-", "_") + (str(n) if kind in ("chain", "spatial-chain") else ""))
    if not IDENT.match(name):
        raise SpecError("--name", f"{name!r} is not a C identifier (a letter, then letters, digits or _)")
    planar = kind in PLANAR
    bodies = [_rod(k, n, planar, mass, length, rotor and k == n, control) for k in range(1, n + 1)]
    description = (f"{'Pendulum' if n == 1 else 'Planar chain' if planar else 'Spatial chain'} of {n} uniform rod{'s' if n > 1 else ''} "
                   f"({mass:g} kg, {length:g} m{' each' if n > 1 else ''})"
                   + (", a rotor in the last" if rotor else "") + (", a motor in every joint" if control else "")
                   + (", on a pivot that vibrates vertically" if driven else ""))
    initial = [0.5 if k == 1 else 0.0 for k in range(1, n + 1)]
    if driven and planar:  # near the inverted position, which the vibration can hold (Kapitza)
        initial[0] = 3.0
    text = environment().get_template("new_spec.toml.jinja").render(
        name=name, description=description, bodies=bodies, driven=driven, kind=kind, planar=planar,
        phi=", ".join(_num(v) for v in initial), phidot=", ".join("0.0" for _ in initial))
    try:
        parse_spec(text)
    except SpecError as exc:
        if exc.field == "name":  # a keyword, too long: the user's --name
            raise SpecError("--name", exc.message) from None
        raise  # anything else the template wrote that load_spec refuses is our bug
    return text


def _rod(k: int, n: int, planar: bool, m: float, length: float, rotor: bool, control: bool) -> Body:
    """Body k: a uniform rod along its own ê₃, hinged at one end (Oᵏ), the next hinge at the other."""
    if k == 1:
        theta = Field("theta", '"pi/2"', "θ¹: the first hinge axis horizontal (0 would make it vertical)") if planar else \
            Field("theta", "0.0", "θ¹ = 0: the first axis vertical, a base turning about the plumb line")
    else:
        theta = Field("theta", "0.0", f"θ{_sup(k)} = 0: axis {k} parallel to axis {k - 1} (a planar chain)") if planar else \
            Field("theta", '"pi/2"', f"θ{_sup(k)} = π/2: axis {k} at right angles to axis {k - 1}")
    fields = [
        theta,
        Field("m", _num(m), "mass (kg)"),
        Field("c", f"[0.0, 0.0, {_num(length / 2)}]", f"centre of mass from O{_sup(k)} in body axes (m): mid-rod, along ê{_sup(k)}₃"
              + (" (down at φ = 0)" if planar else "")),
        Field("I_c", f'["{_across(m, length)}", "{_across(m, length)}", 0, 0, 0, 0]',
              "about the centre of mass, [Ixx, Iyy, Izz, Ixy, Ixz, Iyz] (kg m²): a thin rod, m l²/12 across"),
    ]
    if k < n:
        fields.append(Field("s", f"[0.0, 0.0, {_num(length)}]", f"O{_sup(k)} → O{_sup(k + 1)}: the next hinge at the rod's end (m)"))
    if rotor:
        fields.append(Field("rotor", "{axis = [0, 0, 1], inertia = 2e-4, speed = 500}",
                            "a wheel spinning along the rod: inertia (kg m²) about its axis, speed (rad/s) relative to the rod"))
    if control:
        fields.append(Field("control", "true", f"a motor torque in joint {k} (the input u{k})"))
    fields.append(Field("damping", "0.05", "viscous friction in the joint (N m s): torque −b φ̇", active=False))
    return Body(f"link {k}" + (", the last" if k == n and n > 1 else ""), tuple(fields))


def _num(v: float) -> str:
    return repr(float(v))


def _across(m: float, length: float) -> str:
    """m l²/12 exactly, as a fraction of the decimals given (a spec's strings are exact)."""
    from fractions import Fraction

    return str(Fraction(repr(float(m))) * Fraction(repr(float(length))) ** 2 / 12)


_SUPERSCRIPT = str.maketrans("0123456789", "⁰¹²³⁴⁵⁶⁷⁸⁹")


def _sup(k: int) -> str:
    return str(k).translate(_SUPERSCRIPT)
