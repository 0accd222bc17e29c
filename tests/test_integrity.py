"""The integrity checks on encoder data: quantisation is not clipping, a still or slow plate is not a dropout, while a
clipped or frozen encoder channel is still named."""

import numpy as np
import pytest

from rig.diagnosis.core.integrity import integrity_findings, quantisation_step
from rig.io.record import Record

RATE = 500.0
STEP = 0.01e-3  # m per encoder count


def encoder(z):
    return np.round(z / STEP) * STEP


def checks(values, name="FL/sprung_disp"):
    return {f.check for f in integrity_findings(Record(RATE, {name: values}))}


def sine(amplitude, hz, seconds=20.0):
    t = np.arange(int(seconds * RATE)) / RATE
    return amplitude * np.sin(2 * np.pi * hz * t)


@pytest.mark.parametrize("hz", [0.5, 2.0, 23.3])  # peaks held for ~18, ~4 and 1 sample(s) at 10 mm
def test_an_encoder_quantised_sine_is_neither_clipped_nor_dropped(hz):
    values = encoder(sine(10e-3, hz))
    assert quantisation_step(values) == pytest.approx(STEP)
    assert np.mean(values == values.max()) > 0.002  # the old check's share: its peaks repeat
    assert checks(values) == set()


def test_a_slow_plate_and_a_still_start_are_no_dropout():
    slow = encoder(sine(0.1e-3, 0.05))  # one count every ~30 samples
    still_then_moving = encoder(np.concatenate([np.zeros(1000), sine(2e-3, 1.0, 10.0)]))
    assert checks(slow) == set()
    assert checks(still_then_moving) == set()


def test_a_clipped_encoder_sine_is_clipping():
    values = encoder(np.clip(sine(10e-3, 2.0), -8e-3, 8e-3))
    assert checks(values) == {"clipping"}


def test_a_frozen_or_zeroed_encoder_is_a_dropout():
    frozen, zeroed = encoder(sine(10e-3, 2.0)), encoder(sine(10e-3, 2.0) + 3e-3)
    frozen[1000:1020] = frozen[1000]
    zeroed[2000:2010] = 0.0
    assert checks(frozen) == {"dropout"}
    assert checks(zeroed) == {"dropout"}
    assert checks(np.zeros(1000)) == {"dropout"}  # a dead channel
