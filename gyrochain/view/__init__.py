"""Seeing the motion: the scene of a pose, its rasterisation, animations and stills (animate), and the
maps of a sweep (plot).

Modules: scene, raster, animate, plot.  May import: ensembles, analysis, models, printers, derive,
chainspec (the layers of [tool.importlinter] in pyproject.toml).
"""
