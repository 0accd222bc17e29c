"""Rates of measured signals (a damper rod's velocity from its displacement), zero-phase, with the smoothing
chosen from the signal's own spectrum.

SciPy's Savitzky-Golay differentiator (``scipy.signal.savgol_filter``, ``deriv=1``: a local polynomial least-
squares fit, zero phase, ends fitted rather than padded) with polynomial order 4. Its window is the one that
minimises the rate's expected mean-square error, read from the signal's own periodogram: the signal's lines (those
well above the noise floor, the floor read from the upper half of the band, where a dyno or rig record, sampled
much faster than it moves, holds only noise) distorted by the filter's departure from the exact ``i 2 pi f``,
plus the floor passed through the filter. Given a witness (a damper's force, which the rod's motion drives), a line
counts as the signal's only where the witness is coherent with it (SciPy's magnitude-squared coherence over Welch
segments, above the level unrelated signals reach once in a thousand): a line the witness does not follow is the
sensor's (electrical pickup on a displacement transducer, a motor drive's switching), and no window is chosen to
keep it (the window is then the one its absence would give; its passing is not in the expected error). A
nonlinear damper's force may not follow a weak harmonic of the motion linearly: it is left out too, harmlessly,
as the stronger lines below it set the window. A longer window passes less noise but rounds fast changes (a triangle
test's reversals) more. Used as a regressor (a damper's force against its velocity), both bias a fitted slope: the
noise low by its share of the rate's variance, the rounding high by the gain it loses (measured: 0.2 % at 2 Hz,
0.4 % at 8 Hz for a 1 kHz record with 1 % noise). Written here: the
choice of the window; the filter and the periodogram are SciPy's.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np
from scipy import signal

POLYORDER = 4
MIN_WINDOW = POLYORDER + 3
MAX_WINDOW = 4001
#: a periodogram line stands this far above the noise floor's mean to count as signal (noise alone: e^-14)
SIGNAL_LINE = 14.0
WINDOW_STEPS = 48  # candidate windows, spaced evenly in log between MIN_WINDOW and the longest allowed
COHERENCE_SEGMENTS = 8  # Welch segments (half overlapping) of the coherence with a witness
COHERENCE_LEVEL = 1e-3  # a line whose coherence a witness unrelated to it would exceed this seldom is the signal's


@dataclass(frozen=True)
class Rate:
    """The rate of a signal (its unit per s) and the Savitzky-Golay window it was taken with (samples); the
    expected RMS error of the rate (its unit per s) and the noise floor that estimate assumed (a one-sided PSD)."""

    values: np.ndarray
    window: int
    expected_error: float
    noise_floor: float


def choose_window(values: np.ndarray, rate: float, witness: np.ndarray | None = None) -> tuple[int, float, float]:
    """The odd Savitzky-Golay window (order ``POLYORDER``) that minimises the rate's expected mean-square error,
    that error's RMS, and the noise floor (a one-sided PSD: the upper half of the periodogram, whose median is
    ln 2 times the mean of a chi-square line with 2 degrees of freedom).

    The mean-square error of window w is ``sum S(f) |H_w(f) - i 2 pi f|^2 df + N0 sum |H_w(f)|^2 df``: the
    signal's lines S (the periodogram lines ``SIGNAL_LINE`` times above the floor N0, less the floor; with a
    ``witness`` sampled with ``values``, only those it is coherent with) distorted by the filter, plus the floor
    passed through it.
    """
    n = values.size
    frequencies, power = signal.periodogram(values, rate, window="hann", detrend="linear")
    floor = float(np.median(power[power.size // 2:])) / np.log(2.0)  # a periodogram line is chi^2, 2 dof: mean
    lines = np.where(power > SIGNAL_LINE * floor, power - floor, 0.0)
    content = np.where(_followed(values, witness, rate, frequencies), lines, 0.0) if witness is not None else lines
    df = frequencies[1] - frequencies[0]
    exact = 1j * 2 * np.pi * frequencies
    longest = min(n if n % 2 else n - 1, MAX_WINDOW)
    candidates = np.unique(np.geomspace(MIN_WINDOW, max(longest, MIN_WINDOW), WINDOW_STEPS).astype(int) | 1)
    best = (np.inf, MIN_WINDOW)
    for window in candidates[candidates <= longest]:
        response = _response(window, n, rate)[:frequencies.size]
        error = (np.sum(content * np.abs(response - exact) ** 2) + floor * np.sum(np.abs(response) ** 2)) * df
        best = min(best, (float(error), int(window)))
    return best[1], float(np.sqrt(best[0])), floor


def _followed(values: np.ndarray, witness: np.ndarray, rate: float, frequencies: np.ndarray) -> np.ndarray | bool:
    """Where ``witness`` follows ``values``: their coherence (SciPy's, ``COHERENCE_SEGMENTS`` Hann segments half
    overlapping) above the level ``1 - COHERENCE_LEVEL^(1 / (K - 1))`` that K segments of unrelated signals exceed
    with probability ``COHERENCE_LEVEL``, in the coherence bin of each of ``frequencies``. True everywhere for a
    record too short to tell (segments under 32 samples)."""
    segment = 2 * values.size // (COHERENCE_SEGMENTS + 1)
    if segment < 32:
        return True
    bins, coherence = signal.coherence(values, witness, rate, nperseg=segment)
    segments = (values.size - segment) // (segment - segment // 2) + 1
    followed = coherence > 1.0 - COHERENCE_LEVEL ** (1.0 / (segments - 1))
    return followed[np.clip(np.rint(frequencies / bins[1]).astype(int), 0, bins.size - 1)]


def _response(window: int, n: int, rate: float) -> np.ndarray:
    """The zero-phase frequency response of the Savitzky-Golay differentiator on the n-point FFT grid (per s)."""
    response = np.fft.rfft(_taps(window, rate), n)
    return response * np.exp(1j * 2 * np.pi * np.arange(response.size) / n * (window // 2))


@functools.lru_cache(maxsize=256)
def _taps(window: int, rate: float) -> np.ndarray:
    return signal.savgol_coeffs(window, POLYORDER, deriv=1, delta=1.0 / rate, use="conv")


def rate_of(values: np.ndarray, rate: float, window: int | None = None, witness: np.ndarray | None = None) -> Rate:
    """The rate of ``values`` sampled at ``rate`` Hz, by the Savitzky-Golay differentiator whose window the
    signal's spectrum sets (``choose_window``, the lines ``witness`` follows), or ``window`` samples (odd) when
    given."""
    values = np.asarray(values, dtype=float)
    chosen, error, floor = choose_window(values, rate, witness)
    if window is not None and window != chosen:
        error = float("nan")  # the estimate holds for the chosen window only
    window = window or chosen
    derivative = signal.savgol_filter(values, window, POLYORDER, deriv=1, delta=1.0 / rate, mode="interp")
    return Rate(derivative, window, error, floor)
