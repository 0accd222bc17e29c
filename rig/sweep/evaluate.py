"""One chunk of a sweep: its points run and measured, as a typed result.

Without a controller a chunk is one threaded ``mujoco.rollout`` per speed (track runs, rig/sim/track.py) or one
for the whole chunk (drive replays, rig/sim/replay.py): every point a variant model in the same batch. With a
controller each point is one episode of the suspension environment under it (a Python step per sample).

Metrics per point (worst corner, as ``rig control`` reports them): ``a_w`` (ISO 2631-1 Wk-weighted RMS body
acceleration, m/s^2), ``tyre_load_rms`` (dynamic tyre load RMS over the static load; the record's first sample
is the settled static state), ``travel_rms`` (m); ``power_w`` (W) with a controller; for drive replays also
every response channel's RMS about the static state (SI) and rainflow pseudo-damage (exponent 6,
rig/signal/metrics.py) and the number of post-limit hits (the drive is clipped at the limits and the hits
counted). With ``psd`` every response channel's Welch PSD in the analysis band is kept, for the scatter band of
a Monte-Carlo.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from rig.constants import ANALYSIS_BAND
from rig.io.channels import split_channel
from rig.io.record import Record
from rig.road.roads import RoadProfile
from rig.signal.comfort import weighted_rms
from rig.signal.psd import psd
from rig.signal.metrics import pseudo_damage
from rig.sim.replay import replay_batch
from rig.sim.track import track_runs
from rig.sweep.design import SPEED, SweepError, vehicle_at

RIDE_METRICS = ("a_w", "tyre_load_rms", "travel_rms")
#: channels a chunk measures (RMS, damage and PSD): the responses, not the inputs
PSD_QUANTITIES = ("sprung_acc", "unsprung_acc", "susp_travel", "tyre_force")
PSD_SEGMENT = 4.0  # s, Welch segment length: 0.25 Hz resolution


@dataclass(frozen=True)
class SweepCase:
    """What every point runs: the nominal vehicle file's tables and a road at a speed, or a drive to replay.

    ``controller(vehicle, road, speed, duration, rate) -> (metrics, record)`` runs one controlled episode;
    ``controller_spec`` says which (name, parameters and actuator bounds), for the resume digest.
    """

    vehicle: dict
    road: RoadProfile | None = None
    speed: float | None = None
    drive: Record | None = None
    duration: float | None = None
    rate: float = 512.0
    controller: Callable[..., tuple[dict[str, float], Record]] | None = None
    controller_spec: str = ""
    psd: bool = False
    nthread: int | None = None

    def __post_init__(self) -> None:
        if (self.road is None) == (self.drive is None):
            raise SweepError("a sweep runs either a road (with a speed) or a drive, not both")
        if self.road is not None and self.speed is None:
            raise SweepError("a road sweep needs a speed")
        if self.drive is not None and self.controller is not None:
            raise SweepError("a controller runs the car on a road; it cannot be combined with a drive")

    def fingerprint(self) -> str:
        """A digest of everything the points' results depend on: a resumed sweep must be the same case."""
        digest = hashlib.sha256(json.dumps(self.vehicle, sort_keys=True).encode())
        if self.road is not None:
            digest.update(np.stack([self.road.left, self.road.right]).tobytes() + repr(self.road.spacing).encode())
        if self.drive is not None:
            digest.update(np.stack([self.drive[n] for n in self.drive.names]).tobytes()
                          + repr((self.drive.names, self.drive.rate)).encode())
        controller = self.controller_spec or self.controller is not None
        digest.update(repr((self.speed, self.duration, self.rate, controller, self.psd)).encode())
        return digest.hexdigest()


@dataclass(frozen=True)
class ChunkResult:
    """The measured points of one chunk: ``metrics[i, j]`` is metric ``metric_names[j]`` of point ``points[i]``."""

    points: np.ndarray               # design point indices
    metric_names: tuple[str, ...]
    metrics: np.ndarray
    psd_channels: tuple[str, ...] = ()
    frequency: np.ndarray | None = None   # Hz
    psd: np.ndarray | None = None         # (points, channels, frequencies), SI^2/Hz


def evaluate_chunk(case: SweepCase, keys: tuple[str, ...], points: np.ndarray, values: np.ndarray) -> ChunkResult:
    """Run and measure the design points ``points`` (indices) with key values ``values`` (points x keys)."""
    named = [dict(zip(keys, map(float, row))) for row in values]
    vehicles = [vehicle_at(case.vehicle, p, f"sweep point {i}") for i, p in zip(points, named)]
    if case.drive is not None:
        results = replay_batch(vehicles, [case.drive] * len(vehicles), clip=True, nthread=case.nthread)
        records = [r.record for r in results]
        measured = [{**ride_metrics(r.record), **channel_metrics(r.record), "limit_hits": float(len(r.limit_hits))}
                    for r in results]
    elif case.controller is not None:
        runs = [case.controller(v, case.road, p.get(SPEED, case.speed), case.duration, case.rate)
                for v, p in zip(vehicles, named)]
        measured, records = [m for m, _ in runs], [r for _, r in runs]
    else:
        speeds = np.array([p.get(SPEED, case.speed) for p in named])
        records = [None] * len(named)
        for speed in np.unique(speeds):
            same = np.flatnonzero(speeds == speed)
            runs = track_runs([vehicles[i] for i in same], case.road, float(speed), case.duration, case.rate,
                              nthread=case.nthread)
            for i, run in zip(same, runs):
                records[i] = run.record
        measured = [ride_metrics(r) for r in records]
    names = tuple(measured[0])
    result = ChunkResult(np.asarray(points), names, np.array([[m[n] for n in names] for m in measured]))
    if not case.psd:
        return result
    channels = tuple(n for n in records[0].names if split_channel(n)[1] in PSD_QUANTITIES)
    spectra = [channel_psds(r, channels) for r in records]
    return ChunkResult(result.points, names, result.metrics, channels, spectra[0][0], np.stack([p for _, p in spectra]))


def ride_metrics(record: Record) -> dict[str, float]:
    """a_w (m/s^2), tyre_load_rms (over static) and travel_rms (m), each the worst corner's, of a run from rest."""
    a_w, tyre, travel = [], [], []
    for corner in record.corners_with("sprung_acc"):
        a_w.append(weighted_rms(record[f"{corner}/sprung_acc"], record.rate))
        force = record[f"{corner}/tyre_force"]
        tyre.append(np.sqrt(np.mean(((force - force[0]) / force[0]) ** 2)))
        travel.append(np.sqrt(np.mean(record[f"{corner}/susp_travel"] ** 2)))
    return {"a_w": max(a_w), "tyre_load_rms": float(max(tyre)), "travel_rms": float(max(travel))}


def channel_metrics(record: Record) -> dict[str, float]:
    """Every response channel's RMS about the static state (its first sample; SI: the tyre force's dynamic part)
    and rainflow pseudo-damage, as ``<channel> rms`` / ``<channel> damage``."""
    out = {}
    for name in record.names:
        if split_channel(name)[1] in PSD_QUANTITIES:
            out[f"{name} rms"] = float(np.sqrt(np.mean((record[name] - record[name][0]) ** 2)))
            out[f"{name} damage"] = pseudo_damage(record[name])
    return out


def channel_psds(record: Record, channels: tuple[str, ...]) -> tuple[np.ndarray, np.ndarray]:
    """Frequencies (Hz, in the analysis band) and Welch PSDs (channels x frequencies) of ``record``'s channels."""
    if record.duration < PSD_SEGMENT:
        raise SweepError(f"PSD scatter bands need runs of at least {PSD_SEGMENT:g} s; this one lasts "
                         f"{record.duration:.2f} s (use a longer road or duration)")
    frequency, spectra = psd(np.stack([record[c] for c in channels]), record.rate, 1.0 / PSD_SEGMENT, axis=-1)
    inside = (frequency >= ANALYSIS_BAND[0]) & (frequency <= ANALYSIS_BAND[1])
    return frequency[inside], spectra[:, inside]
