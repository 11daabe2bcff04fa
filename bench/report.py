"""The tables and charts of docs/benchmarks.md (and the integrators' charts of docs/integrators.md),
drawn from the CSV files of bench/results/ alone.

    python bench/report.py            rewrite the tables of docs/benchmarks.md, draw the charts
    python bench/report.py --check    exit 1 if a table or a chart differs from what the CSVs give

`make plot` runs it.  A table of the page sits between ``<!-- table: NAME -->`` and
``<!-- /table -->`` and is rewritten whole, with a line that names the machine, the date and the
flags of its measurement (bench/results/machines.csv, written by the benchmark that measured it).
A chart carries in its PNG text the files it was drawn from and their SHA-256, so a chart drawn
from other figures than its table's is found (tests/tools/test_docs.py)."""
from __future__ import annotations

import csv
import hashlib
import re
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "bench"))
sys.path.insert(0, str(ROOT / "examples"))

from phone_figures import phone_path, save_phone  # noqa: E402
from provenance import RESULTS, read as read_machines  # noqa: E402

PAGE = ROOT / "docs" / "benchmarks.md"
QDD = r"$\ddot\varphi$"
JACOBIAN = r"$\partial\ddot\varphi/\partial(\varphi, \dot\varphi)$"
MACHINES = {"AMD EPYC": "A", "Intel Xeon": "B", "Intel(R) Xeon(R) Processor": "C"}  # each machine's letter on the page


def rows(*files: str) -> list[dict]:
    out = []
    for f in files:
        with (RESULTS / f).open(newline="") as fh:
            out += list(csv.DictReader(fh))
    return out


def num(r: dict, key: str) -> float | None:
    v = r.get(key, "")
    return float(v) if v not in ("", None) else None


def ns(v: float | None) -> str:
    return "—" if v is None else f"{v:,.0f}"


def ratio(v: float | None) -> str:
    return "—" if v is None else f"{v:.2f}"


def sec(v: float | None) -> str:
    return "—" if v is None else f"{v:.1f} s"


def err(v: float | None) -> str:
    return "—" if v is None else f"{v:.1e}"


def machine_letter(cpu: str) -> str:
    for name, letter in MACHINES.items():
        if cpu.startswith(name):
            return letter
    return "?"


def provenance(files: tuple[str, ...]) -> str:
    """One line under a table: where and when its files were measured, and the files."""
    known = read_machines()
    parts = []
    for f in files:
        m = known.get(f)
        if m is None:
            raise SystemExit(f"bench/results/machines.csv: no line for {f} (which machine measured it?)")
        parts.append((machine_letter(m["cpu"]), m["date"], m["flags"]))
    if len(set(p[0] for p in parts)) != 1:
        raise SystemExit(f"one table, one machine: {', '.join(files)} come from machines {sorted(set(p[0] for p in parts))}")
    dates = sorted(set(p[1] for p in parts))
    flags = sorted(set(p[2] for p in parts if p[2]))
    where = f"Machine {parts[0][0]}, {' and '.join(dates)}"
    if flags:
        where += ", " + "; ".join(f"`{f}`" for f in flags)
    return f"*{where}. Data: {', '.join(f'`bench/results/{f}`' for f in files)}.*"


def markdown(header: list[str], body: list[list[str]]) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(r) + " |" for r in body]
    return "\n".join(lines)


@dataclass(frozen=True)
class Table:
    files: tuple[str, ...]
    render: Callable[[list[dict]], tuple[list[str], list[list[str]]]]

    def text(self) -> str:
        header, body = self.render(rows(*self.files))
        return markdown(header, body) + "\n\n" + provenance(self.files)


PEERS = (("casadi", "CasADi"), ("pinocchio", "Pinocchio"), ("mujoco", "MuJoCo"))


def best_peer(r: dict) -> tuple[str, float]:
    found = [(num(r, f"{k}_ns"), name) for k, name in PEERS if num(r, f"{k}_ns") is not None]
    v, name = min(found)
    return name, v


def _qdd(rs):
    header = ["n", "ours (ns)", "CasADi (ns)", "Pinocchio ABA (ns)", r"MuJoCo, $\lambda = 0$ (ns)", "best peer / ours",
              "ours (instructions)", "fewest of a peer (instructions)", "peer / ours, instructions"]
    body = []
    for r in rs:
        fewest = min(v for v in (num(r, f"{k}_instructions") for k, _ in PEERS) if v is not None)
        body.append([r["n"], ns(num(r, "ours_ns")), ns(num(r, "casadi_ns")), ns(num(r, "pinocchio_ns")),
                     ns(num(r, "mujoco_ns")), f"**{ratio(num(r, 'best_peer_over_ours'))}**",
                     ns(num(r, "ours_instructions")), ns(fewest), ratio(fewest / num(r, "ours_instructions"))])
    return header, body


def _qdd_O2(rs):
    header = ["n", "ours (ns)", "CasADi (ns)", "Pinocchio ABA (ns)", r"MuJoCo, $\lambda = 0$ (ns)", "best peer / ours",
              "derive + emit", "gcc -O2 -c", "C per link"]
    return header, [[r["n"], ns(num(r, "ours_ns")), ns(num(r, "casadi_ns")), ns(num(r, "pinocchio_ns")),
                     ns(num(r, "mujoco_ns")), f"**{ratio(num(r, 'best_peer_over_ours'))}**", sec(num(r, "gen_s")),
                     sec(num(r, "cc_s")), f"{num(r, 'c_kb_per_link'):.0f} KB"] for r in rs]


def _jacobian(rs):
    header = ["n", "ours (ns)", r"Pinocchio `computeABADerivatives`, $\lambda = 0$ (ns)", "Pinocchio / ours",
              f"central differences of our {QDD} (ns)", "our error", "Pinocchio's error"]
    return header, [[r["n"], ns(num(r, "ours_ns")), ns(num(r, "pinocchio_ns")),
                     f"**{ratio(num(r, 'pinocchio_ns') / num(r, 'ours_ns'))}**", ns(num(r, "fd_ns")),
                     err(num(r, "ours_err")), err(num(r, "pinocchio_err"))] for r in rs]


def _robots(rs):
    header = ["arm", "n", "derive + emit", f"operations of {QDD} / M / Jacobian", f"{QDD} ours (ns)",
              "Pinocchio on its URDF model (ns)", "Pinocchio / ours", "largest difference"]
    names = {"ur5": "UR5", "panda": "Panda"}
    return header, [[names.get(r["arm"], r["arm"]), r["n"], f"{float(r['derive_emit_s']):.2f} s",
                     f"{r['qdd_ops']} / {r['mass_matrix_ops']} / {r['derivatives_ops']}", ns(num(r, "ours_ns")),
                     ns(num(r, "pinocchio_ns")), f"**{ratio(num(r, 'pinocchio_over_ours'))}**", r["agree"]]
                    for r in rs]


def _scenes(rs):
    header = ["scene (n = 8, the same random draws)", "mass matrix", "forces", QDD, f"{QDD} against the general scene"]
    return header, [[r["scene"], r["mass_matrix"], r["forces"], r["qdd"], ratio(num(r, "qdd_vs_general"))] for r in rs]


def _generate(rs):
    header = ["n", "whole command", "C", "C per link", "LaTeX", "peak memory"]
    return header, [[r["n"], sec(num(r, "whole_s")), f"{float(r['c_mb']):.2f} MB", f"{float(r['c_kb_per_link']):.0f} KB",
                     f"{float(r['latex_mb']):.2f} MB", f"{float(r['peak_gb']):.2f} GB"] for r in rs]


def _loops(rs):
    header = ["n", "C size", "gcc time", "mass matrix", "energy", "momenta", "velocities from momenta", "rate of the momenta"]
    keys = ("c_size", "gcc_time", "mass_matrix", "energy", "momenta", "velocities", "pdot")
    return header, [[r["n"], *(ratio(num(r, k)) for k in keys)] for r in rs]


def _ensemble(rs):
    header = ["implementation", "integrator", "where", "trajectories per second"]
    return header, [[r["implementation"].replace("NAME_integrate_batch", "`NAME_integrate_batch`"),
                     r["integrator"].replace("h = 0.001", "h = 1 ms"), r["where"].replace("thread(s)", "thread(s)"),
                     f"{float(r['traj_per_s']):,.1f}"] for r in rs]


def _lanes(rs):
    header = ["model", "flags", "one trajectory at a time (RK4)", "RK4, batch", "RK4_LANES, batch", "RK4_LANES, one trajectory"]
    names = {"double_pendulum": "double pendulum", "furuta": "Furuta", "spatial3": "spatial3", "ur5": "UR5"}

    def flags(f):
        return "`-O3 -march=native`" if "march" in f else "`-O2` (the product's)"
    body = []
    for r in rs:
        single = num(r, "rk4_single_ns")
        body.append([names.get(r["model"], r["model"]), flags(r["flags"]), f"{single:.0f}",
                     f"{num(r, 'rk4_batch_ns'):.0f} ({single / num(r, 'rk4_batch_ns'):.2f}×)",
                     f"**{num(r, 'rk4_lanes_batch_ns'):.0f} ({single / num(r, 'rk4_lanes_batch_ns'):.2f}×)**",
                     f"{num(r, 'rk4_lanes_single_ns'):.0f}"])
    return header, body


def _casadi_ocp(rs):
    header = ["problem", "model", "IPOPT iterations", "ms per iteration", "constraints (µs)", "their Jacobian (µs)",
              "Lagrangian's Hessian (µs)", "per iteration, to CasADi SX expand", "setup before IPOPT (s)"]
    body = [[r["problem"], r["model"], r["iterations"], r["per_iteration_ms"], r["constraints_us"], r["jacobian_us"],
             r["hessian_us"], f"{num(r, 'ratio'):.2f}×", r["setup_s"]] for r in rs if r["iterations"]]
    return header, body


def _casadi_nmpc(rs):
    header = ["model", "ms per control step (median)", "to CasADi SX expand", "tilt at the end (rad)"]
    body = [[r["model"], r["per_iteration_ms"], f"{num(r, 'ratio'):.2f}×", r["cost"]] for r in rs if not r["iterations"]]
    return header, body


def _gpu(rs):
    header = ["model", "n", "real", "GPU (trajectory-steps/s)", "all CPU cores (trajectory-steps/s)", "GPU / CPU",
              "largest difference from the CPU", "same codes"]
    names = {"double_pendulum": "double pendulum", "ur5": "UR5", "panda": "Panda", "random16": "random spatial chain"}
    def rate(v):
        return f"{float(v):.3g}".replace("e+0", "e").replace("e+", "e")
    body = [[names.get(r["model"], r["model"]), r["n"], r["real"], rate(r["gpu_steps_per_s"]),
             f"{rate(r['cpu_steps_per_s'])} ({r['cores']} cores)" if r["cpu_steps_per_s"] else "—",
             f"**{r['ratio']}×**" if r["ratio"] else "—", r["max_rel_diff"], "yes" if r["codes_equal"] == "True" else "no"]
            for r in rs]
    return header, body


def _measured(f: str, flags: str | None = None) -> str:
    """Machine, date and flags of a file of bench/results/, for a row of the summary; ``flags`` where
    the row's are not the file's (a file whose rows name their own)."""
    m = read_machines()[f]
    flags = m["flags"] if flags is None else flags
    return f"{machine_letter(m['cpu'])}, {m['date']}" + (f", `{flags}`" if flags else "")


def _ratio(peer: float, ours: float) -> str:
    """The peer's time over ours: bold where ours is faster, "(behind)" where the peer is."""
    r = peer / ours
    return f"**{r:.{0 if r >= 10 else 1}f}×**" if r >= 1 else f"{r:.2f}× (behind)"


def _summary_losses() -> list:
    """The rows where a peer is ahead or its compiled form was measured too: the Jacobian at n = 64
    with -O2, and IPOPT per iteration against CasADi SX compiled (jit) on the small problems."""
    jac = {int(r["n"]): r for r in rows("derivatives.csv")}[64]
    out = [[f"[the Jacobian {JACOBIAN}, 64 gyrostats, `-O2`](#derivatives)", f"{num(jac, 'ours_ns'):,.0f} ns",
            f"{num(jac, 'pinocchio_ns'):,.0f} ns (Pinocchio)", _ratio(num(jac, "pinocchio_ns"), num(jac, "ours_ns")),
            _measured("derivatives.csv")]]
    ocp = rows("casadi_ocp.csv")
    for problem, what in (("Furuta swing-up", "an IPOPT iteration, Furuta swing-up"),
                          ("two-link arm swing-up", "an IPOPT iteration, two-link arm"),
                          ("UR5 point to point within its limits", "an IPOPT iteration, UR5 within its limits"),
                          ("Furuta NMPC, per control step", "an NMPC control step, Furuta pendulum")):
        mine = next(r for r in ocp if r["problem"] == problem and r["model"].startswith("gyrochain"))
        peers = [r for r in ocp if r["problem"] == problem and r["model"].startswith("CasADi")]
        best = min(peers, key=lambda r: num(r, "per_iteration_ms"))
        out.append([f"[{what}, exact Hessians](#optimal-control)", f"{num(mine, 'per_iteration_ms'):g} ms",
                    f"{num(best, 'per_iteration_ms'):g} ms ({best['model']})",
                    _ratio(num(best, "per_iteration_ms"), num(mine, "per_iteration_ms")), _measured("casadi_ocp.csv", "")])
    return out


def _summary(_):
    sp = rows("speed_O3_march_native.csv", "speed_O3_march_native_64_128.csv")
    at = {int(r["n"]): r for r in sp}
    jac = {int(r["n"]): r for r in rows("derivatives_O3_march_native.csv")}
    arm = {r["arm"]: r for r in rows("robots.csv")}
    ens = rows("ensemble.csv")
    gen = {int(r["n"]): r for r in rows("generate.csv")}
    out = []
    for n, f in ((8, "speed_O3_march_native.csv"), (128, "speed_O3_march_native_64_128.csv")):
        peer, v = best_peer(at[n])
        out.append([f"[{QDD}, random spatial chain of {n} gyrostats](#forward-dynamics)", f"{num(at[n], 'ours_ns'):,.0f} ns",
                    f"{v:,.0f} ns ({peer})", _ratio(v, num(at[n], "ours_ns")), _measured(f)])
    j = jac[32]
    out.append([f"[the Jacobian {JACOBIAN}, 32 gyrostats](#derivatives)", f"{num(j, 'ours_ns'):,.0f} ns",
                f"{num(j, 'pinocchio_ns'):,.0f} ns (Pinocchio)", _ratio(num(j, "pinocchio_ns"), num(j, "ours_ns")),
                _measured("derivatives_O3_march_native.csv")])
    u = arm["ur5"]
    out.append([f"[{QDD} of the UR5, imported from its URDF](#imported-arms)", f"{num(u, 'ours_ns'):,.0f} ns",
                f"{num(u, 'pinocchio_ns'):,.0f} ns (Pinocchio)", _ratio(num(u, "pinocchio_ns"), num(u, "ours_ns")),
                _measured("robots.csv")])

    def pick(impl, integ, where):
        return next(float(r["traj_per_s"]) for r in ens if r["implementation"].startswith(impl)
                    and r["integrator"].startswith(integ) and r["where"].startswith(where))
    ours = pick("ours, NAME", "RK4_LANES", "2 thread")
    mj = pick("MuJoCo", "RK4", "2 thread")
    out.append(["[double pendulums of 10 s, RK4 at 1 ms, both cores](#ensembles) (trajectories per second)", f"{ours:,.0f}",
                f"{mj:,.1f} (MuJoCo `rollout`)", f"**{ours / mj:.0f}×**", _measured("ensemble.csv", "-O2")])
    out += _summary_losses()
    g = gen[128]
    out.append(["[`gyrochain generate` of a chain of 128 gyrostats](#long-chains), build included", sec(num(g, "whole_s")),
                "—", "—", _measured("generate.csv")])
    # the key figure, the ratio, second: in sight on a phone, where the table scrolls
    return ["", "the peer's time / ours", "ours", "the fastest peer", "machine, date, flags"], \
        [[r[0], r[3], r[1], r[2], r[4]] for r in out]


TABLES: dict[str, Table] = {
    "summary": Table(("speed_O3_march_native.csv", "speed_O3_march_native_64_128.csv", "derivatives_O3_march_native.csv",
                      "robots.csv", "ensemble.csv", "derivatives.csv", "casadi_ocp.csv", "generate.csv"), _summary),
    "qdd": Table(("speed_O3_march_native.csv", "speed_O3_march_native_64_128.csv"), _qdd),
    "qdd-O2": Table(("speed.csv",), _qdd_O2),
    "jacobian": Table(("derivatives_O3_march_native.csv",), _jacobian),
    "jacobian-O2": Table(("derivatives.csv",), _jacobian),
    "robots": Table(("robots.csv",), _robots),
    "scenes": Table(("scenes.csv",), _scenes),
    "generate": Table(("generate.csv",), _generate),
    "loops": Table(("loops.csv",), _loops),
    "ensemble": Table(("ensemble.csv",), _ensemble),
    "lanes": Table(("lanes.csv",), _lanes),
    "casadi-ocp": Table(("casadi_ocp.csv",), _casadi_ocp),
    "casadi-nmpc": Table(("casadi_ocp.csv",), _casadi_nmpc),
    "gpu": Table(("gpu.csv",), _gpu),
}

_BLOCK = re.compile(r"(<!-- table: ([\w-]+) -->\n)(.*?)(<!-- /table -->)", re.S)


def _summary_provenance(files: tuple[str, ...]) -> str:
    known = read_machines()
    letters = sorted({machine_letter(known[f]["cpu"]) for f in files})
    dates = sorted({known[f]["date"] for f in files})
    return f"*Each row is a row of the table it links to, which names its CSV file (machine {', '.join(letters)}, {dates[0]} to {dates[-1]}).*"


def page(text: str) -> str:
    """The page with every table block rewritten from the CSVs."""
    def one(m):
        name = m.group(2)
        if name not in TABLES:
            raise SystemExit(f"docs/benchmarks.md: no table called {name!r} in bench/report.py")
        t = TABLES[name]
        if name == "summary":
            header, body = t.render([])
            body_text = markdown(header, body) + "\n\n" + _summary_provenance(t.files)
        else:
            body_text = t.text()
        return m.group(1) + body_text + "\n" + m.group(4)
    return _BLOCK.sub(one, text)


# ---- charts ---------------------------------------------------------------------------------------------------------

def sha(files: tuple[str, ...]) -> str:
    return " ".join(f"{f}:{hashlib.sha256((RESULTS / f).read_bytes()).hexdigest()[:16]}" for f in files)


def _axes(ax, xs, ylabel):
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xticks(xs, [str(x) for x in xs])
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.yaxis.set_major_locator(LogLocator(base=10))
    ax.yaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:,.0f}" if v >= 1 else f"{v:g}"))
    ax.yaxis.set_minor_formatter(NullFormatter())
    ax.set_xlabel("bodies n", fontsize=12)
    ax.set_ylabel(ylabel, fontsize=12)
    ax.tick_params(labelsize=11)
    ax.grid(True, which="major", alpha=0.35)


def _chart_qdd(plt, rs):
    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4.4))
    for key, label, style in (("ours", "ours (generated C)", "o-"), ("casadi", "CasADi's generated C", "s--"),
                              ("pinocchio", "Pinocchio ABA", "^--"), ("mujoco", "MuJoCo, λ = 0", "v--")):
        for ax, col in ((a, f"{key}_ns"), (b, f"{key}_instructions")):
            pts = [(int(r["n"]), num(r, col)) for r in rs if num(r, col) is not None]
            ax.plot(*zip(*pts), style, label=label, lw=2 if key == "ours" else 1.3)
    xs = [int(r["n"]) for r in rs]
    _axes(a, xs, "ns per call")
    _axes(b, xs, "instructions per call")
    a.set_title("time (median)", fontsize=12)
    b.set_title("instructions (callgrind)", fontsize=12)
    a.legend(fontsize=11)
    fig.tight_layout()
    return fig


def _chart_jacobian(plt, rs):
    fig, a = plt.subplots(figsize=(6.4, 4.4))
    for key, label, style in (("ours", "ours (generated C)", "o-"), ("pinocchio", "Pinocchio, λ = 0", "^--"),
                              ("fd", "central differences of our φ̈", "s:")):
        a.plot([int(r["n"]) for r in rs], [num(r, f"{key}_ns") for r in rs], style, label=label,
               lw=2 if key == "ours" else 1.3)
    _axes(a, [int(r["n"]) for r in rs], "ns per Jacobian")
    a.legend(fontsize=11)
    fig.tight_layout()
    return fig


def _chart_generation(plt, rs):
    fig, a = plt.subplots(figsize=(6.4, 4.4))
    xs = [int(r["n"]) for r in rs]
    a.plot(xs, [num(r, "cc_s") for r in rs], "s--", label="gcc -O2 -c of the C", lw=1.3)
    a.plot(xs, [num(r, "gen_s") for r in rs], "o-", label="derive + emit", lw=2)
    _axes(a, xs, "seconds")
    a.legend(fontsize=11)
    fig.tight_layout()
    return fig


def _series(rs, x, y, **match):
    """The (x, y) points of the rows that match, sorted by x; y floored at 1e-17 for a log axis."""
    pts = sorted((float(r[x]), max(float(r[y]), 1e-17)) for r in rs if all(r[k] == v for k, v in match.items()))
    return [p[0] for p in pts], [p[1] for p in pts]


def _log_axes(ax, xlabel, ylabel):
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(xlabel, fontsize=12)
    ax.set_ylabel(ylabel, fontsize=12)
    ax.tick_params(labelsize=11)
    ax.grid(True, which="major", alpha=0.35)


def _chart_work_precision(plt, rs):
    style = {("DOP853", "C"): ("C0", "o-"), ("RK4", "C"): ("C1", "s-"), ("GAUSS2", "C"): ("C2", "D-"),
             ("RK45", "Python"): ("C3", "v:"), ("DOP853", "Python"): ("C4", "^:"), ("Radau", "Python"): ("C5", "<:"),
             ("RK45", "cffi C"): ("C3", "v--"), ("DOP853", "cffi C"): ("C4", "^--"), ("Radau", "cffi C"): ("C5", "<--")}
    titles = {"gimbal": "gimbal, 10 periods", "spatial3": "spatial3, chaotic, 2 s", "fast_gyro": "fast_gyro, 1 s"}
    fig, axes = plt.subplots(3, 2, figsize=(10, 12.5))
    for i, (pb, title) in enumerate(titles.items()):
        for (m, d), (col, ls) in style.items():
            label = f"{m}, " + ("the emitted C" if d == "C" else f"scipy on the {'Python' if d == 'Python' else 'C'} rhs")
            for j, x in enumerate(("seconds", "n_rhs")):
                xs, ys = _series(rs, x, "error", problem=pb, method=m, driver=d)
                if xs:
                    axes[i, j].plot(xs, ys, ls, color=col, ms=4, label=label)
        _log_axes(axes[i, 0], "wall time (s)", f"{title}: relative error at t1")
        _log_axes(axes[i, 1], "right-hand-side evaluations", "")
    fig.legend(*axes[0, 0].get_legend_handles_labels(), loc="lower center", ncol=3, fontsize=11, frameon=False)
    fig.tight_layout(rect=(0, 0.08, 1, 1))
    return fig


def _chart_drift(plt, rs):
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.6))
    for m in sorted({r["method"] for r in rs}):
        axes[0].plot(*_series(rs, "periods", "energy_error", method=m), label=m)
        axes[1].plot(*_series(rs, "periods", "momentum_error", method=m), label=m)
    _log_axes(axes[0], "gimbal periods", "relative energy error")
    _log_axes(axes[1], "gimbal periods", "relative momentum (27) error")
    axes[0].legend(fontsize=11)
    fig.tight_layout()
    return fig


def _chart_symplectic(plt, rs):
    colours = {"GAUSS2": "C2", "GAUSS2_SYMPLECTIC": "C3", "DOP853": "C0"}
    labels = {"GAUSS2": "GAUSS2", "GAUSS2_SYMPLECTIC": "GAUSS2_SYMPLECTIC", "DOP853": "DOP853 at 1e-10"}
    fig, grid = plt.subplots(2, 2, figsize=(8.0, 7.2))  # the fourth cell holds the legend: legible at a page's 672 px
    axes, key = [grid[0, 0], grid[0, 1], grid[1, 0]], grid[1, 1]
    for m in colours:
        axes[0].plot(*_series(rs, "time", "energy_error", system="gyrostat2", method=m), color=colours[m], label=labels[m])
        axes[1].plot(*_series(rs, "time", "momentum_error", system="gyrostat2", method=m), color=colours[m])
        axes[2].plot(*_series(rs, "time", "energy_error", system="spatial3", method=m), color=colours[m])
    _log_axes(axes[0], "periods", "relative error")
    _log_axes(axes[1], "periods", "")
    _log_axes(axes[2], "time (s)", "")
    axes[0].set_title("gyrostat2: energy", fontsize=12)
    axes[1].set_title("gyrostat2: momentum (27)", fontsize=12)
    axes[2].set_title("spatial3, chaotic: energy", fontsize=12)
    key.axis("off")
    key.legend(*axes[0].get_legend_handles_labels(), loc="center", fontsize=11, frameon=False)
    fig.tight_layout()
    return fig


@dataclass(frozen=True)
class Chart:
    files: tuple[str, ...]
    draw: Callable


CHARTS: dict[str, Chart] = {
    "qdd.png": Chart(TABLES["qdd"].files, _chart_qdd),
    "jacobian.png": Chart(TABLES["jacobian"].files, _chart_jacobian),
    "generation.png": Chart(TABLES["qdd-O2"].files, _chart_generation),
    "work_precision.png": Chart(("work_precision.csv",), _chart_work_precision),  # on docs/integrators.md
    "drift.png": Chart(("drift.csv",), _chart_drift),
    "drift_symplectic.png": Chart(("drift_symplectic.csv",), _chart_symplectic),
}


def draw(name: str, out: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    c = CHARTS[name]
    fig = c.draw(plt, rows(*c.files))  # laid out by its drawing function
    fig.savefig(out, dpi=100, metadata={"Source": sha(c.files), "Software": None})
    save_phone(fig, out, {"Source": sha(c.files)})  # X.phone.png, shown on a phone
    plt.close(fig)


def png_source(path: Path) -> str | None:
    """The ``Source`` text of a PNG (the files a chart was drawn from, with their hashes)."""
    data = path.read_bytes()
    i = 8
    while i < len(data):
        length = int.from_bytes(data[i:i + 4], "big")
        kind = data[i + 4:i + 8]
        if kind == b"tEXt":
            key, _, value = data[i + 8:i + 8 + length].partition(b"\0")
            if key == b"Source":
                return value.decode("latin-1")
        i += 12 + length
    return None


def check() -> list[str]:
    """What differs between the page, the charts and the CSVs (empty when nothing does)."""
    problems = []
    text = PAGE.read_text(encoding="utf-8")
    if page(text) != text:
        problems.append("docs/benchmarks.md: a table differs from its CSV (python bench/report.py rewrites it)")
    for name, c in CHARTS.items():
        for drawn in (RESULTS / name, phone_path(RESULTS / name)):
            src = png_source(drawn) if drawn.exists() else None
            if src != sha(c.files):
                problems.append(f"bench/results/{drawn.name}: drawn from {src or 'unrecorded data'}, not from the "
                                f"current {', '.join(c.files)}")
    return problems


def main(argv: list[str]) -> int:
    if argv == ["--check"]:
        problems = check()
        print("\n".join(problems) or "the tables and charts of docs/benchmarks.md are their CSVs")
        return 1 if problems else 0
    text = PAGE.read_text(encoding="utf-8")
    PAGE.write_text(page(text), encoding="utf-8")
    for name in CHARTS:
        draw(name, RESULTS / name)
    print(f"rewrote the tables of {PAGE.relative_to(ROOT)}; drew {', '.join(CHARTS)} in {RESULTS.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
