"""Linearise the MuJoCo model about its static state: the continuous-time state matrix of the car.

Central finite differences of ``mj_forward`` accelerations with respect to joint positions and
velocities. Used to check the simulated model against the analytic ride model (rig/vehicle/ride_model.py)
without any integrator in the loop.
"""

from __future__ import annotations

import mujoco
import numpy as np

from rig.sim.simulate import Simulator


def car_state_matrix(sim: Simulator, step: float = 1e-6) -> np.ndarray:
    """State matrix A (state = [q, dq/dt] of the car DOFs, posts held) at static ride height."""
    rig = sim.rig
    model = rig.model
    data = mujoco.MjData(model)
    dofs = rig.free_dofs
    qpos0 = sim.static.qpos

    def qacc(qpos: np.ndarray, qvel: np.ndarray) -> np.ndarray:
        data.qpos[:], data.qvel[:] = qpos, qvel
        mujoco.mj_forward(model, data)
        return data.qacc[dofs].copy()

    n = dofs.size
    d_position, d_velocity = np.empty((n, n)), np.empty((n, n))
    for column, dof in enumerate(dofs):
        for target, is_velocity in ((d_position, False), (d_velocity, True)):
            plus_q, minus_q = qpos0.copy(), qpos0.copy()
            plus_v, minus_v = np.zeros(model.nv), np.zeros(model.nv)
            if is_velocity:
                plus_v[dof], minus_v[dof] = step, -step
            else:
                plus_q[model.jnt_qposadr[model.dof_jntid[dof]]] += step
                minus_q[model.jnt_qposadr[model.dof_jntid[dof]]] -= step
            target[:, column] = (qacc(plus_q, plus_v) - qacc(minus_q, minus_v)) / (2 * step)
    return np.block([[np.zeros((n, n)), np.eye(n)], [d_position, d_velocity]])
