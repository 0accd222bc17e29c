"""Validation of a measured rig test, and the integrity checks that run before any diagnosis."""

import json

import numpy as np
import pytest

from rig.cli.main import main
from rig.diagnosis.core.experiment import Experiment
from rig.diagnosis.core.integrity import integrity_findings
from rig.diagnosis.rig_test.synthetic import hidden_cause_records
from rig.diagnosis.core.validation import mean_tddi
from rig.io.files import write_record
from rig.io.record import Record
from rig.vehicle.vehicle_file import load_vehicle


@pytest.fixture(scope="module")
def rig_test():
    vehicle = load_vehicle("proton_x")
    measured, _, truth = hidden_cause_records(vehicle, "none", 3, duration=10.0, holdout_duration=2.0)
    return vehicle, measured, truth


def test_the_truth_model_validates_to_the_noise_floor_and_the_baseline_does_not(rig_test):
    vehicle, measured, truth = rig_test
    experiment = Experiment.from_record(measured, vehicle)
    truth_score = mean_tddi(experiment.measured_all(), experiment.simulate(truth))
    baseline_score = mean_tddi(experiment.measured_all(), experiment.simulate(vehicle))
    assert truth_score < 2e-3  # 2 % noise, of which the 0.5-50 Hz band keeps a part
    assert baseline_score > 2 * truth_score  # a few percent off in rates, damping and masses shows


def test_cli_validate_writes_scores_and_plots(rig_test, tmp_path, capsys):
    _, measured, _ = rig_test
    path = tmp_path / "measured.csv"
    write_record(path, measured)
    assert main(["validate", "--vehicle", "proton_x", "--measured", str(path), "--out", str(tmp_path / "v")]) == 0
    summary = json.loads((tmp_path / "v" / "validation.json").read_text())
    assert set(summary["channels"]["FL/sprung_acc"]) == {"tddi", "rms_error_pct"}
    assert "FL/actuator_disp" in summary["channels"]  # the rig part: drive -> achieved displacement
    for name in ("psd_overlay.png", "pattern_frfs.png"):
        assert (tmp_path / "v" / name).stat().st_size > 0
    assert "mean TDDI" in capsys.readouterr().out


def test_integrity_checks_name_units_clipping_and_dropouts():
    rng = np.random.default_rng(0)
    acc = rng.standard_normal(2000)
    clipped = np.clip(acc, -1.0, 1.0)
    frozen = acc.copy()
    frozen[500:540] = frozen[500]
    record = Record(512.0, {"FL/sprung_acc": acc * 1000.0, "FR/sprung_acc": clipped, "RL/sprung_acc": frozen})
    findings = {(f.channel, f.check) for f in integrity_findings(record)}
    assert ("FL/sprung_acc", "units") in findings  # 1000 m/s^2 RMS on a body: mm/s^2 written as m/s^2?
    assert ("FR/sprung_acc", "clipping") in findings
    assert ("RL/sprung_acc", "dropout") in findings
    assert not any(f[0] == "RR/sprung_acc" for f in findings)


def test_diagnose_refuses_data_with_wrong_units(rig_test, tmp_path, capsys):
    _, measured, _ = rig_test
    broken = Record(measured.rate, {n: (v * 1000 if n == "FL/unsprung_acc" else v)
                                    for n, v in measured.channels.items()})
    path = tmp_path / "broken.csv"
    write_record(path, broken)
    assert main(["diagnose", "--vehicle", "proton_x", "--measured", str(path), "--out", str(tmp_path / "d")]) == 2
    assert "FL/unsprung_acc" in capsys.readouterr().err
