"""The gyrochain command: its parsers, the argument checks, the starter specs and examples, and cli,
which calls one library function per command and prints.

Modules: cliargs, parsers, starter, cli.  May import: every other subpackage (the layers of
[tool.importlinter] in pyproject.toml).
"""
