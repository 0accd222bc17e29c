"""Hardpoints identified from measured K&C curves (``rig kc --fit``), as the source paper ("Validation of a Suspension
Model and its Elastic Behaviour Demonstrated at the Formula Student Race Car of the University Duisburg-Essen") fits
hardpoints to its steering and wheel-travel tests.

The model is the loop closure from the hardpoints (rig/vehicle/suspensions/geometry.py), which ``rig kc`` reproduces
within its checks; the data are K&C records (travel, roll, steer tests) with camber, toe, track change, caster and
kingpin columns. Chosen hardpoint coordinates (``--free``) are fitted by least squares: Levenberg-Marquardt (SciPy
``least_squares``) or Nelder-Mead (SciPy ``minimize``) as the paper does. Residuals are weighted per quantity by the
scatter the fit leaves (angles and lengths apart), so that each coordinate gets a 95 % confidence interval from the
Jacobian, 1.96 sqrt(diag (J^T W J)^-1). The Jacobian's singular values say what the data cannot identify: a
direction whose singular value is below RANK_TOLERANCE of the largest moves the curves by nothing measurable (two
pivots sliding along their own axis, say), and coordinates whose interval exceeds IDENTIFIABLE_LIMIT are named too.
"""

from __future__ import annotations

import dataclasses
import json
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import least_squares, minimize

from rig.causes import with_extension
from rig.causes.hardpoint_error import CAUSE as HARDPOINT_ERROR
from rig.io.kc_record import KcResult
from rig.vehicle.suspensions import kinematics_of, suspension_of
from rig.vehicle.suspensions.geometry import alignment, design_spin_axis, solve
from rig.vehicle.suspensions.hardpoints import Kinematics, KinematicsError
from rig.vehicle.suspensions.linkage import Linkage, corner_axle, corner_side
from rig.vehicle.vehicle_file import Vehicle

FIT_QUANTITIES = ("camber", "toe", "track_change", "caster", "kingpin")
KINEMATIC_TESTS = ("travel", "roll", "steer")
ANGLE_UNIT = np.radians(0.01)  # rad: an angle residual's unit before weighting by the fit's own scatter
LENGTH_UNIT = 5e-5             # m: a length residual's unit
COORDINATE_UNIT = 1e-3         # m: the fitted coordinates' unit (offsets from the table, mm)
RANK_TOLERANCE = 1e-6          # relative singular value below which a direction is not identifiable
IDENTIFIABLE_LIMIT = 5e-3      # m: a 95 % interval wider than this leaves the coordinate unidentified
FAILED = 1e6                   # residual of a candidate whose loop does not close
AXES = "xyz"


@dataclass(frozen=True)
class FreeCoordinate:
    """One fitted coordinate: ``axle``.``point``.x|y|z of the left corner's table (both corners alike), or with
    ``corner`` that corner's point alone, in vehicle axes (``FR.tie_rod_outer.z``)."""

    axle: str
    point: str
    axis: int
    corner: str = ""

    @property
    def name(self) -> str:
        return f"{self.corner or self.axle}.{self.point}.{AXES[self.axis]}"

    def moves(self, corner: str) -> float:
        """How the coordinate moves ``corner``'s point in its axle's left-corner table (0: not at all; -1: a right
        corner's y)."""
        if corner_axle(corner) != self.axle or self.corner not in ("", corner):
            return 0.0
        return -1.0 if self.corner and self.axis == 1 and corner_side(corner) < 0 else 1.0


def parse_free(text: str, vehicle: Vehicle) -> list[FreeCoordinate]:
    """``[front.|rear.|<corner>.]point[.x|.y|.z],...`` -> coordinates; a point alone frees x, y and z. KinematicsError
    names an unknown axle, point or coordinate."""
    free: list[FreeCoordinate] = []
    for item in (t.strip() for t in text.split(",") if t.strip()):
        parts = item.split(".")
        corner = parts.pop(0) if parts[0] in vehicle.corners else ""
        axle = corner_axle(corner) if corner else parts.pop(0) if parts[0] in ("front", "rear") else \
            _default_axle(vehicle)
        kinematics = getattr(vehicle, axle).kinematics if getattr(vehicle, axle) is not None else None
        if kinematics is None:
            raise KinematicsError(f"--free {item}: the {axle} axle of {vehicle.name} has no kinematics table")
        if not parts or parts[0] not in kinematics.points:
            raise KinematicsError(f"--free {item}: no hardpoint {parts[0] if parts else ''!r} on the {axle} axle "
                                  f"(hardpoints: {', '.join(kinematics.points)})")
        axes = [AXES.index(parts[1])] if len(parts) > 1 and parts[1] in AXES else list(range(3))
        if len(parts) > 2 or (len(parts) == 2 and parts[1] not in AXES):
            raise KinematicsError(f"--free {item}: a coordinate is x, y or z")
        free += [c for c in (FreeCoordinate(axle, parts[0], a, corner) for a in axes) if c not in free]
    if not free:
        raise KinematicsError("--free names no hardpoint")
    return free


def _default_axle(vehicle: Vehicle) -> str:
    return "front" if vehicle.front.kinematics is not None else "rear"


def moved_kinematics(vehicle: Vehicle, free: list[FreeCoordinate], offsets: np.ndarray) -> dict[str, Kinematics]:
    """Each linkage corner's kinematics (as built, rig/vehicle/suspensions/) with the free coordinates moved by
    ``offsets`` (m)."""
    out = {}
    for corner in vehicle.corners:
        table = kinematics_of(vehicle, corner)
        if table is None:
            continue
        moves: dict[str, np.ndarray] = {}
        for coordinate, offset in zip(free, offsets):
            if coordinate.moves(corner):
                moves.setdefault(coordinate.point, np.zeros(3))[coordinate.axis] += coordinate.moves(corner) * offset
        out[corner] = table.moved(moves)
    return out


@dataclass
class CurveModel:
    """Predicts a set of K&C records' kinematic columns from hardpoints (warm-started from its last solution)."""

    vehicle: Vehicle
    records: list[KcResult]
    columns: list[tuple[int, str, str]] = field(default_factory=list)  # (record, corner, quantity)
    _starts: dict = field(default_factory=dict)
    _last: dict = field(default_factory=dict)  # (record, corner) -> (kinematics, alignment) of the last prediction

    def __post_init__(self):
        compliance = [r.test for r in self.records if r.test not in KINEMATIC_TESTS]
        if compliance:
            raise KinematicsError(f"hardpoints are fitted to kinematic tests ({', '.join(KINEMATIC_TESTS)}), not "
                                  f"{', '.join(compliance)} (bushing rates are fitted to those)")
        for k, record in enumerate(self.records):
            for corner in record.corners:
                if not isinstance(suspension_of(self.vehicle, corner), Linkage):
                    continue
                self.columns += [(k, corner, q) for q in FIT_QUANTITIES if f"{corner}/{q}" in record.curves]
        if not self.columns:
            raise KinematicsError("the measured records hold no kinematic curves (camber, toe, track_change, caster, "
                                  "kingpin) of a linkage corner")

    def measured(self) -> np.ndarray:
        return np.concatenate([self.records[k].curves[f"{c}/{q}"] for k, c, q in self.columns])

    def units(self) -> np.ndarray:
        return np.concatenate([np.full(self.records[k].sweep.size, LENGTH_UNIT if q == "track_change" else ANGLE_UNIT)
                               for k, _, q in self.columns])

    def predict(self, tables: dict[str, Kinematics]) -> np.ndarray:
        values = {}
        for k, corner in dict.fromkeys((k, c) for k, c, _ in self.columns):
            last = self._last.get((k, corner))
            if last is None or last[0] != tables[corner]:  # a fit moves some corners' points at a time
                last = self._last[(k, corner)] = (tables[corner], self._alignment(k, corner, tables[corner]))
            values[(k, corner)] = last[1]
        return np.concatenate([getattr(values[(k, c)], q) for k, c, q in self.columns])

    def _alignment(self, k: int, corner: str, kinematics: Kinematics):
        record, side = self.records[k], corner_side(corner)
        suspension = suspension_of(self.vehicle, corner)
        travel = record.curves.get(f"{corner}/travel", record.sweep if record.test == "travel" else 0 * record.sweep)
        rack = record.curves.get(f"{corner_axle(corner)}/rack", record.sweep if record.test == "steer"
                                 else 0 * record.sweep)
        start = self._starts.get((k, corner))
        if start is None:
            poses = suspension.solve(kinematics, travel, rack, side)
        else:
            poses = solve(kinematics, suspension.residuals, suspension.rows, travel, rack, side, start)
        self._starts[(k, corner)] = poses.coordinates
        bottom, top = suspension.kingpin
        kingpin_top = kinematics.point(top, side) if top == "strut_top" else poses.moved(_point_of(top))
        return alignment(poses.rotation @ design_spin_axis(kinematics, side), poses.moved("wheel_centre"),
                         poses.moved(_point_of(bottom)), np.broadcast_to(kingpin_top, (travel.size, 3)), side,
                         kinematics.point("wheel_centre", side))


def _point_of(site: str) -> str:
    """The hardpoint at a kingpin site of the MJCF corner."""
    return {"lower_ball": "lower_outer", "upper_ball": "upper_outer"}.get(site, site)


@dataclass(frozen=True)
class HardpointFit:
    """Fitted coordinates (m, the left corner's table), their 95 % intervals, what the data cannot identify."""

    vehicle: Vehicle              # with the fitted hardpoints in its kinematics tables
    free: list[FreeCoordinate]
    nominal: np.ndarray           # m, the table's values
    fitted: np.ndarray            # m
    interval: np.ndarray          # m, 95 % half widths (inf: not identifiable)
    singular_values: np.ndarray   # of the weighted Jacobian per mm, descending
    unidentifiable: list[str]
    residual_rms: dict[str, float]  # per quantity, SI (rad, m)
    method: str
    evaluations: int

    def to_json(self) -> str:
        return json.dumps({
            "method": self.method, "evaluations": self.evaluations,
            "hardpoints": {c.name: {"nominal_m": float(n), "fitted_m": float(f), "interval_95_m": _finite(i)}
                           for c, n, f, i in zip(self.free, self.nominal, self.fitted, self.interval)},
            "singular_values_per_mm": [float(s) for s in self.singular_values],
            "unidentifiable": self.unidentifiable,
            "residual_rms": {q: float(v) for q, v in self.residual_rms.items()}}, indent=2)

    def summary(self) -> str:
        lines = [f"hardpoints fitted by {self.method} ({self.evaluations} evaluations), mm from the table:"]
        for c, n, f, i in zip(self.free, self.nominal, self.fitted, self.interval):
            interval = f"+- {i * 1e3:.3f}" if np.isfinite(i) else "(not identifiable)"
            lines.append(f"  {c.name:28s} {n * 1e3:9.3f} -> {f * 1e3:9.3f} {interval}")
        if self.unidentifiable:
            lines.append("the data cannot identify: " + ", ".join(self.unidentifiable))
        lines.append(rms_line(self.residual_rms))
        return "\n".join(lines)


def rms_line(residual_rms: dict[str, float]) -> str:
    """'residual RMS: camber 0.0200 deg, ...': per quantity (SI) in deg or mm."""
    lengths = ("track_change", "wheelbase_change")
    return "residual RMS: " + ", ".join(f"{q} {v * (1e3 if q in lengths else 180 / np.pi):.4f} "
                                        f"{'mm' if q in lengths else 'deg'}" for q, v in residual_rms.items())


def _finite(value: float) -> float | None:
    return float(value) if np.isfinite(value) else None


def fit_hardpoints(vehicle: Vehicle, records: list[KcResult], free: list[FreeCoordinate], method: str = "lm"
                   ) -> HardpointFit:
    """Fit the ``free`` coordinates to the records' kinematic curves by ``method`` 'lm' or 'nelder-mead'."""
    if method not in ("lm", "nelder-mead"):
        raise KinematicsError(f"unknown fit method {method!r} (lm, nelder-mead)")
    model = CurveModel(vehicle, records)
    measured, units = model.measured(), model.units()
    evaluations = 0

    def residuals(x: np.ndarray) -> np.ndarray:
        nonlocal evaluations
        evaluations += 1
        try:
            return (model.predict(moved_kinematics(vehicle, free, x * COORDINATE_UNIT)) - measured) / units
        except KinematicsError:
            return np.full(measured.size, FAILED)

    if method == "lm":
        x = least_squares(residuals, np.zeros(len(free)), method="lm", diff_step=1e-4, xtol=1e-12, ftol=1e-12).x
    else:
        x = minimize(lambda p: float(np.sum(residuals(p) ** 2)), np.zeros(len(free)), method="Nelder-Mead",
                     options={"xatol": 1e-3, "fatol": 1e-6, "maxfev": 1000 * len(free),
                              "initial_simplex": np.vstack([np.zeros(len(free)), np.eye(len(free))])}).x
    value = residuals(x)
    jacobian = _jacobian(residuals, x, value)
    interval, singular, unidentifiable = _uncertainty(jacobian, value, model, free)
    quantities = np.concatenate([np.full(model.records[k].sweep.size, q) for k, _, q in model.columns])
    residual_rms = {q: float(np.sqrt(np.mean((value[quantities == q] * units[quantities == q]) ** 2)))
                    for q in dict.fromkeys(quantities)}
    nominal = np.array([vehicle_point(vehicle, c) for c in free])
    return HardpointFit(fitted_vehicle(vehicle, free, x * COORDINATE_UNIT), free, nominal,
                        nominal + x * COORDINATE_UNIT, interval, singular, unidentifiable, residual_rms,
                        "Levenberg-Marquardt" if method == "lm" else "Nelder-Mead", evaluations)


def fitted_vehicle(vehicle: Vehicle, free: list[FreeCoordinate], offsets: np.ndarray) -> Vehicle:
    """``vehicle`` with the coordinates moved: an axle's in its kinematics table, a corner's as that corner's
    ``[hardpoint_error.<corner>]`` offsets (rig/causes/hardpoint_error.py)."""
    for axle in dict.fromkeys(c.axle for c in free if not c.corner):
        moves: dict[str, np.ndarray] = {}
        for coordinate, offset in zip(free, offsets):
            if coordinate.axle == axle and not coordinate.corner:
                moves.setdefault(coordinate.point, np.zeros(3))[coordinate.axis] += offset
        current = vehicle.axle_named(axle)
        vehicle = vehicle.with_axle(axle, dataclasses.replace(current, kinematics=current.kinematics.moved(moves)))
    corners: dict[str, dict[str, list[float]]] = {}
    for coordinate, offset in zip(free, offsets):
        if coordinate.corner:
            corners.setdefault(coordinate.corner, {}).setdefault(coordinate.point, [0.0, 0.0, 0.0])[
                coordinate.axis] += float(offset)
    if not corners:
        return vehicle
    section = {**vehicle.extensions.get(HARDPOINT_ERROR.name, {})}
    for corner, points in corners.items():
        section[corner] = {**section.get(corner, {}), **{p: tuple(v) for p, v in points.items()}}
    return with_extension(vehicle, HARDPOINT_ERROR.name, section)


def vehicle_point(vehicle: Vehicle, coordinate: FreeCoordinate) -> float:
    """The coordinate's value in the vehicle file (m): its axle's table's, or its corner's point in vehicle axes."""
    kinematics = getattr(vehicle, coordinate.axle).kinematics
    side = corner_side(coordinate.corner) if coordinate.corner else 1
    return float(kinematics.point(coordinate.point, side)[coordinate.axis])


def _jacobian(residuals, x: np.ndarray, value: np.ndarray, step: float = 1e-3) -> np.ndarray:
    """Central differences of the unit residuals per unit coordinate (mm), step ``step`` mm."""
    columns = []
    for j in range(x.size):
        dx = np.zeros(x.size)
        dx[j] = step
        columns.append((residuals(x + dx) - residuals(x - dx)) / (2 * step))
    return np.column_stack(columns)


def _uncertainty(jacobian: np.ndarray, value: np.ndarray, model: CurveModel, free: list[FreeCoordinate]
                 ) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """95 % half widths (m), singular values of the weighted Jacobian, and the coordinates the data cannot
    identify. Weights: each quantity group's residual scatter left by the fit (its variance, with the degrees of
    freedom shared out)."""
    groups = np.concatenate([np.full(model.records[k].sweep.size, q == "track_change") for k, _, q in model.columns])
    freedom = max(value.size - len(free), 1) / value.size
    weights = np.empty(value.size)
    for group in (True, False):
        chosen = groups == group
        if chosen.any():
            variance = np.sum(value[chosen] ** 2) / (chosen.sum() * freedom)
            weights[chosen] = 1.0 / max(variance, 1e-12)
    weighted = jacobian * np.sqrt(weights)[:, None]
    _, singular, right = np.linalg.svd(weighted, full_matrices=False)
    keep = singular > RANK_TOLERANCE * singular[0]
    covariance = (right[keep].T / singular[keep] ** 2) @ right[keep]  # pseudo-inverse of J^T W J, per mm^2
    interval = 1.96 * np.sqrt(np.diag(covariance)) * COORDINATE_UNIT
    null = right[~keep]
    unidentifiable = [c.name for j, c in enumerate(free)
                      if (null.size and np.max(np.abs(null[:, j])) > 0.1) or interval[j] > IDENTIFIABLE_LIMIT]
    interval[[c.name in unidentifiable for c in free]] = np.inf
    return interval, singular, unidentifiable
