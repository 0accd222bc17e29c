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
         r"\[front\] spring_rate = 23.0 N/m is outside the plausible range.*SI"),
        ("mass = 1153.84", "mass = 1.15384", r"\[sprung\] mass = 1.15384 kg is outside"),
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
