"""A noise-free FRF check: a multisine with exact periodicity at RATE, lines LINES of a PERIOD, and the comparison
of a measured FRF with a closed form."""

import numpy as np

RATE = 512.0
PERIOD = 2048  # samples: 0.25 Hz lines
LINES = np.arange(2, 121)  # 0.5 ... 30 Hz
FREQUENCY = LINES * RATE / PERIOD


def assert_frf_close(measured, expected, tolerance=0.001):
    """Complex error within ``tolerance`` of the closed form, or of 1 % of its peak near a zero (an antiresonance,
    where X_b / F vanishes: the wheel alone on its tyre)."""
    error = np.abs(measured - expected) / np.maximum(np.abs(expected), 0.01 * np.abs(expected).max())
    assert error.max() < tolerance, f"{100 * error.max():.3f} % at {FREQUENCY[np.argmax(error)]} Hz"
