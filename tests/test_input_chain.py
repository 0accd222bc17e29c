"""The measurement chain of a test's inputs, found from the records (rig/diagnosis/rig_test/input_chain.py) and named
by the
diagnosis: a lab bench whose force channel is reversed and 3.5 times too small (tests/lab_rig.py's SciPy bench), a
four-poster whose front-left post displacement is wired the wrong way round (tests/independent_rig.py's NumPy car):
neither simulator is the project's model."""

import dataclasses

import numpy as np
import pytest

from independent_rig import Hidden, independent_records
from lab_rig import lab_records
from rig.diagnosis.rig_test.diagnose import diagnose
from rig.diagnosis.core.experiment import Experiment
from rig.diagnosis.rig_test.input_chain import input_chain
from rig.io.record import Record
from rig.sim.measurement import true_inputs
from rig.vehicle.vehicle_file import load_vehicle

REVERSED_POST = Hidden(sensor_gain={"FL/actuator_disp": -1.0})


def chain_of(record, vehicle):
    return input_chain(Experiment.from_record(record, vehicle), vehicle)


def test_a_reversed_and_scaled_force_is_found_before_any_fit():
    vehicle = load_vehicle("lab_quarter")
    measured, _, _ = lab_records(vehicle, 3, duration=20.0, holdout=2.0, force_constant=-3.5)
    chain = chain_of(measured, vehicle)
    assert chain.reversed("FL/active_force") and chain.gross("FL/active_force")
    assert chain.gains["FL/active_force"] == pytest.approx(-3.5, rel=0.1)  # the data sheet's resonances: ~6 % off
    assert not chain.off("FL/actuator_disp")
    assert "FL/active_force: acts on the responses with -3.3" in " ".join(chain.lines())
    right, _, _ = lab_records(vehicle, 3, duration=20.0, holdout=2.0)
    assert not chain_of(right, vehicle).reversed("FL/active_force")


def test_a_reversed_post_channel_is_found_on_its_corner_alone():
    vehicle = load_vehicle("proton_x")
    measured, _, _ = independent_records(vehicle, REVERSED_POST, 5, duration=12.0, holdout=2.0)
    chain = chain_of(measured, vehicle)
    assert list(chain.faults) == ["FL/actuator_disp"] and chain.gross("FL/actuator_disp")
    assert chain.gains["FL/actuator_disp"] == pytest.approx(-1.0, abs=0.05)
    assert all(chain.gains[f"{c}/actuator_disp"] == pytest.approx(1.0, abs=0.05) for c in ("FR", "RL", "RR"))
    assert chain.explained > 0.99


def test_an_input_gain_takes_a_record_back_to_the_true_motion_and_reports_as_the_channel_records():
    vehicle = dataclasses.replace(load_vehicle("proton_x"), extensions={"input_gain": {"FL/actuator_disp": -2.0}})
    record = Record(100.0, {"FL/actuator_disp": np.linspace(0.0, 1.0, 11), "FR/actuator_disp": np.ones(11)})
    true = true_inputs(record, vehicle.extensions)
    np.testing.assert_allclose(true["FL/actuator_disp"], -0.5 * record["FL/actuator_disp"])
    np.testing.assert_array_equal(true["FR/actuator_disp"], record["FR/actuator_disp"])


@pytest.mark.slow
def test_a_bench_whose_force_is_reversed_and_scaled_is_told_so_with_no_added_body():
    vehicle = load_vehicle("lab_quarter")
    measured, holdout, _ = lab_records(vehicle, 3, duration=30.0, holdout=15.0, force_constant=-3.5)
    diagnosis = diagnose(vehicle, measured, holdout)
    assert str(diagnosis.verdict) == "force_constant_error"
    named = diagnosis.named[0]
    low, high = named.intervals["front_factor"]
    assert named.checked_first and named.params["front_factor"] == pytest.approx(-3.5, rel=0.03) and high < 0
    assert high - low < 0.1 and diagnosis.extended_tddi < 1e-4


@pytest.mark.slow
def test_a_reversed_post_channel_is_named_as_such():
    vehicle = load_vehicle("proton_x")
    measured, holdout, _ = independent_records(vehicle, REVERSED_POST, 7, duration=30.0, holdout=20.0)
    diagnosis = diagnose(vehicle, measured, holdout)
    assert diagnosis.verdict.causes[0] == "input_gain"
    named = diagnosis.named[0]
    assert named.params == {"FL/actuator_disp": pytest.approx(-1.0, abs=0.03)}
    assert diagnosis.extended_tddi < 0.01 < diagnosis.baseline_tddi
