"""A call into a model's C that may run long (an integrator), made so that Ctrl-C ends it at once."""
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
