"""Linkage cars the tests build: a MacPherson car's vehicle file, fs_car with parallel wishbones."""

import tomllib

from rig.vehicle.vehicle_file import resolve_vehicle_path, vehicle_from_dict

MACPHERSON_CAR = """
name = "macpherson_car"
[geometry]
wheelbase = 2.60
cg_to_front_axle = 1.00
track_front = 1.47
track_rear = 1.45
cg_height = 0.55
wheel_radius = 0.31
[sprung]
mass = 1150.0
pitch_inertia = 1750.0
roll_inertia = 440.0
[front]
unsprung_mass = 35.0
spring_rate = 23000.0
parasitic_rate = 2000.0
damping = 3000.0
tyre_rate = 200000.0
[front.kinematics]
type = "macpherson"
lower_front = [0.25, 0.35, 0.14]
lower_rear = [-0.10, 0.38, 0.15]
lower_outer = [0.00, 0.70, 0.13]
strut_top = [-0.03, 0.60, 0.68]
strut_lower = [0.00, 0.66, 0.30]
tie_rod_inner = [-0.15, 0.35, 0.20]
tie_rod_outer = [-0.13, 0.68, 0.20]
wheel_centre = [0.00, 0.735, 0.295]
static_camber = -0.5
static_toe = 0.1
[rear]
unsprung_mass = 40.0
spring_rate = 18000.0
damping = 2400.0
tyre_rate = 200000.0
"""


def parallel_arm_car():
    """fs_car with equal, parallel wishbones 0.2 m apart: a linkage whose wheel moves straight up at design."""
    table = tomllib.loads(resolve_vehicle_path("fs_car").read_text())
    for axle in ("front", "rear"):
        points = table[axle]["kinematics"]
        for upper, lower in (("upper_front", "lower_front"), ("upper_rear", "lower_rear"),
                             ("upper_outer", "lower_outer")):
            points[upper] = [points[lower][0], points[lower][1], points[lower][2] + 0.2]
        points["tie_rod_inner"] = [points["tie_rod_inner"][0], points["lower_front"][1], points["tie_rod_inner"][2]]
    table["name"] = "fs_car_parallel_arms"
    return vehicle_from_dict(table)
