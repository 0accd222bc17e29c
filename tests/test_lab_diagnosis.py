"""The diagnosis of the lab bench (tests/lab_rig.py's SciPy bench: 0.02 mm encoders, a force correlated with the road):
a weak actuator and body-bearing friction hidden together are both named, an exact bench gives ``none``."""

import pytest

from lab_rig import lab_records
from rig.diagnosis.rig_test.diagnose import diagnose
from rig.vehicle.vehicle_file import load_vehicle


def diagnosed(**hidden):
    vehicle = load_vehicle("lab_quarter")
    measured, holdout, bench = lab_records(vehicle, 3, duration=30.0, holdout=15.0, **hidden)
    diagnosis = diagnose(vehicle, measured, holdout)
    print(diagnosis.verdict_text, {c.effect: (round(c.gain, 3), c.params) for c in diagnosis.named},
          diagnosis.recalibration.values, diagnosis.recalibrated_tddi, diagnosis.extended_tddi)
    return diagnosis, vehicle, bench


@pytest.mark.slow
def test_a_weak_actuator_beside_bearing_friction_is_named_with_it():
    diagnosis, _, _ = diagnosed(force_constant=0.8, bearing_friction=0.4)
    named = {c.effect: c for c in diagnosis.named}
    assert set(diagnosis.verdict.causes) == {"force_constant_error", "bearing_friction"}
    assert named["force_constant_error"].params["front_factor"] == pytest.approx(0.8, abs=0.02)
    assert named["bearing_friction"].params["body"] == pytest.approx(0.4, abs=0.04)
    assert all(c.gain >= 0.5 for c in diagnosis.named)


@pytest.mark.slow
def test_an_exact_bench_gives_none_recalibrated_to_its_true_parameters():
    """The recalibration leaves the force path's common scale (rig/diagnosis/rig_test/candidates.py Run.fit_linear): the
    factors land on the bench's own within 0.5 %, so that no cause's joint fit finds anything to gain."""
    diagnosis, vehicle, bench = diagnosed()
    assert str(diagnosis.verdict) == "none"
    axle = vehicle.front
    truth = {"sprung_mass": bench.body / vehicle.sprung_mass, "front_spring_rate": bench.spring / axle.spring_rate,
             "front_damping": bench.damping / axle.damping, "front_tyre_rate": bench.tyre / axle.tyre_rate,
             "front_unsprung_mass": bench.wheel / axle.unsprung_mass}
    assert diagnosis.recalibration.values == pytest.approx(truth, rel=0.005)
