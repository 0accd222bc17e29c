"""Forsén's discrepancy measures between a measurement and a model (Forsén 1999, section 5.2), per channel and per
test.

- TDDI of two signals of equal status (two runs of one test, eq. 7): sum (a - b)^2 / (sum (a - mean a)^2 +
  sum (b - mean b)^2); ``rig.signal.metrics.tddi``.
- TDDI of a simulation f against a measurement a (eq. 8): sum (a - f)^2 / sum (a - mean a)^2, scaled by the measured
  variance alone: 0 for the measurement itself, 1 for its mean, 4 for its negative.
- Ride discomfort discrepancy (eq. 10): the discomfort index DI of the cab's accelerations (ISO 2631-1 Wk-weighted
  RMS; ``cab/seat_acc``), (DI(a) - DI(f)) / DI(a) against a measurement, |DI(a) - DI(b)| / ((DI(a) + DI(b)) / 2)
  between two runs.
- Payload discomfort discrepancy (eq. 11): the same on the frame's accelerations (the body accelerometers,
  ``<corner>/sprung_acc``), one DI per side, the payload's DI their mean (the thesis's gearbox cross-member, left and
  right, between the axles; a vertical model has the frame's vertical accelerations).
- Fatigue damage discrepancy (eqs. 12 and 13): per channel the rainflow damage FD (exponent 6,
  ``rig.signal.metrics.pseudo_damage``; the fatigue strength cancels), (FD(a) - FD(f)) / FD(a) against a measurement,
  |FD(a) - FD(b)| / ((FD(a) + FD(b)) / 2) between runs; the test's index is their mean over the force channels
  (the thesis's wheel forces: ``tyre_force``, ``actuator_force``), over every compared channel where the test has
  none. Against a measurement the per-channel values keep their sign (positive: the model has less damage), so a
  test's mean can hide errors of both signs: the per-channel values say which.

Positive relative discrepancies mean the model (or the second run) responds less than the measurement.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from rig.io.channels import split_channel
from rig.signal.comfort import MIN_RATE, weighted_rms
from rig.signal.metrics import pseudo_damage, tddi

RIDE_QUANTITIES = ("seat_acc",)
PAYLOAD_QUANTITIES = ("sprung_acc",)
FORCE_QUANTITIES = ("tyre_force", "actuator_force")


def tddi_against_measured(measured: np.ndarray, simulated: np.ndarray) -> float:
    """Forsén's eq. 8: sum (a - f)^2 / sum (a - mean a)^2 (inf when the measurement is constant and f is not)."""
    a, f = np.asarray(measured, float), np.asarray(simulated, float)
    spread = np.sum((a - a.mean()) ** 2)
    difference = np.sum((a - f) ** 2)
    if spread == 0.0:
        return 0.0 if difference == 0.0 else float("inf")
    return float(difference / spread)


def relative_discrepancy(measured: float, simulated: float) -> float:
    """Eqs. 10-12 against a measurement: (X(a) - X(f)) / X(a)."""
    return float((measured - simulated) / measured) if measured else float("nan")


def run_discrepancy(first: float, second: float) -> float:
    """Eqs. 10-12 between two runs of equal status: |X(a) - X(b)| / ((X(a) + X(b)) / 2)."""
    mean = (first + second) / 2
    return float(abs(first - second) / mean) if mean else float("nan")


@dataclass(frozen=True)
class ChannelDiscrepancy:
    """One channel's measures: both TDDIs, its rainflow damage discrepancy and, for an acceleration the ride or
    payload index uses, its discomfort index measured and modelled (m/s^2, Wk-weighted RMS)."""

    tddi: float                 # eq. 7
    tddi_measured: float        # eq. 8
    fatigue: float              # eq. 12: (FD(a) - FD(f)) / FD(a)
    discomfort_measured: float | None = None
    discomfort_model: float | None = None

    def to_json(self) -> dict:
        document = {"tddi": self.tddi, "tddi_measured": self.tddi_measured, "fatigue": self.fatigue}
        if self.discomfort_measured is not None:
            document |= {"discomfort_measured": self.discomfort_measured, "discomfort_model": self.discomfort_model}
        return document


@dataclass(frozen=True)
class Discrepancy:
    """A test's measures (``channels`` per channel; the test's: means and indices, None where the test has no
    channel for them or its rate is below what ISO 2631-1's weighting needs)."""

    channels: dict[str, ChannelDiscrepancy]
    tddi: float                     # eq. 9: the mean of eq. 7 over the channels
    tddi_measured: float            # the mean of eq. 8
    fatigue: float                  # eq. 13
    fatigue_channels: tuple[str, ...]
    ride: float | None = None       # eq. 10
    payload: float | None = None    # eq. 11
    ride_di: tuple[float, float] | None = field(default=None)     # DI measured, modelled (m/s^2)
    payload_di: tuple[float, float] | None = field(default=None)

    def to_json(self) -> dict:
        return {"tddi": self.tddi, "tddi_measured": self.tddi_measured, "fatigue": self.fatigue,
                "fatigue_channels": list(self.fatigue_channels), "ride": self.ride, "payload": self.payload,
                "ride_di": None if self.ride_di is None else list(self.ride_di),
                "payload_di": None if self.payload_di is None else list(self.payload_di),
                "channels": {n: c.to_json() for n, c in self.channels.items()}}


def discrepancy(measured: np.ndarray, simulated: np.ndarray, names: list[str], rate: float) -> Discrepancy:
    """Forsén's measures of a model's ``simulated`` channels against the ``measured`` ones (samples x ``names``,
    sampled at ``rate`` Hz; the module docstring says which channels each index takes)."""
    weighted = rate >= MIN_RATE
    comfort = {n for n in names if split_channel(n)[1] in RIDE_QUANTITIES + PAYLOAD_QUANTITIES} if weighted else set()
    channels = {}
    for i, name in enumerate(names):
        a, f = measured[:, i], simulated[:, i]
        di = (weighted_rms(a, rate), weighted_rms(f, rate)) if name in comfort else (None, None)
        channels[name] = ChannelDiscrepancy(tddi(a, f), tddi_against_measured(a, f),
                                            relative_discrepancy(pseudo_damage(a), pseudo_damage(f)), *di)
    forces = tuple(n for n in names if split_channel(n)[1] in FORCE_QUANTITIES) or tuple(names)
    ride = _discomfort(channels, RIDE_QUANTITIES, by_side=False)
    payload = _discomfort(channels, PAYLOAD_QUANTITIES, by_side=True)
    return Discrepancy(channels, float(np.mean([c.tddi for c in channels.values()])),
                       float(np.mean([c.tddi_measured for c in channels.values()])),
                       float(np.mean([channels[n].fatigue for n in forces])), forces,
                       None if ride is None else relative_discrepancy(*ride),
                       None if payload is None else relative_discrepancy(*payload), ride, payload)


def _discomfort(channels: dict[str, ChannelDiscrepancy], quantities: tuple[str, ...], by_side: bool
                ) -> tuple[float, float] | None:
    """The discomfort index (measured, modelled) of the channels of ``quantities``: their mean DI, or (``by_side``)
    the mean of each side's mean (corners ending L and R); None where the test has none."""
    chosen = {n: c for n, c in channels.items() if split_channel(n)[1] in quantities and c.discomfort_measured
              is not None}
    if not chosen:
        return None
    groups = [[c for n, c in chosen.items() if split_channel(n)[0].endswith(side)] for side in "LR"] if by_side \
        else [list(chosen.values())]
    groups = [g for g in groups if g] or [list(chosen.values())]
    return tuple(float(np.mean([np.mean([getattr(c, key) for c in g]) for g in groups]))
                 for key in ("discomfort_measured", "discomfort_model"))
