"""Robot descriptions: URDF and MJCF read into a chain (robot, urdf, mjcf), the spec written from it
(robotspec), and URDF and MJCF written from a spec (exchange).

Modules: robot, robotspec, urdf, mjcf, exchange.  May import: models, printers, derive, chainspec
(the layers of [tool.importlinter] in pyproject.toml).
"""
