"""A measured rig test prepared for simulation, the common ground of validation and diagnosis.

The car part replays the measured post displacements on ideal posts (the car then sees exactly what the
real car saw); the rig part plays the measured drives through the post servo model and compares the
achieved displacements. Both are compared in the analysis band (rig/constants.py: measurement noise and
drift outside it say nothing about the model). A record with every wheel's angle (a track test whose road was
measured) turns the wheels that can turn in the model (a wheel's unbalance) as they turned.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from rig.constants import ANALYSIS_BAND
from rig.io.channels import channel
from rig.io.record import Record, RecordError
from rig.signal.filters import band_pass
from rig.sim.replay import replay_batch
from rig.vehicle.vehicle_file import Vehicle

CAR_QUANTITIES = ("sprung_acc", "unsprung_acc", "susp_travel")


@dataclass
class Experiment:
    """A measured rig test prepared for simulation: post inputs, measured channels (band-passed)."""

    record: Record
    corners: tuple[str, ...]
    car_channels: list[str]
    measured: np.ndarray            # samples x car channels, band-passed
    posts: Record                   # measured actuator_disp channels (low-passed) for ideal-post replay
    drive: Record | None            # measured drive channels, for the rig part
    measured_posts: np.ndarray | None  # samples x corners, band-passed measured actuator_disp
    wheel_angles: np.ndarray | None = None  # samples x corners, rad: the wheels' measured angles (a track test)

    @classmethod
    def from_record(cls, record: Record, vehicle: Vehicle) -> Experiment:
        corners = vehicle.corners
        missing = [channel(c, "actuator_disp") for c in corners if channel(c, "actuator_disp") not in record]
        if missing:
            raise RecordError(f"measured record has no {', '.join(missing)}: the car part replays the measured posts")
        car_channels = [channel(c, q) for q in CAR_QUANTITIES for c in corners if channel(c, q) in record]
        if not car_channels:
            raise RecordError(f"measured record has none of {', '.join(CAR_QUANTITIES)} to compare")
        disp = record.quantity("actuator_disp", corners)
        posts = _post_inputs(disp, record.rate, corners)
        has_drive = all(channel(c, "drive") in record for c in corners)
        drive = record.select([channel(c, "drive") for c in corners]) if has_drive else None
        angles = record.quantity("wheel_angle", corners) if all(channel(c, "wheel_angle") in record for c in corners) \
            else None
        return cls(record, corners, car_channels,
                   _band(np.column_stack([record[n] for n in car_channels]), record.rate),
                   posts, drive, _band(disp, record.rate) if has_drive else None, angles)

    def with_post_noise(self, noise: np.ndarray) -> Experiment:
        """The same test with ``noise`` (samples x corners, m) added to the measured post displacements."""
        disp = self.record.quantity("actuator_disp", self.corners) + noise
        return dataclasses.replace(self, posts=_post_inputs(disp, self.record.rate, self.corners))

    @property
    def names(self) -> list[str]:
        """Compared channels: car channels, then (with drives) the achieved post displacements."""
        return self.car_channels + ([channel(c, "actuator_disp") for c in self.corners] if self.drive else [])

    def simulate_car(self, vehicles: Sequence[Vehicle]) -> list[np.ndarray]:
        """Band-passed car channels (samples x car channels) of each vehicle on the measured posts."""
        angles = None if self.wheel_angles is None else np.repeat(self.wheel_angles[None], len(vehicles), axis=0)
        results = replay_batch(list(vehicles), [self.posts] * len(vehicles), limits=False, wheel_angles=angles)
        return [_band(np.column_stack([r.record[n] for n in self.car_channels]), self.record.rate) for r in results]

    def simulate_posts(self, vehicles: Sequence[Vehicle]) -> list[np.ndarray]:
        """Band-passed achieved post displacements of each vehicle's rig driven by the measured drives."""
        results = replay_batch(list(vehicles), [self.drive] * len(vehicles), clip=True)
        return [_band(r.record.quantity("actuator_disp", self.corners), self.record.rate) for r in results]

    def simulate(self, vehicle: Vehicle) -> np.ndarray:
        """All compared channels of one vehicle (samples x names), as ``measured_all`` holds them measured."""
        car = self.simulate_car([vehicle])[0]
        return car if self.drive is None else np.hstack([car, self.simulate_posts([vehicle])[0]])

    def measured_all(self) -> np.ndarray:
        return self.measured if self.drive is None else np.hstack([self.measured, self.measured_posts])


def _post_inputs(disp: np.ndarray, rate: float, corners: tuple[str, ...]) -> Record:
    """Measured post displacements (samples x corners) as the model's inputs: the analysis band and below
    (noise above it would shake the wheels), starting from rest like the model."""
    smooth = band_pass(disp - disp[0], rate, (0.05, ANALYSIS_BAND[1] * 2 ** 0.5))
    smooth -= smooth[0]
    return Record(rate, {channel(c, "actuator_disp"): smooth[:, i] for i, c in enumerate(corners)})


def _band(values: np.ndarray, rate: float) -> np.ndarray:
    return band_pass(values, rate, ANALYSIS_BAND)
