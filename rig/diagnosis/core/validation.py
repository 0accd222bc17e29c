"""Model validation: simulate a measured rig test with the model and score what it gets wrong.

Channels are compared in the analysis band the record supports (rig.constants.analysis_band) by Forsén's
TDDI (Forsén 1999, eq. 7) and the RMS error in percent, and by his other measures (rig/signal/discrepancy.py: the TDDI
against the measured variance, eq. 8, and the ride, payload and fatigue discrepancy indices); FRFs of measured and
simulated responses are split into the heave, pitch, roll and warp input patterns of the four posts. The model passes
where its mean TDDI is within the detection limit the diagnosis uses: DETECTION_FACTOR times the noise floor measured
on the record itself (rig/diagnosis/core/noise.py). ``validate`` computes; rig/report/validation_report.py presents.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from rig.constants import narrowed_note
from rig.diagnosis.core.experiment import Experiment
from rig.diagnosis.core.noise import DETECTION_FACTOR, input_floor, measurement_floor
from rig.io.channels import CORNERS, channel
from rig.io.checks import require_band, require_signal
from rig.io.record import Record
from rig.signal.discrepancy import Discrepancy, discrepancy
from rig.signal.frf import estimate_frf, spectral_matrices
from rig.signal.metrics import rms_error_pct, tddi
from rig.sim.replay import active_forces
from rig.vehicle.vehicle_file import Vehicle

#: post input patterns (weights on FL, FR, RL, RR; other layouts: ``pattern_weights``)
PATTERNS = {"heave": (0.25, 0.25, 0.25, 0.25), "pitch": (0.25, 0.25, -0.25, -0.25),
            "roll": (0.25, -0.25, 0.25, -0.25), "warp": (0.25, -0.25, -0.25, 0.25)}
PATTERN_SEGMENT = 4.0   # s: Welch segment of the pattern FRFs, 0.25 Hz lines
PATTERN_AVERAGES = 8    # segments a record should hold at least (with half overlap, 15 averages)


@dataclass(frozen=True)
class ChannelScore:
    tddi: float           # Forsén's index, 0 = identical
    rms_error_pct: float  # RMS of measured - simulated in % of the measured RMS


@dataclass
class ValidationReport:
    """A measured rig test against the model's simulation of it (analysis band)."""

    vehicle: str
    band_hz: tuple[float, float]
    mean_tddi: float
    channels: dict[str, ChannelScore]
    measured: Record = field(repr=False)   # compared channels, band-passed
    simulated: Record = field(repr=False)
    car_channels: list[str] = field(default_factory=list)
    #: FRFs from the heave/pitch/roll/warp post patterns to the car channels: frequency (Hz), measured and
    #: simulated (lines x car channels x patterns)
    pattern_frequency: np.ndarray = field(default=None, repr=False)
    pattern_measured: np.ndarray = field(default=None, repr=False)
    pattern_simulated: np.ndarray = field(default=None, repr=False)
    pattern_coherence: np.ndarray = field(default=None, repr=False)  # measured: lines x car channels (0-1)
    pattern_names: tuple[str, ...] = tuple(PATTERNS)  # the inputs in the FRFs' last axis: post patterns, then any
    # actuator force channels (<corner>/active_force, per N)
    noise_floor: float = 0.0   # the mean TDDI measurement noise alone leaves on this record (core/noise.py)
    notes: list[str] = field(default_factory=list)  # what a reader must know (the band narrowed)
    indices: Discrepancy | None = None  # Forsén's measures per channel and for the test (rig/signal/discrepancy.py)

    @property
    def detection_limit(self) -> float:
        """The mean TDDI beyond which the model is wrong: DETECTION_FACTOR times the noise floor."""
        return DETECTION_FACTOR * self.noise_floor

    @property
    def passed(self) -> bool:
        """Whether the model reproduces the record within the detection limit."""
        return self.mean_tddi <= self.detection_limit

    def verdict(self) -> str:
        """The answer in one line."""
        multiple = self.mean_tddi / self.noise_floor if self.noise_floor > 0 else float("inf")
        if self.passed:
            return (f"passed: mean TDDI {self.mean_tddi:.3g} is within the detection limit {self.detection_limit:.3g} "
                    f"({DETECTION_FACTOR:g} times this record's noise floor {self.noise_floor:.3g})")
        return (f"failed: mean TDDI {self.mean_tddi:.3g} is {multiple:.3g} times this record's noise floor "
                f"{self.noise_floor:.3g}, beyond the detection limit {self.detection_limit:.3g}: the model misses "
                f"more than noise")

    def to_json(self) -> dict:
        """validation.json."""
        return {"vehicle": self.vehicle, "band_hz": list(self.band_hz), "mean_tddi": self.mean_tddi,
                "channels": {n: {"tddi": s.tddi, "rms_error_pct": s.rms_error_pct} for n, s in self.channels.items()},
                "noise_floor": self.noise_floor, "detection_limit": self.detection_limit, "passed": self.passed,
                "notes": self.notes} | ({"indices": self.indices.to_json()} if self.indices is not None else {})


def channel_scores(measured: np.ndarray, simulated: np.ndarray, names: list[str]) -> dict[str, ChannelScore]:
    """TDDI and RMS error % per channel (samples x channels)."""
    return {n: ChannelScore(tddi(measured[:, i], simulated[:, i]), rms_error_pct(measured[:, i], simulated[:, i]))
            for i, n in enumerate(names)}


def mean_tddi(measured: np.ndarray, simulated: np.ndarray) -> float:
    """The headline figure: TDDI averaged over the compared channels (docs/contracts.md)."""
    return float(np.mean([tddi(measured[:, i], simulated[:, i]) for i in range(measured.shape[1])]))


def pattern_weights(corners: tuple[str, ...]) -> np.ndarray:
    """Weights (patterns x corners) of the heave, pitch, roll and warp patterns on any layout's posts: PATTERNS on a
    car's four; on a truck's, pitch and warp from the front and rear axles (a middle axle's posts stand still); a
    quarter car's one post has heave only."""
    if tuple(corners) == CORNERS:
        return np.array(list(PATTERNS.values()))
    if len(corners) == 1:
        return np.ones((1, 1))
    pitch = np.array([{"F": 1.0, "R": -1.0}.get(c[:-1], 0.0) for c in corners])
    roll = np.array([1.0 if c.endswith("L") else -1.0 for c in corners])
    return np.array([np.ones(len(corners)), pitch, roll, pitch * roll]) / len(corners)


def pattern_frfs(posts: np.ndarray, responses: np.ndarray, rate: float, nperseg: int,
                 corners: tuple[str, ...] = CORNERS, forces: np.ndarray | None = None
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """FRFs from the heave/pitch/roll/warp post patterns (and, with ``forces``, samples x corners in N, from each
    corner's actuator force between body and wheel, a further input) to each response: (frequency, (F, n_out,
    inputs), and each response's multiple coherence on the inputs (F, n_out))."""
    weights = pattern_weights(corners)  # patterns x corners
    modal = posts @ weights.T if forces is None else np.hstack([posts @ weights.T, forces])
    frf = estimate_frf(spectral_matrices(modal, responses, rate, nperseg))
    return frf.frequency, frf.h1, frf.coherence


def pattern_segment(n_samples: int, rate: float) -> int:
    """Welch segment of the pattern FRFs (samples): 4 s (0.25 Hz lines), shorter when the record holds fewer
    than 8 of them, a power of two."""
    return int(2 ** np.floor(np.log2(min(PATTERN_SEGMENT * rate, n_samples / PATTERN_AVERAGES))))


def validate(vehicle: Vehicle, record: Record, source: str = "measured record") -> ValidationReport:
    """Simulate the measured rig test ``record`` with ``vehicle`` and score every compared channel in the band
    the record supports (``source`` names it in refusals)."""
    band = require_band(record, source, "validation")
    experiment = Experiment.from_record(record, vehicle, band)
    require_signal(record, [channel(c, "actuator_disp") for c in experiment.corners] + experiment.car_channels,
                   source)
    measured, simulated, names = experiment.measured_all(), experiment.simulate(vehicle), experiment.names

    def as_record(values: np.ndarray, label: str) -> Record:
        return Record(record.rate, {n: values[:, i] for i, n in enumerate(names)}, metadata={"model": label})

    posts = experiment.posts.quantity("actuator_disp", experiment.corners)
    car = len(experiment.car_channels)
    segment = pattern_segment(record.n_samples, record.rate)
    forces = active_forces(experiment.posts, experiment.corners)
    frequency, h_measured, coherence = pattern_frfs(posts, measured[:, :car], record.rate, segment, experiment.corners,
                                                    forces)
    _, h_simulated, _ = pattern_frfs(posts, simulated[:, :car], record.rate, segment, experiment.corners, forces)
    inputs = tuple(PATTERNS)[:len(pattern_weights(experiment.corners))] + (
        () if forces is None else tuple(channel(c, "active_force") for c in experiment.corners))
    floors = measurement_floor(experiment) + input_floor(experiment, vehicle, simulated[:, :car])
    return ValidationReport(vehicle.name, band, mean_tddi(measured, simulated),
                            channel_scores(measured, simulated, names), as_record(measured, "measured"),
                            as_record(simulated, "simulated"), experiment.car_channels, frequency, h_measured,
                            h_simulated, coherence, inputs, float(np.mean(floors)),
                            [n for n in [narrowed_note(band, record.rate, record.duration)] if n],
                            discrepancy(measured, simulated, names, record.rate))
