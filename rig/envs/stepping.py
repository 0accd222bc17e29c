"""Advance copies of one model by a control period, in C: one MjData stepped in a loop, or MuJoCo's batch.

Both take the per-substep controls of a control period and of the substep after it, (copies, substeps + 1,
nu), and give what the copies' sensors read at the state the period ends in: after the substeps, the
controls of the next substep are written and ``mj_forward`` runs, so an observation at t_k is the state at
t_k with the action that was held up to t_k. MuJoCo's batch is bit-identical to a loop over MjData (its docs), and
the tests check that the two steppers are.

Both step with MuJoCo's profiler clock off (rig/sim/cores.py: nothing reads its timers). Nothing reads the sensors
inside a control period, so the batch computes them only in the forward at its
end: its substeps run with MuJoCo's sensor stage disabled (``mjDSBL_SENSOR``). Sensors never act on the
dynamics, and MuJoCo keeps a delayed sensor's history all the same (the tests check both against the loop).

The batch hands each call's copies to its threads and waits for them, spinning (its worker 50 µs after each
call): on two shared cores, 55-70 µs of the other thread's CPU for a call without work, and 0.1-0.2 ms of
the caller's wall clock. The substeps need it; the forward of a few hundred copies is cheaper on the caller's
thread alone.
So the forward runs in a second batch, which takes the substeps' state rows before each call (``mj_forward``
changes no state) and works on the caller's thread unless each of its threads gets
``FORWARD_COPIES_PER_THREAD`` copies: one hand-off per env step instead of two.
"""

from __future__ import annotations

import copy

import mujoco
import numpy as np
from mujoco import batch as mj_batch

from rig.sim.cores import clock_off
from rig.sim.simulate import SimulationError

STATE_SPEC = mujoco.mjtState.mjSTATE_FULLPHYSICS  # the static state of rig/vehicle/statics.py
#: Copies each thread of the forward gets at least (else the forward runs on fewer threads, down to the caller's
#: alone): the forward of 256 copies of a quarter car is about 0.45 ms of work, several hand-offs.
FORWARD_COPIES_PER_THREAD = 256


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
        with clock_off():
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
    """``copies`` simulations in MuJoCo's batch (the vector environment): the substeps on ``nthread`` threads
    (0: all CPUs), the forward at the end of a period in a second batch (``observer``) on the caller's thread,
    or on as many of ``nthread`` as get ``FORWARD_COPIES_PER_THREAD`` copies each."""

    def __init__(self, model: mujoco.MjModel, copies: int, nthread: int = 0):
        self.model = model
        quiet = copy.copy(model)  # the batch copies its model: this copy only sets the substeps' flags
        quiet.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_SENSOR
        self.batch = mj_batch.Batch(quiet, copies, nthread)
        forward_threads = max(1, min(self.batch.nthread, copies // FORWARD_COPIES_PER_THREAD))
        self.observer = mj_batch.Batch(model, copies, forward_threads)
        self._state_columns = self._columns(STATE_SPEC)
        # outputs are registered before any call: a field bound later reads zero until the next call
        self._outputs = tuple(self.observer.bind(name) for name in ("sensordata", "actuator_force",
                                                                    "actuator_velocity"))
        self._ctrl = self.observer.bind("ctrl")
        self._warnings = self.batch.warning[..., 1], self.observer.warning[..., 1]  # mjWarningStat: (lastinfo, number)

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
        for batch in (self.batch, self.observer):  # the model's defaults, and no warnings
            batch.reset(ids, stage=mujoco.mjtStage.mjSTAGE_NONE.value)
        rows = self.batch.state
        rows[np.ix_(ids, self._state_columns)] = state[None, :]
        self.forward(ctrl, ids)

    def advance(self, ctrl: np.ndarray) -> None:
        self.substeps(ctrl[:, :-1])
        self.forward(ctrl[:, -1])

    def substeps(self, ctrl: np.ndarray) -> None:
        """Step every copy through ``ctrl`` (copies, substeps, nu), the sensors left out."""
        with clock_off():
            self.batch.rollout(ctrl.shape[1], control=ctrl, record=())

    def forward(self, ctrl: np.ndarray, ids: np.ndarray | None = None) -> None:
        """``mj_forward`` of the copies ``ids`` (None: all) at their states with controls ``ctrl`` (copies, nu),
        the sensors with it. (``mj_forward`` leaves the state as it is: the substeps go on from their own rows.)"""
        rows = slice(None) if ids is None else ids
        self.observer.state[rows] = self.batch.state[rows]
        self._ctrl[rows] = ctrl
        with clock_off():
            self.observer.forward(ids)
        for counts in self._warnings:
            _check_warnings(counts)

    def outputs(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """sensordata, actuator_force, actuator_velocity, each (copies, n): the batch's live read-only views,
        valid until the next call."""
        return self._outputs


def _check_warnings(counts: np.ndarray) -> None:
    """Raise if MuJoCo warned (instability, bad controls): the run's numbers would mean nothing."""
    if counts.any():
        raise SimulationError("MuJoCo warned during the episode (the simulation became unstable); "
                              "check the vehicle, the road and the action bounds")
