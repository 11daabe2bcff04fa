"""Draw the pictures of docs/gallery.md by running each card's own commands (`make gallery`).

Each card of the page shows the commands that draw its picture in an empty folder; this runs exactly
those lines, each card in a fresh folder, with this Python's gyrochain, and keeps the PNG it names
as docs/img/gallery/NAME.png.  So a picture of the gallery is what its card's commands give.

    python examples/gallery.py [NAME ...]      (default: every card)
"""
from __future__ import annotations

import re
import shlex
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PAGE = ROOT / "docs" / "gallery.md"
PICTURES = ROOT / "docs" / "img" / "gallery"
CARD = re.compile(r"^### (\w+)\n.*?```console\n(.*?)```", re.S | re.M)


def cards(text: str) -> dict[str, list[list[str]]]:
    """Each card's name and its commands (the ``$`` lines), as argument lists."""
    return {name: [shlex.split(line[2:]) for line in block.splitlines() if line.startswith("$ ")]
            for name, block in CARD.findall(text)}


def draw(name: str, commands: list[list[str]]) -> Path:
    with tempfile.TemporaryDirectory() as d:
        for argv in commands:
            if argv[0] != "gyrochain":
                raise SystemExit(f"docs/gallery.md, {name}: a command that is not gyrochain's: {shlex.join(argv)}")
            subprocess.run([sys.executable, "-m", "gyrochain", *argv[1:]], cwd=d, check=True,
                           stdout=subprocess.DEVNULL)
        made = Path(d) / f"{name}.png"
        if not made.exists():
            raise SystemExit(f"docs/gallery.md, {name}: the commands did not write {name}.png")
        PICTURES.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(made, PICTURES / made.name)
    return PICTURES / made.name


def main(names: list[str]) -> int:
    found = cards(PAGE.read_text(encoding="utf-8"))
    for name in names or found:
        if name not in found:
            raise SystemExit(f"docs/gallery.md has no card {name!r}")
        print(draw(name, found[name]).relative_to(ROOT), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
