"""What the diagnosis's speed rests on must not change a result: a batch of variants simulates each as it runs alone,
an experiment looks a vehicle it simulated up instead of simulating it again, and fits run beside each other give
what they give one after another (the slow test: a whole diagnosis both ways)."""

import dataclasses

import numpy as np
import pytest

import rig.diagnosis.candidates as candidates
from rig.causes._base import scale_axle
from rig.diagnosis.diagnose import diagnose
from rig.diagnosis.experiment import Experiment
from rig.diagnosis.synthetic import hidden_cause_records
from rig.vehicle.vehicle_file import load_vehicle


@pytest.fixture(scope="module")
def proton_x():
    return load_vehicle("proton_x")


def test_a_batch_of_variants_is_each_run_alone_and_a_vehicle_run_again_is_looked_up(proton_x):
    measured, _, _ = hidden_cause_records(proton_x, "none", 5, 6.0, 3.0)
    softer = scale_axle(proton_x, "front", spring_rate=0.9)
    heavier = dataclasses.replace(proton_x, sprung_mass=proton_x.sprung_mass * 1.05)
    batch = Experiment.from_record(measured, proton_x)
    together = batch.simulate_car([softer, heavier])
    alone = [Experiment.from_record(measured, proton_x).simulate_car([v])[0] for v in (softer, heavier)]
    for a, b in zip(together, alone):
        np.testing.assert_array_equal(a, b)
    assert not np.allclose(together[0], together[1])  # the variants differ: the batch did not run one model twice
    again = batch.simulate_car([heavier, dataclasses.replace(softer)])  # equal vehicles, other objects
    assert again[0] is together[1] and again[1] is together[0]
    assert not again[0].flags.writeable


@pytest.mark.slow
def test_fits_beside_each_other_give_what_they_give_one_after_another(proton_x, monkeypatch):
    measured, holdout, _ = hidden_cause_records(proton_x, "damper_asymmetry", 4, 12.0, 6.0)
    causes = ("damper_asymmetry", "bump_stop", "sensor_gain")
    beside = diagnose(proton_x, measured, holdout, causes=causes)
    monkeypatch.setattr(candidates.os, "cpu_count", lambda: 1)
    alone = diagnose(proton_x, measured, holdout, causes=causes)
    assert beside.verdict == alone.verdict == ("damper_asymmetry",)
    assert (beside.recalibrated_tddi, beside.extended_tddi) == (alone.recalibrated_tddi, alone.extended_tddi)
    assert [(c.effect, c.params, c.tddi_holdout) for c in beside.causes] == \
        [(c.effect, c.params, c.tddi_holdout) for c in alone.causes]
