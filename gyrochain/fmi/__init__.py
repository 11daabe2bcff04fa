"""FMI 3.0 and 2.0 FMUs of a model, for model exchange and co-simulation.

Modules: fmu.  May import: models, printers, derive, chainspec (the layers of [tool.importlinter] in
pyproject.toml).
"""
