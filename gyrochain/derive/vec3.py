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


# Spatial 6-vectors (motions (ω, v), forces (moment, force)) as lists of six, and a body's
# spatial inertia as (A, h, m) about a point: the frame-0 forms (world.py, loopform.py) share them.

def mcross(a, b) -> list:
    """Motion × motion: (ω₁ × ω₂, ω₁ × v₂ + v₁ × ω₂)."""
    return cross(a[:3], b[:3]) + add(cross(a[:3], b[3:]), cross(a[3:], b[:3]))


def fcross(a, f) -> list:
    """Motion ×* force: (ω × n + v × F, ω × F)."""
    return add(cross(a[:3], f[:3]), cross(a[3:], f[3:])) + cross(a[:3], f[3:])


def inertia_apply(I, m6) -> list:
    """(A, h, m) about a point applied to a motion: (Aω + h × v, m v − h × ω)."""
    A, h, m = I
    Aw = [sum((A[i][j] * m6[j] for j in range(3)), ZERO) for i in range(3)]
    return add(Aw, cross(h, m6[3:])) + [m * m6[3 + i] - x for i, x in enumerate(cross(h, m6[:3]))]


def dot6(a, b) -> Poly:
    return sum((a[i] * b[i] for i in range(6)), ZERO)
