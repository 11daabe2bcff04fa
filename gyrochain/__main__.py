"""``python -m gyrochain`` and the ``gyrochain`` console script: the command line (cli.main), with
Ctrl-C answered as everywhere else (one line, exit 130) even while the modules are still loading."""
import os
import signal
import sys
import threading
import time

from . import INTERRUPT, _sigint_noted, caused_by_interrupt


_CTRL_C = {"deferred": False, "quiet_until": 0.0}


def _on_sigint(signum, frame):
    """Ctrl-C as KeyboardInterrupt, but never inside the import machinery: there Python may run
    the handler in a weak-reference callback, where the exception is printed as "Exception
    ignored" and lost, and the command runs on.  While modules load most of the time is the
    machinery's, so the interrupt is handed on: it is raised at the start of the next module's
    body (a trace function that only watches for one), or where a signal that a helper thread
    sends again every 5 ms lands in our own code, whichever comes first."""
    INTERRUPT["requested"] = True  # whatever error follows is this Ctrl-C's doing
    if time.monotonic() < _CTRL_C["quiet_until"]:  # the helper's last signal, just after the delivery
        return
    if frame is not None and frame.f_code.co_filename.startswith("<frozen importlib"):
        if not _CTRL_C["deferred"]:
            _CTRL_C["deferred"] = True
            sys.settrace(_at_next_module)
            threading.Thread(target=_again, name="gyrochain-ctrl-c", daemon=True).start()  # daemon: never holds the exit
        return
    _deliver()


def _deliver():
    _stop_children()
    _CTRL_C["deferred"] = False
    _CTRL_C["quiet_until"] = time.monotonic() + 0.05
    sys.settrace(None)
    raise KeyboardInterrupt


def _at_next_module(frame, event, arg):
    """A module body starting (never a callback): the deferred Ctrl-C is raised there."""
    if event == "call" and frame.f_code.co_name == "<module>" and _CTRL_C["deferred"]:
        _deliver()


def _again() -> None:
    while _CTRL_C["deferred"]:
        time.sleep(0.005)
        if _CTRL_C["deferred"]:
            os.kill(os.getpid(), signal.SIGINT)


def run() -> None:
    if signal.getsignal(signal.SIGINT) in (signal.default_int_handler, _sigint_noted):  # (not where SIGINT is ignored)
        signal.signal(signal.SIGINT, _on_sigint)
    if INTERRUPT["requested"]:  # Ctrl-C while the package loaded (gyrochain/__init__.py noted it)
        print("error: interrupted", file=sys.stderr)
        _end_now(130)
    try:
        from .commandline.cli import main

        code = main()
    except BaseException as exc:  # before cli.main's own handler is in place (numpy, sympy still loading)
        if not caused_by_interrupt(exc):
            raise
        print("error: interrupted", file=sys.stderr)
        code = 130
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # the command has ended: a late Ctrl-C must not interrupt the exit
    if code == 130:
        _end_now(code)
    sys.exit(code)


def _stop_children() -> None:
    """Ctrl-C sent to this process alone (``kill -INT``, a supervisor) does not reach the programs it
    runs: a compiler and LTO's make and shells would run on in the build folder the unwinding
    removes, and print into our stderr after "error: interrupted".  They get SIGTERM, the deepest
    first (Linux's /proc lists each task's children; elsewhere nothing is done)."""
    found, todo = [], [os.getpid()]
    while todo:
        pid = todo.pop()
        for path in _children_files(pid):
            try:
                with open(path) as fh:
                    kids = [int(w) for w in fh.read().split()]
            except (OSError, ValueError):
                continue
            found += kids
            todo += kids
    for pid in reversed(found):
        try:
            os.kill(pid, signal.SIGTERM)
        except OSError:
            pass


def _children_files(pid: int) -> list:
    try:
        return [f"/proc/{pid}/task/{tid}/children" for tid in os.listdir(f"/proc/{pid}/task")]
    except OSError:
        return []


def _end_now(code: int) -> None:
    """Interrupted: every clean-up ran while the stack unwound, so the interpreter's own tear-down
    of sympy's and numpy's objects (0.2 s here, seconds on a busy machine) is skipped."""
    _stop_children()
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)


if __name__ == "__main__":
    run()
