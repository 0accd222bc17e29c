"""Discrepancy diagnosis on rig records with a hidden cause (rig/diagnosis/synthetic.py): the verdict names the
hidden cause, 'none' when there is none, and the extended model halves the held-out TDDI for car causes.

The full matrix (every cause, several seeds) is slow (about a minute a case on two cores) and marked
so; the default run keeps three cases that exercise the car, sensor and no-cause paths."""

import json

import numpy as np
import pytest

from rig.causes import CAUSES, causes_seen_on
from rig.diagnosis.diagnose import diagnose, split_holdout
from rig.diagnosis.synthetic import hidden_cause_records, rig_test_records, truth_vehicle
from rig.report.diagnosis_report import write_diagnosis
from rig.vehicle.vehicle_file import load_vehicle
from rig.vehicle.vehicle_file import load_vehicle as _load

DURATION, HOLDOUT = 20.0, 10.0


@pytest.fixture(scope="module")
def proton_x():
    return load_vehicle("proton_x")


def check(vehicle, cause, seed):
    measured, holdout, _truth = hidden_cause_records(vehicle, cause, seed, DURATION, HOLDOUT)
    result = diagnose(vehicle, measured, holdout)
    assert result.verdict == cause, (cause, seed, [(c.effect, round(c.gain, 3)) for c in result.causes[:4]])
    if cause in CAUSES and CAUSES[cause].subsystem == "car":
        assert result.extended_tddi <= 0.5 * result.recalibrated_tddi
    return result


@pytest.mark.parametrize("cause", ["none", "bump_stop", "sensor_gain"])
def test_diagnosis_names_the_hidden_cause(proton_x, cause):
    check(proton_x, cause, seed=1)


@pytest.mark.slow
@pytest.mark.parametrize("seed", [1, 2])
@pytest.mark.parametrize("cause", (*tuple(n for n in causes_seen_on("rig") if not CAUSES[n].generic), "none"))
def test_diagnosis_names_every_hidden_cause(proton_x, cause, seed):
    check(proton_x, cause, seed)


@pytest.mark.slow
def test_two_causes_that_explain_different_evidence_are_both_named(proton_x):
    """Asymmetric dampers and an anti-roll bar, hidden together: the first cause leaves the second's evidence
    unexplained, so the verdict names both and the model carries both."""
    rng = np.random.default_rng(6)
    truth = CAUSES["anti_roll_bar"].hidden(CAUSES["damper_asymmetry"].hidden(truth_vehicle(proton_x, "none", rng), rng),
                                           rng)
    measured, holdout = rig_test_records(truth, rng, DURATION, HOLDOUT)
    result = diagnose(proton_x, measured, holdout)
    assert set(result.verdict.split("+")) == {"damper_asymmetry", "anti_roll_bar"}, \
        [(c.effect, round(c.gain, 3)) for c in result.causes[:4]]
    assert {"damper_asymmetry", "anti_roll_bar"} <= set(result.extended_vehicle.extensions)


def test_outputs_follow_the_contract(proton_x, tmp_path):
    measured, holdout, _ = hidden_cause_records(proton_x, "damper_asymmetry", 4, 12.0, 6.0)
    result = diagnose(proton_x, measured, holdout, causes=("damper_asymmetry", "sensor_gain"))
    write_diagnosis(result, tmp_path)
    document = json.loads((tmp_path / "diagnosis.json").read_text())
    assert document["verdict"] == "damper_asymmetry"
    first = document["causes"][0]
    assert set(first) == {"effect", "subsystem", "params", "tddi_holdout", "gain"}
    assert first["subsystem"] == "car" and first["gain"] > 0.5
    for key in ("baseline", "recalibrated", "extended"):
        assert document[key]["tddi_holdout"] > 0
    extended = _load(tmp_path / "vehicle_extended.toml")
    ratio = (extended.extensions["damper_asymmetry"]["front"].rebound
             / extended.extensions["damper_asymmetry"]["front"].compression)
    truth = truth_vehicle(proton_x, "damper_asymmetry", np.random.default_rng(4))
    true_ratio = (truth.extensions["damper_asymmetry"]["front"].rebound
                  / truth.extensions["damper_asymmetry"]["front"].compression)
    assert ratio == pytest.approx(true_ratio, rel=0.15)
    assert set(document["evidence"]["force_laws"]["corners"]) == set(proton_x.corners)
    for name in ("report.md", "before_after.png", "evidence.png", "ranking.png", "force_laws.png"):
        assert (tmp_path / name).stat().st_size > 0


def test_holdout_split_keeps_the_last_third(proton_x):
    measured, _, _ = hidden_cause_records(proton_x, "none", 5, 6.0, 2.0)
    fit, held = split_holdout(measured)
    assert held.n_samples == measured.n_samples - fit.n_samples
    assert held.n_samples == pytest.approx(measured.n_samples / 3, abs=2)
    assert held["FL/actuator_disp"][0] == 0.0  # the held-out part starts from rest like the model
