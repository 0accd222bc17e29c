"""Tyre lift-off: over a large drop the tyre force never goes below zero, and airborne time is right.

Reference: the same quarter-car equations (Nurhadiyanto's eq. 3.1-3.2 with a tyre that only pushes)
integrated by SciPy's solve_ivp to 1e-10 tolerance.
"""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from rig.io.channels import channel
from rig.io.record import Record
from rig.io.units import STANDARD_GRAVITY
from rig.sim.replay import replay
from rig.vehicle.vehicle_file import load_vehicle

RATE = 2048.0
DROP = 0.04     # m: within stroke, at 2.1 m/s peak within the post velocity limit
DROP_TIME = 0.03  # s, half-cosine: 219 m/s^2 down, more than the wheel can follow


def road(t):
    phase = np.clip((t - 0.2) / DROP_TIME, 0.0, 1.0)
    return -DROP * (0.5 - 0.5 * np.cos(np.pi * phase))


def reference_tyre_force(vehicle, time):
    axle = vehicle.front
    m_b, m_t, k, c, kt = vehicle.sprung_mass, axle.unsprung_mass, axle.suspension_rate, axle.damping, axle.tyre_rate
    g = STANDARD_GRAVITY
    # static: tyre carries (m_b + m_t) g, suspension m_b g; positions relative to the static state
    tyre_static = (m_b + m_t) * g

    def rhs(t, y):
        x_t, x_b, v_t, v_b = y
        tyre = max(0.0, tyre_static + kt * (road(t) - x_t))
        suspension = k * (x_t - x_b) + c * (v_t - v_b)  # relative to static: static part balances m_b g
        return [v_t, v_b, (tyre - tyre_static - suspension) / m_t, suspension / m_b]

    solution = solve_ivp(rhs, (0, time[-1]), [0, 0, 0, 0], t_eval=time, rtol=1e-10, atol=1e-12, max_step=1e-4)
    return np.maximum(0.0, tyre_static + kt * (road(time) - solution.y[0]))


@pytest.fixture(scope="module")
def drop_run():
    vehicle = load_vehicle("proton_x_quarter")
    time = np.arange(int(1.0 * RATE)) / RATE
    record = Record(RATE, {channel("FL", "actuator_disp"): road(time)})
    return vehicle, time, replay(vehicle, record)


def test_tyre_force_never_negative_and_the_wheel_leaves_the_ground(drop_run):
    _, _, result = drop_run
    force = result.record["FL/tyre_force"]
    assert force.min() >= 0.0
    assert np.sum(force == 0.0) > 10  # airborne for a while, exactly zero force
    assert result.airborne_time()["FL"] > 0.005


def test_airborne_time_and_tyre_force_match_an_independent_integration(drop_run):
    vehicle, time, result = drop_run
    expected = reference_tyre_force(vehicle, time)
    simulated = result.record["FL/tyre_force"]
    expected_airborne = np.sum(expected == 0.0) / RATE
    assert result.airborne_time()["FL"] == pytest.approx(expected_airborne, abs=2.5 / RATE)
    assert np.max(np.abs(simulated - expected)) < 0.01 * expected.max()
