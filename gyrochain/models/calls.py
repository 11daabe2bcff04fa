"""Calls into a model's C: one that may run long (an integrator), made so that Ctrl-C ends it at
once; and the discrete-time model, the derivatives an optimiser asks for and the two-body
quadratures (CModel's methods)."""
from __future__ import annotations

import numpy as np


def interruptible(fn, *args, keep=()):
    """``fn(*args)``, a call into the C that may run long (an integrator), made so that Ctrl-C
    ends it at once: from the main thread the call runs in a helper thread, which cffi lets run
    without the GIL, and the main thread waits for it in short timed waits, which a signal
    interrupts; KeyboardInterrupt then unwinds the caller's stack (its clean-ups run) while the
    abandoned call goes on in its daemon thread until the process exits.  From any other thread
    (a sweep's workers) the call is made directly: the main thread is the one Ctrl-C reaches.
    ``keep``: the arrays the pointers in ``args`` point into (a cffi cast does not keep its buffer
    alive): the helper thread holds them, so an abandoned call never writes into freed memory.
    A thread costs about 0.1 ms; it is used only for the integrators (docs/testing.md)."""
    import threading

    if threading.current_thread() is not threading.main_thread():
        return fn(*args)
    box: dict = {}

    def work(held=keep):  # noqa: ARG001  (held: alive as long as the call runs)
        try:
            box["result"] = fn(*args)
        except BaseException as exc:  # noqa: BLE001  (raised again in the caller's thread)
            box["error"] = exc

    helper = threading.Thread(target=work, name="gyrochain-c-call", daemon=True)
    helper.start()
    while helper.is_alive():
        helper.join(0.05)
    if "error" in box:
        raise box["error"]
    return box["result"]


class DerivativeCalls:
    """CModel's calls of NAME_step, NAME_step_jacobian, NAME_param_derivatives,
    NAME_step_param_derivatives, NAME_rhs_hessian and NAME_step_hessian (CModel's helpers _arr,
    _u, _p, _outs, _call, _checked and _fn)."""

    def step(self, x, h, u=None, params=None, t=0.0):
        """x(t + h) by one classical RK4 step with u held (NAME_step, the discrete-time model)."""
        (xp, _k), (up, _ku) = self._arr(x, 2 * self.n), self._u(u)
        return self._call("step", float(t), xp, up, self._p(params), float(h), out_len=2 * self.n)

    def step_jacobian(self, x, h, u=None, params=None, t=0.0, with_h=True, with_t=False):
        r"""(``xn``, ``Ad``, ``Bd``, ``xn_h``) of NAME_step_jacobian: the step (2n) and its exact
        derivatives in x (2n × 2n), u (2n × nu) and h (2n; None with ``with_h`` False); with
        ``with_t`` (a model that reads t) also ``xn_t`` = $\partial x_n/\partial t$ (2n), the fifth."""
        if with_t and not self.time_dependent:
            raise AttributeError(f"{self.name} does not read t: its step has no derivative in t")
        (xp, _k), (up, _ku), d = self._arr(x, 2 * self.n), self._u(u), 2 * self.n
        (xn, Ad, Bd, dh, dt), ptrs = self._outs(d, (d, d), (d, self.nu), d, d)
        ptrs[2:4] = [ptrs[2] if Bd.size else self.ffi.NULL, ptrs[3] if with_h else self.ffi.NULL]
        ptrs[4:] = [ptrs[4] if with_t else self.ffi.NULL] if self.time_dependent else []
        self._checked("step_jacobian", self._fn("step_jacobian")(float(t), xp, up, self._p(params), float(h), *ptrs))
        return (xn, Ad, Bd, dh if with_h else None) + ((dt,) if with_t else ())

    def time_derivative(self, x, u=None, params=None, t=0.0):
        r"""($\ddot\varphi$, $\partial\ddot\varphi/\partial t$), n numbers each, of NAME_time_derivative (a model that reads t)."""
        (xp, _k), (up, _ku) = self._arr(x, 2 * self.n), self._u(u)
        out, ptrs = self._outs(self.n, self.n)
        self._checked("time_derivative", self._fn("time_derivative")(float(t), xp, up, self._p(params), *ptrs))
        return out[0], out[1]

    def param_derivatives(self, x, u=None, params=None, t=0.0):
        r"""($\ddot\varphi$, $\partial\ddot\varphi/\partial p$) of NAME_param_derivatives: n, and n × NPARAMS (the spec's
        symbolic parameters in their order)."""
        (xp, _k), (up, _ku), npar = self._arr(x, 2 * self.n), self._u(u), self.nparams
        out, ptrs = self._outs(self.n, (self.n, npar))
        self._checked("param_derivatives", self._fn("param_derivatives")(*self._t(t), xp, up, self._p(params), *ptrs))
        return out[0], out[1]

    def step_param_derivatives(self, x, h, u=None, params=None, t=0.0):
        r"""(xn, $\partial x_n/\partial p$) of NAME_step_param_derivatives: 2n, and 2n × NPARAMS."""
        (xp, _k), (up, _ku), npar = self._arr(x, 2 * self.n), self._u(u), self.nparams
        out, ptrs = self._outs(2 * self.n, (2 * self.n, npar))
        self._checked("step_param_derivatives", self._fn("step_param_derivatives")(float(t), xp, up, self._p(params), float(h), *ptrs))
        return out[0], out[1]

    def rhs_hessian(self, x, lam, u=None, params=None, t=0.0):
        r"""$\nabla^2(\lambda\cdot f)$ in z = (x, u), and t last in a model that reads t: a symmetric
        array, 2n + nu (+ 1) square (NAME_rhs_hessian: generate --hessian or --casadi); lam 2n weights."""
        (xp, _k), (up, _ku), (lp, _kl) = self._arr(x, 2 * self.n), self._u(u), self._arr(lam, 2 * self.n)
        z = 2 * self.n + self.nu + int(self.time_dependent)
        return self._call("rhs_hessian", float(t), xp, up, self._p(params), lp, out_len=z * z).reshape(z, z)

    def step_hessian(self, x, h, lam, u=None, params=None, t=0.0):
        r"""$\nabla^2(\lambda\cdot x_n)$ of NAME_step in w = (x, u, h), and t last in a model that reads
        t: a symmetric array, 2n + nu + 1 (+ 1) square (NAME_step_hessian)."""
        (xp, _k), (up, _ku), (lp, _kl) = self._arr(x, 2 * self.n), self._u(u), self._arr(lam, 2 * self.n)
        w = 2 * self.n + self.nu + 1 + int(self.time_dependent)
        return self._call("step_hessian", float(t), xp, up, self._p(params), float(h), lp, out_len=w * w).reshape(w, w)


class QuadratureCalls:
    """CModel's calls of the two-body quadratures (30), in a model with NAME_HAS_QUADRATURES
    (CModel's ``_motions``: the motion kinds by their codes)."""

    def quad_motion(self, x0, params=None) -> dict:
        """The two-body motion from the state x0 (4) by the quadratures (30): a dict of ``kind``
        (libration, rotation, steady), the energy ``E``, the momentum ``k``, ``phi_min``,
        ``phi_max``, the ``period``, ``psi_advance`` per period and ``separatrix_distance``."""
        xp, _k = self._arr(x0, 4)
        info = self.ffi.new(f"{self.name}_quad_info *")
        self._checked("quad_motion", self._fn("quad_motion")(xp, self._p(params), info))
        kinds = self._motions
        fields = ("E", "k", "phi_min", "phi_max", "period", "psi_advance", "separatrix_distance")
        return dict(kind=kinds[info.kind], **{f: getattr(info, f) for f in fields})

    def quad_period(self, x0, params=None) -> float:
        """The period of the motion from the state x0 (4), s, by the quadratures (30)."""
        xp, _k = self._arr(x0, 4)
        out = self.ffi.new(self._ptr)
        self._checked("quad_period", self._fn("quad_period")(xp, self._p(params), out))
        return out[0]

    def quad_state(self, t, x0, params=None) -> np.ndarray:
        """The state at the time t (a float: 4 numbers; an array of m times: m × 4) of the motion
        from x0, by the quadratures (30), without integrating."""
        xp, _k = self._arr(x0, 4)
        ts = np.atleast_1d(np.asarray(t, dtype=float))
        out = np.empty((len(ts), 4), self.dtype)
        p = self._p(params)
        for i, ti in enumerate(ts):
            self._checked("quad_state", self._fn("quad_state")(float(ti), xp, p, self.ffi.cast(self._ptr, self.ffi.from_buffer(out[i]))))
        return out if np.ndim(t) else out[0]

    def quad_functions(self, phi, x0, params=None) -> np.ndarray:
        """The quadratures' functions at the angle phi of the motion from x0: six numbers, J, C,
        the inertia term, E, K and the integrand (docs/integrals.md names them)."""
        xp, _k = self._arr(x0, 4)
        return self._call("quad_functions", float(phi), xp, self._p(params), out_len=6)
