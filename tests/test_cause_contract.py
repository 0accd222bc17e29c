"""The cause contract: the force-law shapes a cause names as its evidence are the ones
rig/diagnosis/rig_test/force_laws.py
can emit (one Enum, every member emitted by a crafted law), one parameter schema with units; and the richer forms
the diagnosis refines causes into (a smooth friction law, a payload's own inertia) against their closed forms."""

import dataclasses

import mujoco
import numpy as np
import pytest

from rig.causes import CAUSES, ParameterSpec, Shape
from rig.causes.mass_error import MassError
from rig.diagnosis.rig_test.force_laws import CornerLaw, ForceLaws, MassProperties, Slope, TyreLaw, _shapes
from rig.sim.simulate import Simulator
from rig.vehicle.mjcf import build_model
from rig.vehicle.vehicle_file import load_vehicle, vehicle_from_dict

QUARTER = {
    "name": "q", "layout": "quarter", "sprung": {"mass": 355.31},
    "front": {"unsprung_mass": 35.19, "spring_rate": 23000.0, "parasitic_rate": 6000.0, "damping": 3959.0,
              "tyre_rate": 208500.0},
}


def corner_law(stiffness=(1.0,) * 8, damping=(1.0,) * 8, friction=0.0, lag=0.0, coupling=0.0) -> CornerLaw:
    """A corner law with segment slopes (x 1e4 N/m, x 1e3 N s/m) known to 1 %, and the step, lag and coupling."""
    def segments(values, scale):
        return [Slope(k - 4.0, k - 3.0, v * scale, 0.01 * scale) for k, v in enumerate(values)]
    empty = (np.zeros(1), np.zeros(1))
    return CornerLaw("FL", segments(stiffness, 1e4), segments(damping, 1e3), (friction, 1.0), (lag, 1e-4),
                     (coupling, 10.0), 0.0, [], empty, empty)


def emitted_corner_shapes() -> set[Shape]:
    laws = [corner_law(stiffness=(2, 1, 1, 1, 1, 1, 1, 2)), corner_law(stiffness=(1, 1, 1, 1, 1, 1, 1, 2)),
            corner_law(stiffness=(2, 1, 1, 1, 1, 1, 1, 1)), corner_law(stiffness=(1, 1, 1, 1, 1, 1, 1, 0.5)),
            corner_law(stiffness=(0.5, 1, 1, 1, 1, 1, 1, 1)), corner_law(damping=(1, 1, 1, 2, 1, 1, 1, 1)),
            corner_law(damping=(2, 1, 1, 1, 1, 1, 1, 2)), corner_law(damping=(0.5, 1, 1, 1, 1, 1, 1, 0.5)),
            corner_law(friction=100.0), corner_law(lag=0.005), corner_law(coupling=5000.0)]
    return {shape for law in laws for shape in _shapes(law, 500.0)}


def emitted_departures() -> set[Shape]:
    vehicle = load_vehicle("proton_x")
    law = corner_law(stiffness=(2,) * 8, damping=(2,) * 8)
    tyre = TyreLaw("FL", (1.5 * vehicle.front.tyre_rate, 100.0), (500.0, 5.0), (np.zeros(1), np.zeros(1)))
    body = MassProperties((1.3 * vehicle.sprung_mass, 1.0), (0.3, 0.001), (0.1, 0.001),
                          (1.5 * vehicle.pitch_inertia, 1.0), (1.5 * vehicle.roll_inertia, 1.0))
    return {d.shape for d in ForceLaws({"FL": law}, {"FL": tyre}, body, []).departures(vehicle)}


def test_every_shape_the_causes_name_can_be_emitted_by_the_force_laws():
    emitted = emitted_corner_shapes() | emitted_departures()
    assert emitted == set(Shape), set(Shape) - emitted
    for cause in CAUSES.values():
        assert all(isinstance(shape, Shape) for shape in cause.evidence), cause.name
    named = {shape for cause in CAUSES.values() for shape in cause.evidence}
    assert named <= emitted


def test_every_cause_states_its_parameters_in_one_schema_with_units():
    vehicle = load_vehicle("proton_x")
    for cause in CAUSES.values():
        assert all(isinstance(p, ParameterSpec) and p.unit for p in cause.parameters()), cause.name
        fitted = cause.fit_parameters(vehicle, {}) + cause.refined_parameters(vehicle, {})
        assert all(p.unit for p in fitted), cause.name
    units = {p.name: p.unit for p in CAUSES["strut_friction"].refined_parameters(vehicle)}
    assert units == {"front_force": "N", "rear_force": "N", "velocity": "m/s"}


def suspension_force(sim, velocity):
    """Upward force (N) on the body from the suspension at ride height and compression rate ``velocity`` m/s."""
    model = sim.rig.model
    data = mujoco.MjData(model)
    data.qpos[:] = sim.static.qpos
    dof = model.joint("car.heave").dofadr[0]
    data.qvel[dof] = -velocity
    mujoco.mj_forward(model, data)
    return data.qfrc_passive[dof] + data.qfrc_actuator[dof]


def test_smooth_strut_friction_is_viscous_below_its_rate_and_saturates_at_its_force():
    """F = clip(force v / velocity, -force, force) beside the linear damper (3959 N s/m)."""
    vehicle = vehicle_from_dict({**QUARTER, "strut_friction": {"front": {"force": 200.0, "velocity": 0.02}}}, "test")
    sim = Simulator.create(build_model(vehicle, 512.0, "ideal"))
    static = suspension_force(sim, 0.0)
    for velocity, friction in ((0.005, 50.0), (-0.01, -100.0), (0.1, 200.0), (-0.3, -200.0)):
        assert suspension_force(sim, velocity) - static == pytest.approx(3959.0 * velocity + friction, rel=1e-6)


def test_smooth_friction_keeps_its_slope_where_rk4_resolves_it():
    from rig.causes.strut_friction import MAX_SLOPE_STEPS, PHYSICS_STEP

    vehicle = vehicle_from_dict({**QUARTER, "strut_friction": {"front": {"force": 800.0, "velocity": 0.002}}}, "test")
    sim = Simulator.create(build_model(vehicle, 512.0, "ideal"))
    slope = MAX_SLOPE_STEPS * 35.19 / PHYSICS_STEP
    static = suspension_force(sim, 0.0)
    assert suspension_force(sim, 0.001) - static == pytest.approx(3959.0 * 0.001 + slope * 0.001, rel=1e-6)


def body_tensor(vehicle) -> tuple[np.ndarray, np.ndarray]:
    """The sprung body's inertia tensor about its CG (kg m^2, body axes) and the CG (m) in the compiled model."""
    body = build_model(vehicle, 512.0, "ideal").model.body("car.body")
    rotation = np.zeros(9)
    mujoco.mju_quat2Mat(rotation, body.iquat)
    rotation = rotation.reshape(3, 3)
    return rotation @ np.diag(body.inertia) @ rotation.T, body.ipos.copy()


def test_a_payloads_own_inertia_adds_to_the_body_about_its_cg():
    vehicle = load_vehicle("proton_x")
    point = dataclasses.replace(vehicle, extensions={"mass_error": MassError(100.0, -0.5, 0.1)})
    spread = dataclasses.replace(vehicle, extensions={"mass_error": MassError(100.0, -0.5, 0.1, 80.0, 30.0)})
    difference = body_tensor(spread)[0] - body_tensor(point)[0]
    np.testing.assert_allclose(difference, np.diag([30.0, 80.0, 110.0]), atol=1e-6)


def body_force_at(vehicle, compression):
    """Upward force (N) on a quarter car's body at ``compression`` m from static ride height, at rest."""
    sim = Simulator.create(build_model(vehicle, 512.0, "ideal"))
    model = sim.rig.model
    data = mujoco.MjData(model)
    data.qpos[:] = sim.static.qpos
    data.qpos[model.joint("car.heave").qposadr[0]] -= compression
    mujoco.mj_forward(model, data)
    dof = model.joint("car.heave").dofadr[0]
    return data.qfrc_passive[dof] + data.qfrc_actuator[dof]


@pytest.mark.parametrize(("section", "sign"), [("bump_stop", 1.0), ("rebound_stop", -1.0)])
def test_a_stiffening_stop_adds_rate_and_quadratic_beyond_its_gap(section, sign):
    """Beyond a 10 mm gap, F = rate d + quadratic d^2 (d: how far the stop is pressed), on top of the 29 kN/m
    suspension; inside the gap nothing."""
    stop = {"front": {"gap": 0.01, "rate": 2e4, "quadratic": 3e6}}
    vehicle = vehicle_from_dict({**QUARTER, section: stop}, "test")
    plain = vehicle_from_dict(QUARTER, "test")
    for travel in (0.005, 0.02, 0.03):
        extra = body_force_at(vehicle, sign * travel) - body_force_at(plain, sign * travel)
        pressed = max(travel - 0.01, 0.0)
        assert extra == pytest.approx(sign * (2e4 * pressed + 3e6 * pressed**2), abs=1e-6)


def test_a_progressive_spring_pressed_into_its_curve_is_stiffer_at_ride_height():
    """Kn x^2 + k3 x^3 about a design position the car sits s below: about static ride height the added force is
    (2 Kn s + 3 k3 s^2) x + (Kn + 3 k3 s) x^2 + k3 x^3."""
    kn, k3, s = 2e5, 3e7, 0.02
    spring = {"front": {"quadratic": kn, "cubic": k3, "sag": s}}
    vehicle = vehicle_from_dict({**QUARTER, "progressive_spring": spring}, "test")
    plain = vehicle_from_dict(QUARTER, "test")
    for x in (-0.02, 0.01, 0.03):
        extra = body_force_at(vehicle, x) - body_force_at(plain, x)
        assert extra == pytest.approx((2 * kn * s + 3 * k3 * s**2) * x + (kn + 3 * k3 * s) * x**2 + k3 * x**3,
                                      rel=1e-6)


def test_a_payload_off_both_centre_lines_couples_pitch_and_roll():
    """The body's inertia tensor about its new CG: the data sheet's principal inertia and the payload as point
    masses, parallel-axis theorem with the products of inertia (I_xy = -sum m x y)."""
    vehicle = load_vehicle("proton_x")
    mass, x, y = 180.0, -1.0, 0.2
    tensor, centre = body_tensor(dataclasses.replace(vehicle, extensions={"mass_error": MassError(mass, x, y)}))
    total = vehicle.sprung_mass + mass
    cg = np.array([mass * x, mass * y, 0.0]) / total
    expected = np.diag([vehicle.roll_inertia, vehicle.pitch_inertia, vehicle.yaw_inertia])
    for m, point in ((vehicle.sprung_mass, -cg), (mass, np.array([x, y, 0.0]) - cg)):
        expected += m * (point @ point * np.eye(3) - np.outer(point, point))
    np.testing.assert_allclose(centre, cg, atol=1e-12)
    np.testing.assert_allclose(tensor, expected, rtol=1e-9, atol=1e-6)
