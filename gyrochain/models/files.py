"""A file the user asked for (a spec, a robot description, an FMU), written whole or not at all."""
from __future__ import annotations

import contextlib
import os
import re
from pathlib import Path

from ..chainspec.errors import SpecError


@contextlib.contextmanager
def folders_for(path: Path):
    """The folder of ``path`` made (its missing parents too) for the block; when the block ends
    with an exception (Ctrl-C included) the folders made here are removed again, innermost first,
    where they are empty: an interrupted first run leaves no empty folder behind."""
    made = [p for p in Path(path).parents if not p.exists()]
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    try:
        yield
    except BaseException:
        for folder in made:
            with contextlib.suppress(OSError):
                folder.rmdir()
        raise


def write_new(path: Path, text: str | bytes, force: bool = False) -> None:
    """Write ``text`` to ``path`` whole or not at all (a temporary file beside it, renamed), with
    the user's umask; an existing file only with ``force``; a missing folder is made."""
    path = Path(path)
    if path.exists() and not force:
        raise SpecError(str(path), "exists; pass --force to replace it")
    if path.is_dir():
        raise SpecError(str(path), "is a folder")
    if path.parent.exists() and not path.parent.is_dir():
        raise SpecError(str(path.parent), "is not a folder")
    path.parent.mkdir(parents=True, exist_ok=True)  # as examples copy and generate make their folder
    tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
    try:
        if isinstance(text, bytes):
            tmp.write_bytes(text)
        else:
            tmp.write_text(text, encoding="utf-8")
        tmp.replace(path)
    except OSError as exc:  # said of the file the user named, never of our temporary one
        raise SpecError(str(path), f"cannot be written: {exc.strerror or exc}") from None
    finally:
        tmp.unlink(missing_ok=True)


def deliver(text: str | bytes, output: str, default: str, force: bool = False, source=None) -> Path | None:
    """A command's file: printed for ``-o -`` (text only; None is returned), else written to
    ``output`` or ``default`` in this folder.  A file the command read (``source``: a path or a
    list of them) is never its output."""
    if output == "-":
        if isinstance(text, bytes):
            raise SpecError("-o -", "a binary file is not printed: name a file")
        print(text, end="")
        return None
    path = target(output, default, force, source)
    write_new(path, text, force)
    return path


def target(output: str, default: str, force: bool = False, source=None, option: str = "-o") -> Path:
    """Where a command will write, checked before its work: not a file it reads (``source``: a
    path or a list of them; ``--force`` does not change that), not a file of the user's without
    ``force``, in a folder it can write."""
    path = Path(output or default)
    sources = [source] if isinstance(source, (str, Path)) else list(source or [])
    for src in sources:
        if src is not None and path.resolve() == Path(src).resolve():
            raise SpecError(f"{option} {path}", "is a file the command reads; name another file")
    if path.is_dir():
        raise SpecError(str(path), "is a folder: name a file")
    if path.exists() and not force:
        raise SpecError(str(path), "exists; pass --force to replace it")
    writable(path)
    return path


def writable(path: Path) -> None:
    """One line, before any work, where ``path`` cannot be written: its folder (or the nearest
    that exists, for one to be made) must be a folder this user may write in."""
    folder = Path(path).parent if str(Path(path).parent) else Path(".")
    while not folder.exists() and folder != folder.parent:
        folder = folder.parent
    if not folder.is_dir():
        raise SpecError(str(folder), "is not a folder")
    if not os.access(folder, os.W_OK | os.X_OK):
        shown = folder if str(folder) not in (".", "") else Path.cwd()
        why = "a read-only file system" if os.statvfs(folder).f_flag & os.ST_RDONLY else "permission denied"
        raise SpecError(str(path), f"cannot be written: the folder {shown} is not writable ({why})")


MAX_TABLE_BYTES = 512 << 20  # a CSV larger than this is refused (a device never ends)
READ_RATE = 50 << 20  # bytes per second numpy reads a CSV of numbers (measured: 56 MiB/s, 2026-11-29)
LONG_TABLE_BYTES = 2 * READ_RATE  # a CSV that takes longer than 2 s to read is announced


def read_table(path: str, what: str, required: list[str], expected: str) -> tuple[list[str], object]:
    """A CSV of numbers under a header of column names (as ``simulate`` writes it): the names and
    the rows, every value finite and the column ``t`` (if required) increasing.  Anything else is
    one line naming ``what`` (the option or the argument) and the file; ``expected`` says what
    the columns should be."""
    if what == path:  # the file is the argument itself: named once
        return _read_table(path, lambda msg: SpecError(path, msg), required, expected)
    return _read_table(path, lambda msg: SpecError(what, f"{path}: {msg}"), required, expected)


def _read_table(path: str, fail, required: list[str], expected: str) -> tuple[list[str], object]:
    import stat
    import warnings

    import numpy as np

    try:
        if not stat.S_ISREG(os.stat(path).st_mode):
            raise fail(f"not a file (a CSV of {expected})")
        size = os.stat(path).st_size
        if size > MAX_TABLE_BYTES:
            raise fail(f"larger than {MAX_TABLE_BYTES >> 20} MiB; thin it out (every k-th row)")
        if size > LONG_TABLE_BYTES:  # more than about two seconds of reading: said first, with its bound
            import sys

            print(f"reading {path}: {size / 2**20:.0f} MiB, about {size / READ_RATE:.0f} s", file=sys.stderr, flush=True)
        with open(path, encoding="utf-8-sig") as f, warnings.catch_warnings():  # Excel's byte-order mark
            warnings.simplefilter("ignore")  # numpy's "input contained no data": said below as one line
            names = [h.strip() for h in f.readline().strip().split(",")]
            data = np.loadtxt(f, delimiter=",", ndmin=2)
    except SpecError:
        raise
    except (OSError, ValueError, UnicodeDecodeError) as exc:
        said = f"{getattr(exc, 'strerror', None) or exc}"
        row = re.search(r"at row (\d+)", said)  # numpy counts the rows of numbers from 0: said as the file's line
        if row:
            said = said.replace(row[0], f"on line {_file_line(path, int(row[1]))}")
        raise fail(said) from None
    missing = [c for c in required if c not in names]
    if missing:
        raise fail(f"no column {missing[0]!r} (expected {expected})")
    if data.shape[0] < 1 or data.shape[1] != len(names):
        raise fail(f"expected rows of {len(names)} numbers under the header")
    bad = np.argwhere(~np.isfinite(data))
    if len(bad):
        r, c = bad[0]
        raise fail(f"line {_file_line(path, r)}, column {names[c]!r} is not finite ({data[r, c]})")
    if "t" in required:
        dt = np.diff(data[:, names.index("t")])
        if np.any(dt <= 0):
            raise fail(f"t does not increase on line {_file_line(path, int(np.argmax(dt <= 0)) + 1)}")
    return names, data


def _file_line(path: str, row: int) -> int:
    """The line of the file (1 the header, as an editor counts) that holds data row ``row`` (0 the
    first): numpy's reader skips blank lines and # comments."""
    with open(path, encoding="utf-8-sig") as f:
        f.readline()
        for number, line in enumerate(f, start=2):
            text = line.split("#", 1)[0].strip()
            if text:
                if row == 0:
                    return number
                row -= 1
    return number
