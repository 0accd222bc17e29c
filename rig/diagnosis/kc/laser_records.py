"""Measured laser records read into the wishbones' and the wheel carrier's angles (``rig kc --lasers FILE``), as the
source paper ("Validation of a Suspension Model and its Elastic Behaviour Demonstrated at the Formula Student Race
Car of the University Duisburg-Essen") reads its seven lasers, optionally calibrated first on records of known
travel and rack (``--calibration CAL.csv ...``).

A laser record is a K&C record (rig/io/kc_record.py) with ``<corner>/laser_1`` .. ``laser_7`` columns (m or mm):
three on the lower wishbone's plate, four on the wheel carrier's, where the vehicle file's ``lasers = true`` puts them
(rig/vehicle/suspensions/lasers.py). The calibration records hold the same lasers' distances over sweeps the rig
sets (each corner's ``travel`` column, the rack's from a steer test's sweep or a ``<axle>/rack`` column): the
linkage's loop closure gives the wishbone's angle and the carrier's pose there, against which each laser's offset
along its beam and its two tilts are calibrated (rig/diagnosis/kc/laser_angles.py).
"""

from __future__ import annotations

import numpy as np

from rig.diagnosis.kc.laser_angles import calibrate_carrier_lasers, calibrate_lasers, carrier_pose, wishbone_angle
from rig.io.kc_record import KcResult
from rig.vehicle.suspensions import kinematics_of, suspension_of
from rig.vehicle.suspensions.geometry import arm_angle
from rig.vehicle.suspensions.hardpoints import KinematicsError
from rig.vehicle.suspensions.lasers import CARRIER_LASERS, WISHBONE_LASERS, Laser, laser_layout
from rig.vehicle.suspensions.linkage import WHEEL_HALF_WIDTH, corner_axle, corner_side
from rig.vehicle.vehicle_file import Vehicle

COUNT = WISHBONE_LASERS + CARRIER_LASERS


def distances(record: KcResult, corner: str) -> np.ndarray | None:
    """A corner's laser distances (samples x 3 or 7, m), None when the record has none of that corner."""
    columns = [f"{corner}/laser_{i}" for i in range(1, COUNT + 1)]
    present = [c for c in columns if c in record.curves]
    if not present:
        return None
    if present not in (columns[:WISHBONE_LASERS], columns):
        raise KinematicsError(f"{corner}: a laser record holds laser_1-3 (the wishbone's) or laser_1-7, got "
                              f"{', '.join(p.split('/')[1] for p in present)}")
    return np.column_stack([record.curves[c] for c in present])


def calibrated_lasers(vehicle: Vehicle, corner: str, calibration: list[KcResult]) -> list[Laser]:
    """The corner's lasers calibrated on the ``calibration`` records together: the loop closure at their travel and
    rack gives the wishbone's angle and the carrier's pose at each sample (a travel sweep alone hardly turns the
    carrier: add a steer sweep)."""
    kinematics, side = kinematics_of(vehicle, corner), corner_side(corner)
    suspension = suspension_of(vehicle, corner)
    lasers, plates = laser_layout(kinematics, side, suspension.upright_top, WHEEL_HALF_WIDTH)
    readings, travel, rack = [], [], []
    for record in calibration:
        found = distances(record, corner)
        if found is None:
            raise KinematicsError(f"the calibration record of a {record.test} test holds no lasers of {corner}")
        sweep = record.sweep
        readings.append(found)
        travel.append(record.curves.get(f"{corner}/travel", sweep if record.test == "travel" else 0.0 * sweep))
        rack.append(record.curves.get(f"{corner_axle(corner)}/rack", sweep if record.test == "steer" else 0.0 * sweep))
    if len({r.shape[1] for r in readings}) > 1:
        raise KinematicsError(f"{corner}: the calibration records hold different lasers")
    found = np.vstack(readings)
    poses = suspension.solve(kinematics, np.concatenate(travel), np.concatenate(rack), side)
    front, rear = kinematics.point("lower_front", side), kinematics.point("lower_rear", side)
    alpha = arm_angle(front, rear, kinematics.point("lower_outer", side), poses.moved("lower_outer"))
    out = calibrate_lasers(found[:, :WISHBONE_LASERS], alpha, lasers[:WISHBONE_LASERS], plates[0], kinematics, side)
    if found.shape[1] == COUNT:
        out += calibrate_carrier_lasers(found[:, WISHBONE_LASERS:], poses, lasers[WISHBONE_LASERS:], plates[1])
    return out


def read_lasers(vehicle: Vehicle, record: KcResult, calibration: list[KcResult] = ()) -> KcResult:
    """The record's laser distances as angles per corner (rad): ``wishbone_angle`` (the lower wishbone's, about
    lower_front -> lower_rear, from design), and with the carrier's four lasers on a double wishbone
    ``upper_wishbone_angle``, ``steering_angle`` (the carrier's turn about the kingpin), ``camber`` and ``toe``."""
    curves = {}
    for corner in record.corners:
        readings = distances(record, corner)
        if readings is None:
            continue
        kinematics, side = kinematics_of(vehicle, corner), corner_side(corner)
        if kinematics is None or not kinematics.lasers:
            raise KinematicsError(f"{corner}: the vehicle file's [{corner_axle(corner)}.kinematics] has no "
                                  f"lasers = true, which says where the lasers are")
        lasers, plates = laser_layout(kinematics, side, suspension_of(vehicle, corner).upright_top, WHEEL_HALF_WIDTH)
        if calibration:
            lasers = calibrated_lasers(vehicle, corner, list(calibration))
        curves[f"{corner}/wishbone_angle"] = wishbone_angle(readings[:, :WISHBONE_LASERS], lasers[:WISHBONE_LASERS],
                                                            kinematics, side)
        if readings.shape[1] == COUNT and kinematics.type == "double_wishbone":
            pose = carrier_pose(readings, lasers, plates[1], kinematics, side)
            curves.update({f"{corner}/upper_wishbone_angle": pose.beta, f"{corner}/steering_angle": pose.delta,
                           f"{corner}/camber": pose.camber, f"{corner}/toe": pose.toe})
    if not curves:
        raise KinematicsError("the record holds no laser columns (<corner>/laser_1 .. laser_7)")
    corners = tuple(dict.fromkeys(n.split("/")[0] for n in curves))
    return KcResult(record.vehicle or vehicle.name, record.test, record.sweep_name, record.sweep, corners, curves)
