"""Full car (proton_x, proton_y): statics and modes against the analytic 7-DOF model of the vehicle file."""

import numpy as np
import pytest

from rig.sim.linearize import car_state_matrix
from rig.sim.simulate import Simulator
from rig.vehicle import ride_model
from rig.vehicle.mjcf import build_model
from rig.vehicle.vehicle_file import load_vehicle

VEHICLES = ["proton_x", "proton_y", "proton_x_quarter"]


@pytest.fixture(scope="module", params=VEHICLES)
def settled(request):
    vehicle = load_vehicle(request.param)
    return vehicle, Simulator.create(build_model(vehicle, 512.0, "servo"))


def test_static_tyre_loads_equal_the_closed_form(settled):
    vehicle, sim = settled
    expected = ride_model.static_loads(vehicle)
    np.testing.assert_allclose(sim.static.tyre_force, expected.tyre_force, rtol=0.005)


def test_static_deflections_equal_the_closed_form(settled):
    vehicle, sim = settled
    expected = ride_model.static_loads(vehicle)
    model = sim.rig.model
    unloaded_suspension = model.tendon_lengthspring[[model.tendon(f"car.{c}/suspension").id
                                                     for c in vehicle.corners], 0]
    spring_deflection = unloaded_suspension - sim.static.suspension_length
    np.testing.assert_allclose(spring_deflection, expected.spring_deflection, rtol=0.005)
    wheel_height = np.array([sim.static.qpos[model.jnt_qposadr[model.joint(f"car.{c}/wheel").id]]
                             for c in vehicle.corners])
    tyre_deflection = -wheel_height  # the template draws the tyre touching the pan unloaded; posts at 0
    np.testing.assert_allclose(tyre_deflection, expected.tyre_deflection, rtol=0.005)


def test_modal_frequencies_and_damping_match_the_analytic_model(settled):
    vehicle, sim = settled
    simulated = np.array(ride_model.modes(car_state_matrix(sim)))
    analytic = np.array(ride_model.modes(ride_model.state_matrix(*ride_model.mck(vehicle))))
    assert simulated.shape == analytic.shape == (len(vehicle.corners) + (3 if vehicle.layout == "full" else 1), 2)
    np.testing.assert_allclose(simulated[:, 0], analytic[:, 0], rtol=0.01)  # frequencies
    np.testing.assert_allclose(simulated[:, 1], analytic[:, 1], rtol=0.01)  # damping ratios


def test_body_modes_are_where_a_ride_engineer_expects_them():
    """Sanity of the thesis data itself: body modes 1-2 Hz, wheel hop 10-15 Hz."""
    for name in ("proton_x", "proton_y"):
        frequencies = [f for f, _ in ride_model.modes(ride_model.state_matrix(*ride_model.mck(load_vehicle(name))))]
        assert all(1.0 < f < 2.2 for f in frequencies[:3]), frequencies
        assert all(10.0 < f < 15.0 for f in frequencies[3:]), frequencies
