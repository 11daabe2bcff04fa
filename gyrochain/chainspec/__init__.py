"""The spec file: its model (ChainSpec, load_spec, parse_spec), the whitelisted expressions of its
numbers, the physical checks of its bodies, the names it may use, the one-line errors (SpecError)
and random specs for the tests.

Modules: spec, physical, names, errors, randspec.  May import: nothing else of gyrochain (the layers
of [tool.importlinter] in pyproject.toml).
"""
