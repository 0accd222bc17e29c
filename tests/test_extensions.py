"""Model extensions against their closed-form force laws, and their vehicle-file sections."""

import mujoco
import numpy as np
import pytest

from rig.model import build_model
from rig.simulate import Simulator
from rig.vehicle import VehicleError, load_vehicle, vehicle_from_dict

QUARTER = {
    "name": "q", "layout": "quarter", "sprung": {"mass": 355.31},
    "front": {"unsprung_mass": 35.19, "spring_rate": 23000.0, "parasitic_rate": 6000.0, "damping": 3959.0,
              "tyre_rate": 208500.0},
}


def quarter_with(**sections):
    return vehicle_from_dict({**QUARTER, **sections}, "test")


def suspension_force(sim, compression, velocity):
    """Upward force (N) on the body from the suspension at ``compression`` m and compression rate ``velocity`` m/s."""
    model = sim.rig.model
    data = mujoco.MjData(model)
    data.qpos[:] = sim.static.qpos
    heave = model.joint("car.heave").qposadr[0]
    data.qpos[heave] -= compression
    data.qvel[model.joint("car.heave").dofadr[0]] = -velocity
    mujoco.mj_forward(model, data)
    # generalised force on the heave DOF from passive springs/dampers and the damper actuators, minus static
    return data.qfrc_passive[model.joint("car.heave").dofadr[0]] + data.qfrc_actuator[model.joint("car.heave").dofadr[0]]


def test_bump_stop_adds_its_rate_beyond_the_gap_from_static_ride_height():
    plain = Simulator.create(build_model(quarter_with(), 512.0, "ideal"))
    stopped = Simulator.create(build_model(quarter_with(bump_stop={"front": {"gap": 0.02, "rate": 1.5e5}}), 512.0, "ideal"))
    for compression in (0.0, 0.015, 0.0199):
        assert suspension_force(stopped, compression, 0.0) == pytest.approx(suspension_force(plain, compression, 0.0))
    for compression in (0.025, 0.04):
        extra = suspension_force(stopped, compression, 0.0) - suspension_force(plain, compression, 0.0)
        assert extra == pytest.approx(1.5e5 * (compression - 0.02), rel=1e-6)


def test_asymmetric_damper_uses_rebound_and_compression_coefficients():
    sim = Simulator.create(build_model(
        quarter_with(damper_asymmetry={"front": {"compression": 2000.0, "rebound": 5000.0}}), 512.0, "ideal"))
    static = suspension_force(sim, 0.0, 0.0)
    # the damper pushes the body up while compressing and pulls it down while extending
    assert suspension_force(sim, 0.0, 0.3) - static == pytest.approx(2000.0 * 0.3, rel=1e-9)
    assert suspension_force(sim, 0.0, -0.3) - static == pytest.approx(-5000.0 * 0.3, rel=1e-9)


def test_extension_sections_are_checked():
    with pytest.raises(VehicleError, match=r"\[bump_stop.front\]: missing rate"):
        quarter_with(bump_stop={"front": {"gap": 0.02}})
    with pytest.raises(VehicleError, match=r"\[bump_stop\] has sub-table\(s\) rear"):
        quarter_with(bump_stop={"rear": {"gap": 0.02, "rate": 1e5}})
    with pytest.raises(VehicleError, match=r"rebound = -1.0 is outside the plausible range"):
        quarter_with(damper_asymmetry={"front": {"compression": 2000.0, "rebound": -1.0}})
    with pytest.raises(VehicleError, match=r"unknown section\(s\) turbo"):
        quarter_with(turbo={"boost": 1})


def test_nonlinear_builtin_vehicle_has_stops_and_asymmetric_dampers():
    vehicle = load_vehicle("proton_x_nonlinear")
    assert set(vehicle.extensions) == {"bump_stop", "damper_asymmetry"}
    assert vehicle.extension("damper_asymmetry", "RR").rebound > vehicle.extension("damper_asymmetry", "RR").compression
