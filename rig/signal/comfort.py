"""Ride comfort: ISO 2631-1 whole-body vibration frequency weighting Wk and the weighted RMS acceleration.

The weighting is built from the standard's analogue definition (ISO 2631-1:1997, Annex A): the product of a
band-limiting high-pass (f1 = 0.4 Hz) and low-pass (f2 = 100 Hz) second-order Butterworth pair, the
acceleration-velocity transition (f3, f4, Q4) and the upward step (f5, Q5, f6, Q6), with the Wk values below
(the same parameters ISO 8041 tabulates for Wk). ``wk_response`` is that analogue response.

``wk_filter`` realises it digitally. The bilinear transform is not good enough at rig sample rates: even
pre-warped factor by factor, its frequency warping leaves it 0.48 dB low at 80 Hz for 512 Hz sampling (2.5 dB
at 256 Hz; it needs about 1.1 kHz for 0.1 dB). Instead every finite pole and zero is mapped exactly
(z = exp(s/rate)) and the three zeros the analogue weighting has at infinity become a third-order FIR factor
fitted to the analogue magnitude (scipy.optimize least squares on log-magnitude, 0.1 Hz to 0.45 x rate); its
zeros are reflected inside the unit circle, so the filter is minimum phase like the analogue one. Checked on
300 rates from 256 Hz to 1 MHz, the magnitude stays within 0.035 dB of the analogue response from 0.5 to 80 Hz
(the tests hold it to 0.1 dB). Rates below 256 Hz (2.56 x the 100 Hz band limit) raise ValueError naming the
rate. Above 80 Hz, where Wk is 0.13 and falling, the filter may read up to about 1.6 dB over the analogue
response near the Nyquist frequency (rates up to 100 kHz).

``weighted_rms`` is the weighted r.m.s. acceleration a_w of ISO 2631-1's basic evaluation method: the record
filtered from rest, then the RMS over the whole record (a start-up transient is included, as in a measurement).
"""

from __future__ import annotations

import numpy as np
from scipy import optimize, signal

from rig.io.channels import split_channel
from rig.io.record import Record

# Wk parameters, ISO 2631-1:1997 Annex A (frequencies in Hz)
F1, F2, Q_BAND = 0.4, 100.0, 1.0 / np.sqrt(2.0)  # band-limiting high-pass and low-pass (Butterworth)
F3, F4, Q4 = 12.5, 12.5, 0.63                    # acceleration-velocity transition
F5, Q5, F6, Q6 = 2.37, 0.91, 3.35, 0.91          # upward step

MIN_RATE = 2.56 * F2  # Hz, lowest sample rate wk_filter accepts (256 Hz)

# Fit of the FIR factor: log-spaced frequencies from _FIT_LOW to F2 (weight 1) and from F2 to _FIT_HIGH x rate
# (weight _FIT_WEIGHT_ABOVE, so the far stop band, where Wk is tiny, cannot pull the 0.5-80 Hz band off).
_FIT_LOW = 0.1            # Hz
_FIT_HIGH = 0.45          # fraction of the sample rate
_FIT_POINTS = (300, 100)  # below and above F2
_FIT_WEIGHT_ABOVE = 0.3
_INFINITE_ZEROS = 3       # analogue poles minus finite zeros: the order of the fitted FIR factor


def _sections() -> list[tuple[list[float], list[float]]]:
    """Numerator and denominator polynomials in s (descending powers) of the four Annex A factors."""
    w1, w2, w3, w4, w5, w6 = (2.0 * np.pi * f for f in (F1, F2, F3, F4, F5, F6))
    return [
        ([1.0, 0.0, 0.0], [1.0, w1 / Q_BAND, w1**2]),         # high-pass: s^2 / (s^2 + s w1/Q + w1^2)
        ([w2**2], [1.0, w2 / Q_BAND, w2**2]),                 # low-pass: w2^2 / (s^2 + s w2/Q + w2^2)
        ([w4**2 / w3, w4**2], [1.0, w4 / Q4, w4**2]),         # transition: (1 + s/w3) / (1 + s/(Q4 w4) + s^2/w4^2)
        ([1.0, w5 / Q5, w5**2], [1.0, w6 / Q6, w6**2]),       # upward step, gain (w5/w6)^2 at 0 Hz, 1 at high f
    ]


def wk_response(frequency: np.ndarray) -> np.ndarray:
    """Complex analogue Wk response (dimensionless) at ``frequency`` (Hz), any array shape."""
    s = 2j * np.pi * np.asarray(frequency, dtype=float)
    response = np.ones_like(s)
    for numerator, denominator in _sections():
        response *= np.polyval(numerator, s) / np.polyval(denominator, s)
    return response


def wk_filter(rate: float) -> np.ndarray:
    """Second-order sections (scipy.signal) realising Wk at ``rate`` Hz, at least ``MIN_RATE`` (256 Hz)."""
    if not np.isfinite(rate) or rate < MIN_RATE:
        raise ValueError(f"sample rate {rate} Hz is too low for the Wk weighting: it needs at least "
                         f"{MIN_RATE:g} Hz (2.56 x the {F2:g} Hz band limit) to hold 0.1 dB up to 80 Hz")
    zeros, poles = [], []
    for numerator, denominator in _sections():
        z, p, _ = signal.tf2zpk(numerator, denominator)
        zeros.extend(np.exp(z / rate))
        poles.extend(np.exp(p / rate))
    below, above = _FIT_POINTS
    freq = np.concatenate([np.geomspace(_FIT_LOW, F2, below), np.geomspace(F2, _FIT_HIGH * rate, above + 1)[1:]])
    weight = np.concatenate([np.ones(below), np.full(above, _FIT_WEIGHT_ABOVE)])
    _, matched = signal.freqz_zpk(zeros, poles, 1.0, worN=freq, fs=rate)
    log_target = np.log(np.abs(wk_response(freq)) / np.abs(matched))
    delays = np.exp(-2j * np.pi * np.outer(freq / rate, np.arange(_INFINITE_ZEROS + 1)))  # z^-m on the circle
    start = np.zeros(_INFINITE_ZEROS + 1)
    start[0] = np.exp(np.median(log_target))
    fir = optimize.least_squares(lambda c: weight * (np.log(np.abs(delays @ c)) - log_target), start, method="lm").x
    roots = np.roots(fir)
    outside = np.abs(roots) > 1.0
    gain = fir[0] * np.prod(np.abs(roots[outside]))  # |z - r| = |r| |z - 1/conj(r)| on the unit circle
    roots[outside] = 1.0 / np.conj(roots[outside])
    return signal.zpk2sos(np.concatenate([zeros, roots]), poles, gain)


def weighted_rms(acceleration: np.ndarray, rate: float) -> float:
    """Wk-weighted RMS acceleration a_w (m/s^2) of ``acceleration`` (m/s^2) sampled at ``rate`` Hz."""
    values = np.asarray(acceleration, dtype=float)
    if values.ndim != 1 or values.size == 0:
        raise ValueError(f"acceleration must be a non-empty one-dimensional array, got shape {values.shape}")
    bad = np.flatnonzero(~np.isfinite(values))
    if bad.size:
        raise ValueError(f"acceleration has a non-finite value ({values[bad[0]]}) at sample {bad[0]}")
    weighted = signal.sosfilt(wk_filter(rate), values)
    return float(np.sqrt(np.mean(weighted**2)))


def comfort_summary(record: Record) -> dict[str, float]:
    """Wk-weighted RMS (m/s^2) of every ``<corner>/sprung_acc`` channel of ``record`` and of a truck's seat point
    (``cab/seat_acc``), keyed by channel name."""
    return {name: weighted_rms(record[name], record.rate) for name in record.names
            if split_channel(name)[0] and split_channel(name)[1] in ("sprung_acc", "seat_acc")}
