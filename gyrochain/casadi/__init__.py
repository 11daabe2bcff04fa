"""The model as CasADi functions for optimal control (``generate --casadi``, NAME_casadi.c): the
dynamics f(x, u, p), one RK4 step F(x, u, p, h), the mass matrix and the energy, each with the exact
Jacobian of the emitted derivatives where it has one, loaded by ``casadi.external`` from one
shared library of NAME_casadi.c and NAME.c.  May import: chainspec, derive, printers, models."""
from .external import CasadiModel, CasadiUnavailable, build_library, functions

__all__ = ["CasadiModel", "CasadiUnavailable", "build_library", "functions"]
