"""The whole `gyrochain generate` command on long chains: derivation, the C, Python and LaTeX files
and the cffi build, a random spatial gyrostat chain (full inertia tensors, rotors) per n, a fresh
model cache for each, the peak memory of the largest process (GNU time's maximum resident size).

    python bench/generate_times.py [n ...]      (default 16 32 64 128)

Writes bench/results/generate.csv."""
from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "bench"))

from gyrochain.randspec import random_spec_text  # noqa: E402
from provenance import RESULTS, write  # noqa: E402


def one(n: int, tmp: Path) -> dict:
    name = f"chain{n}"
    spec = tmp / f"{name}.toml"
    spec.write_text(random_spec_text(np.random.default_rng(n), n, name=name))
    out = tmp / f"out{n}"
    env = dict(os.environ, GYROCHAIN_CACHE=str(tmp / f"cache{n}"), XDG_CACHE_HOME=str(tmp / f"xdg{n}"))
    t0 = time.perf_counter()
    p = subprocess.run(["/usr/bin/time", "-f", "%M", sys.executable, "-m", "gyrochain", "generate", "-q", str(spec),
                        "-o", str(out)], env=env, capture_output=True, text=True)
    whole = time.perf_counter() - t0
    if p.returncode:
        raise SystemExit(f"n = {n}: gyrochain generate failed: {p.stderr.strip().splitlines()[-1]}")
    peak_kb = int(p.stderr.strip().splitlines()[-1])
    size = {f.suffix: f.stat().st_size for f in out.iterdir() if f.is_file()}
    return dict(n=n, whole_s=round(whole, 2), c_mb=round(size[".c"] / 1e6, 3),
                c_kb_per_link=round(size[".c"] / 1e3 / n, 1), latex_mb=round(size[".tex"] / 1e6, 3),
                peak_gb=round(peak_kb / 1e6, 3))


def main(ns: list[int]) -> None:
    rows = []
    with tempfile.TemporaryDirectory() as d:
        for n in ns:
            rows.append(one(n, Path(d)))
            print(rows[-1], flush=True)
    path = RESULTS / "generate.csv"
    write(path, rows, "")
    print(f"wrote {path.relative_to(ROOT)}")


if __name__ == "__main__":
    if not all(a.isdigit() for a in sys.argv[1:]):
        raise SystemExit(__doc__)
    main([int(a) for a in sys.argv[1:]] or [16, 32, 64, 128])
