"""ISO 2631-1 Wk weighting and weighted RMS (rig.comfort): the standard's table, the digital filter, bad input."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import signal

from rig.io.record import Record
from rig.signal.comfort import MIN_RATE, comfort_summary, weighted_rms, wk_filter, wk_response

# ISO 2631-1:1997 Table 3, Wk column: weighting factor x 1000 at 1/3-octave centre frequencies (Hz)
WK_TABLE = {0.5: 418, 1.0: 482, 2.0: 531, 4.0: 967, 8.0: 1036, 16.0: 768}


def db(ratio: np.ndarray) -> np.ndarray:
    return 20.0 * np.log10(np.abs(ratio))


@pytest.mark.parametrize("frequency", sorted(WK_TABLE))
def test_analogue_wk_matches_the_standard_table(frequency: float) -> None:
    tabulated = WK_TABLE[frequency] / 1000.0
    assert abs(db(wk_response(np.array([frequency]))[0] / tabulated)) < 0.5


@pytest.mark.parametrize("rate", [MIN_RATE, 512.0, 1000.0])
def test_digital_filter_matches_analogue_magnitude(rate: float) -> None:
    frequency = np.geomspace(0.5, 80.0, 400)
    _, digital = signal.sosfreqz(wk_filter(rate), worN=frequency, fs=rate)
    assert np.max(np.abs(db(digital / wk_response(frequency)))) < 0.1


def test_filter_is_stable() -> None:
    assert np.all(np.abs(signal.sos2zpk(wk_filter(512.0))[1]) < 1.0)


def test_weighted_rms_of_a_sine() -> None:
    rate, amplitude, frequency = 512.0, 1.5, 4.0
    time = np.arange(int(120 * rate)) / rate  # 120 s: the start-up transient changes the RMS by about 0.03 %
    expected = amplitude / np.sqrt(2.0) * abs(wk_response(np.array([frequency]))[0])
    assert weighted_rms(amplitude * np.sin(2 * np.pi * frequency * time), rate) == pytest.approx(expected, rel=5e-3)


def test_comfort_summary_covers_every_sprung_acc_channel() -> None:
    rate = 512.0
    time = np.arange(int(20 * rate)) / rate
    channels = {"FL/sprung_acc": np.sin(2 * np.pi * 2.0 * time), "RR/sprung_acc": 0.5 * np.sin(2 * np.pi * 8.0 * time),
                "FL/susp_travel": 0.01 * np.sin(2 * np.pi * 1.0 * time)}
    summary = comfort_summary(Record(rate, channels))
    assert summary == {name: weighted_rms(channels[name], rate) for name in ("FL/sprung_acc", "RR/sprung_acc")}


def test_nan_acceleration_is_rejected() -> None:
    acceleration = np.zeros(1000)
    acceleration[17] = np.nan
    with pytest.raises(ValueError, match=r"non-finite value \(nan\) at sample 17"):
        weighted_rms(acceleration, 512.0)


@pytest.mark.parametrize("acceleration", [np.zeros(0), np.zeros((10, 2))])
def test_empty_or_2d_acceleration_is_rejected(acceleration: np.ndarray) -> None:
    with pytest.raises(ValueError, match="non-empty one-dimensional"):
        weighted_rms(acceleration, 512.0)


@pytest.mark.parametrize("rate", [200.0, 255.9, float("nan")])
def test_too_low_rate_is_rejected(rate: float) -> None:
    with pytest.raises(ValueError, match=rf"sample rate {rate} Hz is too low .* at least 256 Hz"):
        weighted_rms(np.zeros(1000), rate)
