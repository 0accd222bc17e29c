"""Gain and time shift between two versions of the same channels (measured against simulated), and the
fractional delay that applies a shift. Written here: SciPy has the cross-correlation, not the sub-sample
peak or the least-squares gain per channel."""

from __future__ import annotations

import numpy as np
from scipy.interpolate import make_interp_spline


def channel_gains(measured: np.ndarray, simulated: np.ndarray) -> np.ndarray:
    """Least-squares factor per channel (samples x channels): measured ~ factor x simulated."""
    return np.sum(measured * simulated, axis=0) / np.sum(simulated**2, axis=0)


def channel_delays(measured: np.ndarray, simulated: np.ndarray, rate: float, max_lag: float = 0.03) -> np.ndarray:
    """Time shift (s) per channel that best aligns simulated with measured (measured later: +), from the
    cross-correlation peak within ``max_lag`` s refined by a parabola through its neighbours."""
    lags = np.arange(-int(max_lag * rate), int(max_lag * rate) + 1)
    delays = []
    for i in range(measured.shape[1]):
        m, s = measured[:, i], simulated[:, i]
        trim = slice(lags.max(), m.size - lags.max())
        correlation = np.array([np.dot(m[trim], np.roll(s, lag)[trim]) for lag in lags])
        k = int(np.clip(np.argmax(correlation), 1, lags.size - 2))
        a, b, c = correlation[k - 1:k + 2]
        offset = 0.5 * (a - c) / (a - 2 * b + c) if (a - 2 * b + c) != 0 else 0.0
        delays.append((lags[k] + offset) / rate)
    return np.array(delays)


def delayed(values: np.ndarray, samples: float) -> np.ndarray:
    """``values`` shifted later by a (fractional) number of samples: cubic interpolation between samples,
    the first value held before the start."""
    times = np.clip(np.arange(values.size) - samples, 0, values.size - 1)
    return make_interp_spline(np.arange(values.size), values, k=3)(times)
