"""A vehicle file's damper on a dynamometer in MuJoCo (rig/sim/dyno.py) against closed forms and a solver
written here: the damper line's causes, the motion ratio, a top mount in series (with its mass), strut friction;
and the measured law's damping ramps acting through a top mount, as the damper's own."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from support.quarter import quarter_with

from rig.causes.top_mount_compliance import mount_mass
from rig.sim.dyno import damper_alone, simulate_dyno
from rig.vehicle.mjcf import build_model
from rig.vehicle.vehicle_file import VehicleError, load_vehicle

RATE = 1000.0
SPEEDS = np.array([-1.2, -0.6, -0.25, -0.05, 0.0, 0.04, 0.2, 0.5, 1.1])  # m/s, damper extension


def _at_speeds(vehicle, motion_ratio=1.0):
    """Force (N, damper) at each constant speed of SPEEDS: one sample per speed, the post's velocity as given."""
    return simulate_dyno(vehicle, "front", np.cumsum(SPEEDS) / RATE, RATE, velocity=SPEEDS,
                         motion_ratio=motion_ratio).force


@pytest.mark.parametrize("motion_ratio", [1.0, 0.6])
def test_asymmetric_quadratic_damper_is_its_closed_form_through_the_motion_ratio(motion_ratio):
    """At the wheel F_w = c(sign) u + Cn u|u| with u = v / MR; at the damper F = F_w / MR."""
    vehicle = quarter_with(damper_asymmetry={"front": {"compression": 1500.0, "rebound": 3500.0}},
                           progressive_damper={"front": {"quadratic": 1000.0}})
    u = SPEEDS / motion_ratio
    wheel = np.where(u > 0, 3500.0, 1500.0) * u + 1000.0 * u * np.abs(u)
    np.testing.assert_allclose(_at_speeds(vehicle, motion_ratio), wheel / motion_ratio, rtol=1e-9, atol=1e-8)


def test_digressive_knees_of_a_measured_law_are_their_closed_form():
    """Ramps in compression rate (measured_law): rebound beyond 0.25 m/s and compression beyond 0.2 m/s soften."""
    vehicle = quarter_with(damper_asymmetry={"front": {"compression": 3000.0, "rebound": 6000.0}},
                           measured_law={"front": {"travel_knots": [], "stiffness_changes": [],
                                                   "rate_knots": [-0.25, 0.2], "damping_changes": [-4500.0, -2200.0]}})
    v = SPEEDS
    closed = np.where(v > 0, np.where(v < 0.25, 6000 * v, 1500.0 + 1500 * (v - 0.25)),
                      np.where(v > -0.2, 3000 * v, -600.0 + 800 * (v + 0.2)))
    np.testing.assert_allclose(_at_speeds(vehicle), closed, rtol=1e-9, atol=1e-8)


@pytest.mark.parametrize("frequency", [2.0, 8.0])
def test_top_mount_in_series_is_the_closed_form_with_its_mass(frequency):
    """Linear damper c through a mount (rate k, the mass that follows the damper) under a sine: steady state
    F = i c w X (k - m w^2) / (k - m w^2 + i c w)."""
    c, k = 3959.0, 4e5
    m = mount_mass(c)
    vehicle = quarter_with(top_mount_compliance={"front": {"rate": k}})
    t = np.arange(4000) / RATE
    w, amplitude = 2 * np.pi * frequency, 0.025
    sim = simulate_dyno(vehicle, "front", amplitude * np.sin(w * t), RATE, velocity=amplitude * w * np.cos(w * t))
    closed = np.imag(1j * c * w * amplitude * (k - m * w ** 2) / (k - m * w ** 2 + 1j * c * w) * np.exp(1j * w * t))
    late = t > 1.0  # the start's transient gone
    assert np.max(np.abs(sim.force[late] - closed[late])) < 2e-3 * np.max(np.abs(closed))


def test_measured_law_damping_goes_through_the_top_mount_as_the_damper_does():
    """A digressive, asymmetric damper in series with a top mount (its mass following the axle's damping) on a
    3e5 N/m bushing, against the same system integrated here (mount: m z'' = -k z - F(z' + e'), F the damper's law
    of its own extension rate)."""
    k, m = 3e5, mount_mass(3959.0)
    vehicle = quarter_with(damper_asymmetry={"front": {"compression": 3000.0, "rebound": 6000.0}},
                           measured_law={"front": {"travel_knots": [], "stiffness_changes": [],
                                                   "rate_knots": [-0.25, 0.2], "damping_changes": [-4500.0, -2200.0]}},
                           top_mount_compliance={"front": {"rate": k}})

    def law(u):
        return np.where(u > 0, np.where(u < 0.25, 6000 * u, 1500.0 + 1500 * (u - 0.25)),
                        np.where(u > -0.2, 3000 * u, -600.0 + 800 * (u + 0.2)))

    t = np.arange(3000) / RATE
    w, amplitude = 2 * np.pi * 5.0, 0.02
    speed = amplitude * w * np.cos(w * t)
    sim = simulate_dyno(vehicle, "front", amplitude * np.sin(w * t), RATE, velocity=speed)

    def mount(s, y):  # y = (z, z'), z the mount's deflection, extension of the damper = z + e
        force = law(y[1] + amplitude * w * np.cos(w * s))
        return [y[1], (-k * y[0] - force) / m]

    solution = solve_ivp(mount, (0, t[-1]), [-law(speed[0]) / k, 0.0], t_eval=t, rtol=1e-10, atol=1e-12,
                         max_step=2e-4)
    reference = law(solution.y[1] + speed)
    late = t > 1.0
    assert np.max(np.abs(sim.force[late] - reference[late])) < 5e-3 * np.max(np.abs(reference))


def test_strut_friction_is_a_coulomb_step_on_the_dyno():
    vehicle = quarter_with(strut_friction={"front": {"force": 120.0}})
    moving = SPEEDS != 0.0
    expected = 3959.0 * SPEEDS + 120.0 * np.sign(SPEEDS)
    np.testing.assert_allclose(_at_speeds(vehicle)[moving], expected[moving], rtol=2e-3)


def test_the_damper_alone_keeps_only_its_line_and_axle():
    vehicle = load_vehicle("proton_x_nonlinear")
    alone = damper_alone(vehicle, "rear")
    assert alone.layout == "quarter" and alone.front == vehicle.rear
    assert set(alone.extensions) == {"damper_asymmetry"}  # the bump stops are springs: left out
    assert alone.extensions["damper_asymmetry"]["front"] == vehicle.extensions["damper_asymmetry"]["rear"]
    with pytest.raises(VehicleError, match="no axle 'rear'"):
        damper_alone(quarter_with(), "rear")


def test_the_dyno_holds_a_measured_laws_damping_ramps_and_not_its_spring_ramps():
    both = quarter_with(measured_law={"front": {"travel_knots": [0.01], "stiffness_changes": [1e4],
                                                "rate_knots": [0.3], "damping_changes": [-500.0]}})
    law = damper_alone(both, "front").extensions["measured_law"]["front"]
    assert (law.travel_knots, law.stiffness_changes, law.rate_knots, law.damping_changes) == ((), (), (0.3,), (-500.0,))
    spring_only = quarter_with(measured_law={"front": {"travel_knots": [0.01], "stiffness_changes": [1e4],
                                                       "rate_knots": [], "damping_changes": []}})
    assert "measured_law" not in damper_alone(spring_only, "front").extensions


def test_the_car_model_puts_measured_damping_ramps_on_the_damper():
    vehicle = quarter_with(measured_law={"front": {"travel_knots": [0.01], "stiffness_changes": [1e4],
                                                   "rate_knots": [0.3], "damping_changes": [-500.0]}})
    model = build_model(vehicle, 512.0, "ideal").model
    damping = model.actuator("car.FL/measured_law_c0")
    travel = model.actuator("car.FL/measured_law_k0")
    line = int(damping.trnid[0])  # the damper's: on a vertical corner the spring's line, which carries its damping
    assert model.tendon(line).name == "car.FL/suspension" and model.tendon_damping[line] == vehicle.front.damping
    assert model.tendon(int(travel.trnid[0])).name == "car.FL/measured_law"
