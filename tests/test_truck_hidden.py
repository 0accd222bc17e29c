"""The truck diagnosis against records of the independent truck simulator (tests/independent_truck.py), not the
project's own model: a rigid-frame truck whose linear parameters are off by up to 3 % on every axle
(rig/diagnosis/rig_test/synthetic.py ``truth_vehicle``) and which carries one hidden truck cause, driven by the
diagnosis's event
drives on its servo posts, 2 % noise on every measured channel, 20 s fitted and 10 s held out at 256 Hz; the model is
the truck's own file with a rigid frame. Each cause must be named, first, with its parameters within 10 %.
(The frame, which the independent simulator does not bend, is tests/test_truck_diagnosis.py's.)"""

import dataclasses

import numpy as np
import pytest
from independent_truck import rig_test_records

from rig import load_vehicle
from rig.diagnosis.rig_test.diagnose import diagnose
from rig.diagnosis.rig_test.synthetic import truth_vehicle

RATE, DURATION, HOLDOUT = 256.0, 20.0, 10.0


def diagnosed(vehicle: str, cause: str, seed: int = 1):
    model = dataclasses.replace(load_vehicle(vehicle), frame=None)
    rng = np.random.default_rng(seed)
    truth = truth_vehicle(model, cause, rng)
    measured, holdout = rig_test_records(truth, rng, DURATION, HOLDOUT, RATE)
    result = diagnose(model, measured, holdout)
    assert result.verdict[0] == cause, [(c.effect, round(c.gain, 3)) for c in result.causes[:4]]
    return truth.extensions[cause], result.named[0].params, result


@pytest.mark.slow
def test_leaf_friction_of_the_front_leaves_is_named_with_its_friction():
    hidden, found, _ = diagnosed("truck_6x4", "leaf_friction")
    assert found["front_friction"] == pytest.approx(hidden["front"].friction, rel=0.1)


@pytest.mark.slow
def test_the_tandems_air_springs_are_named_with_their_volume():
    hidden, found, _ = diagnosed("truck_6x4", "air_spring_law")
    for axle in ("middle", "rear"):
        assert found[f"{axle}_volume"] == pytest.approx(hidden[axle].volume, rel=0.1), axle


@pytest.mark.slow
@pytest.mark.parametrize("cause", ["cab_mounts", "driveline_mounts"])
def test_a_bodys_mounts_are_named_with_their_stiffness_and_damping(cause):
    hidden, found, _ = diagnosed("truck_6x4", cause)
    assert found["stiffness"] == pytest.approx(hidden.stiffness, rel=0.1)
    assert found["damping"] == pytest.approx(hidden.damping, rel=0.1)


@pytest.mark.slow
def test_a_cabs_air_springs_are_named_with_their_volume():
    hidden, found, _ = diagnosed("tractor_4x2", "cab_air_spring")
    assert found["volume"] == pytest.approx(hidden.volume, rel=0.1)


@pytest.mark.slow
def test_a_payload_of_tonnes_is_named_with_its_mass_and_place():
    hidden, found, _ = diagnosed("truck_6x4", "mass_error")
    assert hidden.mass > 2000.0  # a truck's scale: tonnes, beyond a car's bounds
    assert found["mass"] == pytest.approx(hidden.mass, rel=0.1)
    assert found["x"] == pytest.approx(hidden.x, abs=0.1 * load_vehicle("truck_6x4").wheelbase)
