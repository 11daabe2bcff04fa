"""The scene as the LaTeX states it: every input of the spec as given (joints, loads, the
platform's motion, the parameters) and the notation table."""
from __future__ import annotations

import re

import sympy as sp

from ..derive.assemble import Model
from .common import tex_escape
from .texterms import number_text

FORM_TEXT = {
    "c": r"products of $\cos\varphi^k$ and $\sin\varphi^k$ with no $(\sin\varphi^k)^2$ (it is $1 - (\cos\varphi^k)^2$)",
    "s": r"products of $\cos\varphi^k$ and $\sin\varphi^k$ with no $(\cos\varphi^k)^2$ (it is $1 - (\sin\varphi^k)^2$)",
    "C": r"the same with no $\sin^2$, in the sums of the angles of parallel axes, such as $\cos(\varphi^{2} + \varphi^{3})$, where consecutive axes are parallel",
    "S": r"the same with no $\cos^2$, in the sums of the angles of parallel axes",
    "f": r"cosines and sines of integer combinations of the angles, such as $\cos(\varphi^{1} - 2\varphi^{2})$, each with its first angle's multiple positive (no products of them)",
}


def forms_text(used: dict) -> str | None:
    """The normal forms the document's quantities are printed in, and how many of each: every
    quantity is in the form with the fewest terms (ties in the order of FORM_TEXT)."""
    if not used:
        return None
    order = [f for f in FORM_TEXT if used.get(f)]
    listed = "; ".join(f"{FORM_TEXT[f]} ({used[f]} {'quantity' if used[f] == 1 else 'quantities'})" for f in order)
    return ("Each function of the joint angles is written in the one of these normal forms that has the fewest terms "
            "(a tie goes to the first), so that a function prints the same in every document: " + listed + ".")


def angle_text(theta: sp.Expr, w, fold) -> str:
    """A structural angle as given: a rational multiple of π as a fraction of π, else its value."""
    q = sp.nsimplify(theta / sp.pi) if theta.has(sp.pi) else None
    if q is not None and q.is_Rational:
        top = r"\pi" if abs(q.p) == 1 else rf"{abs(q.p)}\pi"
        return ("- " if q < 0 else "") + (top if q.q == 1 else rf"\frac{{{top}}}{{{q.q}}}")
    return w.sum_text(fold(theta))


def _vec(w, fold, v) -> str:
    return r"\begin{pmatrix}" + r" \\ ".join(w.sum_text(fold(sp.sympify(x))) for x in v) + r"\end{pmatrix}"


def scene(spec, w, fold) -> dict:
    """Every input beyond the bodies' table, printed from the parsed spec: the joints' springs,
    rest angles, dampers and torque expressions; the forces and moments with their points and
    frames; the platform's motion r₀(t) and its rotations; the symbolic parameters."""
    show = lambda x: w.sum_text(fold(sp.sympify(x)))  # noqa: E731
    joints = []
    for k, b in enumerate(spec.bodies, start=1):
        if b.spring is not None or b.damping is not None or b.torque is not None:
            none = r"\text{--}"  # the joint has no such element
            joints.append(dict(k=k, spring=show(b.spring) if b.spring is not None else none,
                               rest=show(b.rest) if b.spring is not None else none,
                               damping=show(b.damping) if b.damping is not None else none,
                               torque=show(b.torque) if b.torque is not None else none))
    loads = []
    for k, b in enumerate(spec.bodies, start=1):
        for ld in b.forces:
            loads.append(dict(k=k, kind="force", vec=_vec(w, fold, ld.vec), point=_vec(w, fold, ld.point), frame=ld.frame))
        for ld in b.moments:
            loads.append(dict(k=k, kind="moment", vec=_vec(w, fold, ld.vec), point="", frame=ld.frame))
    base = None
    if spec.base is not None:
        base = dict(position=_vec(w, fold, spec.base.position),
                    rotations=[dict(axis=_vec(w, fold, a), angle=show(t)) for a, t in zip(spec.base.axes, spec.base.angles)])
    params = [dict(tex=w.name(p), name=tex_escape(p.name),
                   value=number_text(sp.Rational(repr(spec.values[p.name]))) if p.name in spec.values else "")
              for p in spec.params]
    return dict(joints=joints, loads=loads, base=base, params=params)


def notation(model: Model, doc: dict, param_names: list[str]) -> list[tuple[str, str, str]]:
    """Every symbol the document uses, once, with its unit and its meaning: the paper's, then this
    document's own; ``doc`` is the document's context (which sections it has)."""
    recursion, moving = bool(doc["recursion"]), doc["moving"]
    rows = [
        (r"$n$, $k$, $r$, $p$, $q$", "", r"the number of bodies; indices of bodies and joints, $1,\dots,n$ (an upper index labels a body and is never summed)"),
        (r"$i$, $j$", "", r"components $1, 2, 3$ in a body's frame; a component index repeated in a product is summed over $1, 2, 3$"),
        (r"$t$", "s", r"time ($t_0$ its initial value)"),
        (r"$S^k$, $O^k$, $l^k$", "", r"body $k$, its joint's point on the axis, the joint axis ($S^0$ the base)"),
        (r"$\hat{\mathbf e}^k_i$, $\mathbf e^k$", "1", r"the frame of body $k$; $\mathbf e^k = \hat{\mathbf e}^k_1$ along $l^k$"),
        (r"$\varphi^k$, $\dot\varphi^k$, $\ddot\varphi^k$", r"rad, rad/s, rad/s$^2$",
         r"the angle of joint $k$ (body $k$ relative to body $k-1$), its rates"),
        (r"$\theta^k$", "rad", r"the angle between $l^{k-1}$ and $l^k$ (the structure)"),
        (r"$m^k$" + (r", $m_c^k$" if recursion else ""), "kg", "mass" + (r"; $m_c^k$ that of the sub-chain $k,\dots,n$" if recursion else "")),
        (r"$\mathbf c^k$, $c^k_i$, $\mathbf s^k$, $s^k_i$", "m", r"centre of mass from $O^k$, the vector $O^kO^{k+1}$, and their components"),
        (r"$\mathbf A^k$, $A^k_{ij}$", r"kg\,m$^2$", r"inertia tensor about $O^k$, its components"),
        (r"$\boldsymbol\lambda^k$, $\lambda^k_i$", r"kg\,m$^2$/s", r"gyrostatic moment of the rotors (constant in the body), its components"),
        (r"$\alpha^{kr}_{ij}$, $\alpha^{k,k-1}$, $\alpha^k$, $\alpha^{prkk}_{i132}$", "1",
         r"$\hat{\mathbf e}^k_i\cdot\hat{\mathbf e}^r_j$, the direction cosines of frame $k$ in frame $r$; $\alpha^k = \alpha^{k0}$; "
         r"$\alpha^{prkk}_{i132} = \hat{\mathbf e}^p_i\cdot(\mathbf e^k\times\mathbf e^r)$"),
        (r"$\boldsymbol\omega^k$, $\omega^k_i$, $\boldsymbol\varepsilon^k$, $\varepsilon^k_i$", r"rad/s, rad/s$^2$",
         r"the angular velocity and acceleration of body $k$ ($k = 0$: the platform), components in its frame"
         + (r" (in the recursion $\varepsilon^k$ is taken at $\ddot\varphi = 0$)" if recursion else "")),
        (r"$M_{kr}$", r"kg\,m$^2$", r"the mass matrix: the coefficient of $\ddot\varphi^r$ in the equation of joint $k$"),
        (r"$Q_k$, $\Gamma_k$, $G_k$", r"N\,m", r"velocity-quadratic, gyroscopic and gravity terms of the paper's (17)--(19)"
         + (r" (in the recursion $\Gamma^k$ is the sub-chain's gyroscopic moment)" if recursion else "")),
        (r"$\mathbf B^{lr}(\mathbf x)$, $\mathbf x$", "", r"the velocity terms of the paper's (6) that $Q_k$'s formula collects, of a vector $\mathbf x$ fixed in body $l$"),
        (r"$L^k$", r"N\,m", r"the control torque of joint $k$"),
        (r"$f_k$, $R_k$", r"N\,m", r"the right side less the left side's terms without $\ddot\varphi$; the residual $\sum_r M_{kr}\ddot\varphi^r - f_k$"),
        (r"$x$, $\Delta$", r"rad, rad/s", r"the state $(\varphi, \dot\varphi)$; $\Delta x$, $\Delta L$ small deviations of the state and the controls"),
        (r"$\mathcal A$, $\mathcal B$", "", r"the matrices of the linearisation"),
        (r"$T$" + (r", $T_2$, $T_1$, $T_0$" if moving else ""), "J",
         "kinetic energy" + (r" (absolute); $T_2$, $T_1$, $T_0$ its parts quadratic, linear and free of $\dot\varphi$" if moving else "")),
        (r"$U$, $E$", "J", r"force function ($-U$ the potential energy), the energy constant of the paper's (23)"),
        (r"$g$", r"m/s$^2$", r"gravity, along $\hat{\mathbf e}^0_1$ (down)"),
        (r"$\mathbf h^k$, $h^k_i$, $\mathbf I^k$, $I^k_{ij}$", r"kg\,m, kg\,m$^2$",
         r"first moment of mass and inertia tensor of the sub-chain $k,\dots,n$ about $O^k$ (Appendix A)"),
    ]
    return rows + _own_rows(model, doc, param_names)


def _own_rows(model: Model, doc: dict, param_names: list[str]) -> list[tuple[str, str, str]]:
    """The notation of what this document has beyond the paper's fixed-base chain."""
    general, recursion, rows = model.spec.general, bool(doc["recursion"]), []
    groups = [(sym, words) for sym, words, key in (
        (r"$\Pi_k$", "platform terms", "Pi"), (r"$\mathring\Lambda_k$", "rotors spinning up", "Lamdot"),
        (r"$W_k$", "generalized forces of the loads", "Phi"),
        (r"$\tau_k$", "joint torques of springs, dampers and torque expressions", "joint")) if doc.get(key)]
    if general and groups:  # the groups of the general case this document prints
        rows.append((", ".join(sym for sym, _ in groups), r"N\,m", ", ".join(words for _, words in groups)
                     + r" (this document's names for the groups of the paper's (8)--(10))"))
    if doc["scene"]["joints"] or any("spring" in w for w, _ in model.integrals.U_extra):
        rows.append((r"$\kappa^k$, $b^k$", r"N\,m/rad, N\,m\,s/rad",
                     r"stiffness and damping of joint $k$ (rest angle $\varphi^k_{\mathrm{rest}}$)"))
    if doc["scene"]["loads"]:
        rows.append((r"$\mathbf P^q$, $\boldsymbol\mu^q$", r"N, N\,m", r"a force applied at a point of body $q$, a moment applied to it"))
    if model.kin.platform is not None:
        rows.append((r"$\mathbf r_0$, $\dot{\mathbf v}_0$, $\dot v_{0,i}$", r"m, m/s$^2$",
                     r"the position of $O^1$ in the fixed frame; its acceleration, in the platform's frame"))
    shares = doc.get("shares")
    if shares:
        rows.append((r"$\sigma^{kp}_i$, $v^{kp}_i$", "m",
                     r"the vector $O^kO^p$ in frame $p$, the velocity of $C^p$ per unit $\dot\varphi^k$ ($\alpha^{kp}_{1i}$: the axis $\mathbf e^k$ in frame $p$)"))
        rows.append((r"$C^p$, $J^p_{ij}$, $d^p$", r"kg\,m$^2$, m", r"the centre of mass of body $p$, its inertia tensor about $C^p$, its depth below $O^1$"))
        rows.append((r"$\mu^p_{kr}$, $\nu^p_k$, $\eta^p_k$", r"kg\,m$^2$, N\,m, N\,m", r"body $p$'s share of $M_{kr}$, of $Q_k$ and of $G_k$"))
        rows.append((r"$a^p_i$, $\bar a^p_i$, $w^p_i$, $N^p_i$", r"m/s$^2$, N\,m",
                     r"the accelerations of $O^p$ (in frames $p$ and $p - 1$) and of $C^p$ at $\ddot\varphi = 0$; the moment about $C^p$ "
                     r"body $p$'s rotation needs"))
        if shares["gyro"]:
            rows.append((r"$\chi^p_i$", r"N\,m", r"$\boldsymbol\omega^p\times\boldsymbol\lambda^p$, the gyroscopic moment of body $p$'s rotors"))
    if general or recursion or shares:
        parts = recursion or shares or model.kin.platform is not None  # components printed: γ⁰ᵢ of the platform rows, γᵏᵢ of the recursion
        rows.append((r"$\boldsymbol\gamma^0$" + (r", $\gamma^k_i$" if parts else ""), "1", r"the downward vertical, $\hat{\mathbf e}^0_1$ of the fixed frame, in the "
                     r"platform's frame (the Poisson vector; not in the paper, whose base does not turn)"
                     + (r"; $\gamma^k_i$ its components in frame $k$" if parts else "")))
    if recursion:
        rows.append((r"$a^k$, $\tilde a^k$, $F^k$, $N^k$", r"m/s$^2$, N, N\,m",
                     r"the acceleration of $O^k$, its part relative to $O^{k-1}$; the sub-chain's inertial force and its "
                     r"moment about $O^k$ (Appendix A)"))
    if doc["pair_form"]:
        rows.append((r"$\xi^k$, $z^k$, $\mathcal I^k$", "", r"the axis of joint $k$ as a twist, its momentum $\mathcal I^k\xi^k$, "
                     r"the spatial inertia of the sub-chain about $O^1$"))
        rows.append((r"$\rho^k_i$", "m", r"the position of $O^k$ from $O^1$, in the platform's frame"))
        rows.append((r"$\Theta^k$, $\bar\Theta^k$, $\eta^k$, $\bar\eta^k$", r"kg\,m$^2$, kg\,m",
                     r"the inertia tensor and the first moment of body $k$ (with a bar: of the sub-chain $k,\dots,n$) "
                     r"about $O^1$, in the platform's frame"))
    if doc["offsets"]:
        rows.append((r"$\delta^k$", "rad", r"the offset of joint $k$"))
    if doc["jacobi"] is not None:
        rows.append((r"$H$", "J", r"Jacobi's integral"))
    if doc["momentum_intro"] is not None:
        rows.append((r"$\mathbf K_{O^1}$, $\ell$", r"kg\,m$^2$/s", r"the angular momentum about $O^1$; the value of the paper's momentum (27)"))
    if doc["quad"] is not None:
        rows.append((r"$\psi$, $\psi_0$", "rad", r"$\psi = \varphi^{1}$ and $\varphi = \varphi^{2}$ in the paper's quadratures (28)--(30); "
                     r"$\varphi_0$, $\psi_0$ initial angles; $\varphi_-$, $\varphi_+$ turning points (simple roots of $\mathcal E(\varphi)J - K^2$)"))
        rows.append((r"$J$, $C$", r"kg\,m$^2$", r"the coefficients of the paper's (28), (29)"))
        rows.append((r"$\mathcal E(\varphi)$", "J", r"$2(E + U)$, the right side of the paper's (28)"))
        rows.append((r"$K(\varphi)$", r"kg\,m$^2$/s", r"the right side of the paper's (29)"))
        rows.append((r"$\Phi$", "s/rad", r"the integrand of (30), $dt/d\varphi$"))
    if doc.get("recursion_aux"):
        rows.append((r"$\zeta_j$", "", r"a function of the angles or the parameters the recursion computes once, defined by its line"))
    if doc["base"] is not None:
        rows.append((r"$Y$, $Y_B$, $\boldsymbol\pi$, $\boldsymbol\beta$, $\beta_i$, $u$, $u_0$", "",
                     r"the regressor and its base columns, the standard and the base parameters, the joint torques and the spec's known part of them"))
    if param_names:
        rows.append((", ".join(f"${w}$" for w in param_names), "as the spec",
                     r"symbolic parameters (table below; set in sans serif)"))
    return rows


def used_rows(rows: list, tex: str) -> list:
    """The notation rows whose symbols the rendered document uses outside the table: a symbol
    counts where its head (without its indices) is written with an index as in the row, or alone."""
    body = re.sub(r"\\begin\{longtable\}\{@\{\}>.*?\\end\{longtable\}", " ", tex, count=1, flags=re.S)
    return [row for row in rows if any(_written(sym, body) for sym in re.findall(r"\$([^$]+)\$", row[0]))]


def _written(sym: str, body: str) -> bool:
    head = re.split(r"[\^_]", sym, maxsplit=1)[0].strip()
    indexed = head != sym.strip()
    before = r"(?<![A-Za-z\\])(?<!\\mathcal )(?<!\\mathbf )(?<!\\boldsymbol)(?<!\\dot)(?<!\\ddot)"
    pattern = before + re.escape(head) + (r"(?:\s*[\^_]|(?![A-Za-z{]))" if indexed else r"(?![A-Za-z])")
    return re.search(pattern, body) is not None


def runs(bodies: list[dict]) -> list[dict]:
    r"""The bodies' table rows: a run of three or more consecutive bodies with the same row (a
    cable's identical links) is one row, its k written $a,\dots,b$."""
    out, same = [], ("theta", "m", "c", "s", "lam", "A", "control")
    for b in bodies:
        if out and all(out[-1]["last"][key] == b[key] for key in same):
            out[-1]["run"].append(b["k"])
            continue
        out.append(dict(b, run=[b["k"]], last=b))
    rows = []
    for r in out:
        ks = r.pop("run")
        r.pop("last")
        if len(ks) >= 3:
            rows.append(dict(r, k=f"{ks[0]},\\dots,{ks[-1]}"))
        else:
            rows.extend(dict(r, k=k) for k in ks)
    return rows


def parallel_links(spec, kin) -> dict:
    """φᵏ → (φᵏ⁻¹, cos θᵏ) for each joint whose axis is parallel to the one before (sin θᵏ = 0,
    no offset): the runs whose bodies turn by sums of angles (trigform's forms C and S)."""
    out = {}
    for k in range(2, spec.n + 1):
        b = spec.bodies[k - 1]
        if sp.sin(b.theta) == 0 and b.offset == 0:
            out[kin.phi[k]] = (kin.phi[k - 1], int(sp.cos(b.theta)))
    return out
