"""A free truck frame's bending and torsion natural frequencies, from its MjSpec's mass and stiffness matrices."""

import mujoco
import numpy as np

from rig.elements.frame import Frame, frame_spec


def frame_frequencies(frame: Frame, mass: float, roll_inertia: float) -> tuple[list[float], list[float]]:
    """Bending and torsion natural frequencies (rad/s, ascending, rigid-body modes left out) of the free frame."""
    model = frame_spec(frame, mass, roll_inertia).compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    mass_matrix = np.zeros((model.nv, model.nv))
    mujoco.mj_fullM(model, data, mass_matrix)
    stiffness = np.diag(model.jnt_stiffness[model.dof_jntid])
    values, vectors = np.linalg.eig(np.linalg.solve(mass_matrix, stiffness))
    axis = model.jnt_axis[model.dof_jntid]
    bending, torsion = [], []
    for value, vector in zip(values.real, vectors.real.T):
        if value < 1e-6:
            continue
        in_bending = np.abs(vector[axis[:, 1] == 1]).sum() + np.abs(vector[axis[:, 2] == 1]).sum()
        (bending if in_bending > np.abs(vector[axis[:, 0] == 1]).sum() else torsion).append(np.sqrt(value))
    return sorted(bending), sorted(torsion)
