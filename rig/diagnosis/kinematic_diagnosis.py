"""Diagnosis on K&C records: does the car's linkage have its hardpoints where its tables put them?

Steps:
1. candidates: every coordinate of the points that locate the upright (ball joints, tie-rod ends; a strut's top
   and axis) on each linkage axle the records measure;
2. the data decide what they can identify: QR with column pivoting of the curves' Jacobian at the table (per mm
   of each coordinate) keeps the coordinates that move the curves independently, strongest first, down to
   SCREEN_TOLERANCE of the strongest (the rest move the curves only as the kept ones do, or not at all);
3. those are fitted by Levenberg-Marquardt (rig/diagnosis/hardpoints.py);
4. verdict: ``hardpoint_error`` when the fit's gain is significant (F test of the residual sums of squares at
   level P_VALUE) and a coordinate moved beyond its 95 % interval and MIN_OFFSET; ``none`` otherwise. The extended
   vehicle carries the fitted offsets as the cause's section (rig/causes/hardpoint_error.py).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg import qr
from scipy.stats import f as f_distribution

from rig.causes._base import with_extension
from rig.diagnosis.hardpoints import (
    COORDINATE_UNIT,
    CurveModel,
    FreeCoordinate,
    HardpointFit,
    fit_hardpoints,
    moved_kinematics,
)
from rig.io.kc_record import KcResult
from rig.vehicle.suspensions.linkage import corner_axle
from rig.vehicle.vehicle_file import Vehicle

CANDIDATE_POINTS = ("lower_outer", "upper_outer", "strut_top", "strut_lower", "tie_rod_outer", "tie_rod_inner")
SCREEN_TOLERANCE = 1e-2  # relative |R_kk| of the pivoted QR below which a coordinate is left to the others
P_VALUE = 1e-3
MIN_OFFSET = 5e-4        # m


@dataclass(frozen=True)
class KcDiagnosis:
    """The verdict on K&C records, the fit behind it and the vehicle extended by it."""

    verdict: str                 # 'hardpoint_error' or 'none'
    fit: HardpointFit
    screened_out: list[str]      # candidates the data cannot tell apart from the fitted ones
    f_statistic: float
    p_value: float
    extended_vehicle: Vehicle

    def to_json(self) -> dict:
        return {"verdict": self.verdict, "test": "kc", "f_statistic": self.f_statistic, "p_value": self.p_value,
                "hardpoints": {c.name: {"offset_m": float(f - n), "interval_95_m": float(i) if np.isfinite(i) else None}
                               for c, n, f, i in zip(self.fit.free, self.fit.nominal, self.fit.fitted,
                                                     self.fit.interval)},
                "screened_out": self.screened_out, "unidentifiable": self.fit.unidentifiable,
                "residual_rms": self.fit.residual_rms}


def candidates(vehicle: Vehicle, records: list[KcResult]) -> list[FreeCoordinate]:
    axles = {corner_axle(c) for r in records for c in r.corners}
    out = []
    for axle in ("front", "rear"):
        kinematics = getattr(vehicle, axle).kinematics if getattr(vehicle, axle) is not None else None
        if axle in axles and kinematics is not None:
            out += [FreeCoordinate(axle, p, k) for p in CANDIDATE_POINTS if p in kinematics.points for k in range(3)]
    return out


def screen(vehicle: Vehicle, records: list[KcResult], free: list[FreeCoordinate]
           ) -> tuple[list[FreeCoordinate], list[FreeCoordinate]]:
    """(kept, left out): the coordinates the curves identify independently, by pivoted QR of their Jacobian."""
    model = CurveModel(vehicle, records)
    units = model.units()

    def curves(x):
        return model.predict(moved_kinematics(vehicle, free, x * COORDINATE_UNIT)) / units

    step = 1e-2  # mm
    jacobian = np.column_stack([(curves(step * e) - curves(-step * e)) / (2 * step) for e in np.eye(len(free))])
    _, r, order = qr(jacobian, mode="economic", pivoting=True)
    strength = np.abs(np.diag(r))
    rank = int(np.sum(strength > SCREEN_TOLERANCE * strength[0]))
    return [free[j] for j in order[:rank]], [free[j] for j in order[rank:]]


def diagnose_kc(vehicle: Vehicle, records: list[KcResult]) -> KcDiagnosis:
    """Name ``hardpoint_error`` (with its offsets) or ``none`` from K&C records of ``vehicle``."""
    kept, left_out = screen(vehicle, records, candidates(vehicle, records))
    fit = fit_hardpoints(vehicle, records, kept)
    model = CurveModel(vehicle, records)
    measured, units = model.measured(), model.units()
    before = np.sum(((model.predict(moved_kinematics(vehicle, kept, np.zeros(len(kept)))) - measured) / units) ** 2)
    after = np.sum(((model.predict(moved_kinematics(vehicle, kept, fit.fitted - fit.nominal)) - measured) / units) ** 2)
    freedom = max(measured.size - len(kept), 1)
    statistic = ((before - after) / len(kept)) / (after / freedom)
    p_value = float(f_distribution.sf(statistic, len(kept), freedom))
    offsets = fit.fitted - fit.nominal
    moved = np.isfinite(fit.interval) & (np.abs(offsets) > fit.interval) & (np.abs(offsets) > MIN_OFFSET)
    verdict = "hardpoint_error" if p_value < P_VALUE and moved.any() else "none"
    extended = vehicle
    if verdict == "hardpoint_error":
        table: dict[str, dict[str, list[float]]] = {}
        for coordinate, offset in zip(kept, offsets):
            point = table.setdefault(coordinate.axle, {}).setdefault(coordinate.point, [0.0, 0.0, 0.0])
            point[coordinate.axis] = float(offset)
        extended = with_extension(vehicle, "hardpoint_error",
                                  {a: {p: tuple(v) for p, v in points.items()} for a, points in table.items()})
    return KcDiagnosis(verdict, fit, [c.name for c in left_out], float(statistic), p_value, extended)
