"""3-vectors and 3×3 matrices of polynomials as plain lists: the one set of helpers that the
kinematics, the dynamics, the integrals, the articulated recursion (aba) and the world form share."""
from __future__ import annotations

from .algebra import ZERO, Poly


def cross(a, b) -> list:
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def dot(a, b) -> Poly:
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def add(*vs) -> list:
    return [sum((v[i] for v in vs), ZERO) for i in range(3)]


def scale(c, v) -> list:
    return [c * x for x in v]


def matvec(A, v) -> list:
    return [A[i][0] * v[0] + A[i][1] * v[1] + A[i][2] * v[2] for i in range(3)]


def skew(v) -> list:
    """[v×]: the matrix with [v×] w = v × w."""
    return [[ZERO, -v[2], v[1]], [v[2], ZERO, -v[0]], [-v[1], v[0], ZERO]]
