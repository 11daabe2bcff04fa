"""The picture of a PDF page on docs/tutorial.md, made from the page's own spec (`make plot`).

Takes the spec of the tutorial (its first ``toml`` block), runs ``gyrochain generate --pdf`` on it in
a fresh folder and renders the top of the page that holds the equations of motion with poppler's
``pdftoppm``, so the picture is what a reader who follows the tutorial gets.

    python examples/tutorial_page.py docs/img/tutorial_page.png
"""
from __future__ import annotations

import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PAGE = ROOT / "docs" / "tutorial.md"
SHOWN = 3  # the page of the PDF with the equations of motion
DPI = 90


def main(out: str) -> int:
    from PIL import Image

    spec = re.search(r"```toml\n(.*?)```", PAGE.read_text(encoding="utf-8"), re.S).group(1)
    name = re.search(r'^name = "(\w+)"', spec, re.M).group(1)
    if shutil.which("pdftoppm") is None:
        raise SystemExit("needs poppler's pdftoppm (apt-get install poppler-utils)")
    with tempfile.TemporaryDirectory() as d:
        (Path(d) / f"{name}.toml").write_text(spec)
        subprocess.run([sys.executable, "-m", "gyrochain", "generate", "-q", "--no-build", "--pdf", f"{name}.toml",
                        "-o", name], cwd=d, check=True, stdout=subprocess.DEVNULL)
        subprocess.run(["pdftoppm", "-png", "-r", str(DPI), "-f", str(SHOWN), "-l", str(SHOWN), "-singlefile",
                        str(Path(d) / name / f"{name}.pdf"), str(Path(d) / "page")], check=True)
        page = Image.open(Path(d) / "page.png").convert("RGB")
    w, h = page.size
    page.crop((0, 0, w, int(h * 0.62))).save(out, optimize=True)
    print(f"wrote {out}: page {SHOWN} of {name}.pdf")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else str(ROOT / "docs" / "img" / "tutorial_page.png")))
