"""Linkage corners (rig/vehicle/suspensions/) and the K&C rig (rig/sim/kc.py) against an independent solver
written for the tests (tests/kinematics_reference.py), the design rates, and refusals of bad hardpoints."""

from __future__ import annotations

import dataclasses
import tomllib

import numpy as np
import pytest

from kinematics_reference import ReferenceCorner, sweep
from support.linkage_cars import MACPHERSON_CAR, parallel_arm_car

from rig.io.kc_record import read_kc_csv, write_kc_csv
from rig.sim.kc import KcError, KcRig, run_kc
from rig.vehicle.mjcf import build_model
from rig.vehicle.ride_model import static_loads
from rig.vehicle.statics import settle
from rig.vehicle.suspensions.linkage import BODY_SITE_HEIGHT
from rig.vehicle.vehicle_file import VehicleError, load_vehicle, vehicle_from_dict, vehicle_to_toml
from rig.vehicle.vehicle_file import resolve_vehicle_path

ANGLE_TOLERANCE = 5e-6   # deg: rig kc against the independent solver (measured 1.5e-6 deg at most)
LENGTH_TOLERANCE = 1e-8  # m (measured 3.3e-9 m)


@pytest.fixture(scope="module")
def fs_car():
    return load_vehicle("fs_car"), tomllib.loads(resolve_vehicle_path("fs_car").read_text())


@pytest.fixture(scope="module")
def macpherson_car():
    table = tomllib.loads(MACPHERSON_CAR)
    return vehicle_from_dict(table), table


def _compare(result, table, corners, steered):
    """Largest differences (deg, deg, m) of camber, toe and track change between ``rig kc`` and the reference."""
    worst = np.zeros(3)
    for corner in corners:
        axle = "front" if corner[0] == "F" else "rear"
        side = 1 if corner[1] == "L" else -1
        kinematic = table[axle]["kinematics"]
        if result.test == "travel":
            reference = sweep(kinematic, side, travels=result.curves[f"{corner}/travel"], steered=steered[axle])
        else:
            reference = sweep(kinematic, side, racks=result.sweep, steered=steered[axle])
        for k, (quantity, scale) in enumerate((("camber", 180 / np.pi), ("toe", 180 / np.pi), ("track_change", 1))):
            difference = result.curves[f"{corner}/{quantity}"] * scale - reference[quantity]
            worst[k] = max(worst[k], np.max(np.abs(difference)))
    return worst


@pytest.mark.parametrize("test", ["travel", "steer"])
def test_double_wishbone_curves_agree_with_the_independent_solver(fs_car, test):
    vehicle, table = fs_car
    result = run_kc(vehicle, test, steps=13)
    assert np.ptp(np.degrees(result.curves["FL/toe"])) > (20.0 if test == "steer" else 0.3)  # the curves move
    camber, toe, track = _compare(result, table, vehicle.corners, {"front": True, "rear": False})
    assert camber < ANGLE_TOLERANCE and toe < ANGLE_TOLERANCE and track < LENGTH_TOLERANCE, (camber, toe, track)


@pytest.mark.parametrize("test", ["travel", "steer"])
def test_macpherson_curves_agree_with_the_independent_solver(macpherson_car, test):
    vehicle, table = macpherson_car
    result = run_kc(vehicle, test, steps=13)
    assert np.ptp(np.degrees(result.curves["FL/camber"])) > 0.5
    camber, toe, track = _compare(result, table, ("FL", "FR"), {"front": True})
    assert camber < ANGLE_TOLERANCE and toe < ANGLE_TOLERANCE and track < LENGTH_TOLERANCE, (camber, toe, track)
    assert np.allclose(result.curves["RL/camber"], 0.0) and np.allclose(result.curves["RL/motion_ratio"], 1.0)


def test_rates_at_the_wheel_at_design_are_the_vehicle_files(fs_car, macpherson_car):
    """Wheel rate = spring + parasitic rate at design (the spring on its mount line, preloaded). The wheel load at
    design is the closed-form static load on a linkage (its preload), the settled car's on a vertical corner (whose
    design is its static ride height; the mixed car settles nose up, its vertical rear springs unloaded in the
    template)."""
    for vehicle, _ in (fs_car, macpherson_car):
        result = run_kc(vehicle, "travel", half_range=0.02, steps=5)
        closed_form = static_loads(vehicle).tyre_force
        settled = settle(build_model(vehicle, rate=1000.0)).tyre_force
        for i, corner in enumerate(vehicle.corners):
            axle = vehicle.axle(corner)
            load = closed_form[i] if axle.kinematics is not None else settled[i]
            assert result.curves[f"{corner}/wheel_rate"][2] == pytest.approx(axle.suspension_rate, rel=1e-3)
            assert result.curves[f"{corner}/wheel_load"][2] == pytest.approx(load, rel=1e-3)
        assert np.ptp(result.curves["FL/motion_ratio"]) > 0.005 if vehicle.name == "fs_car" else True


def test_static_ride_height_is_the_design_position(fs_car):
    """The spring preload carries the closed-form static load: the settled car's linkage sits at its design."""
    vehicle, _ = fs_car
    rig = build_model(vehicle, rate=1000.0)
    static = settle(rig)
    design = np.full(4, BODY_SITE_HEIGHT)  # the body site above the design wheel centre
    assert np.max(np.abs(static.suspension_length - design)) < 2e-5
    assert static.tyre_force == pytest.approx(static_loads(vehicle).tyre_force, rel=2e-4)


def test_kc_record_round_trip(fs_car, tmp_path):
    vehicle, _ = fs_car
    result = run_kc(vehicle, "roll", steps=5)
    write_kc_csv(tmp_path / "kc.csv", result)
    back = read_kc_csv(tmp_path / "kc.csv")
    assert back.test == "roll" and back.sweep == pytest.approx(result.sweep)
    assert back.curves["FL/camber"] == pytest.approx(result.curves["FL/camber"], abs=1e-9)
    # roll: the left wheels rebound as the right ones bump
    assert result.curves["FL/travel"][-1] < 0 < result.curves["FR/travel"][-1]


def test_vehicle_file_with_kinematics_round_trips(fs_car, tmp_path):
    vehicle, _ = fs_car
    path = tmp_path / "fs.toml"
    path.write_text(vehicle_to_toml(vehicle))
    again = load_vehicle(path)
    assert again.front.kinematics == vehicle.front.kinematics and again.rear.kinematics == vehicle.rear.kinematics


def _with(table: dict, axle: str, **points) -> dict:
    changed = {**table, axle: {**table[axle], "kinematics": {**table[axle]["kinematics"], **points}}}
    return changed


@pytest.mark.parametrize("axle, points, message", [
    ("front", {"upper_outer": [0.0, 0.480, 0.120]}, r"link lower_outer - upper_outer has zero length"),
    ("front", {"tie_rod_outer": [0.070, 0.215, 0.135]}, r"link tie_rod_inner - tie_rod_outer has zero length"),
    ("front", {"lower_outer": [0.000, 0.185, 0.1025]}, r"lower_outer lies on the axis lower_front - lower_rear"),
    ("rear", {"wheel_centre": [0.0, 0.60, 0.251]}, r"wheel_centre y = 0.6 m is not half the track"),
    # the upper ball joint on the line of the lower arm's pivots: the upright can turn about it, the loop locks
    ("front", {"upper_front": [0.160, 0.185, 0.105], "upper_rear": [-0.160, 0.185, 0.100],
               "upper_outer": [0.0, 0.48 + 0.3 * 0.295, 0.12 + 0.3 * 0.0175]}, r"loop does not close around design"),
])
def test_bad_hardpoints_are_refused_naming_the_point(fs_car, axle, points, message):
    _, table = fs_car
    with pytest.raises(VehicleError, match=message):
        vehicle_from_dict(_with(table, axle, **points))


def test_a_rack_travel_beyond_reach_is_refused_naming_the_tie_rod(fs_car):
    vehicle, _ = fs_car
    with pytest.raises(KcError, match=r"steer sweep to \+-0.08.*tie_rod_outer cannot reach"):
        run_kc(vehicle, "steer", half_range=0.08, steps=5, rig=KcRig(vehicle))


def _bushed_parallel_arms(rate_y: float):
    """The parallel-arm fs_car (tests/test_kinematics_dynamics.py), springs at the wheel, arms on bushings compliant
    sideways only (``rate_y``; 10 x stiffer along x and z)."""
    vehicle = parallel_arm_car()
    for axle in ("front", "rear"):
        kinematics = getattr(vehicle, axle).kinematics
        points = {k: v for k, v in kinematics.points.items() if not k.startswith(("spring_", "pushrod_", "rocker_"))}
        kinematics = dataclasses.replace(kinematics, points=points, bushing_rate=(10 * rate_y, rate_y, 10 * rate_y),
                                         bushing_damping=(200.0, 200.0, 200.0))
        vehicle = dataclasses.replace(vehicle, **{axle: dataclasses.replace(getattr(vehicle, axle),
                                                                            kinematics=kinematics)})
    return vehicle


def test_compliance_camber_of_bushed_arms_follows_front_view_statics():
    """A side force F at the contact patch, arms at h = 0.12 and 0.32 m above it: the upper arm takes 0.6 F, the
    lower 1.6 F, their bushings (rate k) yield by as much over k, and the upright turns by 2.2 F / (0.2 k): camber
    -11 / k rad per N (-0.630 deg/kN at k = 1 MN/m). rig kc: within 3 % on both axles at zero force."""
    rate = 1e6
    result = run_kc(_bushed_parallel_arms(rate), "lateral", steps=5)
    expected = -11.0 / rate
    for corner in ("FL", "RL"):
        assert result.curves[f"{corner}/compliance_camber"][2] == pytest.approx(expected, rel=0.03)
    assert result.curves["FR/compliance_camber"][2] == pytest.approx(-expected, rel=0.03)  # mirrored


def test_an_anti_roll_bar_on_linkage_corners_stiffens_roll_at_the_wheel():
    """The bar on the lower arms' pivots: in the roll test each wheel's load changes by 2 x its rate more per m of
    travel than without it (left and right travel opposite), as on the vertical twin."""
    from rig.causes.anti_roll_bar import CAUSE as BAR
    from rig.causes.anti_roll_bar import AntiRollBar
    from rig.vehicle.vertical_equivalent import vertical_equivalent

    vehicle = load_vehicle("fs_car")
    for car in (vehicle, vertical_equivalent(vehicle).vehicle):
        slopes = []
        for variant in (car, BAR.on_every_axle(car, lambda axle: AntiRollBar(20000.0))):
            result = run_kc(variant, "roll", half_range=np.radians(0.5), steps=5)
            slopes.append(np.polyfit(result.curves["FL/travel"], result.curves["FL/wheel_load"], 1)[0])
        assert slopes[1] - slopes[0] == pytest.approx(2 * 20000.0, rel=0.01)


def _constructed_roll_centre(table: dict, travel: float, current: bool, step: float = 1e-5) -> float:
    """The roll centre's height (m, above the contact patches) from the independent solver: in the front view, the
    lines through the left and right wheels' contact patches perpendicular to the patch's motion with parallel
    travel meet there. ``current``: the patch where it is at ``travel`` (the construction of the textbooks);
    else the material point of the wheel that was the patch at design."""
    corner = ReferenceCorner(table, 1)
    radius = table["wheel_centre"][2]

    def pose(at: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        corner.solve(at)
        return corner._upright(corner.x)

    def patch(at: float) -> np.ndarray:
        turn, _, _ = pose(at)
        normal = turn @ corner.normal0
        down = np.array([0.0, 0.0, -1.0]) + normal[2] * normal
        return corner.moved("wheel_centre", corner.x) + radius * down / np.linalg.norm(down)

    where = travel if current else 0.0
    point = patch(where)
    turn, reference, position = pose(where)
    local = reference + turn.T @ (point - position)  # the wheel's material point at the patch
    moved = []
    for at in (travel - step, travel + step):
        turn, reference, position = pose(at)
        moved.append(position + turn @ (local - reference))
    centre = patch(travel)
    velocity = (moved[1] - moved[0]) / (2 * step)
    # the line through the patch perpendicular to (v_y, v_z) meets the centre line (y = 0), left and right mirrored
    return float(centre[1] * velocity[1] / velocity[2])


def test_roll_centre_goes_through_the_current_contact_patch():
    """fs_car's front with the rack's tie-rod ends 7.5 mm higher: 2.7 deg of bump steer over +-60 mm. rig kc's roll
    centre against the independent construction through the current contact patch: within 1e-6 m (measured 9e-8 m)
    over the travel; the construction through the design contact point (rig kc's before) is 0.07 and 0.13 mm off
    at +60 and -60 mm."""
    table = tomllib.loads(resolve_vehicle_path("fs_car").read_text())
    table["front"]["kinematics"]["tie_rod_inner"] = [0.070, 0.215, 0.1425]
    vehicle = vehicle_from_dict(table)
    result = run_kc(vehicle, "travel", steps=5)
    assert np.ptp(np.degrees(result.curves["FL/toe"])) > 2.5
    kinematics = table["front"]["kinematics"]
    for k, travel in enumerate(result.curves["FL/travel"]):
        current = _constructed_roll_centre(kinematics, travel, current=True)
        assert result.curves["front/roll_centre_height"][k] == pytest.approx(current, abs=1e-6)
    for travel in (-0.06, 0.06):
        design = _constructed_roll_centre(kinematics, travel, current=False)
        assert abs(design - _constructed_roll_centre(kinematics, travel, current=True)) > 5e-5
