"""The lab bench's causes against independent references: the force constant and the force actuator's lag against
the quarter car's closed form times the cause's own transfer function (periodic multisine, as
tests/test_active_force.py), the bearings' friction against tests/lab_rig.py's SciPy solver of the bench's equations."""

import numpy as np
import pytest

from lab_rig import Bench, Excitation, simulate
from rig.causes import with_extension
from rig.causes.bearing_friction import BearingFriction
from rig.causes.force_actuator_lag import ForceActuatorLag
from rig.causes.force_constant_error import ForceConstant
from rig.io.record import Record
from rig.signal.filters import frf_of_periodic, periodic_multisine
from rig.sim.replay import replay
from rig.sim.simulate import Simulator
from rig.vehicle import ride_model
from rig.vehicle.mjcf import build_model
from rig.vehicle.vehicle_file import load_vehicle
from support.multisine import FREQUENCY, LINES, PERIOD, RATE, assert_frf_close


@pytest.fixture(scope="module")
def bench():
    return load_vehicle("lab_quarter")


def force_frfs(vehicle):
    """Body and wheel displacement over the recorded force (m/N) of ``vehicle`` on still posts."""
    weight = (vehicle.sprung_mass + vehicle.front.unsprung_mass) * 9.81
    force = periodic_multisine(FREQUENCY, RATE, PERIOD, periods=8, rms=0.03 * weight)  # the tyre stays loaded
    out = Simulator.create(build_model(vehicle, RATE, "ideal")).run(np.zeros((force.size, 1)), forces=force[:, None])
    return [frf_of_periodic(out[q][0, :, 0], force, PERIOD, LINES) for q in ("sprung_disp", "unsprung_disp")]


def test_a_force_constant_error_scales_the_force_responses_by_its_factor(bench):
    faulty = with_extension(bench, "force_constant_error", {"front": ForceConstant(0.8)})
    expected = ride_model.quarter_car_force_frf(bench, "FL", FREQUENCY)
    for measured, closed_form in zip(force_frfs(faulty), expected):
        assert_frf_close(measured, 0.8 * closed_form)


def test_a_lagging_force_actuator_is_a_first_order_lag_after_a_delay(bench):
    lag = ForceActuatorLag(bandwidth=8.0, delay=0.006)
    faulty = with_extension(bench, "force_actuator_lag", {"front": lag})
    s = 2j * np.pi * FREQUENCY
    actuator = np.exp(-s * lag.delay) / (1 + s / (2 * np.pi * lag.bandwidth))
    for measured, closed_form in zip(force_frfs(faulty), ride_model.quarter_car_force_frf(bench, "FL", FREQUENCY)):
        assert_frf_close(measured, actuator * closed_form)


@pytest.mark.parametrize("friction", [0.3, 0.8])
def test_bearing_friction_follows_an_independent_solver_of_the_coulomb_law(bench, friction):
    """Body friction of 1.5 % and 4 % of its weight: the body plate sticks at the sweep's slow start and its turns.
    MuJoCo's Coulomb friction loss against a tanh law whose creep rate (0.1 mm/s) is far below the plate's rates."""
    rate = 500.0
    truth = Bench.of(bench, bearing_friction=friction, friction_velocity=1e-4)
    motion = simulate(truth, Excitation(8.0, force_amplitude=0.5, random_force=0.2), rate)
    record = Record(rate, {"FL/actuator_disp": motion["road"], "FL/active_force": motion["force"]})
    model = with_extension(bench, "bearing_friction", BearingFriction(friction))
    body = replay(model, record).record["FL/sprung_disp"]
    frictionless = replay(bench, record).record["FL/sprung_disp"]

    def rms(x):
        return float(np.sqrt(np.mean(x**2)))

    error, effect = rms(body - motion["body"]), rms(frictionless - motion["body"])
    assert error < 0.05 * effect, f"{error:.3g} m against the friction's own effect {effect:.3g} m"
    assert error < 0.02 * rms(motion["body"])
