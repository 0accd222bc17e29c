"""A record sampled far above what a diagnosis uses is decimated before it is diagnosed."""

import numpy as np
import pytest
from independent_rig import Hidden, independent_records

from rig.diagnosis.core.working_rate import MIN_RATE, at_working_rate, working_factor
from rig.diagnosis.rig_test.diagnose import diagnose
from rig.io.multirate import decimated
from rig.io.record import Record
from rig.vehicle.vehicle_file import load_vehicle


@pytest.mark.parametrize(("rate", "factor"), [(200.0, 1), (512.0, 1), (960.0, 1), (1000.0, 2), (1024.0, 2),
                                              (2048.0, 4), (2500.0, 5), (5000.0, 10), (10240.0, 20)])
def test_working_factor_keeps_at_least_the_minimum_rate(rate, factor):
    assert MIN_RATE == 500.0
    assert working_factor(rate) == factor
    assert rate / factor >= MIN_RATE or factor == 1


def test_decimation_keeps_the_bands_used_and_their_timing_and_removes_what_would_alias():
    rate, seconds = 1000.0, 8.0
    t = np.arange(int(rate * seconds)) / rate
    used = np.sin(2 * np.pi * 20.0 * t) + 0.3 * np.sin(2 * np.pi * 150.0 * t + 0.4)
    above = 0.5 * np.sin(2 * np.pi * 300.0 * t) + 0.5 * np.sin(2 * np.pi * 420.0 * t)  # would alias to 200, 80 Hz
    record = Record(rate, {"FL/sprung_acc": used + above}, metadata={"test": "rig"}, start_time=2.0)
    slow = decimated(record, 2)
    assert slow.rate == 500.0 and slow.start_time == 2.0 and slow.metadata["test"] == "rig"
    assert "decimated to 500 Hz" in slow.metadata["resampled"]
    inner = slice(200, -200)  # the filter's start and end
    assert np.max(np.abs(slow["FL/sprung_acc"] - used[::2])[inner]) < 0.01  # in place and in time, nothing aliased


def test_a_fast_record_is_diagnosed_at_the_working_rate():
    """Records of the independent simulator at 1024 Hz: decimated to 512 Hz (said so), the hidden tyre damping found
    at its value."""
    proton_x = load_vehicle("proton_x")
    measured, holdout, _ = independent_records(proton_x, Hidden(tyre_damping=300.0), 4, 12.0, 6.0, rate=1024.0,
                                               events=0.015)
    slow, slow_holdout, notes = at_working_rate(measured, holdout)
    assert (slow.rate, slow_holdout.rate) == (512.0, 512.0) and len(notes) == 2
    result = diagnose(proton_x, measured, holdout, causes=("tyre_damping",))
    assert any("decimated from 1024 to 512 Hz" in n for n in result.notes)
    assert result.compared["measured"].rate == 512.0
    assert result.verdict == ("tyre_damping",)
    for value in result.named[0].params.values():
        assert value == pytest.approx(300.0, rel=0.1)
