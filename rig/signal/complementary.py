"""A rate measured twice, blended: the derivative of a displacement below a crossover frequency and the integral of
an acceleration above it (a complementary filter, as inertial navigation blends its sensors).

Differentiating a displacement multiplies its white noise by 2 pi f, so above a few hertz the rate is mostly noise;
integrating an acceleration divides its noise by 2 pi f but leaves its drift and offset below. With the low-pass
weight W(f) = 1 / (1 + (f / f_c)^4) on the displacement's derivative and 1 - W on the acceleration's integral,

    V(f) = W(f) i 2 pi f X(f) + (1 - W(f)) A(f) / (i 2 pi f),

the two weights sum to one at every frequency (the rate itself passes unchanged) and the integral's weight falls as
f^4 towards zero, faster than 1 / f grows: no drift. A suspension's travel (a potentiometer, an LVDT) and the wheel's
acceleration less the body's give its rate so. The crossover is where the two noises are equal: with white noise of
densities S_x (displacement) and S_a (acceleration), (2 pi f_c)^4 = S_a / S_x, each read as the median of the
signal's Welch periodogram over NOISE_BAND of the Nyquist frequency, where a record sampled well above its motion
holds only noise (clamped to CROSSOVER_RANGE). On the quarter car of tests/test_neuro_law.py (2 % noise on travel
and accelerations) that is 8.2 Hz; the law's residual there is white with it and not with 3 Hz (the integral's
red noise).

Written here (a few lines of NumPy FFT; the periodogram is SciPy's); the record is padded with its end values for
two periods of the crossover at each end, so nothing wraps from its end to its start.
"""

from __future__ import annotations

import numpy as np
from scipy import signal

NOISE_BAND = (0.6, 0.95)       # of the Nyquist frequency: where the noise floors are read
CROSSOVER_RANGE = (0.5, 20.0)  # Hz


def crossover(displacement: np.ndarray, acceleration: np.ndarray, rate: float) -> float:
    """The frequency (Hz) where the displacement's differentiated noise equals the acceleration's integrated noise."""
    frequency, px = signal.welch(displacement, rate, nperseg=min(1024, displacement.shape[0]))
    _, pa = signal.welch(acceleration, rate, nperseg=min(1024, acceleration.shape[0]))
    upper = (frequency > NOISE_BAND[0] * rate / 2) & (frequency < NOISE_BAND[1] * rate / 2)
    ratio = np.median(pa[upper]) / max(np.median(px[upper]), 1e-300)
    return float(np.clip(ratio ** 0.25 / (2 * np.pi), *CROSSOVER_RANGE))


def blended_rate(displacement: np.ndarray, acceleration: np.ndarray, rate: float,
                 crossover_hz: float | None = None) -> np.ndarray:
    """The rate (unit of ``displacement`` per s) of a displacement whose second derivative ``acceleration`` is
    measured too (same samples, one signal), blended at ``crossover_hz`` (default: where their noises are equal)."""
    crossover_hz = crossover(displacement, acceleration, rate) if crossover_hz is None else crossover_hz
    n = displacement.shape[0]
    extra = int(round(2 * rate / crossover_hz))
    shape = [(extra, extra)] + [(0, 0)] * (displacement.ndim - 1)
    x = np.pad(displacement, shape, mode="edge")
    a = np.pad(acceleration - np.mean(acceleration, axis=0), shape)
    frequency = np.fft.rfftfreq(n + 2 * extra, 1.0 / rate)
    s = 2j * np.pi * frequency
    weight = 1.0 / (1.0 + (frequency / crossover_hz) ** 4)
    integral = np.zeros_like(s)
    integral[1:] = (1.0 - weight[1:]) / s[1:]
    spectrum = (weight * s).reshape((-1,) + (1,) * (x.ndim - 1)) * np.fft.rfft(x, axis=0) \
        + integral.reshape((-1,) + (1,) * (a.ndim - 1)) * np.fft.rfft(a, axis=0)
    return np.fft.irfft(spectrum, n + 2 * extra, axis=0)[extra:extra + n]
