"""What a document says of the energy (23) and the momentum (27), in words, from the model's
facts (integrals.Integrals) that also set the header's flags and generate's report."""
from __future__ import annotations

from ..derive.assemble import Model
from . import textype
from .texterms import param_tex


def _joined(reasons, params: dict) -> str:
    """The facts' reasons (plain text, as the CLI prints them) in the document's type (textype):
    O1, l1 as $O^1$, $l^1$, a field such as body[2].force[1] as code."""
    words = textype.in_words(reasons)
    joined = words[0] if len(words) == 1 else "; ".join(words[:-1]) + " and " + words[-1]
    return textype.typeset(joined, params)


def statements(model: Model) -> dict:
    """What the document says of the energy (23) and the momentum (27): from the same facts
    (integrals.Integrals) that set the header's HAS_ENERGY_INTEGRAL, HAS_MOMENTUM_INTEGRAL and
    generate's report; each verdict is one sentence "... is an integral of this model" or "... is
    not an integral of this model: <why>"."""
    spec, facts = model.spec, model.integrals
    params = {p.name: param_tex(p.name) for p in spec.params}
    extra = ""
    if facts.U_extra:
        springs = [w for w, _ in facts.U_extra if "spring" in w]
        kinds = ([r"for a spring $-\tfrac12\kappa^k(\varphi^k-\varphi^k_{\mathrm{rest}})^2$"] if springs else []) + (
            ["for a constant force fixed in space the force dotted with the position of its point from $O^1$"]
            if len(springs) < len(facts.U_extra) else [])
        extra = (r"$U$ includes the force function of " + ", ".join(textype.typeset(w, params) for w, _ in facts.U_extra)
                 + " (" + "; ".join(kinds) + ").  ")
    if facts.has_energy_integral:
        why = (r"the base is fixed, every $\boldsymbol\lambda^k$ is constant, no control torque acts"
               + (", no joint has a damper or a torque expression, and no load but gravity, springs and constant "
                  "forces fixed in space does work" if spec.general else ", and gravity is the only load"))
        energy = extra + f"The energy, the paper's (23), is an integral of this model: {why}."
    elif all(r.startswith("control torques") for r in facts.energy_reasons):
        joints = ", ".join(str(k) for k in spec.controls)
        energy = extra + (r"The energy, the paper's (23), is not an integral of this model for every input: it is conserved when the "
                          rf"control torques vanish ($L^k = 0$), and in general $\dot E = \sum_k L^k\dot\varphi^k$, over the controlled "
                          rf"joint{'s' if len(spec.controls) > 1 else ''} {joints}.")
    else:
        energy = extra + f"The energy, the paper's (23), is not an integral of this model: work is done by {_joined(facts.energy_reasons, params)}."
    K = r"$\hat{\mathbf e}^1_1\cdot\mathbf K_{O^1}$"
    if facts.momentum is None:
        intro = None
        momentum = r"The momentum, the paper's (27), is not an integral of this model: $\theta^1 \ne 0$, the axis $l^1$ is not vertical."
    elif facts.momentum_condition:
        intro = (rf"Momentum, the paper's (27), {K}; it is conserved, $= \ell$, only when "
                 rf"the axis $l^1$ is vertical (the paper's (25)): {textype.typeset(facts.momentum_condition, params)}. The function is")
        momentum = "The momentum, the paper's (27), is not an integral of this model for every value of its parameters."
    elif facts.has_momentum_integral:
        intro = (r"Momentum, the paper's (27): the axis $l^1$ is vertical ($\sin\theta^1 = 0$, the paper's (25)) and nothing turns the chain "
                 r"about it (no torque, spring or damper in joint 1, no load with a moment about $l^1$"
                 + (", the platform turning about $l^1$ only" if spec.base is not None and spec.base.moves else "")
                 + rf"), so {K} $= \ell$ with")
        momentum = "The momentum, the paper's (27), is an integral of this model."
    else:
        where = " in the platform" if spec.base is not None else ""
        intro = rf"Momentum, the paper's (27), {K} (the axis $l^1$ is vertical{where}, $\sin\theta^1 = 0$):"
        momentum = f"The momentum, the paper's (27), is not an integral of this model: {_joined(facts.momentum_reasons, params)}."
    return dict(energy_statement=energy, momentum_intro=intro, momentum_statement=momentum)
