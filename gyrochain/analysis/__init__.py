"""What a model does: simulate (trajectories), steady motions and their stability, Floquet multipliers
of driven models, periodic orbits.

Modules: simulate, floquet, steady, orbits.  May import: models, printers, derive, chainspec (the
layers of [tool.importlinter] in pyproject.toml).
"""
