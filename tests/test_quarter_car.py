"""Quarter car (Proton X front, Nurhadiyanto's Table 4.2) against the closed-form transfer functions.

Noise-free method: a multisine with exact periodicity, FFT of the last period after the transients.
"""

import numpy as np
import pytest

from rig.signal.filters import frf_of_periodic, periodic_multisine
from rig.sim.simulate import Simulator
from rig.vehicle import ride_model
from rig.vehicle.mjcf import build_model
from rig.vehicle.vehicle_file import load_vehicle

RATE = 512.0
PERIOD = 2048  # samples: 0.25 Hz lines
LINES = np.arange(2, 121)  # 0.5 ... 30 Hz
FREQUENCY = LINES * RATE / PERIOD


@pytest.fixture(scope="module")
def quarter():
    return load_vehicle("proton_x_quarter")


def simulate_multisine(vehicle, posts):
    sim = Simulator.create(build_model(vehicle, RATE, posts))
    excitation = periodic_multisine(FREQUENCY, RATE, PERIOD, periods=4, rms=0.002)
    return excitation, {k: v[0, :, 0] for k, v in sim.run(excitation[:, None]).items()}


def assert_frf_close(measured, expected, magnitude_tol, phase_tol_deg):
    magnitude_error = np.abs(np.abs(measured) / np.abs(expected) - 1)
    phase_error = np.abs(np.degrees(np.angle(measured / expected)))
    worst = np.argmax(magnitude_error)
    assert magnitude_error.max() < magnitude_tol, f"{100 * magnitude_error.max():.3f} % at {FREQUENCY[worst]} Hz"
    assert phase_error.max() < phase_tol_deg, f"{phase_error.max():.3f} deg at {FREQUENCY[np.argmax(phase_error)]} Hz"


def test_ideal_post_frfs_match_nurhadiyanto_equations_3_5_and_3_6(quarter):
    road, out = simulate_multisine(quarter, "ideal")
    kt = quarter.front.tyre_rate
    # displacements from the contract channels: tyre force = kt (road - x_t) + static, travel = x_t - x_b
    wheel = road - (out["tyre_force"] - out["tyre_force"].mean()) / kt
    body = wheel - out["susp_travel"]
    expected_body, expected_wheel = ride_model.quarter_car_frf(quarter, "FL", FREQUENCY)
    assert_frf_close(frf_of_periodic(body, road, PERIOD, LINES), expected_body, 0.01, 1.0)
    assert_frf_close(frf_of_periodic(wheel, road, PERIOD, LINES), expected_wheel, 0.01, 1.0)


def test_sprung_acceleration_frf_matches_equation_3_5(quarter):
    road, out = simulate_multisine(quarter, "ideal")
    omega = 2 * np.pi * FREQUENCY
    expected_body, expected_wheel = ride_model.quarter_car_frf(quarter, "FL", FREQUENCY)
    assert_frf_close(frf_of_periodic(out["sprung_acc"], road, PERIOD, LINES), -omega**2 * expected_body, 0.01, 1.0)
    assert_frf_close(frf_of_periodic(out["unsprung_acc"], road, PERIOD, LINES), -omega**2 * expected_wheel, 0.01, 1.0)


def test_servo_post_frfs_match_the_closed_form_rig_model(quarter):
    drive, out = simulate_multisine(quarter, "servo")
    expected = ride_model.quarter_car_on_servo_frf(quarter, "FL", FREQUENCY)
    assert_frf_close(frf_of_periodic(out["actuator_disp"], drive, PERIOD, LINES), expected["post"], 0.01, 1.0)
    omega = 2 * np.pi * FREQUENCY
    assert_frf_close(frf_of_periodic(out["sprung_acc"], drive, PERIOD, LINES), -omega**2 * expected["sprung"],
                     0.01, 1.0)
