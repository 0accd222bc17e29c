"""Which hardpoint coordinates K&C curves cannot tell apart, and which test would.

A fitted coordinate's move changes the curves by J_a d_a (J: the curves' Jacobian per mm, weighted by the scatter
the fit leaves, so that a squared norm is a chi-square). Another candidate b is its alias when moving b instead, with
the other fitted coordinates free to follow, leaves curves that differ from the fit by less than the scatter: the
least-squares fit of J_K d_K by [J_(K without a), J_b] leaves dchi2 < ALIAS_CHI2 (the 95 % point of a chi-square of
one degree of freedom). Its equivalent move is that fit's coefficient of b. The outer tie-rod joint 3 mm higher
and the inner one 2.2 mm lower, say: both tilt the tie rod alike over travel and rack.

A test that would separate them is one whose curves, added to the records at the same scatter, tell the fit from
its alias (the others again free to follow) by more than SEPARATED_CHI2: among K&C sweeps the records lack (a rack
sweep with the wheels held in bump or rebound, a roll test, a travel test with the rack held off centre), computed
by the same loop-closure model; when none does, the points must be measured directly.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rig.diagnosis.kc.hardpoint_fit import COORDINATE_UNIT, CurveModel, FreeCoordinate, moved_kinematics
from rig.io.kc_record import SWEEPS, KcResult
from rig.vehicle.suspensions.linkage import corner_side
from rig.vehicle.vehicle_file import Vehicle

ALIAS_CHI2 = 3.84      # chi-square of one degree of freedom, 95 %
SEPARATED_CHI2 = 25.0  # a test that tells them apart by 5 sigma
MAX_ALIAS = 0.05       # m: an alias needing a larger move is no explanation
JACOBIAN_STEP = 1e-2   # mm
#: tests that may separate aliases: (words, test, rack or roll half range (SI), held travel (m), held rack (m))
PROBES = (
    ("a steer test with the wheels held 40 mm in bump", "steer", 0.02, 0.04, 0.0),
    ("a steer test with the wheels held 40 mm in rebound", "steer", 0.02, -0.04, 0.0),
    ("a travel test with the rack held 20 mm off centre", "travel", 0.06, 0.0, 0.02),
    ("a roll test (+-3 deg)", "roll", np.radians(3.0), 0.0, 0.0),
    ("a travel test", "travel", 0.06, 0.0, 0.0),
    ("a steer test", "steer", 0.02, 0.0, 0.0),
)


@dataclass(frozen=True)
class Alias:
    """A candidate the curves cannot separate from a fitted coordinate: its equivalent move (m), the chi-square by
    which the curves tell them apart (below ALIAS_CHI2), and the probe test that tells them apart best (words;
    dchi2 with it added; it separates them beyond SEPARATED_CHI2)."""

    coordinate: str
    alias: str
    equivalent_m: float
    delta_chi2: float
    separating_test: str
    separating_chi2: float

    def to_json(self) -> dict:
        return {"coordinate": self.coordinate, "alias": self.alias, "equivalent_offset_m": self.equivalent_m,
                "delta_chi2": self.delta_chi2, "best_test": self.separating_test,
                "best_test_delta_chi2": self.separating_chi2, "separable_by_kc": self.separable}

    @property
    def separable(self) -> bool:
        """Whether a K&C test would separate them (its dchi2 beyond SEPARATED_CHI2)."""
        return self.separating_chi2 > SEPARATED_CHI2

    def sentence(self) -> str:
        test = (f"{self.separating_test} would (dchi2 {self.separating_chi2:.0f})" if self.separable else
                f"none of the K&C tests tried would (the best, {self.separating_test}, by dchi2 "
                f"{self.separating_chi2:.1f}): measure the points directly (a coordinate measuring arm)")
        return (f"{self.coordinate}, or as well {self.alias} {self.equivalent_m * 1e3:+.2f} mm: the curves cannot "
                f"tell them apart (dchi2 {self.delta_chi2:.2f}); {test}")


def jacobian(vehicle: Vehicle, records: list[KcResult], free: list[FreeCoordinate], offsets: np.ndarray,
             scatter: np.ndarray) -> np.ndarray:
    """The records' curves per mm of each coordinate about ``offsets`` (m), divided by ``scatter`` (per residual,
    SI), by central differences."""
    model = CurveModel(vehicle, records)

    def curves(x: np.ndarray) -> np.ndarray:
        return model.predict(moved_kinematics(vehicle, free, offsets + x * COORDINATE_UNIT))

    columns = [(curves(JACOBIAN_STEP * e) - curves(-JACOBIAN_STEP * e)) / (2 * JACOBIAN_STEP)
               for e in np.eye(len(free))]
    return np.column_stack(columns) / scatter[:, None]


def _alias_fit(weighted: np.ndarray, kept: list[int], a: int, b: int, moves: np.ndarray
               ) -> tuple[float, float]:
    """(dchi2, b's equivalent move in mm) of explaining the fitted change by b in place of a."""
    target = weighted[:, kept] @ moves
    others = [j for j in kept if j != a]
    design = weighted[:, [*others, b]]
    coefficients = np.linalg.lstsq(design, target, rcond=None)[0]
    return float(np.sum((target - design @ coefficients) ** 2)), float(coefficients[-1])


def find_aliases(vehicle: Vehicle, records: list[KcResult], kept: list[FreeCoordinate], left_out: list[FreeCoordinate],
                 offsets: np.ndarray, moved: list[bool], scatter: dict[bool, float]) -> list[Alias]:
    """For each moved coordinate of ``kept`` (fitted ``offsets``, m), the ``left_out`` candidates of its axle or
    corner that explain the curves as well, each with the probe test that would tell them apart. ``scatter``: the
    fit's residual scatter per kind (True: lengths, m; False: angles, rad)."""
    everything = kept + left_out
    full = np.concatenate([offsets, np.zeros(len(left_out))])
    weighted = jacobian(vehicle, records, everything, full, _row_scatter(vehicle, records, scatter))
    probes: dict[str, np.ndarray] = {}
    indices = list(range(len(kept)))
    out = []
    for a, coordinate in enumerate(kept):
        for b in range(len(kept), len(everything)) if moved[a] else ():
            if (everything[b].axle, everything[b].corner) != (coordinate.axle, coordinate.corner):
                continue
            chi2, equivalent = _alias_fit(weighted, indices, a, b, offsets / COORDINATE_UNIT)
            if chi2 >= ALIAS_CHI2 or abs(equivalent) * COORDINATE_UNIT >= MAX_ALIAS:
                continue
            if not probes:
                probes = _probe_jacobians(vehicle, records, everything, full, scatter)
            best, best_chi2 = "", 0.0
            for words, rows in probes.items():  # the probe's curves beside the records', the others free to follow
                probe_chi2 = _alias_fit(np.vstack([weighted, rows]), indices, a, b, offsets / COORDINATE_UNIT)[0]
                if probe_chi2 > best_chi2:
                    best, best_chi2 = words, probe_chi2
            out.append(Alias(coordinate.name, everything[b].name, equivalent * COORDINATE_UNIT, chi2, best,
                             best_chi2))
    return out


def _row_scatter(vehicle: Vehicle, records: list[KcResult], scatter: dict[bool, float]) -> np.ndarray:
    """Per residual of the records' curves (CurveModel's order): the scatter of its kind."""
    model = CurveModel(vehicle, records)
    return np.concatenate([np.full(records[k].sweep.size, scatter[q == "track_change"]) for k, _, q in model.columns])


def _probe_jacobians(vehicle: Vehicle, records: list[KcResult], free: list[FreeCoordinate], offsets: np.ndarray,
                     scatter: dict[bool, float]) -> dict[str, np.ndarray]:
    """Each probe test's weighted Jacobian (its curves' rows) that the records lack."""
    out = {}
    for words, test, half_range, travel, rack in PROBES:
        if travel == 0.0 and rack == 0.0 and any(r.test == test for r in records):
            continue
        probe = [probe_record(vehicle, records[0], test, half_range, travel, rack)]
        out[words] = jacobian(vehicle, probe, free, offsets, _row_scatter(vehicle, probe, scatter))
    return out


def probe_record(vehicle: Vehicle, record_like: KcResult, test: str, half_range: float, travel: float, rack: float
                 ) -> KcResult:
    """A K&C record of a probe test with the measured records' corners and quantities (values unused): each
    wheel's travel (the sweep in a travel test, the body's roll in a roll test, else held) and the rack's."""
    sweep = np.linspace(-half_range, half_range, 9)
    curves = {"front/rack": np.full(sweep.size, rack)} if test != "steer" else {}
    for corner in record_like.corners:
        track = vehicle.track_front if corner[0] == "F" else vehicle.track_rear
        curves[f"{corner}/travel"] = {"travel": sweep + travel, "roll": -corner_side(corner) * track / 2 * np.tan(sweep)
                                      }.get(test, np.full(sweep.size, travel))
        for name in record_like.curves:
            if name.startswith(f"{corner}/") and not name.endswith("/travel"):
                curves[name] = np.zeros(sweep.size)
    return KcResult(record_like.vehicle, test, SWEEPS[test][0], sweep, record_like.corners, curves)
