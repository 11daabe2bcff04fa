"""The two-body quadratures of every model that has them, in Python, as the generator emits
them: `{model}` becomes the model's name and each `# @generated` line the model's printed code
(printers/kernels.py).  Everything above the `@kernel` line is for linters only: it names what
the kernel takes from the generated module around it."""
import math  # noqa: F401

import numpy as np

from model_stub import NonFiniteResult, SingularMassMatrix, energy, momentum  # the generated module's own

# @kernel


# ---------------------------------------------------------------------------------------------
# The two-body quadratures (28)-(30): the same method as {model}.c (read the comment there).
# psi = phi_1 is cyclic; P(phi) = E(phi) J - K^2, D(phi) = A J - C^2, D phidot^2 = P.
# ---------------------------------------------------------------------------------------------
LIBRATION, ROTATION, STEADY = "libration", "rotation", "steady"
SEPARATRIX_TOL = 1e-14  # relative distance from a double root of P below which SeparatrixError
QUAD_MAXP = 64  # panels per quarter period
QUAD_TOL = 1e-13  # Kronrod - Gauss estimate, relative, per quarter
_WALK_MAX = 100000
_EPS = 2.220446049250313e-16
_XK = np.array([0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
                0.864864423359769072789712788640926, 0.741531185599394439863864773280788,
                0.586087235467691130294144845693013, 0.405845151377397166906606412076961,
                0.207784955007898467600689403773245, 0.0])
_WK = np.array([0.022935322010529224963732008058970, 0.063092092629978553290700663189204,
                0.104790010322250183839876322541518, 0.140653259715525918745189590510238,
                0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
                0.204432940075298892414161999234649, 0.209482141084727828012999174891714])
_WG = np.array([0.129484966168869693270611432679082, 0.279705391489276667901467771423780,
                0.381830050505118944950369775488975, 0.417959183673469387755102040816327])
_X15 = np.concatenate([-_XK[:7], _XK[::-1]])
_W15 = np.concatenate([_WK[:7], _WK[::-1]])
_G15 = np.zeros(15)
_G15[[1, 3, 5, 7, 9, 11, 13]] = np.concatenate([_WG, _WG[2::-1]])


class SeparatrixError(ArithmeticError):
    """The state is on the separatrix (within SEPARATRIX_TOL): phi approaches an unstable
    steady motion and never returns, so there is no period."""


class SteadyMotion(ArithmeticError):
    """phi stays constant (phidot = 0 at a root of P where P' = 0): no period."""


class QuadratureFailed(ArithmeticError):
    """The quadrature did not reach its tolerance with QUAD_MAXP panels, or the root walk failed."""


def quad_terms(phi, p=None):
    """J(phi), C(phi), A, U(phi), beta(phi) (numpy arrays shaped like phi): the mass matrix
    [[J, C], [C, A]], the force function of gravity (22) and e1 . (lambda1 + lambda2)."""
    phi = np.asarray(phi, dtype=float)
    # @generated prologue
    out = [0.0] * 5
    # @generated quad_terms
    return [np.broadcast_to(np.asarray(v, dtype=float), phi.shape) for v in out]


def quad_functions(phi, x0, p=None):
    """The paper's J, C, A = A2_11, E(phi) = 2(E + U), K(phi) = k - beta and Phi of (30) for the
    constants E, k of the initial state x0 (Phi = inf where E(phi) J - K^2 <= 0)."""
    E, k = energy(x0, p), momentum(x0, p)
    J, C, A, U, beta = quad_terms(phi, p)
    Ephi, K = 2.0 * (E + U), k - beta
    P, D = Ephi * J - K * K, A * J - C * C
    with np.errstate(divide="ignore", invalid="ignore"):
        Phi = np.where(P > 0.0, np.sqrt(D / np.where(P > 0.0, P, 1.0)), np.inf)
    return dict(J=J, C=C, A=A, E=Ephi, K=K, Phi=Phi)


def _pfour(c, phi):
    """P, P', P'' at phi from the Fourier coefficients c."""
    d = [c[0], 0.0, 0.0]
    for j in (1, 2, 3):
        cj, sj = math.cos(j * phi), math.sin(j * phi)
        a, b = c[2 * j - 1], c[2 * j]
        d[0] += a * cj + b * sj
        d[1] += j * (b * cj - a * sj)
        d[2] -= j * j * (a * cj + b * sj)
    return d


def _pdelta(c, r, x):
    """P(r + x) - P(r), accurate for small x (x may be an array)."""
    m = r + 0.5 * x
    return sum(2.0 * np.sin(0.5 * j * x) * (c[2 * j] * np.cos(j * m) - c[2 * j - 1] * np.sin(j * m)) for j in (1, 2, 3))


def _pbump(c, s, x):
    """P(s + x) - P(s) - P'(s) sin x at a minimum s of P: no term linear in x (see the C)."""
    p = [c[2 * j] * math.cos(j * s) - c[2 * j - 1] * math.sin(j * s) for j in (1, 2, 3)]
    q = [c[2 * j - 1] * math.cos(j * s) + c[2 * j] * math.sin(j * s) for j in (1, 2, 3)]
    sx, h = np.sin(x), [np.sin(0.5 * j * x) for j in (1, 2, 3)]
    return -4.0 * sx * h[0] ** 2 * p[1] - 4.0 * sx ** 3 * p[2] - 2.0 * (h[0] ** 2 * q[0] + h[1] ** 2 * q[1] + h[2] ** 2 * q[2])


class _Orbit:
    """The motion from x0: constants, Fourier coefficients of P, turning points, panels."""

    def __init__(self, x0, p):
        x0 = [float(v) for v in x0]
        if len(x0) != 4 or not all(map(math.isfinite, x0)):
            raise NonFiniteResult("x0 must be 4 finite numbers")
        self.p = p
        self.E, self.k = energy(x0, p), momentum(x0, p)
        phis = 2.0 * math.pi * np.arange(8) / 8.0
        J, C, A, U, beta = quad_terms(phis, p)
        ej, kk = 2.0 * (self.E + U) * J, (self.k - beta) ** 2
        self.S = float(np.max(np.abs(ej) + kk))
        P = ej - kk
        c = [float(np.sum(P)) / 8.0]
        for j in (1, 2, 3):
            c += [float(np.sum(P * np.cos(j * phis))) / 4.0, float(np.sum(P * np.sin(j * phis))) / 4.0]
        if not math.isfinite(self.S):
            raise NonFiniteResult("E(phi) J - K^2 is not finite")
        phi0, phid0 = x0[1], x0[3]
        J0, C0, A0, _, _ = (float(v) for v in quad_terms(phi0, p))
        D0 = A0 * J0 - C0 * C0
        if not (D0 > 0.0 and J0 > 0.0):
            raise SingularMassMatrix("M is not positive definite at phi0")
        c[0] += D0 * phid0 * phid0 - _pfour(c, phi0)[0]  # P(phi0) = D(phi0) phidot0^2 exactly
        self.c = c
        self.L2 = sum(j * j * (abs(c[2 * j - 1]) + abs(c[2 * j])) for j in (1, 2, 3))
        self.eps = math.inf
        self.phi0, self.dir = phi0, (1.0 if phid0 >= 0.0 else -1.0)
        self.r = [0.0, 0.0]
        self.kind = None
        self.pmin, self.argmin = math.inf, phi0
        d = _pfour(c, phi0)
        if phid0 == 0.0:
            if not abs(d[1]) > SEPARATRIX_TOL * self.S:
                self.kind = STEADY
                return
            self.dir = 1.0 if d[1] > 0.0 else -1.0
            found, root = self._walk(phi0 + self.dir * abs(d[1]) / self.L2, self.dir, 2.0 * math.pi)
            if found != 1:
                raise (SeparatrixError if found == 0 else QuadratureFailed)("no second turning point")
            lo_first = self.dir > 0.0
            self.r = [phi0, root] if lo_first else [root, phi0]
        else:
            found, root = self._walk(phi0, self.dir, 2.0 * math.pi)
            if found < 0:
                raise QuadratureFailed("the walk to the turning point did not converge")
            if found == 0:
                self.kind = ROTATION
            else:
                other_found, other = self._walk(phi0, -self.dir, 2.0 * math.pi)
                if other_found != 1:
                    raise QuadratureFailed("no second turning point")
                self.r = [other, root] if self.dir > 0.0 else [root, other]
        if self.S > 0.0:
            self.eps = self.pmin / self.S
        if self.kind != ROTATION:
            self.kind = LIBRATION
            self.h = 0.5 * (self.r[1] - self.r[0])
            self.slope = []
            for r in self.r:
                d = _pfour(c, r)
                self.slope.append(abs(d[1]))
                e_end = d[1] * d[1] / (2.0 * d[2] * self.S) if d[2] > 0.0 else math.inf
                self.eps = min(self.eps, e_end)
        if self.eps < SEPARATRIX_TOL:
            raise SeparatrixError(
                f"the state is on the separatrix (relative distance {self.eps:.2g} < {SEPARATRIX_TOL:g}): "
                "phi tends to an unstable steady motion and has no period"
            )
        if self.kind == ROTATION:
            self.phis = self.argmin
            d = _pfour(c, self.phis)
            self.Ps = d[0]
            self.w = min(math.sqrt(2.0 * d[0] / d[2]) if d[2] > 0.0 else 1.0, 1.0)  # width of the bump
            self.U = math.asinh(math.pi / self.w)
            self.panels = [self._panels(0, 2.0 * self.U, 8)]
        else:
            self.panels = [self._panels(0, 0.5 * math.pi, 4), self._panels(1, 0.5 * math.pi, 4)]
        self.tot = [pan["total"] for pan in self.panels]

    def _walk(self, a, sig, dmax):
        """(1, root) at the first root of P from a in the sense sig, (0, None) when P > 0 over
        dmax, (-1, None) when the walk does not converge.  Records the least local minimum."""
        c, gone = self.c, 0.0
        d = _pfour(c, a)
        for _ in range(_WALK_MAX):
            if not d[0] > 0.0:
                return 1, a
            step = 2.0 * d[0] / (abs(d[1]) + math.sqrt(d[1] * d[1] + 2.0 * self.L2 * d[0]))
            last = gone + step >= dmax
            if last:
                step = dmax - gone
            elif step <= 4.0 * _EPS * (1.0 + abs(a)):
                return 1, a + sig * step
            dn = _pfour(c, a + sig * step)
            if sig * d[1] < 0.0 < sig * dn[1]:
                lo, hi = a, a + sig * step
                for _i in range(60):
                    mid = 0.5 * (lo + hi)
                    if sig * _pfour(c, mid)[1] < 0.0:
                        lo = mid
                    else:
                        hi = mid
                pm = _pfour(c, 0.5 * (lo + hi))[0]
                if pm < self.pmin:
                    self.pmin, self.argmin = pm, 0.5 * (lo + hi)
            if last:
                return 0, None
            a += sig * step
            gone += step
            d = dn
        return -1, None

    def integrand(self, q, b):
        """dt, dpsi_K, dpsi_C per unit parameter b (array) of quarter q, with phi and g = dt/db."""
        b = np.asarray(b, dtype=float)
        if self.kind == ROTATION:
            # sinh map: a near-double root of P at phis (near the separatrix) becomes a smooth bump
            x = self.w * np.sinh(b - self.U)
            phi = self.phis + x
            dphi = self.w * np.cosh(b - self.U)
            P = self.Ps + _pbump(self.c, self.phis, x)
            s2 = None
        else:
            s2 = np.sin(0.5 * b)
            x = (-2.0 if q else 2.0) * self.h * s2 * s2  # phi - r, kept apart: phi alone rounds it away
            phi = self.r[q] + x
            dphi = self.h * np.sin(b)
            P = _pdelta(self.c, self.r[q], x)
        J, C, A, _U, beta = quad_terms(phi, self.p)
        D = A * J - C * C
        if not (np.all(D > 0.0) and np.all(J > 0.0)):
            raise SingularMassMatrix("M is not positive definite on the path of phi")
        with np.errstate(divide="ignore", invalid="ignore"):
            if s2 is None:
                g = np.sqrt(D / P) * dphi
            else:
                g = np.where(s2 == 0.0, np.sqrt(2.0 * D * self.h / self.slope[q]), np.sqrt(D / P) * dphi)
        if not (np.all(P[s2 != 0.0] > 0.0) if s2 is not None else np.all(P > 0.0)) or not np.all(np.isfinite(g)):
            raise QuadratureFailed("E(phi) J - K^2 is not positive inside the motion")
        K = self.k - beta
        return np.array([g, K * g / J, C * dphi / J]), phi, g

    def kronrod(self, q, a, b):
        """Gauss-Kronrod 7/15 on [a, b]: the three integrals and |K15 - G7| of each."""
        hw, cx = 0.5 * (b - a), 0.5 * (a + b)
        f, _phi, _g = self.integrand(q, cx + hw * _X15)
        v = hw * (f @ _W15)
        # QUADPACK's estimate of the Kronrod error (see the C)
        e = np.abs(v - hw * (f @ _G15))
        asc = abs(hw) * (np.abs(f - 0.5 * (f @ _W15)[:, None]) @ _W15)
        scaled = asc * np.minimum(1.0, (200.0 * e / np.where(asc != 0.0, asc, 1.0)) ** 1.5)
        return v, np.where((asc != 0.0) & (e != 0.0), scaled, e)

    def _panels(self, q, end, start):
        pan = []
        for i in range(start):
            a, b = end * i / start, end * (i + 1) / start
            v, e = self.kronrod(q, a, b)
            pan.append([a, b, v, e])
        while True:
            err = sum(x[3] for x in pan)
            size = sum(np.abs(x[2]) for x in pan)
            if err[0] <= QUAD_TOL * size[0] and err[1] <= QUAD_TOL * size[1] + 1e-300 and err[2] <= QUAD_TOL * size[2] + 1e-300:
                break
            if len(pan) == QUAD_MAXP:
                raise QuadratureFailed(f"no convergence with {QUAD_MAXP} panels")
            w = [float(np.sum(x[3] / (size + 1e-300))) for x in pan]
            i = int(np.argmax(w))  # the first of equal ones, as in the C
            a, b = pan[i][0], pan[i][1]
            m = 0.5 * (a + b)
            v1, e1 = self.kronrod(q, a, m)
            v2, e2 = self.kronrod(q, m, b)
            pan[i] = [a, m, v1, e1]
            pan.append([m, b, v2, e2])
        pan.sort(key=lambda x: x[0])
        a = np.array([x[0] for x in pan])
        b = np.array([x[1] for x in pan])
        v = np.array([x[2] for x in pan])
        cum = np.vstack([np.zeros(3), np.cumsum(v, axis=0)])
        return dict(a=a, b=b, v=v, cum=cum[:-1], total=cum[-1])

    def partial(self, q, b):
        """The integrals from the start of quarter q to parameter b."""
        pan = self.panels[q]
        i = max(int(np.searchsorted(pan["a"], b, side="right")) - 1, 0)
        return pan["cum"][i] + self.kronrod(q, pan["a"][i], b)[0]

    def invert(self, q, tau):
        """The parameter b of quarter q where the time from its start is tau, and the integrals there."""
        pan = self.panels[q]
        i = max(int(np.searchsorted(pan["cum"][:, 0], tau, side="right")) - 1, 0)
        a0, lo, hi = pan["a"][i], pan["a"][i], pan["b"][i]
        x = lo + (hi - lo) * (tau - pan["cum"][i][0]) / pan["v"][i][0]
        x = min(max(x, lo), hi)
        for _ in range(100):
            part = self.kronrod(q, a0, x)[0]
            g = float(self.integrand(q, np.array([x]))[2][0])
            F = pan["cum"][i][0] + part[0] - tau
            if F > 0.0:
                hi = x
            else:
                lo = x
            xn = x - F / g
            if not lo < xn < hi:
                xn = 0.5 * (lo + hi)
            done = abs(xn - x) <= 4.0 * _EPS * abs(x) or hi - lo <= 4.0 * _EPS * abs(x)
            x = xn
            if done:
                break
        return x, pan["cum"][i] + self.kronrod(q, a0, x)[0]

    def lib_phase(self, seg, v):
        """Phase time (from phi_- with phidot > 0) and psi gained at the point with integrals v on
        segment seg: 1 phi_- -> mid, 2 mid -> phi_+ (phidot > 0), 3 phi_+ -> mid, 4 mid -> phi_-."""
        Im, Ip = self.tot
        up = Im[1] - Im[2] + Ip[1] - Ip[2]
        if seg == 1:
            return v[0], v[1] - v[2]
        if seg == 2:
            return Im[0] + Ip[0] - v[0], up - v[1] + v[2]
        if seg == 3:
            return Im[0] + Ip[0] + v[0], up + v[1] + v[2]
        return 2.0 * (Im[0] + Ip[0]) - v[0], 2.0 * (Im[1] + Ip[1]) - v[1] - v[2]


def quad_motion(x0, p=None):
    """The motion of phi from x0 by the integrals: kind ('libration', 'rotation' or 'steady'),
    the constants E and k, the turning points (libration), the period of phi and the psi gained
    per period.  Raises SeparatrixError on the separatrix."""
    o = _Orbit(x0, p)
    out = dict(kind=o.kind, E=o.E, k=o.k, separatrix_distance=o.eps)
    if o.kind == LIBRATION:
        out.update(phi_min=o.r[0], phi_max=o.r[1], period=2.0 * (o.tot[0][0] + o.tot[1][0]),
                   psi_advance=2.0 * (o.tot[0][1] + o.tot[1][1]))
    elif o.kind == ROTATION:
        out.update(phi_min=o.phi0, phi_max=o.phi0 + o.dir * 2.0 * math.pi, period=o.tot[0][0],
                   psi_advance=o.tot[0][1] - o.dir * o.tot[0][2])
    else:
        out.update(phi_min=float(x0[1]), phi_max=float(x0[1]), period=0.0, psi_advance=0.0)
    return out


def quad_period(x0, p=None):
    """The period of phi (libration or rotation) from the quadrature (30)."""
    m = quad_motion(x0, p)
    if m["kind"] == STEADY:
        raise SteadyMotion("phi stays constant: a steady motion has no period")
    return m["period"]


def quad_state(t, x0, p=None):
    """The state [psi, phi, psidot, phidot] at time(s) t from x0 by the quadratures (shape (4,)
    for a scalar t, (len(t), 4) for an array)."""
    o = _Orbit(x0, p)
    x0 = [float(v) for v in x0]
    ts = np.atleast_1d(np.asarray(t, dtype=float))
    if not np.all(np.isfinite(ts)):
        raise NonFiniteResult("t is not finite")
    out = np.empty((len(ts), 4))
    if o.kind == STEADY:
        out[:] = [x0[0], x0[1], x0[2], 0.0]
        out[:, 0] = x0[0] + x0[2] * ts
        return out if np.ndim(t) else out[0]
    if o.kind == ROTATION:
        # one turn: b from 0 (phi = phis - pi) to 2U (phis + pi); the motion runs along b when
        # dir > 0 and against it when dir < 0, where the C part of psi flips
        I = o.tot[0]
        T, dpsi = I[0], I[1] - o.dir * I[2]
        turns = math.floor((x0[1] - o.phis + math.pi) / (2.0 * math.pi))
        v0 = o.partial(0, o.U + math.asinh((x0[1] - o.phis - 2.0 * math.pi * turns) / o.w))

        def rot_phase(v):
            return (v[0], v[1] - v[2]) if o.dir > 0.0 else (T - v[0], I[1] - v[1] + I[2] - v[2])

        phase0, psir0 = rot_phase(v0)
    if o.kind == LIBRATION:
        Im, Ip = o.tot
        T = 2.0 * (Im[0] + Ip[0])
        q = int(x0[1] > 0.5 * (o.r[0] + o.r[1]))
        b0 = ((o.r[1] - x0[1]) if q else (x0[1] - o.r[0])) / (2.0 * o.h)
        b0 = 2.0 * math.asin(math.sqrt(min(max(b0, 0.0), 0.5)))
        seg = (2 if x0[3] > 0.0 else 3) if q else (4 if x0[3] < 0.0 else 1)
        phase0, psir0 = o.lib_phase(seg, o.partial(q, b0))
    for i, ti in enumerate(ts):
        if o.kind == ROTATION:
            n = math.floor((phase0 + ti) / T)
            rem = phase0 + ti - n * T
            b, v = o.invert(0, rem if o.dir > 0.0 else T - rem)
            _f, phi, g = o.integrand(0, np.array([b]))
            phi = float(phi[0]) + 2.0 * math.pi * (turns + o.dir * n)
            psi = x0[0] + n * dpsi + rot_phase(v)[1] - psir0
            phid = o.dir * o.w * math.cosh(b - o.U) / float(g[0])
        else:
            n = math.floor((phase0 + ti) / T)
            rem = phase0 + ti - n * T
            if rem < Im[0]:
                seg, tau = 1, rem
            elif rem < Im[0] + Ip[0]:
                seg, tau = 2, Im[0] + Ip[0] - rem
            elif rem < Im[0] + 2.0 * Ip[0]:
                seg, tau = 3, rem - Im[0] - Ip[0]
            else:
                seg, tau = 4, T - rem
            q = int(seg in (2, 3))
            b, v = o.invert(q, tau)
            _f, phi, g = o.integrand(q, np.array([b]))
            phi = float(phi[0])
            psi = x0[0] + n * 2.0 * (Im[1] + Ip[1]) + o.lib_phase(seg, v)[1] - psir0
            phid = (1.0 if seg <= 2 else -1.0) * o.h * math.sin(b) / float(g[0])
        J, C, _A, _U, beta = (float(v) for v in quad_terms(phi, p))
        out[i] = [psi, phi, (o.k - beta - C * phid) / J, phid]
    return out if np.ndim(t) else out[0]
