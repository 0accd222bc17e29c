"""The lab quarter-car bench through the command line: records of tests/lab_rig.py's SciPy bench (encoders of 0.02 mm,
a correlated actuator force) replayed and validated with ``active_force`` as an input and displacements as responses."""

import json
from pathlib import Path

import numpy as np
import pytest

from lab_rig import Bench, Excitation, record_of, simulate
from rig.cli.main import main
from rig.diagnosis.core.integrity import integrity_findings
from rig.io.files import read_record, write_record
from rig.vehicle.vehicle_file import load_vehicle, resolve_vehicle_path

RATE = 500.0


@pytest.fixture(scope="module")
def records(tmp_path_factory):
    """Bench records (CSV) of the exact bench and of one whose actuator applies 0.8 of its recorded force."""
    folder = tmp_path_factory.mktemp("lab")
    vehicle = load_vehicle("lab_quarter")
    paths = {}
    for name, hidden in (("exact", {}), ("weak_actuator", {"force_constant": 0.8})):
        motion = simulate(Bench.of(vehicle, **hidden), Excitation(20.0), RATE)
        paths[name] = folder / f"{name}.csv"
        write_record(paths[name], record_of(motion, RATE, np.random.default_rng(1)))
    return folder, paths


def validated(folder, vehicle, measured):
    out = folder / f"{measured.stem}_{Path(vehicle).stem}"
    assert main(["validate", "--vehicle", str(vehicle), "--measured", str(measured), "--out", str(out)]) == 0
    return json.loads((out / "validation.json").read_text())


def test_the_exact_bench_validates_to_its_encoder_resolution(records):
    folder, paths = records
    assert integrity_findings(read_record(paths["exact"])) == []  # encoders of 0.02 mm: no clipping, no dropout
    report = validated(folder, "lab_quarter", paths["exact"])
    assert set(report["channels"]) == {"FL/sprung_disp", "FL/unsprung_disp"}
    assert report["mean_tddi"] < 1e-5


def test_a_weak_actuator_shows_in_validation_and_its_cause_in_the_vehicle_file_explains_it(records):
    folder, paths = records
    plain = validated(folder, "lab_quarter", paths["weak_actuator"])["mean_tddi"]
    vehicle = folder / "lab_quarter_weak.toml"
    vehicle.write_text(resolve_vehicle_path("lab_quarter").read_text()
                       + "\n[force_constant_error.front]\nfactor = 0.8\n")
    stated = validated(folder, vehicle, paths["weak_actuator"])["mean_tddi"]
    print(f"mean TDDI: the file's bench {plain:.3g}, with the weak actuator stated {stated:.3g}")
    assert plain > 100 * stated, (plain, stated)
    assert stated < 1e-5


def test_replay_applies_the_recorded_force_and_writes_displacements(records, tmp_path):
    _, paths = records
    out = tmp_path / "replayed.csv"
    assert main(["replay", "--vehicle", "lab_quarter", "--drive", str(paths["exact"]), "--out", str(out)]) == 0
    measured, replayed = read_record(paths["exact"]), read_record(out)
    error = replayed["FL/sprung_disp"] - measured["FL/sprung_disp"]
    assert np.sqrt(np.mean(error**2)) < 0.01 * np.std(measured["FL/sprung_disp"])
