"""The generated models on a microcontroller-class target: cross-compiled for the Cortex-M4F
(arm-none-eabi-gcc -mcpu=cortex-m4 -mfpu=fpv4-sp-d16 -mfloat-abi=hard -Os, newlib) and run in QEMU's
MPS2 AN386 board (semihosting for the output); per example, in float and in double:

- the code size of the model's functions (arm-none-eabi-nm --size of the object) and of all of it;
- the worst-case stack of NAME_qdd and of an RK4 step through NAME_integrate (gcc -fcallgraph-info=su:
  each function's own frame summed along the deepest call chain, not counting newlib's sinf/cosf);
- the instructions per NAME_qdd call, counted by QEMU itself: run with -singlestep -d exec, every
  executed instruction is one logged translation block, and a program calling NAME_qdd three times
  runs (that count − the count with one call) / 2 instructions more (calibrated on a run of 1000 nops).

Prints the table of docs/embedding.md and writes every function's size to bench/results/embedded.csv
(`python bench/embedded.py`, about a minute); the helpers are
what tests/tools/test_m4.py builds and runs with.  Needs gcc-arm-none-eabi, libnewlib-arm-none-eabi
and qemu-system-arm (Debian's packages).
"""
from __future__ import annotations

import csv
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from provenance import record  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
M4 = ROOT / "examples" / "embed" / "m4"
CC = "arm-none-eabi-gcc"
FLAGS = ["-mcpu=cortex-m4", "-mfpu=fpv4-sp-d16", "-mfloat-abi=hard", "-mthumb", "-Os", "-std=c99"]
QEMU = ["qemu-system-arm", "-M", "mps2-an386", "-nographic", "-monitor", "none", "-serial", "none",
        "-semihosting-config", "enable=on,target=native"]


def available() -> str:
    """'' when the tools are here, else what is missing."""
    missing = [t for t in (CC, "arm-none-eabi-nm", "qemu-system-arm") if shutil.which(t) is None]
    if not missing and not Path("/usr/lib/arm-none-eabi/newlib/rdimon.specs").exists():
        missing.append("libnewlib-arm-none-eabi")
    return ", ".join(missing)


def build(sources, out: Path, include=(), defines=(), extra=()) -> Path:
    """A bare-metal ELF for the board: startup.c, the linker script, newlib with semihosting."""
    cmd = [CC, *FLAGS, "-Wall", "-Wextra", "-Wdouble-promotion", "-Wfloat-conversion", "-Werror", "--specs=rdimon.specs",
           "-T", str(M4 / "mps2_an386.ld"), *[f"-I{d}" for d in include], *[f"-D{d}" for d in defines], *extra,
           str(M4 / "startup.c"), *map(str, sources), "-lm", "-o", str(out)]
    res = subprocess.run(cmd, capture_output=True, text=True)
    if res.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)}\n{res.stderr}")
    return out


def run(elf: Path, trace: Path | None = None, timeout: float = 300) -> tuple[int, str]:
    """Run the ELF in QEMU: its exit status and what it printed (with ``trace``, every executed
    instruction logged there)."""
    cmd = QEMU + (["-singlestep", "-d", "exec,nochain", "-D", str(trace)] if trace else []) + ["-kernel", str(elf)]
    res = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    return res.returncode, res.stdout


def executed(elf: Path, work: Path) -> int:
    """The instructions the program executes, by QEMU's one-instruction trace."""
    log = work / (elf.stem + ".trace")
    code, out = run(elf, log)
    if code != 0:
        raise RuntimeError(f"{elf.name} exited {code}: {out}")
    with log.open("rb") as fh:
        n = sum(1 for line in fh if line.startswith(b"Trace"))
    log.unlink()
    return n


def per_call(program: str, include, work: Path, objects=(), defines=()) -> float:
    """Instructions per call of what ``program`` (C text) does CALLS times: (3 calls − 1 call) / 2."""
    src = work / "count.c"
    src.write_text(program)
    counts = []
    for calls in (1, 3):
        elf = build([src, *objects], work / f"count{calls}.elf", include, [f"CALLS={calls}", *defines])
        counts.append(executed(elf, work))
    return (counts[1] - counts[0]) / 2


NOPS = "void nops(void);\nint main(void) { int k; for (k = 0; k < CALLS; ++k) nops(); return 0; }\n" \
       "__attribute__((noinline)) void nops(void) { __asm volatile(" + '"nop\\n\\t"' * 1000 + "); }\n"


def calibrate(work: Path) -> float:
    """Instructions counted per call of a function of 1000 nops (1000 + the call, the return and
    the loop: 1005 or so, if the count is right)."""
    return per_call(NOPS, (), work)


def qdd_program(name: str, n: int, nu: int, params: dict | None, time_dependent: bool) -> str:
    """A program calling NAME_qdd CALLS times on a state that moves a little each time."""
    NAME = name.upper()
    init = ", ".join(f"({NAME}_REAL){float(v)!r}" for v in params.values()) if params else f"({NAME}_REAL)0"
    t = f"({NAME}_REAL)0.1, " if time_dependent else ""
    return (f'#include "{name}.h"\nint main(void)\n{{\n'
            f"    static {NAME}_REAL x[{2 * n}], u[{nu} + 1], q[{n}];\n"
            f"    {name}_params p = {{{init}}};\n    int k, i;\n"
            f"    for (i = 0; i < {2 * n}; ++i) x[i] = ({NAME}_REAL)0.1 * ({NAME}_REAL)(i + 1);\n"
            f"    for (k = 0; k < CALLS; ++k) {{\n        x[0] += ({NAME}_REAL)1e-3;\n"
            f"        if ({name}_qdd({t}x, u, &p, q) > 3) return 1;\n    }}\n"
            f"    return 0;\n}}\n")


def sizes(obj: Path, name: str) -> dict[str, int]:
    """Bytes of each function of the object (arm-none-eabi-nm --size), by name without the model's."""
    out = subprocess.run(["arm-none-eabi-nm", "--size-sort", "-S", str(obj)], capture_output=True, text=True, check=True).stdout
    got = {}
    for line in out.splitlines():
        parts = line.split()
        if len(parts) == 4 and parts[2] in "tT":
            got[re.sub(rf"^{name}_|\.constprop\.\d+$", "", parts[3])] = int(parts[1], 16)
    return got


def stack(ci: Path, entry: str) -> int:
    """The worst-case stack in bytes from ``entry`` down (gcc -fcallgraph-info=su), newlib not counted."""
    frames, calls = {}, {}
    text = ci.read_text()
    for title, label in re.findall(r'node: \{ title: "([^"]+)" label: "([^"]*)"', text):
        m = re.search(r"\\n(\d+) bytes", label)
        frames[title] = int(m.group(1)) if m else 0
    for src, dst in re.findall(r'edge: \{ sourcename: "([^"]+)" targetname: "([^"]+)"', text):
        calls.setdefault(src, set()).add(dst)
    memo: dict = {}

    def worst(f, seen=()):
        if f in memo:
            return memo[f]
        if f in seen:
            raise ValueError(f"recursion through {f}")
        below = max((worst(g, seen + (f,)) for g in calls.get(f, ())), default=0)
        memo[f] = frames.get(f, 0) + below
        return memo[f]

    return worst(entry)


def model_object(folder: Path, name: str, work: Path) -> tuple[Path, Path]:
    """The model's C compiled for the M4: the object and its call graph with frame sizes."""
    obj = work / f"{name}.o"
    subprocess.run([CC, *FLAGS, "-fcallgraph-info=su", "-c", str(folder / f"{name}.c"), "-o", str(obj)],
                   check=True, capture_output=True, cwd=work)
    return obj, work / f"{name}.ci"


def main() -> int:
    sys.path.insert(0, str(ROOT))
    sys.path.insert(0, str(ROOT / "tests"))
    from gyrochain import pipeline
    from gyrochain.spec import load_spec
    from conftest import SHORT_EXAMPLES, example_params

    missing = available()
    if missing:
        print(f"needs {missing} (apt-get install gcc-arm-none-eabi libnewlib-arm-none-eabi qemu-system-arm)")
        return 1
    rows = []  # every function's size, per example and real: bench/results/embedded.csv
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        cal = calibrate(work)
        print(f"calibration: a call of 1000 nops counts {cal:g} instructions\n")
        print("| example | real | qdd (bytes) | qdd_derivatives | integrate_grid | the whole model | stack: qdd | stack: RK4 step | instructions per qdd |")
        print("|---|---|---|---|---|---|---|---|---|")
        for name in SHORT_EXAMPLES:
            spec = load_spec(ROOT / "specs" / f"{name}.toml")
            for real in ("float", "double"):
                folder = work / real / name
                files, _ = pipeline.derive_and_render(spec, f"{name}.toml", targets=("c",), real=real)
                folder.mkdir(parents=True)
                for k, v in files.items():
                    (folder / k).write_text(v)
                obj, ci = model_object(folder, name, folder)
                sz = sizes(obj, name)
                total = sum(sz.values())
                rows += [dict(example=name, real=real, function=fn, bytes=b) for fn, b in sorted(sz.items())]
                qdd_stack = stack(ci, f"{name}_qdd")
                rk4_stack = stack(ci, f"{name}_integrate")
                params = example_params(name)
                prog = qdd_program(name, spec.n, len(spec.controls), params, "TIME_DEPENDENT 1" in files[f"{name}.h"])
                ins = per_call(prog, (folder,), folder, objects=(folder / f"{name}.c",))
                print(f"| {name} | {real} | {sz.get('qdd', 0):,} | {sz.get('qdd_derivatives', 0):,} | "
                      f"{sz.get('integrate_grid', 0):,} | {total:,} | {qdd_stack:,} | {rk4_stack:,} | {ins:,.0f} |", flush=True)
    out = ROOT / "bench" / "results" / "embedded.csv"
    with out.open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    record(out, "-Os")
    print(f"\nwrote {out.relative_to(ROOT)} (the size of every function)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
