"""The pushrod and rocker (rig/vehicle/suspensions/rocker.py) on fs_car's rear axle: the motion ratio of ``rig kc``
(MuJoCo) against an independent computation (the reference loop closure and the rocker's angle by SciPy's brentq,
tests/kinematics_reference.py) and against the planar closed form at design; the tables refused."""

from __future__ import annotations

import tomllib

import numpy as np
import pytest

from kinematics_reference import ReferenceCorner, rocker_spring_lengths
from rig.sim.kc import run_kc
from rig.vehicle.vehicle_file import VehicleError, load_vehicle, resolve_vehicle_path, vehicle_from_dict


@pytest.fixture(scope="module")
def rear():
    table = tomllib.loads(resolve_vehicle_path("fs_car").read_text())["rear"]["kinematics"]
    return table, run_kc(load_vehicle("fs_car"), "travel", steps=7)


def test_motion_ratio_through_pushrod_and_rocker_matches_an_independent_computation(rear):
    """Spring compression per wheel travel over +-60 mm (0.54 to 0.62: the rocker's leverage peaks near +40 mm):
    rig kc against the independent computation within 1e-4 (measured 7e-6) on both rear corners."""
    table, result = rear
    for corner, side in (("RL", 1), ("RR", -1)):
        for k, travel in enumerate(result.curves[f"{corner}/travel"]):
            lengths = rocker_spring_lengths(table, side, [travel - 1e-5, travel + 1e-5])
            assert result.curves[f"{corner}/motion_ratio"][k] == pytest.approx(-np.diff(lengths)[0] / 2e-5, abs=1e-4)
    assert np.ptp(result.curves["RL/motion_ratio"]) > 0.05  # the ratio follows the linkage


def test_motion_ratio_at_design_is_the_levers_closed_form(rear):
    """At design the pushrod's lower end moves along the rod at v_rod per m of travel (the lower arm turning at w per
    m); the rocker, turning at W about its axis a, moves the rod's upper end at W (a x r_p) . rod, which must be the
    same: W = v_rod / ((a x r_p) . rod); the spring's end on the rocker moves at W a x r_s and the spring shortens
    at its part along the spring: MR = -W (a x r_s) . s, s the unit vector from the body's end to the rocker's
    (within 1e-4)."""
    table, result = rear
    point = {k: np.array(v, float) for k, v in table.items() if isinstance(v, list)}
    reference = ReferenceCorner(table, 1)
    angles = []
    for travel in (-1e-6, 1e-6):
        reference.solve(travel)
        angles.append(reference.x[0])
    unit = lambda v: v / np.linalg.norm(v)  # noqa: E731
    turn = (angles[1] - angles[0]) / 2e-6 * unit(point["lower_rear"] - point["lower_front"])  # rad per m of travel
    rod = unit(point["pushrod_inner"] - point["pushrod_outer"])
    v_rod = np.cross(turn, point["pushrod_outer"] - point["lower_front"]) @ rod
    axis = unit(point["rocker_axis"] - point["rocker_pivot"])
    rocker = v_rod / (np.cross(axis, point["pushrod_inner"] - point["rocker_pivot"]) @ rod)
    spring = unit(point["spring_lower"] - point["spring_upper"])
    closed = -rocker * np.cross(axis, point["spring_lower"] - point["rocker_pivot"]) @ spring
    assert result.curves["RL/motion_ratio"][3] == pytest.approx(closed, abs=1e-4)


@pytest.mark.parametrize("drop, message", [
    (("rocker_axis",), r"a pushrod and rocker needs rocker_axis too"),
    (("spring_lower", "spring_upper"), r"needs spring_lower, spring_upper too"),
])
def test_an_incomplete_rocker_is_refused_naming_what_is_missing(drop, message):
    table = tomllib.loads(resolve_vehicle_path("fs_car").read_text())
    for point in drop:
        del table["rear"]["kinematics"][point]
    with pytest.raises(VehicleError, match=message):
        vehicle_from_dict(table)
