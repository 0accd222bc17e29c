"""Per-channel, frequency-dependent iteration gains, as MTS RPC and Simcenter TWR offer them.

The correction of each iterated channel is weighted per octave band of the iteration band: the inverse FRF's
column of the channel is scaled by the band's gain. After each play every channel's error energy in every band
(over the samples where the drive has hold on it) is compared with that of the drive the correction was made
from: where it fell, the gain doubles again (up to the ceiling, the scheme's gain); where it grew, it halves.
A channel or band that the nonlinearity makes the FRF wrong for so slows down alone, while the others keep
their full step.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass
class BandGains:
    """Gains (bands x channels) on octave bands with ``edges`` (Hz), at most ``ceiling``."""

    edges: np.ndarray
    values: np.ndarray
    ceiling: float

    @classmethod
    def uniform(cls, band: tuple[float, float], channels: int, gain: float) -> BandGains:
        """``gain`` on every channel in octave bands from the band's lower edge (the last one cut at its top)."""
        octaves = max(1, int(np.ceil(np.log2(band[1] / band[0]) - 1e-9)))
        edges = band[0] * 2.0 ** np.arange(octaves + 1)
        edges[-1] = band[1]
        return cls(edges, np.full((octaves, channels), float(gain)), float(gain))

    def on_lines(self, frequency: np.ndarray) -> np.ndarray:
        """Gains on frequency lines (F x channels): each band's inside it, the outer bands' beyond the edges."""
        index = np.clip(np.searchsorted(self.edges, frequency, side="right") - 1, 0, self.values.shape[0] - 1)
        return self.values[index]

    def adapt(self, now: np.ndarray, before: np.ndarray) -> None:
        """Double the gains where the band error (bands x channels) fell, halve them where it grew."""
        self.values = np.where(now < before, np.minimum(self.ceiling, 2 * self.values), 0.5 * self.values)

    def halve(self, now: np.ndarray, before: np.ndarray) -> None:
        """After a setback: halve where the band error grew (everywhere, when none did)."""
        grew = now > before
        self.values = np.where(grew if grew.any() else True, 0.5 * self.values, self.values)

    @property
    def mean(self) -> float:
        return float(self.values.mean())


def band_errors(error: np.ndarray, rate: float, edges: np.ndarray) -> np.ndarray:
    """Energy of ``error`` (samples x channels) per band (bands x channels), from its periodogram."""
    spectrum = np.abs(np.fft.rfft(error, axis=0)) ** 2
    frequency = np.fft.rfftfreq(error.shape[0], 1.0 / rate)
    index = np.searchsorted(edges, frequency, side="right") - 1
    return np.array([spectrum[index == b].sum(axis=0) for b in range(edges.size - 1)])
