"""A hanging cable of n uniform rods (specs/cable64.toml is n = 64) and Daniel Bernoulli's hanging
chain.

    python examples/cable.py            # the table of docs/derivatives.md, n = 8 ... 128
    python examples/cable.py --spec 64  # the spec text of specs/cable64.toml

Every link is a thin rod of length l = L/n and mass m = M/n (L = 2 m, M = 1 kg), hinged at its upper
end to the one above on parallel horizontal axes: a planar chain that hangs straight down at φ = 0.
Its small-oscillation frequencies come from `steady` (the linearisation of the generated C at the
equilibrium); as n grows they tend to those of the continuous hanging chain,
ωᵢ = (j₀,ᵢ / 2) √(g / L), j₀,ᵢ the zeros of the Bessel function J₀ (D. Bernoulli, 1733).
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

LENGTH, MASS, G = 2.0, 1.0, 9.81
SIZES = (8, 16, 32, 64, 128)
MODES = 3


def spec_text(n: int) -> str:
    """The spec of the n-link cable (n = 64 is specs/cable64.toml, byte for byte)."""
    l, m = LENGTH / n, MASS / n
    inv = round(12 / (m * l * l))  # I_c = m l² / 12 = 1/inv: an integer for these n
    out = [f'name = "cable{n}"',
           f'description = "A hanging cable of {n} uniform rods (total length L = 2 m, mass 1 kg): its small oscillations tend to '
           "Daniel Bernoulli's hanging chain, omega_i = (j0_i / 2) sqrt(g / L), j0_i the zeros of J0\"",
           f"g = {G}", "",
           f"# Each link: a thin rod of length l = L/{n} = {l} m and mass m = {m} kg, the joint at its upper end,",
           f"# its centre l/2 below, the next joint l below; I_c = m l^2 / 12 = 1/{inv} kg m^2 about the two",
           "# axes across it, 0 along it. The first axis is horizontal (theta = pi/2), the others parallel to it:",
           "# a planar chain, hanging straight down at phi = 0. Written by examples/cable.py --spec " + str(n) + ".", ""]
    for k in range(1, n + 1):
        out += ["[[body]]", 'theta = "pi/2"' if k == 1 else "theta = 0.0", f"m = {m!r}", f"c = [0.0, 0.0, {l / 2!r}]",
                f'I_c = ["1/{inv}", "1/{inv}", 0, 0, 0, 0]']
        if k < n:
            out.append(f"s = [0.0, 0.0, {l!r}]")
        out.append("")
    out += ["[initial]                # released at rest, straight, 0.5 rad from the vertical",
            "phi = [0.5" + ", 0.0" * (n - 1) + "]", "phidot = [" + ", ".join(["0.0"] * n) + "]"]
    return "\n".join(out) + "\n"


def bernoulli(modes: int = MODES) -> np.ndarray:
    """The continuous hanging chain's lowest angular frequencies (rad/s)."""
    from scipy.special import jn_zeros

    return jn_zeros(0, modes) / 2 * np.sqrt(G / LENGTH)


def frequencies(cmodel, model) -> np.ndarray:
    """The chain's small-oscillation angular frequencies at φ = 0, lowest first, from `steady`
    (the eigenvalues ±iω of the generated model's linearisation); raises if the equilibrium is not
    stable."""
    from gyrochain import steady

    st = steady.Analysis(cmodel, model).classify(np.zeros(model.spec.n))
    if not st.verdict.startswith("stable"):
        raise RuntimeError(f"the hanging cable is {st.verdict}: {st.reason}")
    return np.sort(st.eigenvalues.imag[st.eigenvalues.imag > 0])


def table(sizes=SIZES) -> str:
    from gyrochain import pipeline
    from gyrochain.spec import parse_spec

    wb = bernoulli()
    head = "| n | " + " | ".join(f"ω{i + 1} (rad/s)" for i in range(MODES)) + " | " + " | ".join(
        f"ω{i + 1} / Bernoulli − 1" for i in range(MODES)) + " |"
    rows = [head, "|" + "---|" * (2 * MODES + 1)]
    for n in sizes:
        cm, model = pipeline.compiled(parse_spec(spec_text(n)))
        w = frequencies(cm, model)[:MODES]
        rows.append(f"| {n} | " + " | ".join(f"{v:.6f}" for v in w) + " | "
                    + " | ".join(f"{v / b - 1:.2e}" for v, b in zip(w, wb)) + " |")
        print(rows[-1], flush=True)
    rows.append("| ∞ (Bernoulli) | " + " | ".join(f"{v:.6f}" for v in wb) + " | " + " | ".join("0" for _ in wb) + " |")
    return "\n".join(rows)


def links(text: str) -> int:
    n = int(text) if text.isdigit() else 0
    if n < 2:
        raise argparse.ArgumentTypeError(f"expected a number of links >= 2, got {text!r}")
    return n


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--spec", type=links, metavar="N", help="print the spec of the N-link cable and stop")
    ap.add_argument("--n", type=links, nargs="*", default=list(SIZES), help="the chain lengths of the table")
    args = ap.parse_args()
    if args.spec:
        sys.stdout.write(spec_text(args.spec))
        return 0
    print(table(args.n))
    return 0


if __name__ == "__main__":
    sys.exit(main())
