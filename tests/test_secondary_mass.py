"""The cause ``secondary_mass`` (rig/causes/secondary_mass.py): a subsystem on its own mounts, against the
analytic model, and the diagnosis's honest verdicts on records of the independent simulator."""

import numpy as np
import pytest
from support.quarter import quarter_with

from rig.causes import with_extension
from rig.causes.secondary_mass import SecondaryMass
from rig.sim.linearize import car_state_matrix
from rig.sim.simulate import Simulator
from rig.vehicle import ride_model
from rig.vehicle.mjcf import build_model
from rig.vehicle.vehicle_file import load_vehicle


def test_quarter_car_modes_match_the_analytic_three_mass_model():
    """Body (less m) on spring k and damper c to the wheel, the mass m on its mounts (k_e, c_e) on the body,
    the wheel on the tyre: eigenvalues of the analytic 3-DOF model."""
    m, f, zeta = 40.0, 11.0, 0.08
    k, c, kt, m_b, m_w = 29000.0, 3959.0, 208500.0, 355.31, 35.19
    k_e, c_e = m * (2 * np.pi * f) ** 2, 2 * zeta * m * 2 * np.pi * f
    sim = Simulator.create(build_model(quarter_with(secondary_mass={"mass": m, "frequency": f, "damping_ratio": zeta}),
                                       512.0, "ideal"))
    mass = np.diag([m_b - m, m, m_w])
    stiffness = np.array([[k + k_e, -k_e, -k], [-k_e, k_e, 0.0], [-k, 0.0, k + kt]])
    damping = np.array([[c + c_e, -c_e, -c], [-c_e, c_e, 0.0], [-c, 0.0, c]])
    analytic = np.array(ride_model.modes(ride_model.state_matrix(mass, damping, stiffness)))
    simulated = np.array(ride_model.modes(car_state_matrix(sim)))
    np.testing.assert_allclose(simulated, analytic, rtol=1e-3)


def test_total_mass_and_static_loads_stay_those_of_the_data_sheet():
    vehicle = load_vehicle("proton_x")
    engine = with_extension(vehicle, "secondary_mass", SecondaryMass(mass=150.0, frequency=11.0, x=1.2, y=0.1))
    before = Simulator.create(build_model(vehicle, 512.0, "ideal"))
    after = Simulator.create(build_model(engine, 512.0, "ideal"))
    np.testing.assert_allclose(after.static.tyre_force, before.static.tyre_force, rtol=1e-5)  # as test_full_car
    model = after.rig.model
    assert model.body_mass[model.body("car.body").id] == pytest.approx(vehicle.sprung_mass - 150.0)
