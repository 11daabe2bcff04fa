"""Calls into a model's C: one that may run long (an integrator), made so that Ctrl-C ends it at
once; and the discrete-time model and the derivatives an optimiser asks for (CModel's methods)."""
from __future__ import annotations


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

    def step_jacobian(self, x, h, u=None, params=None, t=0.0, with_h=None):
        """(xn, Ad, Bd, xn_h) of NAME_step_jacobian: the step and its exact derivatives in x, u and h
        (``with_h`` False, or None on a model that reads t, which has no ∂xn/∂h: xn_h None)."""
        with_h = not self.time_dependent if with_h is None else with_h
        (xp, _k), (up, _ku), d = self._arr(x, 2 * self.n), self._u(u), 2 * self.n
        (xn, Ad, Bd, dh), ptrs = self._outs(d, (d, d), (d, self.nu), d)
        ptrs[2:] = [ptrs[2] if Bd.size else self.ffi.NULL, ptrs[3] if with_h else self.ffi.NULL]
        self._checked("step_jacobian", self._fn("step_jacobian")(float(t), xp, up, self._p(params), float(h), *ptrs))
        return xn, Ad, Bd, dh if with_h else None

    def param_derivatives(self, x, u=None, params=None, t=0.0):
        """(φ̈, ∂φ̈/∂p) of NAME_param_derivatives, ∂φ̈/∂p n × NPARAMS (the spec's symbolic parameters)."""
        (xp, _k), (up, _ku), npar = self._arr(x, 2 * self.n), self._u(u), self.nparams
        out, ptrs = self._outs(self.n, (self.n, npar))
        self._checked("param_derivatives", self._fn("param_derivatives")(*self._t(t), xp, up, self._p(params), *ptrs))
        return out[0], out[1]

    def step_param_derivatives(self, x, h, u=None, params=None, t=0.0):
        """(xn, ∂xn/∂p) of NAME_step_param_derivatives, ∂xn/∂p 2n × NPARAMS."""
        (xp, _k), (up, _ku), npar = self._arr(x, 2 * self.n), self._u(u), self.nparams
        out, ptrs = self._outs(2 * self.n, (2 * self.n, npar))
        self._checked("step_param_derivatives", self._fn("step_param_derivatives")(float(t), xp, up, self._p(params), float(h), *ptrs))
        return out[0], out[1]

    def rhs_hessian(self, x, lam, u=None, params=None, t=0.0):
        """∇²(λ·f) in z = (x, u), (2n + nu) square (NAME_rhs_hessian: generate --hessian or --casadi)."""
        (xp, _k), (up, _ku), (lp, _kl), z = self._arr(x, 2 * self.n), self._u(u), self._arr(lam, 2 * self.n), 2 * self.n + self.nu
        return self._call("rhs_hessian", float(t), xp, up, self._p(params), lp, out_len=z * z).reshape(z, z)

    def step_hessian(self, x, h, lam, u=None, params=None, t=0.0):
        """∇²(λ·xn) of NAME_step in w = (x, u, h), (2n + nu + 1) square (NAME_step_hessian)."""
        (xp, _k), (up, _ku), (lp, _kl), w = self._arr(x, 2 * self.n), self._u(u), self._arr(lam, 2 * self.n), 2 * self.n + self.nu + 1
        return self._call("step_hessian", float(t), xp, up, self._p(params), float(h), lp, out_len=w * w).reshape(w, w)
