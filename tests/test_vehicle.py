"""Vehicle files: the contract keys load; wrong units and typos are refused with a message that says so."""

import pytest

from rig.vehicle.vehicle_file import VehicleError, builtin_vehicles, load_vehicle

PROTON_X = """
name = "test_car"
[geometry]
wheelbase = 2.60
cg_to_front_axle = 0.998
track_front = 1.47
track_rear = 1.45
[sprung]
mass = 1153.84
pitch_inertia = 1750.0
roll_inertia = 440.0
[front]
unsprung_mass = 35.19
spring_rate = 23000.0
parasitic_rate = 6000.0
damping = 3959.0
tyre_rate = 208500.0
tyre_damping = 0.0
[rear]
unsprung_mass = 41.88
spring_rate = 18000.0
parasitic_rate = 6000.0
damping = 2374.0
tyre_rate = 208500.0
"""


def write(tmp_path, text):
    path = tmp_path / "car.toml"
    path.write_text(text)
    return path


def test_the_design_example_loads_with_the_thesis_values(tmp_path):
    vehicle = load_vehicle(write(tmp_path, PROTON_X))
    assert vehicle.front.suspension_rate == 29000.0
    assert vehicle.rear.tyre_damping == 0.0  # optional key, default 0
    assert vehicle.corner_position("RR") == pytest.approx((0.998 - 2.60, -0.725))


def test_builtin_vehicles_are_found_by_name():
    assert {"proton_x", "proton_y", "proton_x_quarter"} <= set(builtin_vehicles())
    assert load_vehicle("proton_x").sprung_mass == pytest.approx(2 * (355.31 + 221.61))  # Nurhadiyanto's Table 4.2


@pytest.mark.parametrize(
    "old, new, message",
    [
        ("spring_rate = 23000.0", "spring_rate = 23.0",
         r"\[front\] parasitic_rate / spring_rate = 261 \(6000 / 23 N/m.*outside the plausible 0..2.*SI"),
        ("mass = 1153.84", "mass = 1.15384",
         r"\[front\] body \(ride\) frequency = 42.6 Hz \(0.3555 kg .* outside the plausible 0.3..10 Hz"),
        ("damping = 3959.0", "dampnig = 3959.0", r"unknown key\(s\) dampnig in \[front\]"),
        ("tyre_rate = 208500.0\ntyre_damping", "tyre_damping", r"\[front\] is missing 'tyre_rate' \(N/m\)"),
        ("cg_to_front_axle = 0.998", "cg_to_front_axle = 3.0",
         r"cg_to_front_axle must lie between 0 and the wheelbase"),
        ('name = "test_car"', 'name = "test_car"\n[rig]\nstroke = "big"',
         r"\[rig\] stroke must be a non-negative number"),
        ("wheelbase = 2.60", "wheelbase = true", r"wheelbase must be a number in m"),
    ],
)
def test_bad_vehicle_files_are_refused_with_a_clear_message(tmp_path, old, new, message):
    assert old in PROTON_X
    with pytest.raises(VehicleError, match=message):
        load_vehicle(write(tmp_path, PROTON_X.replace(old, new, 1)))


def test_unknown_names_and_bad_toml_are_refused(tmp_path):
    with pytest.raises(VehicleError, match=r"unknown vehicle 'proton_z'.*proton_x"):
        load_vehicle("proton_z")
    with pytest.raises(VehicleError, match="not valid TOML"):
        load_vehicle(write(tmp_path, "name = "))


def test_rig_section_overrides_the_defaults(tmp_path):
    vehicle = load_vehicle(write(tmp_path, PROTON_X + "[rig]\nservo_bandwidth = 80.0\nservo_delay = 0.003\n"))
    assert vehicle.rig.servo_bandwidth == 80.0
    assert vehicle.rig.servo_delay == 0.003
    assert vehicle.rig.stroke == 0.075  # Nurhadiyanto's thesis: 150 mm stroke


# ---- plausibility that fits real rigs (rig/vehicle/plausibility.py) -----------------------------------------------

def _scaled_truck(factor: float) -> dict:
    """truck_6x4's tables with every mass, inertia, rate and damping times ``factor`` (its frequencies and damping
    ratios unchanged): a 26 t truck made a heavier one."""
    import tomllib

    from rig.vehicle.vehicle_file import resolve_vehicle_path

    data = tomllib.loads(resolve_vehicle_path("truck_6x4").read_text())
    scaled = ("mass", "pitch_inertia", "roll_inertia", "unsprung_mass", "spring_rate", "damping", "tyre_rate",
              "tyre_damping", "friction", "stiffness")
    for table in [data["sprung"], *data["axles"], data["cab"], data["driveline"]]:
        for key in scaled:
            if key in table:
                table[key] *= factor
        for law in ("leaf_spring", "air_spring"):
            if law in table:
                table[law] = {k: v * factor if k in ("friction", "area", "volume") else v
                              for k, v in table[law].items()}
    return data


def test_a_lab_quarter_car_and_a_40_t_truck_both_load():
    from rig.vehicle.plausibility import stations
    from rig.vehicle.vehicle_file import vehicle_from_dict

    lab = load_vehicle("lab_quarter")
    (station,) = stations(lab)
    # the university bench: 2.1 kg body, 1.76 kg wheel, 1483 N/m spring, 1935 N/m tyre
    ride = 1483.0 * 1935.0 / (1483.0 + 1935.0)
    assert station.body_hz == pytest.approx((ride / 2.1) ** 0.5 / (2 * 3.141592653589793))  # 3.18 Hz
    assert station.wheel_hop_hz == pytest.approx(((1483.0 + 1935.0) / 1.76) ** 0.5 / (2 * 3.141592653589793))
    truck = vehicle_from_dict(_scaled_truck(40.0 / 26.0), "truck_40t")
    gross = (truck.sprung_mass + truck.cab.mass + truck.driveline.mass
             + 2 * sum(a.unsprung_mass for a in truck.axles))
    assert gross == pytest.approx(40e3, rel=0.01)
    assert [s.body_hz for s in stations(truck)] == pytest.approx([s.body_hz for s in stations(
        load_vehicle("truck_6x4"))], rel=0.1)


LAB = """
name = "bench"
layout = "quarter"
[sprung]
mass = 2.1
[front]
unsprung_mass = 1.76
spring_rate = 1483.0
damping = 7.5
tyre_rate = 1935.0
"""


@pytest.mark.parametrize("text, old, new, message", [
    (LAB, "spring_rate = 1483.0", "spring_rate = 1.483",  # N/mm read as N/m
     r"\[front\] suspension rate / tyre rate = 0.000766 .* outside the plausible 0.01..5"),
    (LAB, "mass = 2.1", "mass = 2100.0",  # g read as kg
     r"\[front\] body \(ride\) frequency = 0.101 Hz \(2100 kg .* outside the plausible 0.3..10 Hz"),
    (LAB, "unsprung_mass = 1.76", "unsprung_mass = 1760.0",
     r"\[front\] wheel-hop frequency = 0.222 Hz .* outside the plausible 1.5..60 Hz"),
    (LAB, "damping = 7.5", "damping = 7500.0",  # N s/mm read as N s/m
     r"\[front\] body damping ratio = 67.2 .* outside the plausible 0.002..5"),
    (PROTON_X, "tyre_rate = 208500.0\ntyre_damping", "tyre_rate = 208.5\ntyre_damping",
     r"\[front\] suspension rate / tyre rate = 139 .* outside the plausible 0.01..5"),
    (PROTON_X, "damping = 3959.0", "damping = 3.959",
     r"\[front\] body damping ratio = 0.000617 .* outside the plausible 0.002..5"),
    (PROTON_X, "pitch_inertia = 1750.0", "pitch_inertia = 1.75e6",  # g m^2 read as kg m^2
     r"\[sprung\] pitch radius of gyration / wheelbase = 15 .* outside the plausible 0.1..2"),
])
def test_unit_mistakes_are_refused_naming_the_check_and_its_numbers(tmp_path, text, old, new, message):
    assert old in text
    with pytest.raises(VehicleError, match=message) as err:
        load_vehicle(write(tmp_path, text.replace(old, new, 1)))
    assert "\n" not in str(err.value) and "SI units" in str(err.value)


def test_a_unit_mistake_in_a_truck_axle_is_refused_naming_the_axle():
    from rig.vehicle.vehicle_file import vehicle_from_dict

    data = _scaled_truck(1.0)
    data["axles"][0]["unsprung_mass"] = 0.35  # t read as kg
    with pytest.raises(VehicleError, match=r"\[\[axles\]\] 1 \(front\) wheel-hop frequency = 313 Hz"):
        vehicle_from_dict(data, "truck")


def test_a_car_no_equilibrium_can_be_found_for_is_refused_in_one_line():
    """Tyres a thousand times too stiff leave the settling's finite differences no digits (a singular matrix): the
    builder says there is no static equilibrium instead of letting numpy's error out."""
    import dataclasses

    from rig.sim.simulate import Simulator
    from rig.vehicle.mjcf import build_model
    from rig.vehicle.statics import EquilibriumError

    car = load_vehicle("proton_x")
    stiff = dataclasses.replace(car, front=dataclasses.replace(car.front, tyre_rate=car.front.tyre_rate * 1e3))
    with pytest.raises(EquilibriumError, match="no static equilibrium for proton_x"):
        Simulator.create(build_model(stiff, 512.0, "ideal"))
