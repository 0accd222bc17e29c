"""An actuator force between body and wheel (``<corner>/active_force``) and the displacement responses
(``sprung_disp``, ``unsprung_disp``) against the quarter car's closed form (rig/vehicle/ride_model.py).

Noise-free method as tests/test_quarter_car.py: a multisine with exact periodicity, FFT of the last of eight periods
(the lab bench rings for seconds: its body mode has 7 % of critical damping)."""

import numpy as np
import pytest

from support.multisine import FREQUENCY, LINES, PERIOD, RATE, assert_frf_close

from rig.io.channels import channel
from rig.io.record import Record
from rig.signal.filters import frf_of_periodic, periodic_multisine
from rig.sim.replay import replay
from rig.sim.simulate import Simulator
from rig.vehicle import ride_model
from rig.vehicle.mjcf import build_model
from rig.vehicle.vehicle_file import load_vehicle

@pytest.fixture(scope="module", params=["lab_quarter", "proton_x_quarter"])
def quarter(request):
    vehicle = load_vehicle(request.param)
    return vehicle, Simulator.create(build_model(vehicle, RATE, "ideal"))


def test_force_to_body_and_wheel_frfs_match_the_closed_form(quarter):
    vehicle, sim = quarter
    weight = (vehicle.sprung_mass + vehicle.front.unsprung_mass) * 9.81
    force = periodic_multisine(FREQUENCY, RATE, PERIOD, periods=8, rms=0.03 * weight)  # the tyres stay loaded
    out = sim.run(np.zeros((force.size, 1)), forces=force[:, None])
    expected_body, expected_wheel = ride_model.quarter_car_force_frf(vehicle, "FL", FREQUENCY)
    assert_frf_close(frf_of_periodic(out["sprung_disp"][0, :, 0], force, PERIOD, LINES), expected_body)
    assert_frf_close(frf_of_periodic(out["unsprung_disp"][0, :, 0], force, PERIOD, LINES), expected_wheel)
    # travel (compression positive) is the wheel's rise less the body's
    travel = out["unsprung_disp"][0, :, 0] - out["sprung_disp"][0, :, 0]
    assert np.max(np.abs(travel - out["susp_travel"][0, :, 0])) < 1e-9


def test_displacement_responses_to_the_road_match_nurhadiyanto_equations_3_5_and_3_6(quarter):
    vehicle, sim = quarter
    road = periodic_multisine(FREQUENCY, RATE, PERIOD, periods=8, rms=0.0005)
    out = sim.run(road[:, None])
    expected_body, expected_wheel = ride_model.quarter_car_frf(vehicle, "FL", FREQUENCY)
    assert_frf_close(frf_of_periodic(out["sprung_disp"][0, :, 0], road, PERIOD, LINES), expected_body)
    assert_frf_close(frf_of_periodic(out["unsprung_disp"][0, :, 0], road, PERIOD, LINES), expected_wheel)


def test_a_replayed_record_applies_its_force_beside_the_posts_from_its_first_sample():
    """Posts and force together superpose (the model is linear while the tyre stays loaded), the force's first
    sample (a load cell's offset) moves nothing, and the replay writes the displacements and the force it applied."""
    vehicle = load_vehicle("lab_quarter")
    time = np.arange(int(4 * RATE)) / RATE
    posts = 0.002 * np.sin(2 * np.pi * 2.0 * time) * np.minimum(time, 1.0)
    force = 0.8 * np.sin(2 * np.pi * 5.0 * time + 1.0) * np.minimum(time, 1.0)
    both = replay(vehicle, Record(RATE, {"FL/actuator_disp": posts, "FL/active_force": force + 3.0})).record
    only_posts = replay(vehicle, Record(RATE, {"FL/actuator_disp": posts})).record
    only_force = replay(vehicle, Record(RATE, {"FL/actuator_disp": 0 * posts, "FL/active_force": force})).record
    for quantity in ("sprung_disp", "unsprung_disp", "sprung_acc"):
        name = channel("FL", quantity)
        assert np.max(np.abs(both[name] - only_posts[name] - only_force[name])) < 1e-6 * np.max(np.abs(both[name]))
    assert np.allclose(both["FL/active_force"], force)
    assert both.units["FL/sprung_disp"] == "m"
