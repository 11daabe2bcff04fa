"""What the LaTeX says of where it comes from: the works it cites and its source line, and the
base parameters' section of ``generate --regressor``."""
from __future__ import annotations

import hashlib

import sympy as sp

from ..derive.assemble import Model
from .common import one_line, tex_escape
from .texlayout import DISPLAY_WIDTH, TexEquation
from .texterms import breaks, param_tex


def _coefficient(c) -> str:
    """An exact coefficient as a reviewer reads it: a decimal when it is one (lengths and their
    products), else a fraction; a numerical one as its double."""
    if isinstance(c, sp.Rational):
        q = int(c.q)
        while q % 2 == 0:
            q //= 2
        while q % 5 == 0:
            q //= 5
        if q == 1:
            text = format(sp.Float(abs(c), 30), "f").rstrip("0").rstrip(".")
        else:
            text = rf"\tfrac{{{abs(c.p)}}}{{{c.q}}}"
    else:
        text = f"{abs(float(c)):.15g}"
    return text


def base_parameters(model: Model) -> dict | None:
    """The base parameters' section (generate --regressor): π, and each βᵢ as a formula of it."""
    if model.reg is None:
        return None
    params, base = model.reg.params, model.base
    rows = []
    for i, row in enumerate(base.K):
        pieces = [("- " if float(c) < 0 else "") + (params[j].tex if abs(c) == 1 else rf"{_coefficient(abs(c))}\,{params[j].tex}")
                  for j, c in row]
        rows.append(TexEquation(rf"\beta_{{{i + 1}}}", tuple(breaks(pieces, DISPLAY_WIDTH))))
    return dict(
        pi=r",\allowbreak ".join(p.tex for p in params),
        count=len(params),
        nbase=base.count,
        rows=rows,
        numerical=[i + 1 for i, flag in enumerate(base.numerical) if flag],
        damping=any(p.kind == "b" for p in params),
        at=", ".join(f"${param_tex(name)} = {value:g}$" for name, value in base.at),
        rotors=any(p.kind == "lam" for p in params),
    )


# the works a document cites: the paper and the one it builds on always, the others where the
# document uses them (Nikolai's quadratures) or the spec's description names them
REFERENCES = {
    "paper": r"\emph{Sostavnoi prostranstvennyi mayatnik} [A compound spatial pendulum], in a collection on rigid-body dynamics "
             r"from Donetsk that also holds [2].  Our copy of the paper gives neither its authors nor its year, volume or pages.",
    "kharlamov": r"P.~V.~Kharlamov, \emph{On the equations of motion of a system of rigid bodies}, in the same collection as [1].",
    "gyrochain": r"The gyrochain developers, \emph{gyrochain {version}: equations of compound spatial pendulums, generated}, "
                 r"software, MIT licence (its \texttt{CITATION.cff} says how to cite it).",
    "nikolai": r"E.~L.~Nikolai, \emph{On the motion of a balanced gyroscope in a Cardan suspension}, Prikladnaya Matematika i Mekhanika (PMM) 3(4), 1939.",
    "kapitza": r"P.~L.~Kapitza, \emph{Dynamic stability of a pendulum when its point of suspension vibrates}, Zh. Eksp. Teor. Fiz. 21 (1951) 588--597.",
    "floquet": r"G.~Floquet, \emph{Sur les \'equations diff\'erentielles lin\'eaires \`a coefficients p\'eriodiques}, Ann. Sci. \'Ec. Norm. Sup. 12 (1883) 47--88.",
    "mathieu": r"\'E.~Mathieu, \emph{M\'emoire sur le mouvement vibratoire d'une membrane de forme elliptique}, J. Math. Pures Appl. 13 (1868) 137--203.",
    "ziegler": r"H.~Ziegler, \emph{Die Stabilit\"atskriterien der Elastomechanik}, Ingenieur-Archiv 20 (1952) 49--56.",
}


def references(model: Model) -> list[str]:
    """The keys of REFERENCES this document cites, in the order of their numbers."""
    keys = ["paper", "kharlamov"]
    if model.quad is not None and model.quad.nikolai or "nikolai" in model.spec.description.lower():
        keys.append("nikolai")
    keys += [k for k in ("kapitza", "floquet", "mathieu", "ziegler") if k in model.spec.description.lower()]
    return keys + ["gyrochain"]


def reference_texts(model: Model, version: str) -> list[str]:
    """The references' list as the document prints it, numbered in this order."""
    return [REFERENCES[k].replace("{version}", tex_escape(version)) for k in references(model)]


def source_text(model: Model, context: dict) -> str:
    """Where the document comes from: the paper and the works it builds on, the spec and its
    sha256, the generator's and sympy's versions (the same facts as MANIFEST.json)."""
    spec, cited = model.spec, references(model)
    named = [k for k in cited[2:-1] if k != "nikolai" or model.quad is None or not model.quad.nikolai]
    nikolai = "nikolai" in cited and model.quad is not None and model.quad.nikolai
    return (rf"Derived from the spec \texttt{{{tex_escape(one_line(context['label']))}}} "
            rf"(sha256 \texttt{{{hashlib.sha256(spec.source.encode('utf-8')).hexdigest()[:16]}}}\dots) by gyrochain "
            rf"{tex_escape(context['gyrochain_version'])} [{len(cited)}] with sympy {tex_escape(context['sympy_version'])}, following the paper "
            r"\emph{The compound spatial pendulum} [1], whose equations of motion build on Kharlamov's [2]"
            + (rf"; the quadratures of the balanced gyroscope follow Nikolai [{cited.index('nikolai') + 1}]" if nikolai else "")
            + (r". The description names " + ", ".join(f"[{cited.index(k) + 1}]" for k in named) if named else "") + ".")
