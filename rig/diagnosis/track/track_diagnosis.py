"""Diagnosis of a track test: a car driven on the road, its accelerations, travel and wheel angles measured.

The road under the tyres is usually unknown, so the model cannot be asked to reproduce the record. It is judged
on what does not need the road:
- **order content**: what is locked to each wheel's measured angle, identified as that wheel's unbalance
  (rig/diagnosis/track/unbalance.py, the transputer paper); the verdict names ``wheel_unbalance`` (the most significant
  wheel,
  its ``corner``, ``unbalance_kgm`` and ``angle_deg``) or ``none``;
- **transmissibility** between channels: per corner, the body's acceleration over the wheel's (H1, 0.5-20 Hz),
  measured against the model's on a random road at the record's speed (left and right tracks independent): a
  check of the model, reported, not a verdict.
With a ``road`` channel at every corner, the record is also a rig test on ideal posts (the road moved the
tyres as posts would), and the rig-style diagnosis (rig/diagnosis/rig_test/diagnose.py) runs on it with the
model carrying the identified unbalance, its wheels turned by their measured angles; its verdict joins the
unbalance's (``wheel_unbalance+damper_asymmetry``, or ``wheel_unbalance+unexplained`` when the rest is wrong
beyond the noise and no cause explains it).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from rig.causes import causes_seen_on, with_extension
from rig.causes.wheel_unbalance import CAUSE as UNBALANCE
from rig.causes.wheel_unbalance import WheelUnbalance
from rig.diagnosis.rig_test.diagnose import Diagnosis, diagnose, split_holdout
from rig.diagnosis.core.integrity import Finding, integrity_findings, refuse_errors
from rig.diagnosis.rig_test.diagnosis_results import Verdict
from rig.diagnosis.track.unbalance import (
    UnbalanceIdentification,
    identify_unbalance,
    record_speed,
    remove_orders,
    unbalance_frf,
    wheel_speeds,
)
from rig.io.channels import channel
from rig.io.record import Record
from rig.road.roads import iso8608_road
from rig.sim.cores import one_blas_thread
from rig.signal.frf import estimate_frf, spectral_matrices
from rig.sim.track import track_run
from rig.vehicle.vehicle_file import Vehicle

TRANSMISSIBILITY_BAND = (0.5, 20.0)  # Hz: body over wheel acceleration, where the road drives both well
TRANSMISSIBILITY_SEGMENT = 4.0      # s: Welch segments of the transmissibility estimates


@dataclass
class Transmissibility:
    """Per corner, the body's acceleration over the wheel's: measured and the model's, and how far apart."""

    frequency: np.ndarray
    measured: dict[str, np.ndarray]   # complex H1 per corner
    model: dict[str, np.ndarray]
    coherence: dict[str, np.ndarray]  # measured coherence per corner
    error: dict[str, float]           # coherence-weighted RMS of the log magnitude ratio, as a relative figure

    def to_json(self) -> dict:
        return {"band_hz": list(TRANSMISSIBILITY_BAND), "error": self.error}


@dataclass
class OrderCurve:
    """The named wheel's order response as the model predicts it with the identified unbalance, over speeds."""

    corner: str
    speed: np.ndarray        # m/s
    frequency: np.ndarray    # Hz, the wheel's order
    amplitude: np.ndarray    # speeds x channels
    channels: list[str]


@dataclass
class TrackDiagnosis:
    """What ``diagnose_track`` found; ``to_json`` is diagnosis.json."""

    verdict: Verdict
    unbalance: UnbalanceIdentification
    transmissibility: Transmissibility | None
    extended_vehicle: Vehicle
    data_sheet: Vehicle
    findings: list[Finding]
    road: Diagnosis | None = None  # the rig-style diagnosis, when the record carries the road
    curve: OrderCurve | None = None  # the named wheel's predicted order response over speeds

    def causes(self) -> list[dict]:
        """Every wheel's unbalance, the named one first, then the rig-style diagnosis's candidates."""
        named = self.unbalance.named
        wheels = sorted(self.unbalance.wheels.values(), key=lambda w: (w is not named, -w.t2))
        listed = [{"effect": UNBALANCE.name, "subsystem": "car",
                   "params": {"corner": w.corner, "unbalance_kgm": w.unbalance_kgm, "angle_deg": w.angle_deg},
                   "std": {"unbalance_kgm": w.std_kgm, "angle_deg": w.std_deg}, "t2": w.t2, "threshold": w.threshold,
                   "significant": w.significant} for w in wheels]
        return listed + ([c.summary() for c in self.road.causes] if self.road is not None else [])

    def to_json(self) -> dict:
        document = {"verdict": str(self.verdict), "test": "track", "causes": self.causes(),
                    "unbalance": self.unbalance.to_json(), "integrity": [vars(f) for f in self.findings]}
        if self.transmissibility is not None:
            document["transmissibility"] = self.transmissibility.to_json()
        if self.road is not None:
            document["road_diagnosis"] = self.road.to_json()
        return document


@one_blas_thread
def diagnose_track(vehicle: Vehicle, measured: Record | Sequence[Record], holdout: Record | None = None,
                   progress: Callable[[str], None] | None = None) -> TrackDiagnosis:
    """Diagnose ``vehicle`` on track records (see the module docstring): ``measured`` (one record per constant
    speed), judged on ``holdout`` (default: the last third of a single measured record). BLAS runs on one thread
    meanwhile (rig/sim/cores.py)."""
    progress = progress or (lambda step: None)
    measured = [measured] if isinstance(measured, Record) else list(measured)
    findings = [f for record in measured + ([holdout] if holdout is not None else [])
                for f in integrity_findings(record)]
    refuse_errors(findings)
    if holdout is None and len(measured) == 1:
        fit, holdout = split_holdout(measured[0])
        measured = [fit]
    progress("order analysis and unbalance")
    unbalance = identify_unbalance(vehicle, measured, holdout)
    progress("transmissibility")
    transmissibility = measure_transmissibility(remove_orders(measured[0], unbalance, vehicle), vehicle)
    named = unbalance.named
    identified = vehicle if named is None else with_extension(
        vehicle, UNBALANCE.name, WheelUnbalance(named.corner, named.unbalance_kgm, named.angle_deg))
    road = None
    if all(r.corners_with("road") == list(vehicle.corners) for r in measured + ([holdout] if holdout else [])):
        # the model with the identified unbalance, its wheels turned as they were measured to turn
        progress("rig-style diagnosis on the road as ideal posts")
        road = diagnose(identified, as_rig_test(measured[0]), as_rig_test(holdout) if holdout is not None else None,
                        causes=causes_seen_on("rig"), progress=progress)
    verdicts = ([UNBALANCE.name] if named else []) + (list(road.verdict) if road and road.verdict != "none" else [])
    extended = road.extended_vehicle if road is not None and road.named else identified
    curve = order_curve(vehicle, unbalance, measured[0].rate) if named else None
    return TrackDiagnosis(Verdict(verdicts), unbalance, transmissibility, extended, vehicle, findings, road,
                          curve)


def order_curve(vehicle: Vehicle, unbalance: UnbalanceIdentification, rate: float, points: int = 25) -> OrderCurve:
    """The named wheel's order amplitude per channel over speeds about those recorded (the model's FRF times the
    identified unbalance); the wheel's rolling radius from a record's speed, else the tyre's."""
    named = unbalance.named
    records = unbalance.records + ([unbalance.holdout] if unbalance.holdout is not None else [])
    radii = [r.speed / r.omega[r.corners.index(named.corner)] for r in records if r.speed]
    radius = float(np.mean(radii)) if radii else vehicle.wheel_radius
    omega = np.array([r.omega[r.corners.index(named.corner)] for r in records])
    grid = np.linspace(0.7 * omega.min(), 1.3 * omega.max(), points)
    channels = unbalance.records[0].channels
    frf = unbalance_frf(vehicle, named.corner, grid, rate, channels)
    u = unbalance.unbalance[unbalance.corners.index(named.corner)]
    return OrderCurve(named.corner, grid * radius, grid / (2 * np.pi), np.abs(frf * u), channels)


def as_rig_test(record: Record) -> Record:
    """A track record as a rig test on ideal posts: the road under each tyre as the posts' displacement (the wheel
    angles stay: the model's turning wheels follow them)."""
    channels = {}
    for name, values in record.channels.items():
        corner, _, quantity = name.partition("/")
        if quantity == "road":
            channels[channel(corner, "actuator_disp")] = values - values[0]
        else:
            channels[name] = values
    return Record(record.rate, channels, metadata={**record.metadata, "test": "rig"}, start_time=record.start_time)


def measure_transmissibility(record: Record, vehicle: Vehicle, seed: int = 0) -> Transmissibility | None:
    """Body over wheel acceleration per corner, measured and simulated on a random road at the record's speed;
    None when the record has no corner with both accelerations."""
    corners = [c for c in vehicle.corners
               if channel(c, "sprung_acc") in record and channel(c, "unsprung_acc") in record]
    if not corners:
        return None
    speed = record_speed(record)
    angled = [c for c in vehicle.corners if channel(c, "wheel_angle") in record]
    radii = None
    if angled:
        omega = dict(zip(angled, wheel_speeds(record, angled)))
        if speed is None:
            speed = float(np.mean(list(omega.values()))) * vehicle.wheel_radius
        radii = {c: speed / omega.get(c, speed / vehicle.wheel_radius) for c in vehicle.corners}
    if speed is None:
        return None
    duration = min(record.duration, 60.0)
    road = iso8608_road("B", speed * duration + 10.0, seed=seed)
    model = track_run(vehicle, road, speed, duration, record.rate, rolling_radius=radii).record
    segment = int(TRANSMISSIBILITY_SEGMENT * record.rate)
    out = {}
    for label, source in (("measured", record), ("model", model)):
        settled = slice(int(record.rate), None)  # the test's start
        estimates = {}
        for c in corners:
            wheel = source[channel(c, "unsprung_acc")][settled, None]
            body = source[channel(c, "sprung_acc")][settled, None]
            estimates[c] = estimate_frf(spectral_matrices(wheel, body, record.rate, segment))
        out[label] = estimates
    frequency = out["measured"][corners[0]].frequency
    band = (frequency >= TRANSMISSIBILITY_BAND[0]) & (frequency <= TRANSMISSIBILITY_BAND[1])
    measured, simulated, coherence, error = {}, {}, {}, {}
    for c in corners:
        h_measured, h_model = out["measured"][c].h1[band, 0, 0], out["model"][c].h1[band, 0, 0]
        weight = out["measured"][c].coherence[band, 0] * out["model"][c].coherence[band, 0]
        ratio = np.log(np.abs(h_measured) / np.maximum(np.abs(h_model), 1e-30))
        error[c] = float(np.expm1(np.sqrt(np.sum(weight * ratio**2) / max(np.sum(weight), 1e-30))))
        measured[c], simulated[c], coherence[c] = h_measured, h_model, out["measured"][c].coherence[band, 0]
    return Transmissibility(frequency[band], measured, simulated, coherence, error)
