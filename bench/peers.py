"""The peers of bench/speed.py, built from the same numeric chain (gyrochain.reference.NumericChain).

Conventions (digest §3): frame k turns from frame k-1 by alpha^k = R1(phi) R2(theta) (v^(k) =
alpha v^(k-1)), the joint axis is e1 of frame k, O^k sits at s^(k-1) in frame k-1 (O^1 at the
suspension point), gravity is g along e^0_1, a gyrostat adds the moment -omega x lambda.
"""
from __future__ import annotations

import numpy as np


def _R2(theta: float) -> np.ndarray:
    ct, st = np.cos(theta), np.sin(theta)
    return np.array([[ct, 0.0, -st], [0.0, 1.0, 0.0], [st, 0.0, ct]])


# --------------------------------------------------------------------------- CasADi
def casadi_aba(ch, name: str, torques: bool = False):
    """Featherstone's articulated-body algorithm in CasADi SX (spatial 6-vectors [w; v],
    numbers folded in), returned as a casadi Function x -> qdd; with ``torques``, (x, u) -> qdd,
    u the torques of the controlled joints and the joints' viscous damping (a chain with no other
    general term: no springs, loads or moving platform)."""
    import casadi as ca

    n = ch.n
    x = ca.SX.sym("x", 2 * n)
    q, qd = x[:n], x[n:]
    tau = [0] * n
    if torques:
        uc = ca.SX.sym("u", len(ch.controls))
        for i, joint in enumerate(ch.controls):
            tau[joint - 1] = uc[i]
        if ch.general is not None:
            tau = [tau[k] - float(ch.general.damping[k]) * qd[k] for k in range(n)]

    def skew(v):
        return ca.vertcat(ca.horzcat(0, -v[2], v[1]), ca.horzcat(v[2], 0, -v[0]), ca.horzcat(-v[1], v[0], 0))

    def crm(v):  # motion cross product matrix
        w, u = v[:3], v[3:]
        Z = ca.SX.zeros(3, 3)
        return ca.vertcat(ca.horzcat(skew(w), Z), ca.horzcat(skew(u), skew(w)))

    def crf(v):
        return -crm(v).T

    X, S, c, IA, pA, v = [None] * n, ca.DM([1, 0, 0, 0, 0, 0]), [None] * n, [None] * n, [None] * n, [None] * n
    for k in range(n):
        cp, sp_ = ca.cos(q[k]), ca.sin(q[k])
        R1 = ca.vertcat(ca.horzcat(1, 0, 0), ca.horzcat(0, cp, sp_), ca.horzcat(0, -sp_, cp))
        E = ca.mtimes(R1, ca.DM(_R2(ch.theta[k])))
        r = ch.s[k - 1] if k > 0 else np.zeros(3)
        X[k] = ca.vertcat(ca.horzcat(E, ca.SX.zeros(3, 3)), ca.horzcat(-ca.mtimes(E, ca.DM(skew_np(r))), E))
        vJ = S * qd[k]
        v[k] = vJ if k == 0 else ca.mtimes(X[k], v[k - 1]) + vJ
        c[k] = ca.mtimes(crm(v[k]), vJ)
        m, cc, A = ch.m[k], ch.c[k], ch.A[k]
        C = skew_np(cc)
        I = np.block([[A, m * C], [m * C.T, m * np.eye(3)]])
        IA[k] = ca.SX(ca.DM(I))
        pA[k] = ca.mtimes(crf(v[k]), ca.mtimes(IA[k], v[k]))
        lam = ca.DM(ch.lam[k])
        pA[k] = pA[k] + ca.vertcat(ca.cross(v[k][:3], lam), ca.SX.zeros(3))
    U, D, u = [None] * n, [None] * n, [None] * n
    for k in range(n - 1, -1, -1):
        U[k] = IA[k][:, 0]
        D[k] = U[k][0]
        u[k] = tau[k] - pA[k][0]
        if k > 0:
            Ia = IA[k] - ca.mtimes(U[k], U[k].T) / D[k]
            pa = pA[k] + ca.mtimes(Ia, c[k]) + U[k] * u[k] / D[k]
            IA[k - 1] = IA[k - 1] + ca.mtimes(ca.mtimes(X[k].T, Ia), X[k])
            pA[k - 1] = pA[k - 1] + ca.mtimes(X[k].T, pa)
    a0 = ca.DM([0, 0, 0, -ch.g, 0, 0])
    qdd = [None] * n
    a = None
    for k in range(n):
        a = ca.mtimes(X[k], a0 if k == 0 else a) + c[k]
        qdd[k] = (u[k] - ca.mtimes(U[k].T, a)) / D[k]
        a = a + S * qdd[k]
    return ca.Function(name, [x, uc] if torques else [x], [ca.vertcat(*qdd)], {"cse": True})


def skew_np(v) -> np.ndarray:
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


# --------------------------------------------------------------------------- Pinocchio
def pinocchio_data(ch) -> str:
    """The chain for bench/pinocchio.cpp: n, g, then per body the joint placement (rotation
    R2(theta)^T row by row, translation s^(k-1)), mass, centre of mass, central inertia and the
    gyrostatic moment."""
    out = [str(ch.n), repr(float(ch.g))]
    for k in range(ch.n):
        m, c, A = ch.m[k], ch.c[k], ch.A[k]
        AG = A - m * (c @ c * np.eye(3) - np.outer(c, c))
        r = ch.s[k - 1] if k > 0 else np.zeros(3)
        vals = [*np.ravel(_R2(ch.theta[k]).T), *r, m, *c, *np.ravel(AG), *ch.lam[k]]
        out.append(" ".join(repr(float(v)) for v in vals))
    return "\n".join(out) + "\n"


# --------------------------------------------------------------------------- MuJoCo
def mujoco_xml(ch) -> str:
    """The chain as MJCF (hinge joints about x, no geoms, no contacts).  MuJoCo has no internal
    rotor momentum, so the benchmark gives it the chain with lambda = 0."""
    def vec(a):
        return " ".join(repr(float(t)) for t in a)

    body = ""
    for k in range(ch.n - 1, -1, -1):
        R = _R2(ch.theta[k]).T  # child axes in parent coordinates
        r = ch.s[k - 1] if k > 0 else np.zeros(3)
        m, c, A = ch.m[k], ch.c[k], ch.A[k]
        AG = A - m * (c @ c * np.eye(3) - np.outer(c, c))
        full = [AG[0, 0], AG[1, 1], AG[2, 2], AG[0, 1], AG[0, 2], AG[1, 2]]
        body = (
            f'<body name="b{k}" pos="{vec(r)}" xyaxes="{vec(R[:, 0])} {vec(R[:, 1])}">'
            f'<joint name="j{k}" type="hinge" axis="1 0 0"/>'
            f'<inertial pos="{vec(c)}" mass="{float(m)!r}" fullinertia="{vec(full)}"/>'
            + body + "</body>"
        )
    return (
        '<mujoco model="chain"><option gravity="' + vec([ch.g, 0, 0]) + '" integrator="Euler">'
        '<flag contact="disable" constraint="disable" energy="disable"/></option>'
        "<worldbody>" + body + "</worldbody></mujoco>"
    )


def mujoco_c(n: int, xml_path: str) -> str:
    return f"""#include <stdio.h>
#include <stdlib.h>
#include <mujoco/mujoco.h>
static mjModel *m_;
static mjData *d_;
static int bench_setup(void)
{{
    char err[1000];
    m_ = mj_loadXML("{xml_path}", 0, err, 1000);
    if (!m_) {{ fprintf(stderr, "%s\\n", err); exit(1); }}
    d_ = mj_makeData(m_);
    return {n};
}}
static int bench_qdd(const double *x, double *qdd)
{{
    int i;
    for (i = 0; i < {n}; ++i) {{ d_->qpos[i] = x[i]; d_->qvel[i] = x[{n} + i]; }}
    mj_forward(m_, d_);
    for (i = 0; i < {n}; ++i) qdd[i] = d_->qacc[i];
    return 0;
}}
#include "harness.h"
"""
