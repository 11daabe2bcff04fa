"""``python -m gyrochain`` and the ``gyrochain`` console script: the command line (cli.main), with
Ctrl-C answered as everywhere else (one line, exit 130) even while the modules are still loading."""
import sys


def run() -> None:
    try:
        from .cli import main

        code = main()
    except KeyboardInterrupt:  # before cli.main's own handler is in place (numpy, sympy still loading)
        print("error: interrupted", file=sys.stderr)
        code = 130
    sys.exit(code)


if __name__ == "__main__":
    run()
