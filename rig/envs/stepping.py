"""Advance copies of one model by a control period, in C: one MjData stepped in a loop, or MuJoCo's batch.

Both take the per-substep controls of a control period and of the substep after it, (copies, substeps + 1,
nu), and give what the copies' sensors read at the state the period ends in: after the substeps, the
controls of the next substep are written and ``mj_forward`` runs, so an observation at t_k is the state at
t_k with the action that was held up to t_k. MuJoCo's batch is bit-identical to a loop over MjData (its docs), and
the tests check that the two steppers are.

Nothing reads the sensors inside a control period, so the batch computes them only in the forward at its
end: its substeps run with MuJoCo's sensor stage disabled (``mjDSBL_SENSOR``). Sensors never act on the
dynamics, and MuJoCo keeps a delayed sensor's history all the same (the tests check both against the loop).
"""

from __future__ import annotations

import mujoco
import numpy as np
from mujoco import batch as mj_batch

from rig.sim.simulate import SimulationError

STATE_SPEC = mujoco.mjtState.mjSTATE_FULLPHYSICS  # the static state of rig/vehicle/statics.py


class LoopStepper:
    """One MjData, stepped with ``mj_step`` in a loop (the single environment)."""

    def __init__(self, model: mujoco.MjModel):
        self.model = model
        self.data = mujoco.MjData(model)

    def reset(self, state: np.ndarray, ctrl: np.ndarray, ids: np.ndarray | None = None) -> None:
        """Reset to ``state`` (FULLPHYSICS, the rest as the model's defaults) with controls ``ctrl`` (1, nu)."""
        mujoco.mj_resetData(self.model, self.data)
        mujoco.mj_setState(self.model, self.data, state, STATE_SPEC)
        self.data.ctrl[:] = ctrl[0]
        mujoco.mj_forward(self.model, self.data)

    def advance(self, ctrl: np.ndarray) -> None:
        """Step through ``ctrl[:, :-1]`` (1, substeps, nu), then forward with ``ctrl[:, -1]``."""
        model, data = self.model, self.data
        for row in ctrl[0, :-1]:
            data.ctrl[:] = row
            mujoco.mj_step(model, data)
        data.ctrl[:] = ctrl[0, -1]
        mujoco.mj_forward(model, data)
        _check_warnings(np.array([w.number for w in data.warning]))

    def outputs(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """sensordata, actuator_force, actuator_velocity, each (1, n): views, valid until the next call."""
        d = self.data
        return d.sensordata[None], d.actuator_force[None], d.actuator_velocity[None]


class BatchStepper:
    """``copies`` simulations in one ``mujoco.batch.Batch`` on ``nthread`` threads (the vector environment)."""

    def __init__(self, model: mujoco.MjModel, copies: int, nthread: int = 0):
        self.model = model
        self.batch = mj_batch.Batch(model, copies, nthread)
        self._state_size = mujoco.mj_stateSize(model, STATE_SPEC)
        self._state_columns = self._columns(STATE_SPEC)
        # outputs are registered before any call: a field bound later reads zero until the next call
        self._outputs = tuple(self.batch.bind(name) for name in ("sensordata", "actuator_force", "actuator_velocity"))
        self._ctrl = self.batch.bind("ctrl")
        self._flags = self.batch.expand("opt.disableflags")
        self._forward_flags = int(model.opt.disableflags)
        self._substep_flags = self._forward_flags | int(mujoco.mjtDisableBit.mjDSBL_SENSOR)

    def _columns(self, spec: mujoco.mjtState) -> np.ndarray:
        """Columns of the batch's state rows that hold the components of ``spec``, in mj_getState order."""
        columns, offset = [], 0
        integration = mujoco.mjtState.mjSTATE_INTEGRATION.value
        for bit in range(mujoco.mjtState.mjNSTATE.value):
            component = 1 << bit
            if not integration & component:
                continue
            size = mujoco.mj_stateSize(self.model, component)
            if spec.value & component:
                columns.extend(range(offset, offset + size))
            offset += size
        return np.array(columns, int)

    def reset(self, state: np.ndarray, ctrl: np.ndarray, ids: np.ndarray | None = None) -> None:
        ids = np.arange(self.batch.nsim) if ids is None else np.asarray(ids)
        self.batch.reset(ids, stage=mujoco.mjtStage.mjSTAGE_NONE.value)
        rows = self.batch.state
        rows[np.ix_(ids, self._state_columns)] = state[None, :]
        self._ctrl[ids] = ctrl
        self.batch.forward(ids)

    def advance(self, ctrl: np.ndarray) -> None:
        self.substeps(ctrl[:, :-1])
        self.forward(ctrl[:, -1])

    def substeps(self, ctrl: np.ndarray) -> None:
        """Step every copy through ``ctrl`` (copies, substeps, nu), the sensors left out."""
        self._flags[:] = self._substep_flags
        try:
            self.batch.rollout(ctrl.shape[1], control=ctrl, record=())
        finally:
            self._flags[:] = self._forward_flags

    def forward(self, ctrl: np.ndarray) -> None:
        """``mj_forward`` of every copy with controls ``ctrl`` (copies, nu), the sensors with it."""
        self._ctrl[:] = ctrl
        self.batch.forward()
        _check_warnings(self.batch.warning[..., 1])  # mjWarningStat: (lastinfo, number)

    def outputs(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """sensordata, actuator_force, actuator_velocity, each (copies, n): the batch's live read-only views,
        valid until the next call."""
        return self._outputs


def _check_warnings(counts: np.ndarray) -> None:
    """Raise if MuJoCo warned (instability, bad controls): the run's numbers would mean nothing."""
    if counts.any():
        raise SimulationError("MuJoCo warned during the episode (the simulation became unstable); "
                              "check the vehicle, the road and the action bounds")
