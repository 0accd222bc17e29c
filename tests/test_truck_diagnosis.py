"""The rig diagnosis of a truck (truck_6x4 on its six posts): a record whose truck carries a hidden truck cause, and
one whose truck differs from its model only by a few percent in its linear parameters (rig/diagnosis/synthetic.py:
2 % noise, 20 s fitted, 10 s held out at 256 Hz)."""

import pytest

from rig import load_vehicle
from rig.diagnosis.diagnose import diagnose
from rig.diagnosis.synthetic import hidden_cause_records

RATE, DURATION, HOLDOUT = 256.0, 20.0, 10.0


@pytest.mark.slow
def test_a_trucks_hidden_leaf_friction_is_named_and_its_friction_found():
    truck = load_vehicle("truck_6x4")
    measured, holdout, truth = hidden_cause_records(truck, "leaf_friction", 1, DURATION, HOLDOUT, RATE)
    result = diagnose(truck, measured, holdout)
    assert result.verdict == ("leaf_friction",), [(c.effect, round(c.gain, 3)) for c in result.causes[:4]]
    hidden = truth.extensions["leaf_friction"]["front"].friction
    assert hidden > 1.4 * truck.front.law.friction  # the model's 2500 N: the record's leaves rub harder
    assert result.named[0].params["front_friction"] == pytest.approx(hidden, rel=0.15)
    assert result.extended_tddi <= 0.5 * result.recalibrated_tddi
