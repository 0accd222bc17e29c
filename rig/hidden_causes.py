"""Synthetic rig tests with a hidden cause: the ground truth for checking the discrepancy diagnosis.

A truth vehicle is the baseline with its linear parameters off by up to ±3 % (rates, damping, masses,
tyre rates: no real car matches its data sheet) plus one hidden cause of the DESIGN.md vocabulary with
random parameters (or none). It is driven on the servo-post rig by a broadband random drive with a few
large road events (bumps on single posts and axle pairs, suspension travel up to about ±25 mm), and the
record gets 2 % white measurement noise on every measured channel: drive (exact), actuator_disp,
sprung_acc, unsprung_acc and susp_travel per corner.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from rig.channels import channel
from rig.extensions import (AntiRollBar, BumpStop, DamperAsymmetry, MassError, ProgressiveSpring, StrutFriction,
                            TopMountCompliance)
from rig.record import Record
from rig.replay import replay
from rig.signals import band_limited_noise
from rig.vehicle import Vehicle

CAUSES = ("damper_asymmetry", "strut_friction", "bump_stop", "progressive_spring", "anti_roll_bar",
          "top_mount_compliance", "mass_error", "tyre_damping", "actuator_lag", "sensor_gain", "sensor_delay")
MEASURED = ("actuator_disp", "sprung_acc", "unsprung_acc", "susp_travel")
NOISE = 0.02          # of each channel's RMS
LINEAR_ERROR = 0.03   # relative, uniform


def truth_vehicle(baseline: Vehicle, cause: str, rng: np.random.Generator) -> Vehicle:
    """The baseline with linear-parameter errors and the hidden ``cause`` ('none' for none)."""
    def off(value: float) -> float:
        return value * rng.uniform(1 - LINEAR_ERROR, 1 + LINEAR_ERROR)

    def axle(a):
        return dataclasses.replace(a, spring_rate=off(a.spring_rate), damping=off(a.damping),
                                   tyre_rate=off(a.tyre_rate), unsprung_mass=off(a.unsprung_mass))

    truth = dataclasses.replace(baseline, sprung_mass=off(baseline.sprung_mass), front=axle(baseline.front),
                                rear=axle(baseline.rear) if baseline.rear else None)
    axles = ("front", "rear") if baseline.layout == "full" else ("front",)
    extensions: dict = {}
    if cause == "damper_asymmetry":
        ratio = rng.uniform(2.0, 3.0)
        extensions[cause] = {a: DamperAsymmetry(compression=2 * truth.axle(a[0].upper()).damping / (1 + ratio),
                                                rebound=2 * ratio * truth.axle(a[0].upper()).damping / (1 + ratio))
                             for a in axles}
    elif cause == "strut_friction":
        extensions[cause] = {a: StrutFriction(rng.uniform(150.0, 300.0)) for a in axles}
    elif cause == "bump_stop":
        gap, rate = rng.uniform(0.012, 0.018), rng.uniform(1e5, 2e5)
        extensions[cause] = {a: BumpStop(gap, rate) for a in axles}
    elif cause == "progressive_spring":
        # stiffness 30-50 % up at 25 mm of compression: 2 Kn x = share x K0
        share = rng.uniform(0.3, 0.5)
        extensions[cause] = {a: ProgressiveSpring(quadratic=share * truth.axle(a[0].upper()).suspension_rate / 0.05)
                             for a in axles}
    elif cause == "anti_roll_bar":
        extensions[cause] = {"front": AntiRollBar(rng.uniform(10000.0, 20000.0)),
                             "rear": AntiRollBar(rng.uniform(5000.0, 10000.0))}
    elif cause == "top_mount_compliance":
        extensions[cause] = {a: TopMountCompliance(rng.uniform(1.5e5, 3.5e5)) for a in axles}
    elif cause == "mass_error":
        # payload: two rear passengers and luggage
        extensions[cause] = MassError(mass=rng.uniform(120.0, 220.0), x=rng.uniform(-1.3, -0.7), y=rng.uniform(-0.3, 0.3))
    elif cause == "tyre_damping":
        truth = dataclasses.replace(truth, front=dataclasses.replace(truth.front, tyre_damping=rng.uniform(200.0, 400.0)),
                                    rear=dataclasses.replace(truth.rear, tyre_damping=rng.uniform(200.0, 400.0))
                                    if truth.rear else None)
    elif cause == "actuator_lag":
        truth = dataclasses.replace(truth, rig=dataclasses.replace(truth.rig, servo_bandwidth=rng.uniform(12.0, 20.0),
                                                                   servo_delay=rng.uniform(0.005, 0.009)))
    elif cause == "sensor_gain":
        name = channel(rng.choice(truth.corners), rng.choice(["sprung_acc", "unsprung_acc"]))
        extensions[cause] = {name: float(rng.choice([-1, 1]) * rng.uniform(0.08, 0.15) + 1)}
    elif cause == "sensor_delay":
        corner = rng.choice(truth.corners)
        delay = rng.uniform(0.003, 0.008)
        extensions[cause] = {channel(corner, q): delay for q in ("sprung_acc", "unsprung_acc")}
    elif cause != "none":
        raise ValueError(f"unknown cause '{cause}' (known: {', '.join(CAUSES)}, none)")
    return dataclasses.replace(truth, name=f"{baseline.name}_truth", extensions=extensions)


def event_drive(corners: tuple[str, ...], duration: float, rate: float, rng: np.random.Generator,
                rms: float = 0.0025, events: int = 5, amplitude: float = 0.035) -> np.ndarray:
    """Broadband random post drives (0.5-25 Hz) with half-sine road events on single posts and axles."""
    drive = band_limited_noise(duration, rate, (0.5, 25.0), rms, len(corners), int(rng.integers(1 << 31)))
    time = np.arange(drive.shape[0]) / rate
    for start in np.linspace(1.5, duration - 1.5, events):
        width = rng.uniform(0.12, 0.2)
        height = rng.choice([-1, 1]) * rng.uniform(0.7, 1.0) * amplitude
        bump = height * np.sin(np.pi * np.clip((time - start) / width, 0, 1))
        if len(corners) == 1:
            hit = [0]
        else:
            hit = [[0], [1], [2], [3], [0, 1], [2, 3], [0, 3]][int(rng.integers(7))]
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
        for name, values in played.record.channels.items():
            quantity = name.split("/")[1]
            if quantity == "drive":
                channels[name] = values
            elif quantity in MEASURED:
                noise = rng.standard_normal(values.size) * NOISE * np.sqrt(np.mean((values - values.mean()) ** 2))
                channels[name] = values + noise
        records.append(Record(rate, channels, metadata={"vehicle": truth.name, "test": "rig",
                                                        "source": "synthetic rig test (rig/hidden_causes.py)"}))
    return records[0], records[1]
