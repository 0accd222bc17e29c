"""A record sampled well above what a diagnosis uses is resampled before it is diagnosed."""

from fractions import Fraction

import numpy as np
import pytest
from independent_rig import Hidden, independent_records

from rig.diagnosis.core.working_rate import MIN_RATE, RATE_MARGIN, at_working_rate, working_ratio
from rig.diagnosis.rig_test.diagnose import diagnose
from rig.io.multirate import resampled
from rig.io.record import Record
from rig.vehicle.mjcf import timestep_for
from rig.sim.step_size import COARSE_TIMESTEP
from rig.vehicle.vehicle_file import load_vehicle


@pytest.mark.parametrize(("rate", "ratio"), [(200.0, 1), (512.0, 1), (599.0, 1), (600.0, Fraction(5, 6)),
                                             (800.0, Fraction(5, 8)), (819.2, Fraction(11, 18)),
                                             (960.0, Fraction(12, 23)), (999.0, Fraction(167, 333)),
                                             (1000.0, Fraction(1, 2)), (1024.0, Fraction(1, 2)),
                                             (2048.0, Fraction(1, 4)), (2500.0, Fraction(1, 5)),
                                             (5000.0, Fraction(1, 10)), (10240.0, Fraction(1, 20))])
def test_the_working_rate_keeps_at_least_the_minimum_rate_and_one_coarse_step_a_sample(rate, ratio):
    assert MIN_RATE == 500.0
    assert working_ratio(rate) == ratio
    working = rate * ratio
    assert working == rate or MIN_RATE <= working <= (2 if ratio.numerator == 1 else 1 + RATE_MARGIN) * MIN_RATE
    assert working == rate or timestep_for(working, COARSE_TIMESTEP)[1] == 1


@pytest.mark.parametrize(("rate", "ratio"), [(1000.0, Fraction(1, 2)), (800.0, Fraction(5, 8))])
def test_resampling_keeps_the_bands_used_and_their_timing_and_removes_what_would_alias(rate, ratio):
    seconds = 8.0
    t = np.arange(int(rate * seconds)) / rate
    used = lambda t: np.sin(2 * np.pi * 20.0 * t) + 0.3 * np.sin(2 * np.pi * 150.0 * t + 0.4)  # noqa: E731
    above = 0.5 * np.sin(2 * np.pi * 300.0 * t) + 0.5 * np.sin(2 * np.pi * 370.0 * t)  # would alias to 200, 130 Hz
    record = Record(rate, {"FL/sprung_acc": used(t) + above}, metadata={"test": "rig"}, start_time=2.0)
    slow = resampled(record, ratio)
    assert slow.rate == 500.0 and slow.start_time == 2.0 and slow.metadata["test"] == "rig"
    assert "resampled to 500 Hz" in slow.metadata["resampled"]
    inner = slice(200, -200)  # the filter's start and end
    on_grid = used(np.arange(slow["FL/sprung_acc"].size) / slow.rate)
    assert np.max(np.abs(slow["FL/sprung_acc"] - on_grid)[inner]) < 0.01  # in place and in time, nothing aliased


@pytest.mark.parametrize(("rate", "working", "how"), [(1024.0, 512.0, "decimated"), (800.0, 500.0, "resampled")])
def test_a_fast_record_is_diagnosed_at_the_working_rate(rate, working, how):
    """Records of the independent simulator at 1024 and 800 Hz: decimated to 512 Hz and resampled to 500 Hz (said
    so), the hidden tyre damping found at its value."""
    proton_x = load_vehicle("proton_x")
    measured, holdout, _ = independent_records(proton_x, Hidden(tyre_damping=300.0), 4, 12.0, 6.0, rate=rate,
                                               events=0.015)
    slow, slow_holdout, notes = at_working_rate(measured, holdout)
    assert (slow.rate, slow_holdout.rate) == (working, working) and len(notes) == 2
    result = diagnose(proton_x, measured, holdout, causes=("tyre_damping",))
    assert any(f"{how} from {rate:g} to {working:g} Hz" in n for n in result.notes)
    assert result.compared["measured"].rate == working
    assert result.verdict == ("tyre_damping",)
    for value in result.named[0].params.values():
        assert value == pytest.approx(300.0, rel=0.1)
