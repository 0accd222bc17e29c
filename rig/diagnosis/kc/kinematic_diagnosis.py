"""Diagnosis on K&C records: does the car's linkage have its hardpoints where its tables put them, and its bushings
the rates its file gives?

Kinematic records (travel, roll, steer) decide the hardpoints:
1. candidates: every coordinate of the points that locate the upright (ball joints, tie-rod ends; a strut's top
   and axis) on each linkage axle the records measure;
2. the data decide what they can identify: QR with column pivoting of the curves' Jacobian at the table (per mm
   of each coordinate) keeps the coordinates that move the curves independently, strongest first, down to
   SCREEN_TOLERANCE of the strongest (the rest move the curves only as the kept ones do, or not at all);
3. those are fitted by Levenberg-Marquardt (rig/diagnosis/kc/hardpoint_fit.py), both corners of an axle alike, and again
   each corner its own (each corner's candidates screened on its own curves); the corners' own fit is kept when it
   gains significantly over the axle's (F test at P_VALUE, residuals weighted by the scatter that fit leaves): the
   records show a left-right difference;
4. the coordinates the curves cannot separate from a moved one are named beside it, with the test that would
   separate them (rig/diagnosis/kc/kc_aliases.py);
5. ``hardpoint_error`` when the fit's gain over the table is significant (F test) and a coordinate moved beyond its
   interval at the same level (P_VALUE, two-sided) and MIN_OFFSET.
Compliance records (lateral, longitudinal, aligning) decide the bushings, on the car with the fitted hardpoints:
the rates its bushing tables give are screened alike (their logarithms), fitted (rig/diagnosis/kc/bushing_fit.py),
and ``bushing_compliance`` is named when the gain is significant and a rate moved beyond its interval at the
verdict's level, by more than MIN_FACTOR, on an axle whose own curves gain significantly (an axle measured as its
file says keeps its rates: with a dozen rates fitted, noise alone moves one beyond 3 sigma now and then). The
verdict names the causes found (joined by '+'), or ``none``. The extended vehicle carries them as the causes'
sections (``[hardpoint_error.front]`` or ``[hardpoint_error.FL]``, ``[bushing_compliance.front.<joint>]``).
Residuals are given per record, corner and curve, before and after.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.linalg import qr
from scipy.stats import f as f_distribution
from scipy.stats import norm

from rig.causes import with_extension
from rig.causes.bushing_compliance import CAUSE as BUSHING_COMPLIANCE
from rig.causes.hardpoint_error import CAUSE as HARDPOINT_ERROR
from rig.diagnosis.kc import bushing_fit
from rig.diagnosis.kc.hardpoint_fit import (
    COORDINATE_UNIT,
    KINEMATIC_TESTS,
    CurveModel,
    FreeCoordinate,
    HardpointFit,
    fit_hardpoints,
    moved_kinematics,
)
from rig.diagnosis.kc.kc_aliases import Alias, find_aliases
from rig.io.kc_record import KcResult
from rig.vehicle.suspensions.linkage import corner_axle
from rig.vehicle.vehicle_file import Vehicle

CANDIDATE_POINTS = ("lower_outer", "upper_outer", "strut_top", "strut_lower", "tie_rod_outer", "tie_rod_inner")
SCREEN_TOLERANCE = 1e-2  # relative |R_kk| of the pivoted QR below which a coordinate is left to the others
P_VALUE = 1e-3
MIN_OFFSET = 5e-4        # m
MIN_FACTOR = 1.1         # a rate off its file's by less than 10 % is not named
LOG_STEP = 0.05          # the rates' screening Jacobian: a 5 % change


@dataclass(frozen=True)
class Significance:
    """An F test of a fit's gain: statistic, p value, degrees of freedom (numerator, denominator)."""

    f_statistic: float
    p_value: float
    freedom: tuple[int, int]

    @classmethod
    def of(cls, before: float, after: float, extra: int, residuals: int) -> Significance:
        denominator = max(residuals, 1)
        statistic = ((before - after) / max(extra, 1)) / max(after / denominator, 1e-300)
        return cls(float(statistic), float(f_distribution.sf(statistic, max(extra, 1), denominator)),
                   (extra, denominator))


@dataclass(frozen=True)
class HardpointFinding:
    """The hardpoints the kinematic records show: the fit (axle-wide or per corner), what it left to the fitted
    coordinates, the moved ones and their aliases, and the F tests (against the table; per corner against the
    axle-wide fit)."""

    fit: HardpointFit
    per_corner: bool
    screened_out: list[str]
    moved: list[str]
    aliases: list[Alias]
    significance: Significance
    left_right: Significance | None

    @property
    def found(self) -> bool:
        return self.significance.p_value < P_VALUE and bool(self.moved)


@dataclass(frozen=True)
class BushingFinding:
    """The bushing rates the compliance records show: the fit, what it left out, the moved rates, the F test."""

    fit: bushing_fit.BushingFit
    screened_out: list[str]
    moved: list[str]
    significance: Significance

    @property
    def found(self) -> bool:
        return self.significance.p_value < P_VALUE and bool(self.moved)


@dataclass(frozen=True)
class KcDiagnosis:
    """The verdict on K&C records, the findings behind it, the vehicle extended by them, and the model's curves
    per record before (the file's car) and after (the extended car), for the report."""

    verdict: str
    hardpoints: HardpointFinding | None
    bushings: BushingFinding | None
    extended_vehicle: Vehicle
    records: list[KcResult]
    before: list[dict[str, np.ndarray]] = field(default_factory=list)
    after: list[dict[str, np.ndarray]] = field(default_factory=list)

    def residuals(self) -> dict[str, dict[str, float]]:
        """RMS of measured minus model per '<test>/<corner>/<quantity>' (SI), before and after."""
        out = {}
        for record, before, after in zip(self.records, self.before, self.after):
            for name in before:
                measured = record.curves[name]
                out[f"{record.test}/{name}"] = {"before": _rms(measured - before[name]),
                                                "after": _rms(measured - after[name])}
        return out

    def to_json(self) -> dict:
        out: dict = {"verdict": self.verdict, "test": "kc", "residuals_per_curve": self.residuals()}
        if self.hardpoints is not None:
            out.update(_hardpoint_json(self.hardpoints))
        if self.bushings is not None:
            finding = self.bushings
            out["bushings"] = {r.name: {"nominal": float(n), "fitted": float(v), "unit": r.unit,
                                        "interval_95": [float(v / x), float(v * x)] if np.isfinite(x) else None}
                               for r, n, v, x in zip(finding.fit.free, finding.fit.nominal, finding.fit.fitted,
                                                     finding.fit.factor)}
            out["bushing_f_statistic"] = finding.significance.f_statistic
            out["bushing_p_value"] = finding.significance.p_value
            out["bushings_screened_out"] = finding.screened_out
            out["bushings_unidentifiable"] = finding.fit.unidentifiable
        return out


def _hardpoint_json(finding: HardpointFinding) -> dict:
    fit = finding.fit
    return {"f_statistic": finding.significance.f_statistic, "p_value": finding.significance.p_value,
            "per_corner": finding.per_corner,
            "left_right": None if finding.left_right is None else {
                "f_statistic": finding.left_right.f_statistic, "p_value": finding.left_right.p_value},
            "hardpoints": {c.name: {"offset_m": float(f - n), "interval_95_m": float(i) if np.isfinite(i) else None}
                           for c, n, f, i in zip(fit.free, fit.nominal, fit.fitted, fit.interval)},
            "moved": finding.moved, "aliases": [a.to_json() for a in finding.aliases],
            "screened_out": finding.screened_out, "unidentifiable": fit.unidentifiable,
            "residual_rms": fit.residual_rms}


def _rms(values: np.ndarray) -> float:
    return float(np.sqrt(np.mean(values**2)))


# ---- hardpoints ------------------------------------------------------------------------------------------------
def candidates(vehicle: Vehicle, records: list[KcResult], corner: str = "") -> list[FreeCoordinate]:
    """The candidate coordinates on the measured linkage axles (both corners alike), or ``corner``'s own."""
    axles = {corner_axle(c) for r in records for c in r.corners} if not corner else {corner_axle(corner)}
    out = []
    for axle in ("front", "rear"):
        kinematics = getattr(vehicle, axle).kinematics if getattr(vehicle, axle) is not None else None
        if axle in axles and kinematics is not None:
            out += [FreeCoordinate(axle, p, k, corner) for p in CANDIDATE_POINTS if p in kinematics.points
                    for k in range(3)]
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
    return pivoted(jacobian, free)


def pivoted(jacobian: np.ndarray, free: list) -> tuple[list, list]:
    """(kept, left out) of ``free`` by QR with column pivoting of ``jacobian``, down to SCREEN_TOLERANCE."""
    _, r, order = qr(jacobian, mode="economic", pivoting=True)
    strength = np.abs(np.diag(r))
    rank = int(np.sum(strength > SCREEN_TOLERANCE * strength[0]))
    return [free[j] for j in order[:rank]], [free[j] for j in order[rank:]]


def _weighted_sums(model: CurveModel, value: np.ndarray, scatter: dict[bool, float]) -> float:
    """Sum of squares of unit residuals ``value`` (the model's units) over the scatter per kind."""
    lengths = np.concatenate([np.full(model.records[k].sweep.size, q == "track_change") for k, _, q in model.columns])
    units = model.units()
    return float(np.sum((value * units / np.where(lengths, scatter[True], scatter[False])) ** 2))


def _scatter(model: CurveModel, fit: HardpointFit) -> dict[bool, float]:
    """The fit's residual scatter per kind (True: lengths, m; False: angles, rad)."""
    rms = fit.residual_rms
    angles = [v for q, v in rms.items() if q != "track_change"]
    return {True: max(rms.get("track_change", 1e-6), 1e-9), False: max(np.sqrt(np.mean(np.square(angles))), 1e-9)}


def _residual(model: CurveModel, vehicle: Vehicle, free: list[FreeCoordinate], offsets: np.ndarray) -> np.ndarray:
    return (model.predict(moved_kinematics(vehicle, free, offsets)) - model.measured()) / model.units()


def _moved(fit: HardpointFit) -> list[bool]:
    """Coordinates off the table by more than MIN_OFFSET and beyond their interval at the verdict's level (P_VALUE
    two-sided: with some 18 candidates per axle, 95 % intervals would name one that did not move in every few)."""
    offsets = fit.fitted - fit.nominal
    strict = fit.interval * norm.ppf(1 - P_VALUE / 2) / norm.ppf(0.975)
    return list(np.isfinite(fit.interval) & (np.abs(offsets) > strict) & (np.abs(offsets) > MIN_OFFSET))


def _corner_fit(vehicle: Vehicle, records: list[KcResult], corners: list[str]
                ) -> tuple[HardpointFit, list[FreeCoordinate]]:
    """Each corner's own coordinates, screened on its own curves, fitted together; and those left out."""
    kept, left_out = [], []
    for corner in corners:
        own = [r for r in (_corner_record(r, corner) for r in records) if r is not None]
        k, o = screen(vehicle, own, candidates(vehicle, own, corner))
        kept, left_out = kept + k, left_out + o
    return fit_hardpoints(vehicle, records, kept), left_out


def _corner_record(record: KcResult, corner: str) -> KcResult | None:
    curves = {n: v for n, v in record.curves.items() if n.startswith(f"{corner}/") or "/" not in n
              or n.split("/")[0] in ("front", "rear")}
    if not any(n.startswith(f"{corner}/") for n in curves):
        return None
    return KcResult(record.vehicle, record.test, record.sweep_name, record.sweep, (corner,), curves)


def diagnose_hardpoints(vehicle: Vehicle, records: list[KcResult]) -> HardpointFinding:
    """Hardpoints from kinematic records: axle-wide, or per corner where the records show a left-right difference."""
    model = CurveModel(vehicle, records)
    kept, left_out = screen(vehicle, records, candidates(vehicle, records))
    fit = fit_hardpoints(vehicle, records, kept)
    per_corner, left_right = False, None
    corners = [c for c in dict.fromkeys(c for r in records for c in r.corners) if c[0] in "FR"]
    both = [c for c in corners if (c[0] + ("R" if c.endswith("L") else "L")) in corners
            and getattr(vehicle, corner_axle(c)).kinematics is not None]
    if both:
        own, own_left_out = _corner_fit(vehicle, records, both)
        scatter = _scatter(model, own)
        axle_wide = _weighted_sums(model, _residual(model, vehicle, kept, fit.fitted - fit.nominal), scatter)
        corner_wise = _weighted_sums(model, _residual(model, vehicle, own.free, own.fitted - own.nominal), scatter)
        left_right = Significance.of(axle_wide, corner_wise, len(own.free) - len(kept),
                                     model.measured().size - len(own.free))
        if left_right.p_value < P_VALUE:
            per_corner, fit, kept, left_out = True, own, own.free, own_left_out
    scatter = _scatter(model, fit)
    before = _weighted_sums(model, _residual(model, vehicle, kept, np.zeros(len(kept))), scatter)
    after = _weighted_sums(model, _residual(model, vehicle, kept, fit.fitted - fit.nominal), scatter)
    significance = Significance.of(before, after, len(kept), model.measured().size - len(kept))
    moved = _moved(fit)
    aliases = find_aliases(vehicle, records, kept, left_out, fit.fitted - fit.nominal, moved, scatter)
    return HardpointFinding(fit, per_corner, [c.name for c in left_out], [c.name for c, m in zip(kept, moved) if m],
                            aliases, significance, left_right)


# ---- bushings --------------------------------------------------------------------------------------------------
def rate_candidates(vehicle: Vehicle, records: list[KcResult]) -> list[bushing_fit.FreeRate]:
    """Every rate the bushing tables give on the axles the compliance records measure."""
    axles = dict.fromkeys(corner_axle(c) for r in records for c in r.corners)
    out = []
    for axle in axles:
        kinematics = vehicle.axle_named(axle).kinematics
        for joint, bushing in ({} if kinematics is None else kinematics.bushings).items():
            out += [bushing_fit.FreeRate(axle, joint, rate) for rate in bushing_fit.RATES
                    if np.isfinite(getattr(bushing, rate)) and getattr(bushing, rate) > 0]
    return out


def diagnose_bushings(vehicle: Vehicle, records: list[KcResult]) -> BushingFinding | None:
    """Bushing rates from compliance records (None when the measured axles have no bushing tables)."""
    free = rate_candidates(vehicle, records)
    if not free:
        return None
    model = bushing_fit.ComplianceModel(records)
    measured, units = model.measured(), model.units()
    nominal = np.array([bushing_fit.rate_of(vehicle, r) for r in free])
    base = model.predict(vehicle)
    jacobian = np.column_stack([(model.predict(bushing_fit.with_free_rates(vehicle, free, nominal * np.exp(
        LOG_STEP * e))) - base) / (LOG_STEP * units) for e in np.eye(len(free))])
    kept, left_out = pivoted(jacobian, free)
    fit = bushing_fit.fit_bushings(vehicle, records, kept)
    lengths = model.kinds()
    scatter = np.where(lengths, max(_kind_rms(fit, True), 1e-9), max(_kind_rms(fit, False), 1e-9))
    before, after = ((base - measured) / scatter) ** 2, ((model.predict(fit.vehicle) - measured) / scatter) ** 2
    significance = Significance.of(float(before.sum()), float(after.sum()), len(kept), measured.size - len(kept))
    axles = np.concatenate([np.full(model.records[k].sweep.size, corner_axle(name.split("/")[0]))
                            for k, name in model.columns])
    gains = {axle: Significance.of(float(before[axles == axle].sum()), float(after[axles == axle].sum()),
                                   sum(r.axle == axle for r in kept), int(np.sum(axles == axle)))
             for axle in dict.fromkeys(axles)}
    strict = norm.ppf(1 - P_VALUE / 2) / norm.ppf(0.975)
    moved = [r.name for r, x, f in zip(kept, fit.fitted / fit.nominal, fit.factor)
             if np.isfinite(f) and abs(np.log(x)) > max(strict * np.log(f), np.log(MIN_FACTOR))
             and gains[r.axle].p_value < P_VALUE]
    return BushingFinding(fit, [r.name for r in left_out], moved, significance)


def _kind_rms(fit: bushing_fit.BushingFit, lengths: bool) -> float:
    values = [v for q, v in fit.residual_rms.items() if (q in ("track_change", "wheelbase_change")) == lengths]
    return float(np.sqrt(np.mean(np.square(values)))) if values else 1.0


# ---- the verdict -----------------------------------------------------------------------------------------------
def diagnose_kc(vehicle: Vehicle, records: list[KcResult]) -> KcDiagnosis:
    """Name ``hardpoint_error``, ``bushing_compliance`` (joined by '+') or ``none`` from K&C records of ``vehicle``."""
    kinematic = [r for r in records if r.test in KINEMATIC_TESTS]
    compliance = [r for r in records if r.test not in KINEMATIC_TESTS]
    hardpoints = diagnose_hardpoints(vehicle, kinematic) if kinematic else None
    extended, causes = vehicle, []
    if hardpoints is not None and hardpoints.found:
        causes.append(HARDPOINT_ERROR.name)
        extended = _with_hardpoint_error(vehicle, hardpoints)
    bushings = diagnose_bushings(extended, compliance) if compliance else None
    if bushings is not None and bushings.found:
        causes.append(BUSHING_COMPLIANCE.name)
        section = {}
        for rate, value in zip(bushings.fit.free, bushings.fit.fitted):
            if rate.name in bushings.moved:
                section.setdefault(rate.axle, {}).setdefault(rate.joint, {})[rate.rate] = float(value)
        extended = with_extension(extended, BUSHING_COMPLIANCE.name, section)
    return KcDiagnosis("+".join(causes) or "none", hardpoints, bushings, extended, kinematic + compliance,
                       *_model_curves(vehicle, extended, kinematic, compliance))


def _with_hardpoint_error(vehicle: Vehicle, finding: HardpointFinding) -> Vehicle:
    """The vehicle with the moved points' fitted offsets (all their fitted coordinates, so that a point's place is
    kept whole) as ``[hardpoint_error.<axle>]`` (left corner's table) or ``[hardpoint_error.<corner>]`` (vehicle
    axes), as rig/causes/hardpoint_error.py reads them."""
    fit = finding.fit
    moved = {(c.axle, c.corner, c.point) for c in fit.free if c.name in finding.moved}
    section = {key: dict(points) for key, points in vehicle.extensions.get(HARDPOINT_ERROR.name, {}).items()}
    for coordinate, offset in zip(fit.free, fit.fitted - fit.nominal):
        if (coordinate.axle, coordinate.corner, coordinate.point) in moved:
            key = coordinate.corner or coordinate.axle
            point = list(section.setdefault(key, {}).get(coordinate.point, (0.0, 0.0, 0.0)))
            point[coordinate.axis] += float(offset)
            section[key][coordinate.point] = tuple(point)
    return with_extension(vehicle, HARDPOINT_ERROR.name, section)


def _model_curves(vehicle: Vehicle, extended: Vehicle, kinematic: list[KcResult], compliance: list[KcResult]
                  ) -> tuple[list[dict], list[dict]]:
    """The model's curves for each record (in the records' order), of the file's car and of the extended car."""
    out = []
    for car in (vehicle, extended):
        curves = {}
        if kinematic:
            model = CurveModel(car, kinematic)
            values = model.predict(moved_kinematics(car, [], np.zeros(0)))
            for (k, corner, quantity), chunk in zip(model.columns, np.split(values, np.cumsum(
                    [kinematic[k].sweep.size for k, _, _ in model.columns])[:-1])):
                curves.setdefault(id(kinematic[k]), {})[f"{corner}/{quantity}"] = chunk
        if compliance:
            model = bushing_fit.ComplianceModel(compliance)
            for k, simulated in enumerate(model.simulate(car)):  # about the measured curves' means, as fitted
                record = compliance[k]
                curves[id(record)] = {name: simulated.curves[name] - np.mean(simulated.curves[name])
                                      + np.mean(record.curves[name]) for j, name in model.columns if j == k}
        out.append([curves.get(id(r), {}) for r in kinematic + compliance])
    return out[0], out[1]
