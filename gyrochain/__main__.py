"""``python -m gyrochain`` and the ``gyrochain`` console script: the command line (cli.main), with
Ctrl-C answered as everywhere else (one line, exit 130) even while the modules are still loading."""
import os
import signal
import sys
import threading

from . import caused_by_interrupt


def _on_sigint(signum, frame):
    """Ctrl-C as KeyboardInterrupt, but never inside the import machinery: there Python may run
    the handler in a weak-reference callback, where the exception is printed as "Exception
    ignored" and lost, and the command runs on.  So the signal is sent again 50 ms later, until it
    lands in our own code."""
    if frame is not None and frame.f_code.co_filename.startswith("<frozen importlib"):
        again = threading.Timer(0.05, os.kill, (os.getpid(), signal.SIGINT))
        again.daemon = True  # a command that ends first is not held back by it
        again.start()
        return
    raise KeyboardInterrupt


def run() -> None:
    if signal.getsignal(signal.SIGINT) is signal.default_int_handler:  # (not where SIGINT is ignored)
        signal.signal(signal.SIGINT, _on_sigint)
    try:
        from .cli import main

        code = main()
    except BaseException as exc:  # before cli.main's own handler is in place (numpy, sympy still loading)
        if not caused_by_interrupt(exc):
            raise
        print("error: interrupted", file=sys.stderr)
        code = 130
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # the command has ended: a late Ctrl-C must not interrupt the exit
    sys.exit(code)


if __name__ == "__main__":
    run()
