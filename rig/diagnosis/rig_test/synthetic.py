"""Synthetic rig tests with a hidden cause: the ground truth for checking the discrepancy diagnosis.

A truth vehicle is the baseline with its linear parameters off by up to ±3 % (rates, damping, masses,
tyre rates, on every axle of a truck too: no real car matches its data sheet) plus one hidden cause of the
vocabulary in docs/contracts.md with random parameters (or none), as the cause's module draws it (rig/causes/).
It is driven on the servo-post rig by a broadband random drive with a few large road events (bumps on single posts and
axle pairs, suspension travel up to about ±25 mm), and the record gets 2 % white measurement noise on
every measured channel: drive (exact), actuator_disp, sprung_acc, unsprung_acc and susp_travel per
corner, and a truck cab's seat acceleration.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from rig.causes import CAUSES
from rig.io.channels import channel
from rig.io.record import Record
from rig.signal.filters import band_limited_noise
from rig.sim.replay import replay
from rig.vehicle.vehicle_file import Vehicle

MEASURED = ("actuator_disp", "sprung_acc", "unsprung_acc", "susp_travel", "seat_acc")
NOISE = 0.02          # of each channel's RMS
LINEAR_ERROR = 0.03   # relative, uniform


def truth_vehicle(baseline: Vehicle, cause: str, rng: np.random.Generator) -> Vehicle:
    """The baseline with linear-parameter errors and a random instance of the hidden ``cause`` ('none' for
    none; rig/causes/), one that a rig test shows."""
    hideable = [name for name, c in CAUSES.items() if not c.generic and c.seen_on == "rig"]
    if cause != "none" and cause not in hideable:
        raise ValueError(f"cannot hide cause '{cause}' (hideable: {', '.join(hideable)}, none)")

    def off(value: float) -> float:
        return value * rng.uniform(1 - LINEAR_ERROR, 1 + LINEAR_ERROR)

    def axle(a):
        return dataclasses.replace(a, spring_rate=off(a.spring_rate), damping=off(a.damping),
                                   tyre_rate=off(a.tyre_rate), unsprung_mass=off(a.unsprung_mass))

    truth = dataclasses.replace(baseline, name=f"{baseline.name}_truth", extensions={},
                                sprung_mass=off(baseline.sprung_mass), front=axle(baseline.front),
                                middle=tuple(axle(a) for a in baseline.middle),
                                rear=axle(baseline.rear) if baseline.rear else None)
    return truth if cause == "none" else CAUSES[cause].hidden(truth, rng)


def event_drive(corners: tuple[str, ...], duration: float, rate: float, rng: np.random.Generator,
                rms: float = 0.0025, events: int = 5, amplitude: float = 0.035) -> np.ndarray:
    """Broadband random post drives (0.5-25 Hz) with half-sine road events on single posts and axles."""
    drive = band_limited_noise(duration, rate, (0.5, 25.0), rms, len(corners), int(rng.integers(1 << 31)))
    time = np.arange(drive.shape[0]) / rate
    for start in np.linspace(1.5, duration - 1.5, events):
        width = rng.uniform(0.12, 0.2)
        height = rng.choice([-1, 1]) * rng.uniform(0.7, 1.0) * amplitude
        bump = height * np.sin(np.pi * np.clip((time - start) / width, 0, 1))
        hit = [0] if len(corners) == 1 else [[0], [1], [2], [3], [0, 1], [2, 3], [0, 3]][int(rng.integers(7))]
        drive[:, hit] += bump[:, None]
    return drive


def hidden_cause_records(baseline: Vehicle, cause: str, seed: int, duration: float = 60.0,
                         holdout_duration: float = 30.0, rate: float = 512.0) -> tuple[Record, Record, Vehicle]:
    """Measured and holdout rig records of a truth car with a hidden ``cause``, and the truth vehicle."""
    rng = np.random.default_rng(seed)
    truth = truth_vehicle(baseline, cause, rng)
    measured, holdout = rig_test_records(truth, rng, duration, holdout_duration, rate)
    return measured, holdout, truth


def rig_test_records(truth: Vehicle, rng: np.random.Generator, duration: float = 60.0, holdout_duration: float = 30.0,
                     rate: float = 512.0) -> tuple[Record, Record]:
    """Measured and holdout rig records of ``truth`` driven by event drives, with measurement noise."""
    records = []
    for length in (duration, holdout_duration):
        drive = event_drive(truth.corners, length, rate, rng)
        played = replay(truth, Record(rate, {channel(c, "drive"): drive[:, i] for i, c in enumerate(truth.corners)}))
        channels = {}
        # wheel-pan load cells' noise from a child stream: the other channels keep their noise for a given seed
        load_cells = rng.spawn(1)[0]
        for name, values in played.record.channels.items():
            quantity = name.split("/")[1]
            if quantity == "drive":
                channels[name] = values
            elif quantity in MEASURED or quantity == "tyre_force":
                source = load_cells if quantity == "tyre_force" else rng
                noise = source.standard_normal(values.size) * NOISE * np.sqrt(np.mean((values - values.mean()) ** 2))
                channels[name] = values + noise
        source = "synthetic rig test (rig/diagnosis/rig_test/synthetic.py)"
        records.append(Record(rate, channels, metadata={"vehicle": truth.name, "test": "rig", "source": source}))
    return records[0], records[1]
