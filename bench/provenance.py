"""Which machine measured each file of bench/results/, and when: bench/results/machines.csv.

Every benchmark that writes a CSV calls ``record``; docs/benchmarks.md names the machine and the
date of each table from this file (bench/report.py), so a table cannot claim another machine's
figures."""
from __future__ import annotations

import csv
import datetime
import os
from pathlib import Path

RESULTS = Path(__file__).resolve().parent / "results"
MACHINES = RESULTS / "machines.csv"
FIELDS = ("file", "cpu", "cores", "date", "flags")


def cpu() -> str:
    """The processor's model name, as /proc/cpuinfo gives it."""
    try:
        for ln in Path("/proc/cpuinfo").read_text().splitlines():
            if ln.startswith("model name"):
                return ln.split(":", 1)[1].strip()
    except OSError:
        pass
    return "unknown CPU"


def read() -> dict[str, dict]:
    if not MACHINES.exists():
        return {}
    with MACHINES.open(newline="") as fh:
        return {r["file"]: r for r in csv.DictReader(fh)}


def write(path: Path, rows: list[dict], flags: str = "") -> None:
    """Write ``rows`` as the CSV ``path`` of bench/results/ and record which machine measured them."""
    with Path(path).open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    record(path, flags)


def record(path: Path, flags: str = "") -> None:
    """Note that ``path`` (a file of bench/results/) was just measured on this machine, today."""
    rows = read()
    rows[Path(path).name] = dict(file=Path(path).name, cpu=cpu(), cores=str(os.cpu_count()),
                                 date=datetime.date.today().isoformat(), flags=flags)
    with MACHINES.open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=FIELDS)
        w.writeheader()
        w.writerows(sorted(rows.values(), key=lambda r: r["file"]))
