"""Rollout equals a plain mj_step loop bit for bit; no shipped model makes MuJoCo warn."""

import mujoco
import numpy as np
import pytest
from mujoco import rollout

from rig.sim.broadband import broadband_drive
from rig.sim.simulate import Simulator
from rig.vehicle.mjcf import POST_MODES, build_model
from rig.vehicle.statics import STATE_SPEC
from rig.vehicle.vehicle_file import builtin_vehicles, load_vehicle


def test_rollout_equals_an_mj_step_loop_bit_for_bit():
    sim = Simulator.create(build_model(load_vehicle("proton_x"), 512.0, "servo"))
    drive = broadband_drive(sim.rig.corners, duration=2.0).quantity("drive")
    ctrl = sim.controls(drive[None])[0]
    model = sim.rig.model
    states, sensors = rollout.rollout(model, mujoco.MjData(model), sim.static.state, ctrl[None])
    data = mujoco.MjData(model)
    mujoco.mj_setState(model, data, sim.static.state, STATE_SPEC)
    state = np.empty(mujoco.mj_stateSize(model, STATE_SPEC))
    for k in range(ctrl.shape[0]):
        data.ctrl[:] = ctrl[k]
        mujoco.mj_step(model, data)
        mujoco.mj_getState(model, data, state, STATE_SPEC)
        assert np.array_equal(sensors[0, k], data.sensordata), f"sensors differ at step {k}"
        assert np.array_equal(states[0, k], state), f"state differs at step {k}"


@pytest.mark.parametrize("name", builtin_vehicles())
@pytest.mark.parametrize("posts", POST_MODES)
def test_no_shipped_model_raises_a_mujoco_warning(name, posts):
    vehicle = load_vehicle(name)
    sim = Simulator.create(build_model(vehicle, 512.0, posts))
    drive = broadband_drive(vehicle.corners, duration=3.0).quantity("drive", vehicle.corners)
    out = sim.run(drive)  # raises SimulationError on any MuJoCo warning
    assert np.all(np.isfinite(out["sprung_acc"]))
    data = mujoco.MjData(sim.rig.model)
    mujoco.mj_forward(sim.rig.model, data)
    assert not any(w.number for w in data.warning)
