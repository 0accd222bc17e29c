"""Model extensions against their closed-form force laws, and their vehicle-file sections."""

import mujoco
import numpy as np
import pytest

from support.quarter import quarter_with, suspension_force

from rig.causes.anti_roll_bar import AntiRollBar
from rig.sim.simulate import Simulator
from rig.vehicle.mjcf import build_model
from rig.vehicle.vehicle_file import VehicleError, load_vehicle

def test_bump_stop_adds_its_rate_beyond_the_gap_from_static_ride_height():
    plain = Simulator.create(build_model(quarter_with(), 512.0, "ideal"))
    stopped = Simulator.create(build_model(quarter_with(bump_stop={"front": {"gap": 0.02, "rate": 1.5e5}}), 512.0,
                                           "ideal"))
    for compression in (0.0, 0.015, 0.0199):
        assert suspension_force(stopped, compression, 0.0) == pytest.approx(suspension_force(plain, compression, 0.0))
    for compression in (0.025, 0.04):
        extra = suspension_force(stopped, compression, 0.0) - suspension_force(plain, compression, 0.0)
        assert extra == pytest.approx(1.5e5 * (compression - 0.02), rel=1e-6)


def test_rebound_stop_adds_its_rate_beyond_the_gap_in_extension_only():
    plain = Simulator.create(build_model(quarter_with(), 512.0, "ideal"))
    stopped = Simulator.create(build_model(quarter_with(rebound_stop={"front": {"gap": 0.02, "rate": 1.5e5}}), 512.0,
                                           "ideal"))
    for compression in (0.04, 0.0, -0.015, -0.0199):
        assert suspension_force(stopped, compression, 0.0) == pytest.approx(suspension_force(plain, compression, 0.0))
    for compression in (-0.025, -0.04):  # the stop pulls the body down, as the extended spring does
        extra = suspension_force(stopped, compression, 0.0) - suspension_force(plain, compression, 0.0)
        assert extra == pytest.approx(1.5e5 * (compression + 0.02), rel=1e-6)


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
    rear = vehicle.extensions["damper_asymmetry"]["rear"]
    assert rear.rebound > rear.compression


def test_progressive_spring_follows_the_neuro_model_k0_x_plus_kn_x2_about_static():
    """The neuro-model paper's eq. 3: F = K0 x + Kn x^2 with x the suspension compression from equilibrium."""
    kn, k3 = 4.0e5, 2.0e6
    plain = Simulator.create(build_model(quarter_with(), 512.0, "ideal"))
    progressive = Simulator.create(build_model(
        quarter_with(progressive_spring={"front": {"quadratic": kn, "cubic": k3}}), 512.0, "ideal"))
    np.testing.assert_allclose(progressive.static.qpos, plain.static.qpos, atol=1e-12)  # same ride height
    for x in (0.02, -0.02):
        extra = (suspension_force(progressive, x, 0.0) - suspension_force(plain, x, 0.0))
        assert extra == pytest.approx(kn * x**2 + k3 * x**3, rel=1e-6)


def test_strut_friction_holds_the_strut_until_the_friction_force():
    """Coulomb friction: a static push below the friction force leaves the suspension travel unchanged
    (< 0.05 mm); above it the strut slides by about (push - friction) / rate."""
    sim = Simulator.create(build_model(quarter_with(strut_friction={"front": {"force": 300.0}}), 512.0, "ideal"))
    model = sim.rig.model
    data = mujoco.MjData(model)
    heave = model.joint("car.heave").dofadr[0]
    spring = model.tendon("car.FL/suspension").id
    travel = []
    for push in (200.0, 600.0):
        mujoco.mj_setState(model, data, sim.static.state, mujoco.mjtState.mjSTATE_FULLPHYSICS)
        steps = 3000
        for k in range(steps):  # ramped slowly so that no inertial force adds to the push
            data.qfrc_applied[heave] = -push * min(1.0, k / (0.75 * steps))  # down: compresses the strut
            mujoco.mj_step(model, data)
        travel.append(sim.static.suspension_length[0] - data.ten_length[spring])
    assert abs(travel[0]) < 5e-5
    assert travel[1] == pytest.approx((600.0 - 300.0) / 29000.0, rel=0.15)


def test_anti_roll_bar_couples_left_and_right_travel():
    rate = 20000.0
    plain = Simulator.create(build_model(load_vehicle("proton_x"), 512.0, "ideal"))
    vehicle = load_vehicle("proton_x")
    import dataclasses

    with_bar = dataclasses.replace(vehicle, extensions={"anti_roll_bar": {"front": AntiRollBar(rate)}})
    barred = Simulator.create(build_model(with_bar, 512.0, "ideal"))
    for sim in (plain, barred):
        model = sim.rig.model
        data = mujoco.MjData(model)
        data.qpos[:] = sim.static.qpos
        data.qpos[model.joint("car.FL/wheel").qposadr[0]] += 0.01  # left wheel up 10 mm: left compresses
        mujoco.mj_forward(model, data)
        sim.force = data.qfrc_passive[model.joint("car.FR/wheel").dofadr[0]]
    # the bar pushes the right wheel up by rate x (left - right compression) = rate x 10 mm
    assert barred.force - plain.force == pytest.approx(rate * 0.01, rel=1e-9)


def test_mass_error_moves_the_static_loads_by_the_moment_balance():
    import dataclasses

    from rig.causes.mass_error import MassError

    vehicle = load_vehicle("proton_x")
    loaded = dataclasses.replace(vehicle, extensions={"mass_error": MassError(mass=100.0, x=-0.9, y=0.0)})
    before = Simulator.create(build_model(vehicle, 512.0, "ideal")).static.tyre_force
    after = Simulator.create(build_model(loaded, 512.0, "ideal")).static.tyre_force
    g = 9.80665
    a = vehicle.cg_to_front_axle
    rear_share = (a + 0.9) / vehicle.wheelbase  # the payload sits 0.9 m behind the CG
    assert (after - before)[2:].sum() == pytest.approx(100.0 * g * rear_share, rel=2e-3)
    assert (after - before)[:2].sum() == pytest.approx(100.0 * g * (1 - rear_share), rel=2e-3)


def test_top_mount_puts_a_bushing_in_series_with_the_damper():
    """Modes of the quarter car with a compliant top mount against the analytic 3-DOF model: body (less the
    mount, 0.6 c times the 1 ms step: 2.4 kg) on spring k to the wheel, mount on bushing k_m to the body and damper c
    to the wheel, tyre."""
    from rig.sim.linearize import car_state_matrix
    from rig.vehicle import ride_model

    k, c, kt, k_m = 29000.0, 3959.0, 208500.0, 3.0e5
    m_m = 0.6 * c * 1e-3
    m_b, m_w = 355.31 - m_m, 35.19
    sim = Simulator.create(build_model(quarter_with(top_mount_compliance={"front": {"rate": k_m}}), 512.0, "ideal"))
    mass = np.diag([m_b, m_m, m_w])
    stiffness = np.array([[k + k_m, -k_m, -k], [-k_m, k_m, 0.0], [-k, 0.0, k + kt]])
    damping = np.array([[0.0, 0.0, 0.0], [0.0, c, -c], [0.0, -c, c]])
    analytic = np.array(ride_model.modes(ride_model.state_matrix(mass, damping, stiffness)))
    simulated = np.array(ride_model.modes(car_state_matrix(sim)))
    np.testing.assert_allclose(simulated, analytic, rtol=1e-3)


def test_sensor_chain_scales_and_delays_channels():
    from rig.sim.measurement import apply_sensor_model

    rate, t = 512.0, np.arange(2048) / 512.0
    sine = np.sin(2 * np.pi * 3.0 * t)
    out = apply_sensor_model({"FL/sprung_acc": sine, "FR/sprung_acc": sine},
                             {"sensor_gain": {"FL/sprung_acc": 1.1}, "sensor_delay": {"FR/sprung_acc": 0.004}}, rate)
    np.testing.assert_allclose(out["FL/sprung_acc"], 1.1 * sine)
    later = np.sin(2 * np.pi * 3.0 * (t - 0.004))  # a 4 ms delay: 2.05 samples, not a whole number
    np.testing.assert_allclose(out["FR/sprung_acc"][10:], later[10:], atol=1e-6)
    with pytest.raises(ValueError, match="RR/tyre_force"):
        apply_sensor_model({"FL/sprung_acc": sine}, {"sensor_gain": {"RR/tyre_force": 1.1}}, rate)
