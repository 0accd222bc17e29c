"""MIMO FRF estimation and the regularised inverse, on systems with known transfer functions."""

import numpy as np
import pytest
from scipy import signal

from rig.signal.frf import estimate_frf, spectral_matrices
from rig.signal.inverse import apply_frf, band_window, regularised_inverse

RATE = 512.0
N = 2**16


@pytest.fixture(scope="module")
def two_by_two():
    """y1 = B20(x1) + 0.5 L5(x2), y2 = 2 x2, with B20 a 20 Hz Butterworth low-pass and L5 a 5 Hz one."""
    rng = np.random.default_rng(0)
    x = rng.standard_normal((N, 2))
    b1, a1 = signal.butter(2, 20, fs=RATE)
    b2, a2 = signal.butter(1, 5, fs=RATE)
    y = np.column_stack([signal.lfilter(b1, a1, x[:, 0]) + 0.5 * signal.lfilter(b2, a2, x[:, 1]), 2 * x[:, 1]])
    return x, y, (b1, a1), (b2, a2)


def test_h1_and_hv_match_the_known_filters(two_by_two):
    x, y, f1, f2 = two_by_two
    frf = estimate_frf(spectral_matrices(x, y, RATE, 2048))
    band = (frf.frequency > 1) & (frf.frequency < 40)
    w = 2 * np.pi * frf.frequency[band] / RATE
    h11 = signal.freqz(*f1, worN=w)[1]
    h12 = 0.5 * signal.freqz(*f2, worN=w)[1]
    for estimate in (frf.h1, frf.hv):
        np.testing.assert_allclose(estimate[band, 0, 0], h11, rtol=0.02)
        np.testing.assert_allclose(estimate[band, 0, 1], h12, rtol=0.03)
        np.testing.assert_allclose(estimate[band, 1, 1], 2.0, rtol=1e-6)
        np.testing.assert_allclose(estimate[band, 1, 0], 0.0, atol=1e-6)
    assert frf.coherence[band].min() > 0.99  # noise-free and linear


def test_coherence_drops_with_output_noise(two_by_two):
    x, y, _, _ = two_by_two
    noisy = y + np.random.default_rng(1).standard_normal(y.shape) * y.std(axis=0)  # SNR 0 dB
    frf = estimate_frf(spectral_matrices(x, noisy, RATE, 2048))
    band = (frf.frequency > 1) & (frf.frequency < 15)
    assert 0.4 < np.median(frf.coherence[band, 1]) < 0.6  # y2 = 2 x2 plus white noise of equal power
    assert np.median(frf.coherence[band, 0]) > 0.85  # y1 is low-pass: its noise is spread to 256 Hz


def test_inverse_undoes_the_system_in_band_and_is_zero_outside(two_by_two):
    x, y, _, _ = two_by_two
    frf = estimate_frf(spectral_matrices(x, y, RATE, 2048))
    inverse = regularised_inverse(frf.h1, frf.coherence, frf.frequency, band=(1.0, 40.0), alpha=1e-3, floor=0.0)
    product = inverse @ frf.h1
    band = (frf.frequency > 1.5) & (frf.frequency < 28)
    np.testing.assert_allclose(product[band], np.broadcast_to(np.eye(2), product[band].shape), atol=5e-3)
    assert np.all(inverse[frf.frequency > 40 * 2**0.5] == 0) and np.all(inverse[frf.frequency < 2**-0.5] == 0)


def test_band_window_is_one_in_band_and_smooth_at_the_edges():
    f = np.concatenate([[0.0], np.logspace(-2, 2, 4001)])
    window = band_window(f, (0.5, 50.0))
    assert np.all(window[(f >= 0.5) & (f <= 50)] == 1.0)
    assert window[f == 0].item() == 0.0 and np.all(window[f > 50 * 2**0.5 + 1e-9] == 0)
    assert np.max(np.abs(np.diff(window))) < 0.02


def test_filtering_by_an_frf_does_not_wrap_around():
    frequency = np.fft.rfftfreq(1024, 1 / RATE)
    delay = np.exp(-2j * np.pi * frequency * 0.05)[:, None, None]  # a 50 ms delay
    impulse = np.zeros((4096, 1))
    impulse[-10] = 1.0  # 10 samples before the end: a circular filter would bring it back at the start
    out = apply_frf(delay, impulse)
    assert np.abs(out[:1000]).max() < 1e-6
