"""A measured rig test prepared for simulation, the common ground of validation and diagnosis.

The car part replays the measured post displacements on ideal posts (the car then sees exactly what the
real car saw); the rig part plays the measured drives through the post servo model and compares the
achieved displacements. Both are compared in an analysis band (rig/constants.py: measurement noise and
drift outside it say nothing about the model; a short or low-rate record supports only part of it). An
experiment cut from inside a longer test starts with the car moving while the model starts from rest: its first
``settle`` samples are simulated, so that the model's start transient dies away, and not compared. A record with
every wheel's angle (a track test whose road was measured) turns the wheels that can turn in the model (a wheel's
unbalance) as they turned. A record's actuator forces between body and wheel
(``<corner>/active_force``) are inputs beside the posts, and its displacements from static (``sprung_disp``,
``unsprung_disp``: a lab bench's encoders) are compared like its accelerations; a record may carry either or both.
"""

from __future__ import annotations

import dataclasses
import pickle
import threading
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from rig.constants import ANALYSIS_BAND
from rig.io.channels import channel
from rig.io.record import Record, RecordError
from rig.signal.filters import band_pass
from rig.sim.replay import active_forces, replay_batch
from rig.sim.simulate import SimulationError
from rig.vehicle.mjcf import MAX_TIMESTEP
from rig.vehicle.statics import EquilibriumError
from rig.vehicle.vehicle_file import Vehicle, VehicleError

CAR_QUANTITIES = ("sprung_acc", "unsprung_acc", "susp_travel", "sprung_disp", "unsprung_disp")
BODY_CHANNELS = ("cab/seat_acc",)  # compared where a record has them: a truck cab's seat (its mounts show there)
POST_INPUT_TOP = 0.45  # the post inputs' low-pass at most this share of the sample rate (below Nyquist)
CACHED_RUNS = 32       # simulations of an experiment kept, so that a vehicle simulated again is looked up instead
#: what a fit's trial vehicle that no vehicle can be ends in: a model MuJoCo refuses to build, no static equilibrium,
#: a run that diverges
INFEASIBLE = (VehicleError, EquilibriumError, SimulationError)


@dataclass
class Experiment:
    """A measured rig test prepared for simulation: post inputs, measured channels (band-passed, compared
    samples only)."""

    record: Record
    corners: tuple[str, ...]
    car_channels: list[str]
    measured: np.ndarray            # compared samples x car channels, band-passed
    posts: Record                   # measured actuator_disp (and active_force) channels, low-passed: the model's inputs
    drive: Record | None            # measured drive channels, for the rig part
    measured_posts: np.ndarray | None  # compared samples x corners, band-passed measured actuator_disp
    wheel_angles: np.ndarray | None = None  # samples x corners, rad: the wheels' measured angles (a track test)
    band: tuple[float, float] = ANALYSIS_BAND  # Hz: where channels are compared
    settle: int = 0                 # samples at the start that settle the model: simulated, not compared
    longest: float = MAX_TIMESTEP   # s: the longest physics step the car may take (rig/sim/step_size.py)
    _simulated: dict = field(default_factory=dict, init=False, repr=False, compare=False)  # vehicle's pickle -> car
    _cache_lock: threading.Lock = field(default_factory=threading.Lock, init=False, repr=False, compare=False)

    @classmethod
    def from_record(cls, record: Record, vehicle: Vehicle, band: tuple[float, float] = ANALYSIS_BAND,
                    settle: int = 0, longest: float = MAX_TIMESTEP) -> Experiment:
        corners = vehicle.corners
        missing = [channel(c, "actuator_disp") for c in corners if channel(c, "actuator_disp") not in record]
        if missing:
            raise RecordError(f"measured record has no {', '.join(missing)}: the car part replays the measured posts")
        car_channels = [channel(c, q) for q in CAR_QUANTITIES for c in corners if channel(c, q) in record] + [
            n for n in BODY_CHANNELS if n in record]
        if not car_channels:
            raise RecordError(f"measured record has none of {', '.join(CAR_QUANTITIES)} to compare")
        disp = record.quantity("actuator_disp", corners)
        posts = _post_inputs(disp, record.rate, corners, band, active_forces(record, corners))
        has_drive = all(channel(c, "drive") in record for c in corners)
        drive = record.select([channel(c, "drive") for c in corners]) if has_drive else None
        angles = record.quantity("wheel_angle", corners) if all(channel(c, "wheel_angle") in record for c in corners) \
            else None
        measured = _band(np.column_stack([record[n] for n in car_channels]), record.rate, band)[settle:]
        return cls(record, corners, car_channels, measured, posts, drive,
                   _band(disp, record.rate, band)[settle:] if has_drive else None, angles, band, settle, longest)

    def with_post_noise(self, noise: np.ndarray) -> Experiment:
        """The same test with ``noise`` (samples x corners, m) added to the measured post displacements."""
        disp = self.record.quantity("actuator_disp", self.corners) + noise
        return dataclasses.replace(self, posts=_post_inputs(disp, self.record.rate, self.corners, self.band,
                                                            active_forces(self.record, self.corners)))

    @property
    def compared_seconds(self) -> float:
        """How long the compared part lasts (s)."""
        return self.measured.shape[0] / self.record.rate

    @property
    def names(self) -> list[str]:
        """Compared channels: car channels, then (with drives) the achieved post displacements."""
        return self.car_channels + ([channel(c, "actuator_disp") for c in self.corners] if self.drive else [])

    def simulate_car(self, vehicles: Sequence[Vehicle]) -> list[np.ndarray]:
        """Band-passed car channels (samples x car channels) of each vehicle on the measured posts (read-only: the
        latest CACHED_RUNS are kept, and a vehicle simulated among them is looked up instead of simulated again)."""
        keys = [pickle.dumps(v) for v in vehicles]
        with self._cache_lock:  # fits beside each other on threads share the experiment
            found = {k: run for k in keys if (run := self._simulated.pop(k, None)) is not None}
        new = {k: v for k, v in zip(keys, vehicles) if k not in found}
        if new:
            angles = None if self.wheel_angles is None else np.repeat(self.wheel_angles[None], len(new), axis=0)
            results = replay_batch(list(new.values()), [self.posts] * len(new), limits=False, wheel_angles=angles,
                                   longest=self.longest, qpos=False)
            for key, result in zip(new, results):
                found[key] = self._compared(result.record)
                found[key].flags.writeable = False
        with self._cache_lock:
            self._simulated.update(found)  # the latest last
            while len(self._simulated) > CACHED_RUNS:
                self._simulated.pop(next(iter(self._simulated)))
        return [found[k] for k in keys]

    def each_input_alone(self, vehicle: Vehicle) -> dict[str, np.ndarray]:
        """Band-passed car channels (samples x car channels) of ``vehicle`` moved by each of the test's inputs alone
        (a post's displacement, an actuator's force), the others held still: input channel -> response."""
        alone = [dataclasses.replace(self.posts, channels={n: v if n == name else np.zeros_like(v)
                                                           for n, v in self.posts.channels.items()})
                 for name in self.posts.names]
        results = replay_batch(vehicle, alone, limits=False, longest=self.longest, qpos=False)
        return {name: self._compared(result.record) for name, result in zip(self.posts.names, results)}

    def _compared(self, record: Record) -> np.ndarray:
        """A run's car channels as they are compared: band-passed, the settling samples left out."""
        return _band(np.column_stack([record[n] for n in self.car_channels]), self.record.rate, self.band)[self.settle:]

    def simulate_trials(self, vehicles: Sequence[Vehicle]) -> list[np.ndarray]:
        """``simulate_car`` for a fit's trial vehicles: one that no vehicle can be (INFEASIBLE: a body lighter than
        nothing or off the triangle inequality of inertia, a trial law that softens past zero stiffness and
        diverges) gets the measured channels negated, which scores worse than any feasible model (TDDI 2, the
        measure's largest): the fit backs away from it instead of stopping the diagnosis."""
        return feasible(self.simulate_car, vehicles, -self.measured)

    def simulate_post_trials(self, vehicles: Sequence[Vehicle]) -> list[np.ndarray]:
        """``simulate_posts`` for a fit's trial vehicles, an infeasible one scored as ``simulate_trials`` does."""
        return feasible(self.simulate_posts, vehicles, -self.measured_posts)

    def simulate_posts(self, vehicles: Sequence[Vehicle]) -> list[np.ndarray]:
        """Band-passed achieved post displacements of each vehicle's rig driven by the measured drives."""
        results = replay_batch(list(vehicles), [self.drive] * len(vehicles), clip=True, qpos=False)
        return [_band(r.record.quantity("actuator_disp", self.corners), self.record.rate, self.band)[self.settle:]
                for r in results]

    def simulate(self, vehicle: Vehicle) -> np.ndarray:
        """All compared channels of one vehicle (samples x names), as ``measured_all`` holds them measured."""
        car = self.simulate_car([vehicle])[0]
        return car if self.drive is None else np.hstack([car, self.simulate_posts([vehicle])[0]])

    def measured_all(self) -> np.ndarray:
        return self.measured if self.drive is None else np.hstack([self.measured, self.measured_posts])


def feasible(simulate, vehicles: Sequence[Vehicle], worst: np.ndarray) -> list[np.ndarray]:
    """``simulate(vehicles)``, each vehicle that is INFEASIBLE given ``worst`` instead (a fit's trials: rollouts here,
    a linear car's frequency response in rig/diagnosis/rig_test/frequency_fit.py)."""
    try:
        return simulate(vehicles)
    except INFEASIBLE:
        if len(vehicles) > 1:
            return [feasible(simulate, [v], worst)[0] for v in vehicles]
        return [worst]


def _post_inputs(disp: np.ndarray, rate: float, corners: tuple[str, ...], band: tuple[float, float],
                 forces: np.ndarray | None = None) -> Record:
    """Measured post displacements (samples x corners, m), and actuator forces (N) if the record has them, as the
    model's inputs: the analysis band and half an octave above it, below the record's Nyquist frequency (noise
    above it would shake the wheels), starting from rest like the model."""
    inputs = {"actuator_disp": disp} | ({} if forces is None else {"active_force": forces})
    channels = {}
    for quantity, values in inputs.items():
        smooth = band_pass(values - values[0], rate, (0.05, min(band[1] * 2 ** 0.5, POST_INPUT_TOP * rate)))
        smooth -= smooth[0]
        channels |= {channel(c, quantity): smooth[:, i] for i, c in enumerate(corners)}
    return Record(rate, channels)


def _band(values: np.ndarray, rate: float, band: tuple[float, float]) -> np.ndarray:
    return band_pass(values, rate, band)
