"""Discrepancy measures: the properties docs/contracts.md names for TDDI, RMS error and rainflow damage."""

import numpy as np
import pytest

from rig.signal.metrics import (
    DAMAGE_EXPONENT,
    ChannelMetrics,
    channel_metrics,
    damage_ratio,
    pseudo_damage,
    rms_error_pct,
    tddi,
)

T = np.linspace(0, 10, 5001)
SINE = np.sin(2 * np.pi * 1.3 * T)


def test_tddi_properties_of_forsen_eq_7():
    assert tddi(SINE, SINE) == 0.0
    assert tddi(SINE, np.full_like(SINE, SINE.mean())) == pytest.approx(1.0)  # against a constant at its mean
    assert tddi(SINE, -SINE) == pytest.approx(2.0)
    assert tddi(SINE, 1.1 * SINE) == pytest.approx(0.01 / (1 + 1.21))


def test_rms_error_is_percent_of_the_target_rms():
    assert rms_error_pct(SINE, 0.9 * SINE) == pytest.approx(10.0)
    assert rms_error_pct(SINE, SINE) == 0.0


def test_pseudo_damage_counts_full_cycles_of_range_to_the_sixth():
    # a triangle wave between -1 and 1 with 5 full cycles: 5 cycles of range 2
    wave = np.tile([0.0, 1.0, 0.0, -1.0], 5)
    wave = np.append(wave, 0.0)
    assert pseudo_damage(wave) == pytest.approx(5 * 2.0**DAMAGE_EXPONENT, rel=0.11)  # half cycles at the ends
    assert damage_ratio(SINE, 1.1 * SINE) == pytest.approx(1.1**6, rel=1e-9)


def test_peak_error_is_the_larger_miss_of_the_extremes():
    from rig.signal.metrics import peak_error_pct

    assert peak_error_pct(SINE, 1.1 * SINE) == pytest.approx(10.0)
    assert peak_error_pct(SINE, np.clip(SINE, -0.7, None)) == pytest.approx(30.0)  # the valley cut off
    assert peak_error_pct(SINE, np.roll(SINE, 17)) == pytest.approx(0.0, abs=1e-12)  # extremes, wherever they are


def test_channel_metrics_per_column():
    target = np.column_stack([SINE, 2 * SINE])
    metrics = channel_metrics(target, target * [1.0, 0.5], ["a", "b"])
    assert metrics["a"] == ChannelMetrics(rms_error_pct=0.0, tddi=0.0, peak_error_pct=0.0, damage_ratio=1.0)
    assert metrics["b"].rms_error_pct == pytest.approx(50.0)


def test_the_analysis_band_shrinks_with_a_low_rate_or_a_short_record_and_vanishes_below_two_octaves():
    from rig.constants import ANALYSIS_BAND, analysis_band

    assert analysis_band(512.0, 20.0) == ANALYSIS_BAND
    assert analysis_band(50.0, 20.0) == (0.5, 20.0)           # 0.8 of the Nyquist frequency
    assert analysis_band(512.0, 5.0) == (0.8, 50.0)           # four periods of the lowest frequency
    assert analysis_band(512.0, 0.5) == (8.0, 50.0)
    assert analysis_band(20.0, 2.0) == (2.0, 8.0)             # two octaves: still analysable
    assert analysis_band(10.0, 2.0) is None                   # 2-4 Hz: one octave
    assert analysis_band(512.0, 0.2) is None                  # 20-50 Hz
