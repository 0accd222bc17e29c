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


def test_the_constraint_stage_is_off_only_where_it_has_nothing_to_solve_and_then_changes_no_number():
    """A car on ideal posts holds no contact, limit, equality or friction loss: its models skip MuJoCo's constraint
    stage (rig/vehicle/mjcf.py ``without_idle_constraint_solver``), and with each cause a rig test fits present in
    turn, states and sensors equal those of the same model with the stage on, bit for bit. Servo posts keep it (their
    stroke is a joint limit), and so does strut friction (a tendon's friction loss)."""
    from rig.causes import CAUSES, causes_seen_on

    proton_x = load_vehicle("proton_x")
    off = int(mujoco.mjtDisableBit.mjDSBL_CONSTRAINT)
    assert not build_model(proton_x, 512.0, "servo").model.opt.disableflags & off
    rng = np.random.default_rng(5)

    def hidden(name):  # a cause of another kind of car (an air-spring axle, a frame) has none on proton_x
        try:
            return CAUSES[name].hidden(proton_x, rng)
        except (ValueError, NotImplementedError):
            return None

    variants = {"none": proton_x} | {name: v for name in causes_seen_on("rig") if (v := hidden(name)) is not None}
    assert len(variants) >= 15
    drive = broadband_drive(proton_x.corners, duration=2.0).quantity("drive")
    for name, vehicle in variants.items():
        sim = Simulator.create(build_model(vehicle, 512.0, "ideal"))
        model = sim.rig.model
        assert bool(model.opt.disableflags & off) == (name != "strut_friction"), name
        if name == "strut_friction":
            continue
        ctrl = sim.controls(drive[None])
        skipped = rollout.rollout(model, mujoco.MjData(model), sim.static.state, ctrl)
        model.opt.disableflags &= ~off
        solved = rollout.rollout(model, mujoco.MjData(model), sim.static.state, ctrl)
        for a, b in zip(skipped, solved, strict=True):
            assert np.array_equal(a, b), name
