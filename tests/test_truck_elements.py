"""The truck's model elements against closed forms written here (docs/trucks.md): Fancher's leaf-spring loop, the
polytropic air spring, the segmented frame's modes against the Euler-Bernoulli beam and the torsion rod, a beam
axle's hop and tramp, a cab's bounce, pitch and roll on their springs, the driveline's modes and damping ratios on its
mounts in both truck models (the MJCF and tests/independent_truck.py); and vehicle files refused with the key."""

import dataclasses

import mujoco
import numpy as np
import pytest

from independent_truck import Truck
from support.frames import frame_frequencies

from rig.elements.air_spring import AirSpring, add_air_spring
from rig.elements.frame import Frame
from rig.elements.leaf_spring import LeafFriction, add_leaf_friction
from rig.vehicle.mjcf import build_model
from rig.vehicle.statics import STATE_SPEC, settle
from rig.vehicle.vehicle_file import VehicleError, load_vehicle, vehicle_from_dict, vehicle_to_toml

ATMOSPHERE = 101325.0


def slider_with_tendon(length: float = 0.5) -> mujoco.MjSpec:
    """A slider of 1e8 kg (it goes where it is sent, whatever the spring) below a fixed point, a vertical tendon
    between them; RK4 at 1 ms, as the rig's models."""
    spec = mujoco.MjSpec()
    spec.option.timestep, spec.option.integrator = 1e-3, mujoco.mjtIntegrator.mjINT_RK4
    spec.option.gravity = [0.0, 0.0, 0.0]
    spec.worldbody.add_site(name="top", pos=[0.0, 0.0, length])
    body = spec.worldbody.add_body(name="slider")
    body.add_joint(name="x", type=mujoco.mjtJoint.mjJNT_SLIDE, axis=[0, 0, 1])
    body.add_geom(type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[0.05, 0, 0], mass=1e8)
    body.add_site(name="bottom")
    tendon = spec.add_tendon(name="spring")
    tendon.wrap_site("top")
    tendon.wrap_site("bottom")
    return spec


def test_leaf_spring_loop_under_slow_sine_follows_fanchers_law_within_two_percent():
    """Compression 30 mm sin(2 pi 0.2 t): the spring and its LuGre/Dahl actuator against Fancher's exponential
    approach to the envelopes k x +- F_c, computed here step by step from the travel."""
    law, rate = LeafFriction(friction=2500.0, decay_length=0.004), 3.5e5
    spec = slider_with_tendon()
    spec.tendon("spring").stiffness = [rate, 0.0, 0.0]
    spec.tendon("spring").springlength = [0.5, 0.5]
    add_leaf_friction(spec, "friction", "spring", law)
    model = spec.compile()
    data = mujoco.MjData(model)
    friction, h = model.actuator("friction").id, model.opt.timestep
    travel, force = [], []
    for _ in range(int(10.0 / h)):  # two periods
        data.qvel[0] = 0.03 * 2 * np.pi * 0.2 * np.cos(2 * np.pi * 0.2 * (data.time + h / 2))  # up: compression
        mujoco.mj_forward(model, data)
        compression = 0.5 - data.ten_length[0]
        travel.append(compression)
        force.append(rate * compression + data.actuator_force[friction])  # the pushing force along the spring
        mujoco.mj_step(model, data)
    x, f = np.array(travel), np.array(force)
    friction_law = np.zeros_like(x)  # Fancher (1980): between reversals s F_c + (F0 - s F_c) exp(-|dx| / beta)
    for k in range(1, x.size):
        s = np.sign(x[k] - x[k - 1])
        friction_law[k] = s * law.friction + (friction_law[k - 1] - s * law.friction) * np.exp(
            -abs(x[k] - x[k - 1]) / law.decay_length)
    expected = rate * x + friction_law
    second = slice(x.size // 2, None)
    assert np.ptp(x[second]) == pytest.approx(0.06, rel=1e-3)
    assert np.max(np.abs(f[second] - expected[second])) < 0.02 * law.friction
    loop = f[second] - rate * x[second]
    assert np.ptp(loop) == pytest.approx(2 * law.friction, rel=0.02)  # the envelopes +-F_c are reached
    assert np.ptp(f[second]) > 2 * rate * 0.03  # a loop about the spring line, not the friction alone


def test_air_spring_force_follows_the_polytropic_law_within_half_a_percent_over_60_mm():
    spring = AirSpring(area=0.07, volume=0.04, pressure=5.55e5, polytropic_index=1.4, area_slope=0.03)
    spec = slider_with_tendon()
    add_air_spring(spec, "air", spec.tendon("spring"), spring, 0.5)
    model = spec.compile()
    data = mujoco.MjData(model)
    compression = np.linspace(-0.06, 0.06, 121)
    realised = []
    for x in compression:
        data.qpos[0] = x  # the slider up by x: the spring shorter by x
        mujoco.mj_forward(model, data)
        realised.append(-(data.qfrc_passive[0] + data.qfrc_actuator[0]))  # the push: down on the slider below
    volume = spring.volume - spring.area * compression - spring.area_slope * compression**2 / 2
    law = ((spring.pressure + ATMOSPHERE) * (spring.volume / volume) ** 1.4 - ATMOSPHERE) * (
        spring.area + spring.area_slope * compression)
    assert np.max(np.abs(np.array(realised) / law - 1)) < 0.005
    assert law[-1] / law[0] > 1.3  # a nonlinear spring over the range: 60 mm is 10 % of the gas volume


@pytest.mark.parametrize("n", [1.0, 1.4])
def test_air_spring_rate_at_design_is_the_polytropic_derivative(n):
    spring = AirSpring(area=0.07, volume=0.04, pressure=5.0e5, polytropic_index=n, area_slope=0.0)
    expected = n * (spring.pressure + ATMOSPHERE) * spring.area**2 / spring.volume
    assert spring.rate == pytest.approx(expected, rel=1e-12)
    assert spring.cubic[1] == pytest.approx(expected, rel=0.005)


FRAME_MASS, FRAME_LENGTH, FRAME_ROLL, EI, GJ = 8000.0, 7.5, 3000.0, 4.0e7, 2.0e6
BEAM_ROOTS = (4.730040744862704, 7.853204624095838)  # free-free Euler-Bernoulli: beta_n L


def relative_errors(segments: int) -> tuple[float, float, float]:
    frame = Frame(length=FRAME_LENGTH, front_overhang=1.0, bending_stiffness=EI, torsion_stiffness=GJ,
                  segments=segments, damping_ratio=0.0)
    bending, torsion = frame_frequencies(frame, FRAME_MASS, FRAME_ROLL)
    per_length = FRAME_MASS / FRAME_LENGTH
    beam = [root**2 * np.sqrt(EI / (per_length * FRAME_LENGTH**4)) for root in BEAM_ROOTS]
    rod = np.pi / FRAME_LENGTH * np.sqrt(GJ / (FRAME_ROLL / FRAME_LENGTH))
    return bending[0] / beam[0] - 1, bending[1] / beam[1] - 1, torsion[0] / rod - 1


def test_shipped_segment_count_gives_the_frames_first_modes_within_two_percent():
    """Eight segments (the shipped trucks'): first and second bending against Euler-Bernoulli free-free, first
    torsion against the free-free rod."""
    errors = relative_errors(8)
    assert max(abs(e) for e in errors) < 0.02, errors
    assert load_vehicle("truck_6x4").frame.segments == 8 and load_vehicle("tractor_4x2").frame.segments == 8


def test_frame_modes_converge_with_the_segment_count():
    counts = (4, 8, 16)
    errors = np.abs([relative_errors(n) for n in counts])
    assert np.all(np.diff(errors, axis=0) < 0), errors  # every mode closer with more segments
    assert np.all(errors[-1] < 0.002), errors


def test_frame_stiffness_from_target_frequencies_gives_those_frequencies():
    data = {"length": FRAME_LENGTH, "front_overhang": 1.0, "bending_frequency": 9.0, "torsion_frequency": 6.0,
            "segments": 16}
    from rig.elements.frame import parse_frame

    frame = parse_frame(data, "test", FRAME_MASS, FRAME_ROLL)
    bending, torsion = frame_frequencies(frame, FRAME_MASS, FRAME_ROLL)
    assert bending[0] / (2 * np.pi) == pytest.approx(9.0, rel=0.005)
    assert torsion[0] / (2 * np.pi) == pytest.approx(6.0, rel=0.005)


def settled_matrices(vehicle):
    """Mass, stiffness and damping matrices of the settled model (dof order), the joints' names and the suspension
    springs' compressions at rest."""
    rig = build_model(vehicle, 256.0)
    static = settle(rig)
    model = rig.model
    data = mujoco.MjData(model)
    mujoco.mj_setState(model, data, static.state, STATE_SPEC)
    mujoco.mj_forward(model, data)
    mass = np.zeros((model.nv, model.nv))
    mujoco.mj_fullM(model, data, mass)

    def force(q):
        data.qpos[:] = q
        mujoco.mj_forward(model, data)
        return data.qfrc_passive + data.qfrc_actuator - data.qfrc_bias

    compression = {corner: vehicle.cg_height - vehicle.wheel_radius - data.ten_length[
        model.tendon(f"car.{corner}/suspension").id] for corner in vehicle.corners}  # springs at rest, m
    q0, step = data.qpos.copy(), 1e-6
    stiffness = np.column_stack([-(force(q0 + step * e) - force(q0 - step * e)) / (2 * step) for e in np.eye(model.nv)])
    data.qpos[:] = q0

    def velocity_force(v):
        data.qvel[:] = v
        mujoco.mj_forward(model, data)
        return data.qfrc_passive + data.qfrc_actuator - data.qfrc_bias

    damping = np.column_stack([-(velocity_force(step * e) - velocity_force(-step * e)) / (2 * step)
                               for e in np.eye(model.nv)])
    names = [model.joint(model.dof_jntid[i]).name for i in range(model.nv)]
    return mass, stiffness, damping, names, compression


def held_frequencies(mass, stiffness, names, joints) -> np.ndarray:
    """Natural frequencies (rad/s) of ``joints`` with every other coordinate held."""
    index = [names.index(j) for j in joints]
    block = np.ix_(index, index)
    return np.sort(np.sqrt(np.linalg.eigvals(np.linalg.solve(mass[block], stiffness[block])).real))


@pytest.fixture(scope="module")
def truck_matrices():
    return load_vehicle("truck_6x4"), *settled_matrices(load_vehicle("truck_6x4"))


def test_beam_axle_hop_and_tramp_with_the_frame_held(truck_matrices):
    """Heave: 2 k_s + 2 n k_t over the axle's mass; roll: springs at +-s/2, tyres at +-t/2 (twins at +-(t +- d)/2) over
    its roll inertia. Front axle single tyres, middle axle twins."""
    truck, mass, stiffness, _, names, compression = truck_matrices
    for name, twins in (("front", False), ("middle", True)):
        axle = truck.axle_named(name)
        spring = axle.spring_rate
        if twins:  # the air spring's rate at its compression at rest, from the law
            x = compression["ML"]
            spring = (axle.law.force(x + 1e-5) - axle.law.force(x - 1e-5)) / 2e-5
        tyres = 2 * axle.tyre_rate * (2 if twins else 1)
        heave = np.sqrt((2 * spring + tyres) / (2 * axle.unsprung_mass))
        lateral = axle.tyre_rate * ((axle.track**2 + axle.dual_spacing**2) if twins else axle.track**2 / 2)
        roll = np.sqrt((spring * axle.spring_track**2 / 2 + lateral) / axle.roll_inertia)
        found = held_frequencies(mass, stiffness, names, [f"car.{name}/beam_heave", f"car.{name}/beam_roll"])
        assert found == pytest.approx(sorted([heave, roll]), rel=2e-3), name


def test_cab_bounce_pitch_and_roll_on_its_mounts_with_the_frame_held(truck_matrices):
    truck, mass, stiffness, _, names, _ = truck_matrices
    cab = truck.cab
    expected = [np.sqrt(4 * cab.stiffness / cab.mass),
                np.sqrt(4 * cab.stiffness * (cab.mount_base / 2) ** 2 / cab.pitch_inertia),
                np.sqrt(4 * cab.stiffness * (cab.mount_track / 2) ** 2 / cab.roll_inertia)]
    found = held_frequencies(mass, stiffness, names, ["car.cab/heave", "car.cab/pitch", "car.cab/roll"])
    # within 0.5 %: at rest the frame is pitched (the front leaves sag 93 mm more than the air springs), so the mounts
    # lean a little from the vertical
    assert found == pytest.approx(sorted(expected), rel=5e-3)


def held_modes(mass, stiffness, damping, names, joints) -> list[tuple[float, float]]:
    """(natural frequency rad/s, damping ratio) of the modes of ``joints`` with every other coordinate held, by
    frequency: the roots of det(M s^2 + C s + K) = 0 on their block."""
    index = [names.index(j) for j in joints]
    block, n = np.ix_(index, index), len(index)
    inverse = np.linalg.inv(mass[block])
    system = np.block([[np.zeros((n, n)), np.eye(n)], [-inverse @ stiffness[block], -inverse @ damping[block]]])
    return sorted((abs(r), -r.real / abs(r)) for r in np.linalg.eigvals(system) if r.imag > 0)


def independent_matrices(vehicle):
    """Mass, stiffness and damping matrices of the independent truck simulator at rest on its held posts, and its
    coordinates' names."""
    truck = Truck(vehicle)
    state, n = truck.rest(), truck.n

    def acceleration(q, qd):
        shifted = state.copy()
        shifted[:n], shifted[n:2 * n] = state[:n] + q, qd
        return truck.derivative(shifted, np.zeros(len(truck.corners)))[1]["qdd"]

    step, zero = 1e-6, np.zeros(n)
    mass = np.diag(truck.mass)
    stiffness = np.column_stack([-(acceleration(step * e, zero) - acceleration(-step * e, zero)) / (2 * step)
                                 for e in np.eye(n)])
    damping = np.column_stack([-(acceleration(zero, step * e) - acceleration(zero, -step * e)) / (2 * step)
                               for e in np.eye(n)])
    return mass, mass @ stiffness, mass @ damping, truck.names


@pytest.mark.parametrize("mounts", [None, (1.165e6, 3369.0)], ids=["file", "softer"])
def test_driveline_bounce_pitch_and_roll_on_its_mounts_with_the_frame_held_in_both_models(mounts):
    """Heave k = 4 k_m over m, pitch 4 k_m (b/2)^2 over I_y, roll 4 k_m (t/2)^2 over I_x, each with its damping ratio
    c / (2 sqrt(k m)) of the mounts' dampers at the same points: the MJCF's mount tendons and the independent
    simulator's mount lines, the mounts as the file gives them or as the diagnosis's hidden ones (seed 1)."""
    truck = dataclasses.replace(load_vehicle("truck_6x4"), frame=None)
    if mounts is not None:
        truck = dataclasses.replace(truck, driveline=dataclasses.replace(truck.driveline, stiffness=mounts[0],
                                                                         damping=mounts[1]))
    body = truck.driveline
    expected = []
    for arm, inertia in ((1.0, body.mass), (body.mount_base / 2, body.pitch_inertia),
                         (body.mount_track / 2, body.roll_inertia)):
        k, c = 4 * body.stiffness * arm**2, 4 * body.damping * arm**2
        expected.append((np.sqrt(k / inertia), c / (2 * np.sqrt(k * inertia))))
    expected.sort()
    mass, stiffness, damping, names, _ = settled_matrices(truck)
    found = held_modes(mass, stiffness, damping, names, [f"car.driveline/{j}" for j in ("heave", "pitch", "roll")])
    assert np.array(found) == pytest.approx(np.array(expected), rel=1e-4)
    mass, stiffness, damping, names = independent_matrices(truck)
    found = held_modes(mass, stiffness, damping, names, [f"driveline/{j}" for j in ("z", "theta", "phi")])
    assert np.array(found) == pytest.approx(np.array(expected), rel=1e-4)


def truck_table(**changes) -> dict:
    table = {"name": "t", "layout": "truck",
             "geometry": {"wheelbase": 4.0, "cg_to_front_axle": 2.0},
             "sprung": {"mass": 10000.0, "pitch_inertia": 50000.0, "roll_inertia": 5000.0},
             "axles": [{"position": 0.0, "track": 2.0, "unsprung_mass": 300.0, "spring_rate": 3e5,
                        "damping": 1e4, "tyre_rate": 1e6},
                       {"position": 4.0, "track": 1.8, "unsprung_mass": 500.0, "damping": 1e4, "tyre_rate": 9e5,
                        "suspension": "beam_air", "spring_track": 1.2,
                        "air_spring": {"area": 0.07, "volume": 0.04, "pressure": 5e5}}]}
    for path, value in changes.items():
        *keys, last = path.split("__")
        node = table
        for key in keys:
            node = node[int(key)] if isinstance(node, list) else node[key]
        if value is None:
            del node[last]
        else:
            node[last] = value
    return table


@pytest.mark.parametrize("changes, named", [
    ({"axles__1__position": 4.6}, "position = 4.6 m lies outside the wheelbase"),
    ({"axles__1__tyres": "dual"}, "needs dual_spacing"),
    ({"axles__1__air_spring__volume": 0.0}, "volume = 0.0"),
])
def test_bad_truck_input_is_refused_naming_the_key(changes, named):
    with pytest.raises(VehicleError, match=named):
        vehicle_from_dict(truck_table(**changes))


def test_truck_corners_axles_and_file_round_trip():
    truck = load_vehicle("truck_6x4")
    assert truck.corners == ("FL", "FR", "ML", "MR", "RL", "RR")
    assert truck.axle_names == ("front", "middle", "rear")
    four = vehicle_from_dict(truck_table(axles=[*truck_table()["axles"][:1], *[
        {**truck_table()["axles"][1], "position": p} for p in (2.6, 3.3, 4.0)]]))
    assert four.corners == ("FL", "FR", "M1L", "M1R", "M2L", "M2R", "RL", "RR")
    from rig.vehicle.vehicle_file import vehicle_to_toml
    import tomllib

    assert vehicle_from_dict(tomllib.loads(vehicle_to_toml(truck)), truck.source) == truck
    assert dataclasses.replace(truck, frame=None).frame is None


def test_the_command_line_refuses_a_bad_truck_file_in_one_line(tmp_path, capsys):
    from rig.cli.main import main

    text = vehicle_to_toml(load_vehicle("truck_6x4")).replace("dual_spacing = 0.35\n", "", 1)
    path = tmp_path / "bad.toml"
    path.write_text(text)
    assert main(["model", "--vehicle", str(path), "--export", str(tmp_path / "bad.xml")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "(middle)" in err and "dual_spacing" in err and "Traceback" not in err
