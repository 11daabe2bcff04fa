"""The two pictures of docs/identify.md, made by the page's own commands (`make plot`).

Runs the page's Python blocks and ``$ gyrochain`` lines in order in a fresh folder, as a reader
following the page would, and keeps the two pictures that its ``--plot`` options write (each with its phone variant):
furuta_fit.png as docs/img/identify_furuta.png and bench_fit.png as docs/img/identify_gimbal.png.

    python examples/identify_pictures.py
"""
from __future__ import annotations

import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PAGE = ROOT / "docs" / "identify.md"
KEEP = {"furuta_fit.png": "identify_furuta.png", "bench_fit.png": "identify_gimbal.png"}
BLOCK = re.compile(r"^```(console|python)\n(.*?)^```", re.S | re.M)


def main() -> int:
    with tempfile.TemporaryDirectory() as d:
        (Path(d) / "specs").symlink_to(ROOT / "specs")
        cwd = os.getcwd()
        for kind, text in BLOCK.findall(PAGE.read_text(encoding="utf-8")):
            if kind == "python":
                os.chdir(d)
                try:
                    exec(compile(text, str(PAGE), "exec"), {"__name__": "identify_page"})
                finally:
                    os.chdir(cwd)
                continue
            for line in text.splitlines():
                if line.startswith("$ gyrochain "):
                    subprocess.run([sys.executable, str(ROOT / "examples" / "phone_figures.py"), "-m", "gyrochain", *shlex.split(line[len("$ gyrochain "):])], cwd=d,
                                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        for made, kept in KEEP.items():  # each with its phone variant (examples/phone_figures.py)
            for suffix in (".png", ".phone.png"):
                shutil.copyfile(Path(d) / (Path(made).stem + suffix), ROOT / "docs" / "img" / (Path(kept).stem + suffix))
                print(f"wrote docs/img/{Path(kept).stem + suffix}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
