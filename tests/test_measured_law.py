"""The generic element ``measured_law`` (rig/causes/measured_law.py): a piecewise-linear suspension law in
travel and rate, inside mj_step, equal to its closed form on both sides of ride height; its vehicle-file
section checked and written back."""

import tomllib

import numpy as np
import pytest
from support.quarter import quarter_with, suspension_force

from rig.causes.measured_law import MeasuredLaw, ramp_force
from rig.sim.simulate import Simulator
from rig.vehicle.mjcf import build_model
from rig.vehicle.vehicle_file import VehicleError, vehicle_from_dict, vehicle_to_toml

SECTION = {"travel_knots": [-0.01, -0.004, 0.0, 0.006, 0.015], "stiffness_changes": [8e4, -5e3, 1.2e4, 3e4, -2e4],
           "rate_knots": [-0.2, 0.0, 0.1], "damping_changes": [-1500.0, 800.0, -1200.0]}


def test_force_is_the_closed_form_piecewise_law_in_travel_and_rate():
    plain = Simulator.create(build_model(quarter_with(), 512.0, "ideal"))
    extended = Simulator.create(build_model(quarter_with(measured_law={"front": SECTION}), 512.0, "ideal"))
    law = MeasuredLaw(*(tuple(SECTION[k]) for k in SECTION))
    checked = 0
    for x in (-0.03, -0.012, -0.006, -0.001, 0.0, 0.003, 0.01, 0.02):
        for v in (-0.5, -0.1, 0.0, 0.05, 0.3):
            extra = suspension_force(extended, x, v) - suspension_force(plain, x, v)
            expected = float(ramp_force(law, np.array(x), np.array(v)))
            assert extra == pytest.approx(expected, rel=1e-6, abs=1e-6), (x, v)
            checked += abs(expected) > 1.0
    assert checked > 20  # most points sit beyond some knot


def test_section_is_checked_and_written_back():
    vehicle = quarter_with(measured_law={"front": SECTION})
    again = vehicle_from_dict(tomllib.loads(vehicle_to_toml(vehicle)), "round trip")
    assert again.extensions["measured_law"] == vehicle.extensions["measured_law"]
    with pytest.raises(VehicleError, match=r"\[measured_law.front\]: travel_knots must increase"):
        quarter_with(measured_law={"front": {**SECTION, "travel_knots": [0.0, -0.01, 0.0, 0.006, 0.015]}})
    with pytest.raises(VehicleError, match="rate_knots and damping_changes must have the same length"):
        quarter_with(measured_law={"front": {**SECTION, "damping_changes": [1.0]}})
    with pytest.raises(VehicleError, match="wrong or missing: damping_changes"):
        quarter_with(measured_law={"front": {k: v for k, v in SECTION.items() if k != "damping_changes"}})
