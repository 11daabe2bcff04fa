"""Periodic orbits of autonomous models by Newton shooting on the emitted variational equations
(``gyrochain orbits SPEC``): the nonlinear normal modes that grow out of a stable equilibrium's
linear modes, continued along the energy or a parameter, and the steady rotations of a cyclic φ¹
(steady precessions) as periodic orbits; each with its Floquet multipliers and a verdict.

* Shooting.  The unknowns are the start x₀ and the period T; the equations
      x(T; x₀) − x₀ − s = 0          (s: 2π per turn of an angle that turns, 0 for a libration)
      a phase condition              (x₀ⱼ = its value: a turning point φ̇ʲ(0) = 0 of a mode, φ¹(0) = 0
                                      of a rotation; the orbit's time origin)
      E(x₀) = E*, [p₁(x₀) = p₁*]     (the energy (23) fixes the member of the family; on a rotation
                                      about a cyclic φ¹ the momentum (27) too)
  with the Jacobian [Φ(T) − I, f(x(T))] over (x₀, T) from NAME_integrate_variational and the
  gradients of E and p₁ by central differences of the emitted integrals.  Gauss–Newton (least
  squares: the equations are consistent and one more than the unknowns, as the energy makes one
  of the first 2n dependent), with backtracking; converged when |x(T) − x₀ − s| ≤ TOL max(1, |x₀|).
* Starts.  A nonlinear normal mode starts from the linear mode (iω, v) of A = NAME_linearize at
  a stable equilibrium: x₀ = x* + σ Re(v e^{iθ}), θ making the largest velocity component vanish,
  σ from the energy, T = 2π/ω.  Continuation: a secant predictor from the last two orbits over
  the continuation value, the corrector above, the step halved when Newton fails (at most
  MAX_HALVINGS times, then the branch is reported as stopped there).
* Multipliers: the eigenvalues of Φ(T).  An autonomous orbit has two at 1 (along the flow, and
  across the family: a Jordan block); they are dropped (the two nearest 1, and how near is
  printed), the others decide the verdict as floquet.verdict (on or inside the unit circle:
  linearly stable, which for a conservative model is orbital stability to first order).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from . import floquet
from ..chainspec.errors import SpecError

RTOL, ATOL = floquet.RTOL, floquet.ATOL  # of the variational integration over a period
TOL = 1e-10  # the orbit closes to this, relative to max(1, |x₀|)
MAX_ITER = 30
MAX_HALVINGS = 6
TRIVIAL = 2  # multipliers at 1 of an autonomous periodic orbit


@dataclass
class Orbit:
    value: float  # the continuation value: the energy above the equilibrium's (J), or the parameter
    x0: np.ndarray  # the start (a turning point of the mode, or φ¹ = 0)
    period: float
    energy: float  # E(x₀)
    multipliers: np.ndarray  # the nontrivial ones, by decreasing modulus
    trivial_gap: float  # how far the two dropped multipliers are from 1
    verdict: str
    reason: str
    closure: float  # |x(T) − x₀ − s| / max(1, |x₀|)
    monodromy: np.ndarray = field(repr=False, default=None)


@dataclass
class Family:
    """A branch of orbits: how it started and the orbits in the order of the continuation."""

    title: str
    name: str  # what is continued ("E - E0", a parameter, "omega")
    orbits: list = field(default_factory=list)
    stopped: str = ""


class Shooting:
    """The shooting equations of a built autonomous model (gyrochain.build.CModel) at ``params``."""

    def __init__(self, cm, params=None, u=None, shift=None, phase: int = 0, momentum: bool = False):
        self.c, self.n, self.params = cm, cm.n, params
        self.u = None if u is None else np.asarray(u, float)
        self.shift = np.zeros(2 * cm.n) if shift is None else np.asarray(shift, float)
        self.phase, self.momentum = phase, momentum
        self.last_growth = 0.0  # the largest |μ| of the last monodromy computed (why Newton may fail)

    def energy(self, x) -> float:
        return float(self.c.energy(np.asarray(x, float), self.params))

    def _gradient(self, f, x) -> np.ndarray:
        g = np.empty(len(x))
        for i in range(len(x)):
            h = 1e-6 * max(1.0, abs(x[i]))
            e = np.zeros(len(x))
            e[i] = h
            g[i] = (f(x + e) - f(x - e)) / (2 * h)
        return g

    def _equations(self, x0, T, E, P, phase_value):
        x1, Phi = self.c.integrate_variational(0.0, T, x0, u=self.u, params=self.params, rtol=RTOL, atol=ATOL)
        self.last_growth = float(np.max(np.abs(np.linalg.eigvals(Phi)))) if np.all(np.isfinite(Phi)) else math.inf
        f1 = self.c.rhs(T, x1, self.u, self.params)
        close = x1 - x0 - self.shift
        F = [close, [x0[self.phase] - phase_value], [self.energy(x0) - E]]
        rows = [np.hstack([Phi - np.eye(2 * self.n), f1[:, None]]), np.eye(1, 2 * self.n + 1, self.phase),
                np.append(self._gradient(self.energy, x0), 0.0)[None, :]]
        if self.momentum:
            mom = lambda x: float(self.c.momentum(x, self.params))  # noqa: E731
            F.append([mom(x0) - P])
            rows.append(np.append(self._gradient(mom, x0), 0.0)[None, :])
        return np.concatenate(F), np.vstack(rows), Phi, close

    def solve(self, x0, T, E, P=0.0, phase_value=0.0):
        """Newton from (x₀, T) onto the orbit of energy E (and momentum P): (x₀, T, Φ(T),
        closure) or None when it does not converge (or the integration fails)."""
        x0, T = np.array(x0, float), float(T)
        try:
            F, J, Phi, close = self._equations(x0, T, E, P, phase_value)
            for _ in range(MAX_ITER):
                scale = max(1.0, np.max(np.abs(x0)))
                if np.max(np.abs(close)) <= TOL * scale and np.max(np.abs(F[2 * self.n:])) <= TOL * max(1.0, abs(E)):
                    return x0, T, Phi, float(np.max(np.abs(close)) / scale)
                dz = np.linalg.lstsq(J, -F, rcond=None)[0]
                lam, norm = 1.0, np.linalg.norm(F)
                while lam > 1e-3:
                    xt, Tt = x0 + lam * dz[:-1], T + lam * dz[-1]
                    if Tt > 0:
                        try:
                            F2, J2, Phi2, close2 = self._equations(xt, Tt, E, P, phase_value)
                            if np.linalg.norm(F2) < norm:
                                break
                        except ArithmeticError:
                            pass
                    lam /= 2
                else:
                    return None
                x0, T, F, J, Phi, close = xt, Tt, F2, J2, Phi2, close2
        except ArithmeticError:
            return None
        return None

    def orbit(self, value, x0, T, E, P=0.0, phase_value=0.0) -> Orbit | None:
        got = self.solve(x0, T, E, P, phase_value)
        if got is None:
            return None
        x0, T, Phi, closure = got
        mu = np.linalg.eigvals(Phi)
        near = np.argsort(np.abs(mu - 1.0))
        trivial, rest = mu[near[:TRIVIAL]], mu[near[TRIVIAL:]]
        rest = rest[np.lexsort((-rest.imag, -np.abs(rest)))]
        v, why = floquet.verdict(rest)
        return Orbit(value, x0, T, self.energy(x0), rest, float(np.max(np.abs(trivial - 1.0))), v, why, closure, Phi)


UNSHOOTABLE = 1e8  # a monodromy growing beyond this over a period defeats single shooting


def _why_not(sh: Shooting) -> str:
    """Why Newton may have failed: an orbit so unstable that round-off grows past its size."""
    if sh.last_growth > UNSHOOTABLE:
        size = f"{sh.last_growth:.0e}" if math.isfinite(sh.last_growth) else "beyond 1e308"
        return f": the orbit is strongly unstable (its monodromy grows to {size} over a period), beyond single shooting"
    return ""


def linear_modes(cm, phi, params=None, u=None):
    """The oscillatory modes (ω, v) of the linearisation at the equilibrium φ (eigenvalues iω of
    A = NAME_linearize with ω > 0, slowest first); SpecError unless every eigenvalue is on the
    imaginary axis (a stable equilibrium of a conservative model)."""
    x = np.concatenate([phi, np.zeros(cm.n)])
    A, _ = cm.linearize(x, u, params)
    lam, V = np.linalg.eig(A)
    size = max(1.0, np.max(np.abs(lam)))
    if np.max(np.abs(lam.real)) > 1e-7 * size:
        worst = lam[np.argmax(np.abs(lam.real))]
        raise SpecError("--at", f"phi = {floquet.fmt_phi(phi)} is not a stable equilibrium of a conservative model "
                                f"(eigenvalue {worst.real:.6g}{worst.imag:+.6g}i): its linear modes are not oscillations")
    keep = [(lam[i].imag, V[:, i]) for i in range(len(lam)) if lam[i].imag > 1e-9 * size]
    return sorted(keep, key=lambda m: m[0])


def mode_start(sh: Shooting, phi, omega, v, dE):
    """x₀ of the linear mode (ω, v) at the equilibrium φ with the energy dE above it: the phase
    where the largest velocity component is 0 (its index is the phase condition)."""
    n = sh.n
    j = int(np.argmax(np.abs(v[n:])))
    w = np.real(v * np.exp(1j * (np.pi / 2 - np.angle(v[n + j]))))
    w /= np.max(np.abs(w[:n])) or 1.0
    xs = np.concatenate([phi, np.zeros(n)])
    E0 = sh.energy(xs)
    h = 1e-4
    q = (sh.energy(xs + h * w) + sh.energy(xs - h * w) - 2 * E0) / (2 * h * h)  # E ≈ E0 + q σ²
    if not q > 0:
        raise SpecError("--at", "the energy does not grow along the linear mode: not a stable equilibrium")
    return xs + math.sqrt(dE / q) * w, n + j, E0


def continue_family(sh: Shooting, fam: Family, values, first_x0, first_T, energy_of, phase_value=0.0, P_of=None,
                    set_value=None) -> Family:
    """Continue an orbit over ``values`` (increasing): ``energy_of(v)`` is the energy E* to solve for
    at v, ``P_of(v)`` the momentum, ``set_value(v)`` (a parameter) is called first.  A secant
    predictor from the last two orbits; where Newton fails the step is halved (the orbits of the
    intermediate values are kept), at most MAX_HALVINGS times."""
    done: list = []  # (value, x0, T) of the orbits found

    def attempt(v):
        if set_value is not None:
            set_value(v)
        if len(done) >= 2:
            (va, xa, Ta), (vb, xb, Tb) = done[-2], done[-1]
            r = (v - vb) / (vb - va)
            guess_x, guess_T = xb + r * (xb - xa), Tb + r * (Tb - Ta)
        elif done:
            guess_x, guess_T = done[-1][1], done[-1][2]
        else:
            guess_x, guess_T = first_x0, first_T
        return sh.orbit(v, guess_x, guess_T, energy_of(v), P_of(v) if P_of else 0.0, phase_value)

    for target in map(float, values):
        v, halvings = target, 0
        while True:
            orb = attempt(v)
            if orb is not None:
                done.append((v, orb.x0, orb.period))
                fam.orbits.append(orb)
                if v == target:
                    break
                v, halvings = target, 0  # from the intermediate orbit, the whole way again
                continue
            if not done or halvings >= MAX_HALVINGS:
                fam.stopped = f"Newton did not converge at {fam.name} = {v:.6g}" + _why_not(sh)
                return fam
            v, halvings = (done[-1][0] + v) / 2, halvings + 1
    return fam


def normal_modes(cm, phi, energies, params=None, u=None, modes=None, vary=None) -> list[Family]:
    """The nonlinear normal modes at the stable equilibrium φ: each linear mode (or those numbered
    in ``modes``, 1 = the slowest) continued over the energies above the equilibrium's
    (``energies``, increasing, > 0), or, with ``vary`` = (name, values), at the first energy over
    a parameter (the equilibrium followed by Newton)."""
    lin = linear_modes(cm, phi, params, u)
    picked = range(1, len(lin) + 1) if not modes else modes
    for k in picked:
        if not 1 <= k <= len(lin):
            raise SpecError("--mode", f"the equilibrium has {len(lin)} linear modes; got {k}")
    out = []
    for k in picked:
        omega, v = lin[k - 1]
        sh = Shooting(cm, params, u)
        x0, sh.phase, E0 = mode_start(sh, phi, omega, v, energies[0])
        title = (f"nonlinear normal mode {k} at phi = {_fmt(phi)} (linear: omega = {omega:.10g} rad/s, "
                 f"period {2 * np.pi / omega:.10g} s)")
        if vary is None:
            fam = Family(title, "E - E0")
            out.append(continue_family(sh, fam, energies, x0, 2 * np.pi / omega, lambda dE, E0=E0: E0 + dE))
            continue
        name, values = vary
        base = dict(params or {})
        state = {"phi": np.array(phi, float)}

        def set_value(val, sh=sh, base=base, name=name, state=state):
            sh.params = {**base, name: val}
            got = floquet.equilibrium(cm, state["phi"], (0.0,), sh.params, sh.u)
            if got is None:
                raise SpecError("--vary", f"the equilibrium is lost at {name} = {val:g}")
            state["phi"] = got[0]
            state["E0"] = sh.energy(np.concatenate([got[0], np.zeros(cm.n)]))

        fam = Family(title + f", E - E0 = {energies[0]:.6g} J", name)
        set_value(float(values[0]))
        out.append(continue_family(sh, fam, values, x0, 2 * np.pi / omega, lambda _v, state=state: state["E0"] + energies[0],
                                   set_value=set_value))
        sh.params = base or None
    return out


def rotations(cm, omegas, phi_start, params=None, u=None) -> Family:
    """The steady rotations φ̇¹ = ω (the other joints at rest, φ¹ cyclic) over ``omegas`` as
    periodic orbits of period 2π/|ω| (φ¹ turns once); the orbit at each ω from Newton on φ̈ = 0
    with φ̇ = (ω, 0, …) (the steady rotation), then shooting at its energy and momentum."""
    n = cm.n
    fam = Family(f"steady rotations phidot1 = omega as periodic orbits (phi1 turns by 2 pi per period)", "omega")
    phi = np.array(phi_start, float)
    for w in omegas:
        if w == 0:
            continue
        got = _rotation(cm, phi, w, params, u)
        if got is None:
            fam.stopped = f"no steady rotation found at omega = {w:.6g}"
            break
        phi = got
        x0 = np.concatenate([phi, [w], np.zeros(n - 1)])
        sh = Shooting(cm, params, u, shift=np.eye(1, 2 * n, 0)[0] * 2 * np.pi * np.sign(w), phase=0, momentum=True)
        orb = sh.orbit(float(w), x0, 2 * np.pi / abs(w), sh.energy(x0), float(cm.momentum(x0, params)), 0.0)
        if orb is None:
            fam.stopped = f"Newton did not converge at omega = {w:.6g}" + _why_not(sh)
            break
        fam.orbits.append(orb)
    return fam


def _rotation(cm, phi, w, params, u, iters: int = 40):
    """φ (φ¹ = 0) with φ̈ = 0 at φ̇ = (ω, 0, …): Gauss–Newton over φ², …, φⁿ."""
    n = cm.n
    phi = np.array(phi, float)
    phi[0] = 0.0
    for _ in range(iters):
        x = np.concatenate([phi, [w], np.zeros(n - 1)])
        q, dq, _, _ = cm.qdd_derivatives(x, u, params)
        if np.max(np.abs(q)) <= 1e-12 * max(1.0, np.max(np.abs(dq))):
            return phi
        phi[1:] += np.linalg.lstsq(dq[:, 1:], -q, rcond=None)[0]
    return None


def _fmt(v) -> str:
    return "[" + ", ".join(f"{x:.6g}" for x in v) + "]"


def report(families: list[Family]) -> str:
    out = []
    for fam in families:
        out.append(fam.title + ":")
        out.append(f"  {fam.name:>10}  {'period (s)':>14}  {'start phi (rad)':<28} verdict")
        for o in fam.orbits:
            out.append(f"  {o.value:>10.6g}  {o.period:>14.10g}  {_fmt(o.x0[:len(o.x0) // 2]):<28} {o.verdict}: "
                       f"{floquet.fmt_multipliers(o.multipliers, o.period).split(';')[0]}")
        if fam.orbits:
            gap = max(o.trivial_gap for o in fam.orbits)
            out.append(f"  (every orbit closes to {TOL:.0e} of its size; the two trivial multipliers are within "
                       + ("1e-4 of 1)" if gap <= 1e-4 else f"{gap:.1e} of 1: near a bifurcation)"))
        if fam.stopped:
            out.append(f"  stopped: {fam.stopped}")
    return "\n".join(out)


def stable_equilibrium(cm, params=None, u=None):
    """The stable equilibrium of least energy among those Newton finds from floquet.start_grid,
    and the energy barrier to the nearest other equilibrium (inf if none)."""
    def solve(s):
        got = floquet.equilibrium(cm, s, (0.0,), params, u)
        return None if got is None else got[0]

    found = floquet.distinct(floquet.start_grid(cm.n), solve)
    energy = {i: float(cm.energy(np.concatenate([f, np.zeros(cm.n)]), params)) for i, f in enumerate(found)}
    stable = []
    for i, f in enumerate(found):
        try:
            linear_modes(cm, f, params, u)
            stable.append(i)
        except SpecError:
            continue
    if not stable:
        raise SpecError("orbits", "no stable equilibrium was found (give one with --at)")
    best = min(stable, key=lambda i: energy[i])
    others = [energy[i] - energy[best] for i in energy if i != best and energy[i] > energy[best]]
    return found[best], min(others, default=math.inf)


def removed(reasons, pushed: bool) -> list[str]:
    """What removes an integral in this run: its reasons but the control torques, which are 0
    unless --u gives them (``pushed``)."""
    out = [r for r in reasons if not r.startswith("control torque")]
    return out + ["the control torques --u"] if pushed and any(r.startswith("control torque") for r in reasons) else out


def analyze(spec, params=None, u=None, at=None, energies=None, modes=None, vary=None, omegas=None) -> list[Family]:
    """The periodic orbits ``gyrochain orbits`` prints: the nonlinear normal modes at the stable
    equilibrium ``at`` (default: the one of least energy) over ``energies`` above its energy
    (default: 20 values up to half the lowest barrier to another equilibrium), or along ``vary``;
    with ``omegas``, the steady rotations of a cyclic φ¹ as orbits."""
    from ..models import pipeline
    from ..derive.assemble import VARIATIONAL_MAX_N, time_dependent

    if spec.n > VARIATIONAL_MAX_N:  # before anything is built
        raise SpecError("orbits", f"needs NAME_integrate_variational, emitted up to n = {VARIATIONAL_MAX_N} (n = {spec.n})")
    cm, model = pipeline.compiled(spec)
    if time_dependent(model):
        raise SpecError("orbits", "the model depends on t: the stability of its equilibria for all t is `gyrochain steady`'s")
    ints = model.integrals
    pushed = u is not None and np.any(np.asarray(u) != 0)
    why = removed(ints.energy_reasons, pushed)  # control torques held at 0 (--u not given) remove nothing
    if why:
        raise SpecError("orbits", f"the energy (23) is not an integral here ({'; '.join(why)} removed it): periodic "
                                  "orbits are continued in the energy, which must be conserved")
    if omegas is not None:
        m_why = removed(ints.momentum_reasons, pushed and np.asarray(u).ravel()[0] != 0 and 1 in spec.controls)
        if not getattr(cm, "has_momentum", False) or m_why or (not ints.has_momentum_integral and not ints.momentum_reasons):
            raise SpecError("--omega", "phi1 is not cyclic (" + ("; ".join(m_why) if m_why else "l1 not vertical")
                                       + "): no steady rotations")
        start = np.zeros(cm.n) if at is None else np.asarray(at, float)
        return [rotations(cm, omegas, start, params, u)]
    if at is None:
        phi, barrier = stable_equilibrium(cm, params, u)
    else:
        got = floquet.equilibrium(cm, at, (0.0,), params, u)
        if got is None or np.max(np.abs(floquet.wrap(got[0] - np.asarray(at)))) > 1e-3:
            raise SpecError("--at", f"no equilibrium at phi = {list(at)} (Newton went elsewhere or did not converge)")
        phi, barrier = floquet.wrap(got[0]), math.inf
    if energies is None:
        top = 0.5 * barrier if math.isfinite(barrier) else 1.0
        energies = np.linspace(top / 20, top, 20)
    if vary is not None:
        energies = np.asarray(energies[:1])
    return normal_modes(cm, phi, np.asarray(energies, float), params, u, modes, vary)
