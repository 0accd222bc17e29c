"""Test signals (band-limited random drives for demos and rig identification, multisines for FRFs), the
zero-phase band-pass, and band-limited integration of measured accelerations."""

from __future__ import annotations

import functools

import numpy as np
from scipy import signal


def band_limited_noise(duration: float, rate: float, band: tuple[float, float], rms: float, channels: int,
                       seed: int = 0, taper: float = 1.0, slope: float = 0.0) -> np.ndarray:
    """Gaussian noise (samples x channels) with a PSD proportional to f^-slope inside ``band`` Hz (flat by
    default, pink for ``slope=1``) and ``rms`` per channel.

    Shaped in the frequency domain (exactly zero outside the band); ``taper`` s of raised-cosine fade at
    each end, so the signal starts and ends at zero.
    """
    n = int(round(duration * rate))
    rng = np.random.default_rng(seed)
    spectrum = np.fft.rfft(rng.standard_normal((n, channels)), axis=0)
    frequency = np.fft.rfftfreq(n, 1.0 / rate)
    outside = (frequency < band[0]) | (frequency > band[1])
    spectrum[outside] = 0.0
    spectrum[~outside] *= frequency[~outside, None] ** (-slope / 2)
    noise = np.fft.irfft(spectrum, n, axis=0)
    noise *= fade_window(n, int(round(taper * rate)))[:, None]
    return noise * (rms / np.sqrt(np.mean(noise**2, axis=0)))


def fade_window(n: int, fade: int, fade_out: bool = True) -> np.ndarray:
    """Ones with a raised-cosine fade-in (and, by default, fade-out) of ``fade`` samples."""
    window = np.ones(n)
    if fade > 0:
        ramp = 0.5 - 0.5 * np.cos(np.pi * np.arange(fade) / fade)
        window[:fade] = ramp
        if fade_out:
            window[n - fade:] = ramp[::-1]
    return window


def periodic_multisine(frequencies: np.ndarray, rate: float, period_samples: int, periods: int, rms: float,
                       seed: int = 0) -> np.ndarray:
    """Multisine with exact periodicity: ``frequencies`` must be multiples of rate / period_samples.

    Random phases; returns ``periods`` repetitions (the first ones let transients die out).
    """
    resolution = rate / period_samples
    lines = np.round(np.asarray(frequencies) / resolution).astype(int)
    if not np.allclose(lines * resolution, frequencies):
        raise ValueError("multisine frequencies must lie on the grid rate / period_samples")
    spectrum = np.zeros(period_samples // 2 + 1, complex)
    spectrum[lines] = np.exp(1j * np.random.default_rng(seed).uniform(0, 2 * np.pi, lines.size))
    one_period = np.fft.irfft(spectrum, period_samples)
    one_period *= rms / np.sqrt(np.mean(one_period**2))
    return np.tile(one_period, periods)


def frf_of_periodic(response: np.ndarray, excitation: np.ndarray, period_samples: int, lines: np.ndarray) -> np.ndarray:
    """FRF response/excitation at FFT ``lines`` of the last full period (noise-free for periodic signals)."""
    last = slice(-period_samples, None)
    return np.fft.rfft(response[last], axis=0)[lines] / np.fft.rfft(excitation[last], axis=0)[lines]


@functools.lru_cache(maxsize=64)
def _band_pass_design(order: int, low: float, high: float, rate: float) -> np.ndarray:
    """The Butterworth band-pass's second-order sections, designed once per band and rate (a diagnosis band-passes
    every simulation of a fit: 2 ms a design); the caller's to copy (SciPy's filter takes only a writable array)."""
    return signal.butter(order, (low, high), btype="bandpass", fs=rate, output="sos")


def band_pass(values: np.ndarray, rate: float, band: tuple[float, float], order: int = 8) -> np.ndarray:
    """Zero-phase Butterworth band-pass along the first axis (forward-backward: twice ``order``).

    As RPC practice does to measured targets before iterating (Nurhadiyanto's thesis, section 4.1.1: 0.6-50 Hz) and
    the Duisburg-Essen validation paper to its data (zero-phase Butterworth).
    """
    sos = _band_pass_design(order, float(band[0]), float(band[1]), float(rate)).copy()
    # pad (odd reflection) by several periods of the lowest frequency, not the default few samples, so the
    # filter's start-up does not distort the ends
    padlen = min(values.shape[0] - 1, int(3 * rate / band[0]))
    return signal.sosfiltfilt(sos, values, axis=0, padlen=padlen)


def integrate(values: np.ndarray, rate: float, low: float, times: int = 1, pad: bool = False) -> np.ndarray:
    """Band-limited integral (``times`` times) along the first axis: division by (j omega)^times in the
    frequency domain at and above ``low`` Hz, nothing below (there the division would only amplify drift and
    leakage). Written here because the usual cumulative trapezoid drifts on measured accelerations
    (Nurhadiyanto's thesis, section 4.2.2: the "sine trend" its integrated signals show). With ``pad`` the record
    is padded with rest for 1 / low s at each end, so nothing wraps from its end to its start."""
    n = values.shape[0]
    extra = int(round(rate / low)) if pad else 0
    spectrum = np.fft.rfft(np.pad(values, [(extra, extra)] + [(0, 0)] * (values.ndim - 1)), axis=0)
    omega = 2 * np.pi * np.fft.rfftfreq(n + 2 * extra, 1.0 / rate)
    inside = omega >= 2 * np.pi * low
    factor = np.zeros(omega.shape, complex)
    factor[inside] = (1j * omega[inside]) ** -times
    integral = np.fft.irfft(spectrum * factor.reshape((-1,) + (1,) * (values.ndim - 1)), n + 2 * extra, axis=0)
    return integral[extra:extra + n]
