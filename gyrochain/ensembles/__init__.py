"""Many motions at once: sweep (grids and random samples on threads or Dask), the resumable Zarr store,
and the measures a sweep records.

Modules: measures, store, sweep.  May import: analysis, models, printers, derive, chainspec (the
layers of [tool.importlinter] in pyproject.toml).
"""
