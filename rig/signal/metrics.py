"""Discrepancy measures between a target (measured) and a response (simulated) signal.

- Forsén's time-domain discrepancy index (Forsén 1999, eq. 7; docs/contracts.md):
  TDDI(a, b) = sum (a - b)^2 / (sum (a - mean a)^2 + sum (b - mean b)^2): 0 for identical signals, 1 against
  a constant, 2 for a sine against its negative.
- RMS error in percent of the target's RMS.
- Peak error: the response's largest maximum and deepest minimum against the target's, in percent of the
  target's largest magnitude (what a durability engineer checks beside RMS when events matter).
- Drive error (Nurhadiyanto's thesis, Tables 6.1-6.3): RMS of an estimated minus the true drive
  over the true drive's RMS, both in the drive band.
- Rainflow pseudo-damage ratio: sum of cycle counts x range^m of the response over that of the target,
  with m = 6 as in Forsén (1999); cycles counted by the ``rainflow`` package (ASTM E1049-85).
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np
import rainflow

from rig.constants import ANALYSIS_BAND
from rig.signal.filters import band_pass

DAMAGE_EXPONENT = 6.0


def tddi(target: np.ndarray, response: np.ndarray) -> float:
    """Forsén's time-domain discrepancy index of two equally long signals."""
    a, b = np.asarray(target, float), np.asarray(response, float)
    spread = np.sum((a - a.mean()) ** 2) + np.sum((b - b.mean()) ** 2)
    difference = np.sum((a - b) ** 2)
    if spread == 0.0:
        return 0.0 if difference == 0.0 else float("inf")
    return float(difference / spread)


def rms_error_pct(target: np.ndarray, response: np.ndarray) -> float:
    """RMS of (target - response) in percent of the target's RMS."""
    a, b = np.asarray(target, float), np.asarray(response, float)
    return float(100.0 * np.sqrt(np.mean((a - b) ** 2)) / np.sqrt(np.mean(a**2)))


def peak_error_pct(target: np.ndarray, response: np.ndarray) -> float:
    """The larger miss of the response's maximum and minimum against the target's, in percent of the target's
    largest magnitude: 0 when both extremes are reproduced, whenever they occur."""
    a, b = np.asarray(target, float), np.asarray(response, float)
    miss = max(abs(b.max() - a.max()), abs(b.min() - a.min()))
    return float(100.0 * miss / np.abs(a).max())


def pseudo_damage(signal: np.ndarray, exponent: float = DAMAGE_EXPONENT) -> float:
    """Rainflow pseudo-damage: sum over cycles of count x range^exponent (units of the signal^exponent)."""
    return float(sum(count * rng**exponent
                     for rng, _, count, _, _ in rainflow.extract_cycles(np.asarray(signal, float))))


def damage_ratio(target: np.ndarray, response: np.ndarray, exponent: float = DAMAGE_EXPONENT) -> float:
    """Pseudo-damage of the response over that of the target (1 = same fatigue content)."""
    return pseudo_damage(response, exponent) / pseudo_damage(target, exponent)


@dataclass(frozen=True)
class ChannelMetrics:
    """A channel's response against its target: RMS error and peak error (% of the target's), TDDI, and the ratio of
    the response's rainflow pseudo-damage to the target's."""

    rms_error_pct: float
    tddi: float
    peak_error_pct: float
    damage_ratio: float

    @classmethod
    def from_json(cls, document: dict) -> ChannelMetrics:
        """From a history.json entry's channel (a metric an older file lacks: NaN)."""
        return cls(**{f.name: float(document.get(f.name, np.nan)) for f in fields(cls)})


def channel_metrics(target: np.ndarray, response: np.ndarray, names: list[str]) -> dict[str, ChannelMetrics]:
    """Per channel (columns of samples x channels arrays): its ``ChannelMetrics``."""
    return {name: ChannelMetrics(*(metric(target[:, i], response[:, i])
                                   for metric in (rms_error_pct, tddi, peak_error_pct, damage_ratio)))
            for i, name in enumerate(names)}


def drive_error_pct(true: np.ndarray, estimate: np.ndarray, rate: float,
                    band: tuple[float, float] = ANALYSIS_BAND) -> np.ndarray:
    """Nurhadiyanto's drive error per corner: RMS of (estimate - true drive) over the true drive's RMS, both
    band-passed to the drive band, in %."""
    with np.errstate(over="ignore", invalid="ignore"):  # a diverged free run: inf or nan, as it is
        difference = band_pass(estimate - true, rate, band)
        reference = band_pass(true, rate, band)
        return 100 * np.sqrt(np.mean(difference**2, axis=0) / np.mean(reference**2, axis=0))
