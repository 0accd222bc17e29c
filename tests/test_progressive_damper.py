"""The cause ``progressive_damper`` (rig/causes/progressive_damper.py): the neuro-model paper's quadratic damper as a
vehicle-file section, its force law inside mj_step, and the diagnosis naming it when it is hidden."""

import pytest
from support.quarter import QUARTER, quarter_with, suspension_force

from rig.causes import CAUSES
from rig.diagnosis.rig_test.diagnose import diagnose
from rig.diagnosis.rig_test.synthetic import hidden_cause_records
from rig.sim.simulate import Simulator
from rig.vehicle.mjcf import build_model
from rig.vehicle.vehicle_file import VehicleError, load_vehicle, vehicle_from_dict, vehicle_to_toml


def test_force_is_c0_v_plus_cn_v_abs_v_in_both_directions():
    """F = C0 v + Cn v |v| (the neuro-model paper's C0 + Cn v damping, odd in v), v the compression rate."""
    c0, cn = QUARTER["front"]["damping"], 6000.0
    sim = Simulator.create(build_model(quarter_with(progressive_damper={"front": {"quadratic": cn}}), 512.0, "ideal"))
    static = suspension_force(sim, 0.0, 0.0)
    for v in (0.05, 0.3, -0.3, -0.8):
        assert suspension_force(sim, 0.0, v) - static == pytest.approx(c0 * v + cn * v * abs(v), rel=1e-9)


def test_combines_with_an_asymmetric_damper():
    """The quadratic term adds to each branch of the bilinear damper."""
    sim = Simulator.create(build_model(quarter_with(
        damper_asymmetry={"front": {"compression": 2000.0, "rebound": 5000.0}},
        progressive_damper={"front": {"quadratic": 4000.0}}), 512.0, "ideal"))
    static = suspension_force(sim, 0.0, 0.0)
    assert suspension_force(sim, 0.0, 0.3) - static == pytest.approx(2000.0 * 0.3 + 4000.0 * 0.09, rel=1e-9)
    assert suspension_force(sim, 0.0, -0.3) - static == pytest.approx(-5000.0 * 0.3 - 4000.0 * 0.09, rel=1e-9)


def test_section_is_checked_and_written_back():
    with pytest.raises(VehicleError, match=r"\[progressive_damper.front\]: quadratic = -5.0 is outside"):
        quarter_with(progressive_damper={"front": {"quadratic": -5.0}})
    vehicle = quarter_with(progressive_damper={"front": {"quadratic": 2500.0}})
    import tomllib

    again = vehicle_from_dict(tomllib.loads(vehicle_to_toml(vehicle)), "round trip")
    assert again.extensions["progressive_damper"]["front"].quadratic == 2500.0
    assert CAUSES["progressive_damper"].subsystem == "car"


@pytest.mark.slow
def test_diagnosis_names_a_hidden_progressive_damper():
    vehicle = load_vehicle("proton_x")
    measured, holdout, _ = hidden_cause_records(vehicle, "progressive_damper", 1, 20.0, 10.0)
    result = diagnose(vehicle, measured, holdout)
    assert result.verdict == "progressive_damper", [(c.effect, round(c.gain, 3)) for c in result.causes[:4]]
    assert result.extended_tddi <= 0.5 * result.recalibrated_tddi
