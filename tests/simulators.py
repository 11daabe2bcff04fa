"""The simulators the robot tests hold our φ̈ to: Pinocchio's ABA on a URDF file and MuJoCo's
``mj_forward`` on a URDF or MJCF model, each cut to a chain's joints (the others locked at their
values, or at rest at the model's pose), φ̈ in the chain's order.  Imported by the tests that
have already skipped where the simulator is missing."""
from __future__ import annotations

import numpy as np


def _chain_state(joints, x, n_q, n_v, q):
    """(q, v) with the chain's joints set from x = (φ, φ̇): a continuous joint as (cos φ, sin φ)."""
    n = len(joints)
    v = np.zeros(n_v)
    for k, j in enumerate(joints):
        if j.nq == 2:
            q[j.idx_q:j.idx_q + 2] = np.cos(x[k]), np.sin(x[k])
        else:
            q[j.idx_q] = x[k]
        v[j.idx_v] = x[n + k]
    return q, v


class Pin:
    """Pinocchio's model of a URDF file with every joint but ``names`` locked at ``locks`` or its
    zero (``buildReducedModel``), gravity g along −z.  Where Pinocchio cannot reduce the model (a
    joint and a link of one name), the full model's equations cut to the chain: M_cc φ̈ = τ − b_c."""

    def __init__(self, path, names, locks: dict, g: float):
        import pinocchio as pin

        self.pin = pin
        full = pin.buildModelFromUrdf(str(path))
        q0 = pin.neutral(full)
        for joint, value in locks.items():
            q0[full.joints[full.getJointId(joint)].idx_q] = float(value)
        drop = [full.getJointId(j) for j in full.names[1:] if j not in names]
        try:
            self.model, self.q0 = (pin.buildReducedModel(full, drop, q0) if drop else full), None
        except ValueError:
            self.model, self.q0 = full, q0
        self.model.gravity.linear[:] = [0.0, 0.0, -g]
        self.data = self.model.createData()
        self.joints = [self.model.joints[self.model.getJointId(j)] for j in names]

    def qdd(self, x, tau):
        pin, m = self.pin, self.model
        q = pin.neutral(m) if self.q0 is None else self.q0.copy()
        q, v = _chain_state(self.joints, x, m.nq, m.nv, q)
        idx = [j.idx_v for j in self.joints]
        t = np.zeros(m.nv)
        t[idx] = tau
        if self.q0 is None:
            return pin.aba(m, self.data, q, v, t)[idx]
        M = pin.crba(m, self.data, q)
        M = np.triu(M) + np.triu(M, 1).T
        b = pin.rnea(m, self.data, q, v, np.zeros(m.nv))
        return np.linalg.solve(M[np.ix_(idx, idx)], t[idx] - b[idx])


class Mj:
    """MuJoCo's model (``model``: compiled), constraints off (a joint limit is not part of the
    chain's dynamics), every joint but ``names`` at rest at the model's pose; torques as applied
    forces.  Where the chain is the whole model this is ``qacc``; else M_cc φ̈ = τ + passive − bias."""

    def __init__(self, model, names):
        import mujoco

        self.mujoco, self.model = mujoco, model
        model.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONSTRAINT
        self.data = mujoco.MjData(model)
        ids = [model.joint(j).id for j in names]
        self.qpos = [model.jnt_qposadr[i] for i in ids]
        self.dof = [model.jnt_dofadr[i] for i in ids]

    @classmethod
    def of_text(cls, xml: str, names):
        import mujoco

        return cls(mujoco.MjModel.from_xml_string(xml), names)

    @classmethod
    def of_file(cls, path, names):
        import mujoco

        return cls(mujoco.MjModel.from_xml_path(str(path)), names)

    def qdd(self, x, tau):
        mujoco, m, d, n = self.mujoco, self.model, self.data, len(self.dof)
        d.qpos[:], d.qvel[:], d.qfrc_applied[:], d.ctrl[:] = m.qpos0, 0, 0, 0
        d.qpos[self.qpos], d.qvel[self.dof], d.qfrc_applied[self.dof] = x[:n], x[n:], tau
        mujoco.mj_forward(m, d)
        if n == m.nv:
            return d.qacc[self.dof].copy()
        M = np.zeros((m.nv, m.nv))
        mujoco.mj_fullM(m, d, M)
        rhs = d.qfrc_applied + d.qfrc_passive - d.qfrc_bias
        return np.linalg.solve(M[np.ix_(self.dof, self.dof)], rhs[self.dof])
