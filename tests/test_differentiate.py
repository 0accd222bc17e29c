"""Rates of measured signals (rig/signal/differentiate.py): the Savitzky-Golay derivative against the exact one,
its window following the signal's spectrum, and its expected error against the error measured."""

import numpy as np
import pytest

from rig.signal.differentiate import choose_window, rate_of

RATE = 1000.0


def _noisy_sine(frequency, seconds=6.0, amplitude=0.025, noise=0.01, seed=0):
    t = np.arange(int(seconds * RATE)) / RATE
    x = amplitude * np.sin(2 * np.pi * frequency * t)
    rng = np.random.default_rng(seed)
    return x + noise * np.std(x) * rng.standard_normal(t.size), amplitude * 2 * np.pi * frequency * np.cos(
        2 * np.pi * frequency * t)


@pytest.mark.parametrize("frequency", [0.5, 2.0, 8.0])
def test_rate_of_a_noisy_sine_is_within_its_expected_error(frequency):
    """1 % noise on the displacement: the rate is within 1 % RMS of the exact cos, its gain within 0.5 % of one,
    and the error the window choice expected is the one found (within 20 %)."""
    x, exact = _noisy_sine(frequency)
    rate = rate_of(x, RATE)
    error = rate.values - exact
    assert np.std(error) / np.std(exact) < 0.01
    assert np.dot(rate.values, exact) / np.dot(exact, exact) == pytest.approx(1.0, abs=5e-3)
    assert np.sqrt(np.mean(error ** 2)) == pytest.approx(rate.expected_error, rel=0.2)


def test_window_shortens_as_the_signal_gets_faster_and_lengthens_with_noise():
    windows = [choose_window(_noisy_sine(f)[0], RATE)[0] for f in (0.5, 2.0, 8.0)]
    assert windows[0] > windows[1] > windows[2]
    quiet = choose_window(_noisy_sine(2.0, noise=1e-4)[0], RATE)[0]
    assert quiet < windows[1]


def test_a_polynomial_is_differentiated_exactly():
    """Order 4 fits a cubic exactly over any window: the rate of t^3 is 3 t^2 to rounding."""
    t = np.arange(2000) / RATE
    rate = rate_of(t ** 3, RATE, window=101)
    np.testing.assert_allclose(rate.values, 3 * t ** 2, atol=1e-9)
