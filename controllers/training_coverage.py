"""Whether a training record covers a target, and a training drive designed to.

A NARX learns the drive from the responses it was trained on; where a target's responses go beyond them, it
extrapolates, and its tanh neurons saturate where the car keeps stiffening. Per corner, ``coverage`` compares the
quantities the networks see: the body's and the wheel's acceleration (m/s^2), the suspension's travel (m) and its
rate (m/s) (controllers/narx.py ``suspension_motion``): the target is beyond the training where it leaves the
training's range by more than ``SLACK`` of the range's larger end, and each such quantity is an ``Excess``.

``training_drive`` designs a drive whose responses cover a target's: the target's drive estimated by Nurhadiyanto's
inverse model (Eq 5.1 through the servo, controllers/inverse_model.py) sets the level, and the design is pink noise
at that RMS (0.3-40 Hz) with half-sine road events on every post and every axle, bumps and holes at
``EVENT_LEVELS`` of ``EVENT_REACH`` times the estimate's largest excursion, widths across ``EVENT_WIDTHS``, in
random order: every corner meets the target's largest events and beyond, at several speeds, as a road's bumps
and holes do. Heights
stay within 0.9 of the post's stroke and widths give at most 0.8 of its velocity limit.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from controllers.inverse_model import inverse_model_drive
from controllers.narx import RESPONSES, suspension_motion
from rig.io.record import Record
from rig.signal.filters import band_limited_noise, fade_window
from rig.vehicle.vehicle_file import Vehicle

SLACK = 0.05  # of the training range's larger end: beyond it the target counts as outside the training
G = 9.80665
_QUANTITIES = {"sprung_acc": ("body acceleration", "m/s^2"), "unsprung_acc": ("wheel acceleration", "m/s^2"),
               "travel": ("suspension travel", "m"), "travel_rate": ("suspension travel rate", "m/s")}

EVENT_REACH = 1.25              # the design's largest event against the target's largest estimated excursion
EVENT_WIDTHS = (0.06, 0.3)      # s: the half-sines' durations
EVENT_LEVELS = (0.3, 0.55, 0.8, 1.0)  # event heights, as shares of the reach: each post and axle, up and down
NOISE_BAND = (0.3, 40.0)        # Hz


@dataclass(frozen=True)
class Excess:
    """A quantity of a corner the target takes beyond the training's range, for ``duration`` s in total."""

    corner: str
    quantity: str
    target_range: tuple[float, float]
    training_range: tuple[float, float]
    duration: float

    def describe(self) -> str:
        label, unit = _QUANTITIES[self.quantity]
        scale, unit = (1e3, "mm") if unit == "m" else (1.0, unit)
        (lo, hi), (tlo, thi) = self.target_range, self.training_range
        return (f"{self.corner} {label}: the target reaches {lo * scale:.3g} to {hi * scale:.3g} {unit}, the training "
                f"{tlo * scale:.3g} to {thi * scale:.3g} {unit}; {self.duration:.2g} s of the target beyond")


@dataclass
class Coverage:
    """The excesses of a target over a training record, and where (samples x corners, True: beyond)."""

    excesses: list[Excess]
    beyond: np.ndarray

    @property
    def covered(self) -> bool:
        return not self.excesses

    def describe(self) -> str:
        if self.covered:
            return "the training record covers the target's amplitudes"
        return ("the target's amplitudes exceed the training's, the NARX extrapolates there: "
                + "; ".join(e.describe() for e in self.excesses))


def _seen(record: Record, corners: tuple[str, ...], band: tuple[float, float], measured: bool) -> dict[str, np.ndarray]:
    travel, rate = suspension_motion(record, corners, band, measured)
    seen = {q: record.quantity(q, corners) for q in RESPONSES}
    seen.update(travel=travel, travel_rate=rate)
    return seen


def coverage(train: Record, target: Record, corners: tuple[str, ...], band: tuple[float, float],
             measured_travel: bool = False) -> Coverage:
    """Where ``target``'s responses leave ``train``'s ranges, per corner and quantity (see the module docstring)."""
    trained, wanted = _seen(train, corners, band, measured_travel), _seen(target, corners, band, measured_travel)
    excesses, beyond = [], np.zeros((target.n_samples, len(corners)), bool)
    for quantity in _QUANTITIES:
        for i, corner in enumerate(corners):
            lo, hi = float(trained[quantity][:, i].min()), float(trained[quantity][:, i].max())
            slack = SLACK * max(abs(lo), abs(hi))
            values = wanted[quantity][:, i]
            outside = (values < lo - slack) | (values > hi + slack)
            if outside.any():
                excesses.append(Excess(corner, quantity, (float(values.min()), float(values.max())), (lo, hi),
                                       float(outside.sum() / target.rate)))
                beyond[:, i] |= outside
    return Coverage(excesses, beyond)


def training_drive(vehicle: Vehicle, target: Record, duration: float = 60.0, band: tuple[float, float] = (0.5, 50.0),
                   seed: int = 0) -> np.ndarray:
    """A training drive (samples x corners, m, at the target's rate) whose responses cover ``target``'s (see the
    module docstring), faded in and out over 1 s."""
    estimate = inverse_model_drive(vehicle, target, band)
    rate, corners = target.rate, len(vehicle.corners)
    drive = band_limited_noise(duration, rate, NOISE_BAND, 1.0, corners, seed, slope=1.0)
    drive *= np.sqrt(np.mean(estimate**2, axis=0))[None]
    reach = np.minimum(EVENT_REACH * np.abs(estimate).max(axis=0), 0.9 * vehicle.rig.stroke)
    rng = np.random.default_rng(seed)
    time = np.arange(drive.shape[0]) / rate
    posts = [[i] for i in range(corners)] + [[i, i + 1] for i in range(0, corners - 1, 2)]  # single, then axles
    events = [(hit, level, sign) for hit in posts for level in EVENT_LEVELS for sign in (1, -1)]
    order = rng.permutation(len(events))
    starts = np.linspace(1.5, duration - 1.5, len(events)) + rng.uniform(-0.1, 0.1, len(events))
    for start, k in zip(starts, order):
        hit, level, sign = events[k]
        height = sign * level * reach[hit].min()
        slowest = np.pi * abs(height) / (0.8 * vehicle.rig.velocity_limit)  # s: a half-sine's peak speed is pi h / w
        width = rng.uniform(max(EVENT_WIDTHS[0], slowest), max(EVENT_WIDTHS[1], slowest))
        drive[:, hit] += (height * np.sin(np.pi * np.clip((time - start) / width, 0.0, 1.0)))[:, None]
    return drive * fade_window(drive.shape[0], int(rate))[:, None]
