"""Forsén's discrepancy measures (Forsén 1999, eqs. 7-13; rig/signal/discrepancy.py) against values computed by hand,
and on a validation of a truck's rig test."""

import numpy as np
import pytest

from rig.signal.comfort import wk_response
from rig.signal.discrepancy import discrepancy, relative_discrepancy, run_discrepancy, tddi_against_measured
from rig.signal.metrics import tddi

RATE = 512.0


def test_the_tddi_against_the_measured_variance_is_eq_8_beside_eq_7():
    a, f = np.array([1.0, 2.0, 3.0, 4.0]), np.array([1.0, 2.0, 2.0, 5.0])
    # by hand: sum (a - f)^2 = 2; sum (a - 2.5)^2 = 5; sum (f - 2.5)^2 = 9
    assert tddi_against_measured(a, f) == pytest.approx(2 / 5, rel=1e-12)
    assert tddi(a, f) == pytest.approx(2 / 14, rel=1e-12)
    sine = np.sin(np.linspace(0, 20 * np.pi, 2001))
    assert tddi_against_measured(sine, np.zeros_like(sine)) == pytest.approx(1.0, rel=1e-3)  # the mean
    assert tddi_against_measured(sine, -sine) == pytest.approx(4.0, rel=1e-3)   # eq. 7 gives 2
    assert tddi(sine, -sine) == pytest.approx(2.0, rel=1e-3)
    assert tddi_against_measured(sine, sine) == 0.0


def test_the_scalar_indices_are_the_thesis_forms():
    assert relative_discrepancy(2.0, 1.5) == pytest.approx(0.25)          # (DI(a) - DI(f)) / DI(a)
    assert relative_discrepancy(2.0, 2.5) == pytest.approx(-0.25)         # the model responds more
    assert run_discrepancy(2.0, 1.5) == pytest.approx(0.5 / 1.75)         # |DI(a) - DI(b)| / mean
    assert run_discrepancy(1.5, 2.0) == run_discrepancy(2.0, 1.5)


def sine(amplitude: float, frequency: float = 4.0, seconds: float = 20.0) -> np.ndarray:
    return amplitude * np.sin(2 * np.pi * frequency * np.arange(int(seconds * RATE)) / RATE)


def test_ride_payload_and_fatigue_indices_of_scaled_sines_are_what_the_scaling_says():
    """A model whose seat moves 0.8 times the measured seat gives a ride index of 0.2; body accelerometers 1 m/s^2 on
    the left and 2 m/s^2 on the right, modelled at half, give a payload index of 0.5 and a payload DI of the two sides'
    mean; a wheel force at half amplitude has 1/64 of the damage (exponent 6): its fatigue index is 63/64, and the
    test's fatigue index takes the force channels only."""
    names = ["cab/seat_acc", "FL/sprung_acc", "FR/sprung_acc", "RL/sprung_acc", "RR/sprung_acc", "FL/tyre_force",
             "FL/susp_travel"]
    measured = np.column_stack([sine(1.0), sine(1.0), sine(2.0), sine(1.0), sine(2.0), sine(1000.0), sine(0.01)])
    model = measured * np.array([0.8, 0.5, 0.5, 0.5, 0.5, 0.5, 1.0])
    result = discrepancy(measured, model, names, RATE)
    weight = abs(wk_response(np.array([4.0]))[0])
    assert result.ride == pytest.approx(0.2, rel=1e-9)
    assert result.ride_di[0] == pytest.approx(weight / np.sqrt(2), rel=0.01)  # a_w of a unit sine: |Wk| / sqrt 2
    assert result.payload == pytest.approx(0.5, rel=1e-9)
    assert result.payload_di[0] == pytest.approx(1.5 * weight / np.sqrt(2), rel=0.01)  # (1 + 2) / 2 per side
    assert result.channels["FL/tyre_force"].fatigue == pytest.approx(63 / 64, rel=1e-9)
    assert result.fatigue_channels == ("FL/tyre_force",) and result.fatigue == pytest.approx(63 / 64, rel=1e-9)
    assert result.channels["FL/susp_travel"].tddi == 0.0 and result.channels["FL/susp_travel"].fatigue == 0.0
    # eq. 8 of a signal at half: sum (a/2)^2 / sum a^2 = 1/4; eq. 7: (1/4) / (1 + 1/4) = 1/5
    assert result.channels["FL/sprung_acc"].tddi_measured == pytest.approx(0.25, rel=1e-6)
    assert result.channels["FL/sprung_acc"].tddi == pytest.approx(0.2, rel=1e-6)
    assert result.tddi == pytest.approx(np.mean([c.tddi for c in result.channels.values()]))
    assert result.channels["FL/susp_travel"].discomfort_measured is None  # not an acceleration of ride or payload


def test_a_test_without_a_cab_or_force_channel_has_no_ride_index_and_its_fatigue_over_every_channel():
    names = ["FL/sprung_acc", "FL/unsprung_acc"]
    measured = np.column_stack([sine(1.0), sine(3.0)])
    result = discrepancy(measured, measured * [1.0, 0.5], names, RATE)
    assert result.ride is None and result.ride_di is None
    assert result.fatigue_channels == tuple(names)
    assert result.fatigue == pytest.approx((0 + 63 / 64) / 2, rel=1e-9)
    low = discrepancy(measured[::4], measured[::4], names, RATE / 4)  # below ISO 2631-1's 256 Hz: no weighting
    assert low.payload is None and low.tddi == 0.0
