"""Parameter identification: excitation design (excite), measured recordings (measured), the estimate
and its validation (identify), and the checks that data are consistent.

Modules: consistency, measured, excite, identify.  May import: analysis, models, printers, derive,
chainspec (the layers of [tool.importlinter] in pyproject.toml).
"""
