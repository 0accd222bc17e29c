"""A test matrix with repeats, as Forsén ran his truck (roads x speeds, five runs each): the model driven over each
road at each speed, against repeated runs of the same case, whose scatter is the accuracy it must reach
(rig/diagnosis/track/scatter.py).

The repeats are measured records given for a case (compared as given: synchronised, one rate), or seeded runs of a
vehicle that stands for the physical one (by default the model itself): each repeat drives the same road at the case's
speed scattered by ``speed_scatter`` (a normal share, clipped at two of it: a driver holds a test speed to a per cent or
two), its compared channels with white measurement noise of ``noise`` times their RMS. A seeded repeat covers the same
stretch of road as the model's run and is compared where its wheels are on the road (sampled at the rate that puts its
samples where the model's run has its own, then read on the model's time axis), as synchronising runs on an obstacle
does at one point: compared in time, a 1 % speed difference drifts a rough-road run's phase by a tenth of a second over
10 s, and the repeats' TDDI against each other reached 0.7-0.9 on truck_6x4's wheel and body accelerations, as if
unrelated (the drift of the thesis's Figure 11).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from rig.diagnosis.track.scatter import COMPARED, CaseScatter, case_scatter
from rig.io.channels import split_channel
from rig.io.record import Record
from rig.road.roads import road_from_spec
from rig.sim.track import track_run
from rig.vehicle.vehicle_file import Vehicle

SPEED_CLIP = 2.0  # a repeat's speed departs by at most this many speed_scatter


@dataclass(frozen=True)
class MatrixCase:
    """A road (spec or file: rig/road/roads.py) at a speed (m/s); ``records``: measured repeats (files), or none for
    seeded ones."""

    road: str
    speed: float
    records: tuple[str, ...] = ()

    @property
    def label(self) -> str:
        return f"{self.road} at {self.speed:g} m/s"


@dataclass
class MatrixResult:
    """The matrix's cases, each with its repeats' scatter and the model's verdict per channel, and the model's runs."""

    vehicle: str
    repeats_of: str                      # the vehicle whose seeded runs are the repeats, or 'measured records'
    cases: list[CaseScatter]
    model_runs: dict[str, Record] = field(repr=False)

    def to_json(self) -> dict:
        return {"vehicle": self.vehicle, "repeats_of": self.repeats_of, "cases": [c.to_json() for c in self.cases]}


def seeded_repeats(vehicle: Vehicle, road_spec: str, speed: float, repeats: int, duration: float, rate: float,
                   speed_scatter: float, noise: float, rng: np.random.Generator) -> list[Record]:
    """``repeats`` runs of ``vehicle`` over the stretch of road a run at ``speed`` covers in ``duration`` s, at
    scattered speeds, with measurement noise, each on the time axis of the run at ``speed`` (module docstring)."""
    road = road_from_spec(road_spec)
    speeds = speed * (1 + speed_scatter * np.clip(rng.standard_normal(repeats), -SPEED_CLIP, SPEED_CLIP))
    samples = int(round(duration * rate))
    runs = []
    for run_speed in speeds:
        # sampled where the run at ``speed`` is sampled on the road: no interpolation between samples
        run_rate = rate * run_speed / speed
        record = track_run(vehicle, road, float(run_speed), samples / run_rate, run_rate).record
        channels = {}
        for name, values in record.channels.items():
            values = values[:samples]
            if split_channel(name)[1] in COMPARED:
                values = values + noise * np.std(values) * rng.standard_normal(values.size)
            channels[name] = values
        runs.append(Record(rate, channels, metadata={**record.metadata, "repeat": f"{run_speed:.4g} m/s"}))
    return runs


def run_matrix(model: Vehicle, cases: Sequence[MatrixCase], repeats: int = 5, repeats_of: Vehicle | None = None,
               rate: float = 512.0, duration: float | None = None, speed_scatter: float = 0.01, noise: float = 0.02,
               seed: int = 0, read: Callable[[str], Record] | None = None) -> MatrixResult:
    """Each case's repeats (its measured records, read by ``read``, or ``repeats`` seeded runs of ``repeats_of``,
    default the model) and the model's run of it, compared channel by channel (rig/diagnosis/track/scatter.py)."""
    truth = repeats_of or model
    rng = np.random.default_rng(seed)
    results, runs = [], {}
    for case in cases:
        road = road_from_spec(case.road)
        if case.records:
            measured = [read(path) for path in case.records]
            case_rate = measured[0].rate
            length = min(r.duration for r in measured) if duration is None else duration
        else:
            case_rate = rate
            length = duration or road.length / (case.speed * (1 + SPEED_CLIP * speed_scatter))  # every repeat on it
            measured = seeded_repeats(truth, case.road, case.speed, repeats, length, rate, speed_scatter, noise, rng)
        runs[case.label] = track_run(model, road, case.speed, length, case_rate).record
        results.append(case_scatter(case.label, runs[case.label], measured))
    source = "measured records" if any(c.records for c in cases) else f"runs of {truth.name}"
    return MatrixResult(model.name, source, results, runs)
