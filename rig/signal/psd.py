"""Power spectral densities, one way for every stage: Welch's average of Hann-windowed segments (SciPy), the
segment set by the frequency resolution wanted and cut to the record when it is shorter."""

from __future__ import annotations

import numpy as np
from scipy.signal import welch

#: Hz: the default line spacing (4 s segments): the analysis band's lowest octave gets a few lines
RESOLUTION = 0.25


def psd(values: np.ndarray, rate: float, resolution: float = RESOLUTION, axis: int = 0
        ) -> tuple[np.ndarray, np.ndarray]:
    """Frequencies (Hz) and one-sided PSD (unit²/Hz) of ``values`` sampled at ``rate`` Hz along ``axis``, with
    segments of 1 / ``resolution`` s (the whole record when it is shorter)."""
    segment = min(values.shape[axis], int(round(rate / resolution)))
    return welch(values, rate, nperseg=segment, axis=axis)
