"""Each group of the printed equations of motion, from the independent model (gyrochain/derive/reference.py)
alone: every other group switched off (issue 49, item 1).

With f = G + L + W + τ − Q − Γ − Π − Λ̊ the right side of M φ̈ = f (gyrochain/derive/reference.py's
``forces`` at φ̈ = 0), and the model's inputs taken away one kind at a time:

- Π_k: f minus f with the platform frozen at its attitude and position at t (no ω⁰, ε⁰, v̇₀);
- Λ̊_k: f minus f with every λ̊ = 0;
- τ_k: the springs, dampers and torque expressions themselves (reference.joint_torque_terms);
- W_k: the frozen f minus the same without the loads;
- then, frozen, with no loads, joint torques or λ̊: G_k is f minus f at g = 0, Γ_k f minus f at
  λ = 0, and Q_k what is left at g = 0, λ = 0.

Every group enters f linearly in what is switched off, so each difference is the group, exactly."""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from gyrochain import reference


def _frozen(gen, t: float):
    """The platform held at its attitude and position at ``t``: no ω⁰, ε⁰, v̇₀."""
    rotations = [(a, (lambda _t, v=th(t): v), (lambda _t: 0.0), (lambda _t: 0.0)) for a, th, _, _ in gen.rotations]
    r = np.asarray(gen.r0[0](t), float)
    return replace(gen, rotations=rotations, r0=[lambda _t, v=r: v, lambda _t: np.zeros(3), lambda _t: np.zeros(3)])


def groups(ch: reference.NumericChain, x, t: float, platform_in_q: bool = False) -> dict[str, np.ndarray]:
    """{"Q", "Gamma", "G"} and, in the general case, {"Pi", "Lamdot", "W", "tau"}: each (n,) at (x, t).
    ``platform_in_q``: the platform's terms not apart but where a document that does not expand them
    (n ≥ 3) has them, through ω⁰, ε⁰ and v̇₀ in Q and through ωᵏ (ω⁰ included) in Γ; Π is then 0."""
    n, x = ch.n, np.asarray(x, float)

    def f(c):
        return reference.forces(c, x, None, t)

    gen, out = ch.general, {}
    if gen is not None:
        zero = np.zeros(3)
        frozen = replace(ch, general=_frozen(gen, t))
        out["Pi"] = -(f(ch) - f(frozen))
        out["Lamdot"] = -(f(ch) - f(replace(ch, general=replace(gen, lam=[(lam, lambda _t: zero) for lam, _ in gen.lam]))))
        spring, other = reference.joint_torque_terms(ch, t, x[:n], x[n:])
        out["tau"] = spring + other
        unloaded = replace(frozen.general, forces=[[] for _ in range(n)], moments=[[] for _ in range(n)])
        out["W"] = f(frozen) - f(replace(frozen, general=unloaded))
        lam_t = [(lambda _t, v=np.asarray(lam(t), float): v, lambda _t: zero) for lam, _ in gen.lam]
        base = replace(frozen, general=replace(unloaded, spring=np.zeros(n), damping=np.zeros(n), torque=[None] * n, lam=lam_t))
        no_lam = replace(base, lam=np.zeros((n, 3)), general=replace(base.general, lam=[(lambda _t: zero, lambda _t: zero)] * n))
    else:
        base, no_lam = ch, replace(ch, lam=np.zeros((n, 3)))
    out["G"] = f(base) - f(replace(base, g=0.0))
    out["Gamma"] = -(f(base) - f(no_lam))
    out["Q"] = -f(replace(no_lam, g=0.0))
    if gen is not None and platform_in_q:
        # the platform's share without rotors (λ = 0 and λ̊ = 0 with the platform moving, then frozen) is Q's,
        # the rest of it Γ's (ω⁰ × λ and the like)
        bare = replace(ch, lam=np.zeros((n, 3)), general=replace(gen, lam=[(lambda _t: zero, lambda _t: zero)] * n))
        pi_bare = -(f(bare) - f(replace(bare, general=_frozen(bare.general, t))))
        out["Q"], out["Gamma"], out["Pi"] = out["Q"] + pi_bare, out["Gamma"] + out["Pi"] - pi_bare, np.zeros(n)
    return out
