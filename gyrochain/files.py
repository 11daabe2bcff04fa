"""A file the user asked for (a spec, a robot description, an FMU), written whole or not at all."""
from __future__ import annotations

import os
from pathlib import Path

from .errors import SpecError


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
    finally:
        tmp.unlink(missing_ok=True)


def deliver(text: str | bytes, output: str, default: str, force: bool = False, source: str | None = None) -> Path | None:
    """A command's file: printed for ``-o -`` (text only; None is returned), else written to
    ``output`` or ``default`` in this folder.  The file a command read (``source``) is never its output."""
    if output == "-":
        if isinstance(text, bytes):
            raise SpecError("-o -", "a binary file is not printed: name a file")
        print(text, end="")
        return None
    path = target(output, default, force, source)
    write_new(path, text, force)
    return path


def target(output: str, default: str, force: bool = False, source: str | None = None) -> Path:
    """Where a command will write (checked before its work: not the file it reads, not a file of
    the user's without ``force``)."""
    path = Path(output or default)
    if source is not None and path.resolve() == Path(source).resolve():
        raise SpecError(f"-o {path}", "is the file the command reads")
    if path.exists() and not force:
        raise SpecError(str(path), "exists; pass --force to replace it")
    return path
