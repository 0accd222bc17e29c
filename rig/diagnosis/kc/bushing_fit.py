"""Bushing rates identified from measured compliance tests (``rig kc --fit ... --free
front.bushings.lower_front.radial``), as the source paper ("Validation of a Suspension Model and its Elastic
Behaviour Demonstrated at the Formula Student Race Car of the University Duisburg-Essen") fits bushing elasticities
so that a rigid-body model reproduces the measured compliance.

The model is the K&C rig itself (rig/sim/kc.py: MuJoCo statics of the car with its bushings); the data are K&C
records of compliance tests (lateral, longitudinal, aligning) with camber, toe, track change and wheelbase change
columns. Each curve is compared about its own mean (its shape under the load: the static alignment belongs to the
hardpoints and the rig's zero). The chosen rates are fitted in their logarithm (a rate is positive and known to a
factor, not a number of N/m) by SciPy's trust-region least squares within the vehicle file's plausible range.
Residuals are weighted per kind by the scatter the fit leaves (angles and lengths apart), and each rate's 95 %
interval is a factor exp(+-1.96 sigma) from the Jacobian. What the tests cannot identify is named: a rate along a
direction of the Jacobian with a singular value below RANK_TOLERANCE of the largest, or whose interval is wider than
a factor IDENTIFIABLE_FACTOR (a rate whose joint the loads hardly deflect: an axial rate under a side force).
"""

from __future__ import annotations

import dataclasses
import json
import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from rig.elements.bushing_rates import RANGES as FILE_RANGES
from rig.diagnosis.kc.hardpoint_fit import rms_line
from rig.io.kc_record import KcResult
from rig.sim.kc import COMPLIANCE_TESTS, KcRig, sweep_kc
from rig.vehicle.suspensions.bushings import RATES, joints_of, with_rates
from rig.vehicle.suspensions.hardpoints import KinematicsError
from rig.vehicle.vehicle_file import Vehicle

FIT_QUANTITIES = ("camber", "toe", "track_change", "wheelbase_change")
ANGLE_UNIT = np.radians(0.005)  # rad: an angle residual's unit before weighting by the fit's own scatter
LENGTH_UNIT = 1e-5              # m: a length residual's unit
RANK_TOLERANCE = 1e-6
IDENTIFIABLE_FACTOR = 2.0       # a 95 % interval wider than x / 2 .. 2 x leaves the rate unidentified
#: the fit's bounds: the vehicle file's ranges, a rotational rate above 1 N m/rad (its logarithm is fitted)
RANGES = {rate: (max(low, 1.0), high) for rate, (low, high) in FILE_RANGES.items()}
FAILED = 1e6                    # residual of a candidate the rig cannot solve
#: the Jacobian's step in log(rate): 2 %, so that a curve's change (~1e-4 deg) stands well above the K&C rig's
#: solver precision (~1e-6 deg); 1e-4 left the Jacobian 30 % wrong and a many-rate fit wandering
DIFF_STEP = 2e-2


@dataclass(frozen=True)
class FreeRate:
    """One fitted rate: ``axle``.bushings.``joint``.``rate``."""

    axle: str
    joint: str
    rate: str

    @property
    def name(self) -> str:
        return f"{self.axle}.bushings.{self.joint}.{self.rate}"

    @property
    def unit(self) -> str:
        return "N/m" if self.rate in ("radial", "axial") else "N m/rad"


def is_rate_name(item: str) -> bool:
    """Whether a ``--free`` name is a bushing rate (``<axle>.bushings.<joint>[.<rate>]``)."""
    return ".bushings." in item or item.startswith("bushings.")


def parse_free_rates(text: str, vehicle: Vehicle) -> list[FreeRate]:
    """``[front.|rear.]bushings.joint[.rate],...`` -> rates; a joint alone frees every rate its table gives. Each
    must have a starting value in the vehicle file (KinematicsError names what is missing)."""
    free: list[FreeRate] = []
    for item in (t.strip() for t in text.split(",") if t.strip()):
        parts = item.split(".")
        axle = parts.pop(0) if parts[0] in ("front", "rear") else "front"
        kinematics = vehicle.axle_named(axle).kinematics if axle in vehicle.axle_names else None
        if len(parts) < 2 or parts[0] != "bushings" or kinematics is None:
            raise KinematicsError(f"--free {item}: a bushing rate is <axle>.bushings.<joint>.<rate> on an axle with a "
                                  f"kinematics table")
        joint = parts[1]
        if joint not in joints_of(kinematics):
            raise KinematicsError(f"--free {item}: no joint {joint!r} on the {axle} {kinematics.type} (joints: "
                                  f"{', '.join(joints_of(kinematics))})")
        bushing = kinematics.bushings.get(joint)
        if bushing is None:
            raise KinematicsError(f"--free {item}: {joint} has no bushing in the vehicle file; give "
                                  f"[{axle}.bushings.{joint}] a rate to start from")
        rates = [parts[2]] if len(parts) > 2 else [r for r in RATES if _given(getattr(bushing, r))]
        for rate in rates:
            if rate not in RATES:
                raise KinematicsError(f"--free {item}: a bushing rate is one of {', '.join(RATES)}")
            if not _given(getattr(bushing, rate)):
                raise KinematicsError(f"--free {item}: [{axle}.bushings.{joint}] gives no {rate} rate (rigid or free "
                                      f"there); give one to start from")
            if FreeRate(axle, joint, rate) not in free:
                free.append(FreeRate(axle, joint, rate))
    if not free:
        raise KinematicsError("--free names no bushing rate")
    return free


def _given(value: float) -> bool:
    return math.isfinite(value) and value > 0


def rate_of(vehicle: Vehicle, rate: FreeRate) -> float:
    return float(getattr(vehicle.axle_named(rate.axle).kinematics.bushings[rate.joint], rate.rate))


def with_free_rates(vehicle: Vehicle, free: list[FreeRate], values: np.ndarray) -> Vehicle:
    """``vehicle`` with the free rates set to ``values`` (N/m, N m/rad)."""
    for axle in dict.fromkeys(r.axle for r in free):
        changes = {(r.joint, r.rate): v for r, v in zip(free, values) if r.axle == axle}
        current = vehicle.axle_named(axle)
        vehicle = vehicle.with_axle(axle, dataclasses.replace(current, kinematics=with_rates(current.kinematics,
                                                                                            changes)))
    return vehicle


@dataclass
class ComplianceModel:
    """Predicts compliance records' curves (about their means) from a vehicle on the K&C rig."""

    records: list[KcResult]

    def __post_init__(self):
        tests = [r.test for r in self.records if r.test not in COMPLIANCE_TESTS]
        if tests:
            raise KinematicsError(f"bushing rates are fitted to compliance tests ({', '.join(COMPLIANCE_TESTS)}), "
                                  f"not {', '.join(tests)}")
        self.columns = [(k, name) for k, record in enumerate(self.records)
                        for name in record.curves if name.split("/", 1)[1] in FIT_QUANTITIES
                        and name.split("/")[0] not in ("front", "rear")]
        if not self.columns:
            raise KinematicsError("the compliance records hold no camber, toe, track_change or wheelbase_change curve")

    def measured(self) -> np.ndarray:
        return np.concatenate([_centred(self.records[k].curves[name]) for k, name in self.columns])

    def units(self) -> np.ndarray:
        return np.concatenate([np.full(self.records[k].sweep.size, _unit(name)) for k, name in self.columns])

    def kinds(self) -> np.ndarray:
        """Per residual: True for a length, False for an angle."""
        return np.concatenate([np.full(self.records[k].sweep.size, _unit(name) == LENGTH_UNIT)
                               for k, name in self.columns])

    def simulate(self, vehicle: Vehicle) -> list[KcResult]:
        """The records' tests of ``vehicle`` on the K&C rig, at their sweep points."""
        rig = KcRig(vehicle)
        return [sweep_kc(rig, r.test, r.sweep, derivatives=False) for r in self.records]

    def predict(self, vehicle: Vehicle) -> np.ndarray:
        simulated = self.simulate(vehicle)
        return np.concatenate([_centred(simulated[k].curves[name]) for k, name in self.columns])


def _centred(values: np.ndarray) -> np.ndarray:
    return values - np.mean(values)


def _unit(name: str) -> float:
    return LENGTH_UNIT if name.endswith(("track_change", "wheelbase_change")) else ANGLE_UNIT


@dataclass(frozen=True)
class BushingFit:
    """Fitted rates (N/m, N m/rad), their 95 % intervals (factors), and what the tests cannot identify."""

    vehicle: Vehicle                  # with the fitted rates in its bushing tables
    free: list[FreeRate]
    nominal: np.ndarray
    fitted: np.ndarray
    factor: np.ndarray                # 95 % interval: fitted / factor .. fitted x factor (inf: not identifiable)
    singular_values: np.ndarray
    unidentifiable: list[str]
    residual_rms: dict[str, float]    # per quantity, SI (rad, m)
    evaluations: int

    def to_json(self) -> str:
        return json.dumps({
            "method": "trust-region least squares in log(rate)", "evaluations": self.evaluations,
            "bushings": {r.name: {"unit": r.unit, "nominal": float(n), "fitted": float(f),
                                  "interval_95": [float(f / x), float(f * x)] if np.isfinite(x) else None}
                         for r, n, f, x in zip(self.free, self.nominal, self.fitted, self.factor)},
            "singular_values": [float(s) for s in self.singular_values],
            "unidentifiable": self.unidentifiable,
            "residual_rms": self.residual_rms}, indent=2)

    def summary(self) -> str:
        lines = [f"bushing rates fitted to the compliance tests ({self.evaluations} evaluations):"]
        for r, n, f, x in zip(self.free, self.nominal, self.fitted, self.factor):
            interval = f"95 %: {f / x:.4g} .. {f * x:.4g}" if np.isfinite(x) else "(not identifiable)"
            lines.append(f"  {r.name:38s} {n:10.4g} -> {f:10.4g} {r.unit}  {interval}")
        if self.unidentifiable:
            lines.append("the tests cannot identify: " + ", ".join(self.unidentifiable))
        lines.append(rms_line(self.residual_rms))
        return "\n".join(lines)


def fit_bushings(vehicle: Vehicle, records: list[KcResult], free: list[FreeRate]) -> BushingFit:
    """Fit the ``free`` rates of ``vehicle`` to the compliance ``records``."""
    model = ComplianceModel(records)
    measured, units = model.measured(), model.units()
    nominal = np.array([rate_of(vehicle, r) for r in free])
    evaluations = 0

    def residuals(x: np.ndarray) -> np.ndarray:
        nonlocal evaluations
        evaluations += 1
        try:
            return (model.predict(with_free_rates(vehicle, free, nominal * np.exp(x))) - measured) / units
        except KinematicsError:
            return np.full(measured.size, FAILED)

    low = np.log(np.array([RANGES[r.rate][0] for r in free]) / nominal)
    high = np.log(np.array([RANGES[r.rate][1] for r in free]) / nominal)
    solution = least_squares(residuals, np.zeros(len(free)), bounds=(low, high), method="trf", diff_step=DIFF_STEP,
                             x_scale=1.0, xtol=1e-10, ftol=1e-10)
    value = solution.fun
    factor, singular, unidentifiable = _uncertainty(solution.jac, value, model.kinds(), free)
    quantities = np.concatenate([np.full(model.records[k].sweep.size, name.split("/", 1)[1])
                                 for k, name in model.columns])
    residual_rms = {q: float(np.sqrt(np.mean((value[quantities == q] * units[quantities == q]) ** 2)))
                    for q in dict.fromkeys(quantities)}
    fitted = nominal * np.exp(solution.x)
    return BushingFit(with_free_rates(vehicle, free, fitted), free, nominal, fitted, factor, singular, unidentifiable,
                      residual_rms, evaluations)


def _uncertainty(jacobian: np.ndarray, value: np.ndarray, lengths: np.ndarray, free: list[FreeRate]
                 ) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """95 % interval factors, singular values of the weighted Jacobian (per unit log rate), the rates the tests
    cannot identify. Weights: each kind's residual scatter left by the fit."""
    freedom = max(value.size - len(free), 1) / value.size
    weights = np.empty(value.size)
    for kind in (True, False):
        chosen = lengths == kind
        if chosen.any():
            weights[chosen] = 1.0 / max(np.sum(value[chosen] ** 2) / (chosen.sum() * freedom), 1e-12)
    _, singular, right = np.linalg.svd(jacobian * np.sqrt(weights)[:, None], full_matrices=False)
    keep = singular > RANK_TOLERANCE * singular[0]
    covariance = (right[keep].T / singular[keep] ** 2) @ right[keep]
    factor = np.exp(np.minimum(1.96 * np.sqrt(np.diag(covariance)), 700.0))
    null = right[~keep]
    unidentifiable = [r.name for j, r in enumerate(free)
                      if (null.size and np.max(np.abs(null[:, j])) > 0.1) or factor[j] > IDENTIFIABLE_FACTOR]
    factor[[r.name in unidentifiable for r in free]] = np.inf
    return factor, singular, unidentifiable
