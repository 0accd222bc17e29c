"""Drive iteration on a lab bench (tests/lab_rig.py's SciPy bench: 0.02 mm encoders, a force correlated with the road).
The actuator force is a measured input that every iteration plays beside the drive, so the drive iterated on the
exact model reproduces the encoders' displacements as on a passive car and recovers the base plate's motion (the road)
the bench was driven with; without the force the same drive misses them."""

import json

import numpy as np
import pytest

from lab_rig import lab_records, with_bench
from rig.cli.main import main
from rig.io.files import read_record, write_record
from rig.signal.filters import band_pass
from rig.sim.replay import replay
from rig.vehicle.vehicle_file import load_vehicle, vehicle_to_toml

SWEEP = (2.0, 12.0)  # Hz: where the road sweeps and the bench's force acts with it


@pytest.fixture(scope="module")
def iterated(tmp_path_factory):
    folder = tmp_path_factory.mktemp("lab_iteration")
    vehicle = load_vehicle("lab_quarter")
    target, _, bench = lab_records(vehicle, 3, duration=20.0, holdout=5.0)
    exact = with_bench(vehicle, bench)
    (folder / "bench.toml").write_text(vehicle_to_toml(exact))
    write_record(folder / "target.csv", target)
    assert main(["iterate", "--vehicle", str(folder / "bench.toml"), "--target", str(folder / "target.csv"),
                 "--out", str(folder / "run"), "--quiet"]) == 0
    return exact, target, folder / "run"


def relative_error(achieved: np.ndarray, wanted: np.ndarray, rate: float, band: tuple[float, float]) -> float:
    """RMS of the difference over the wanted's in ``band`` (Hz), leaving out the 1 s end tapers, in %."""
    difference, reference = (band_pass(x - x[0], rate, band)[int(rate):-int(rate)] for x in (achieved - wanted, wanted))
    return float(100 * np.sqrt(np.mean(difference**2) / np.mean(reference**2)))


def test_the_encoders_displacements_are_iterated_to_3_percent_with_the_force_played(iterated):
    _, _, run = iterated
    history = json.loads((run / "history.json").read_text())["iterations"]
    best = min(history, key=lambda h: h["total_error_pct"])
    assert set(best["channels"]) == {"FL/sprung_disp", "FL/unsprung_disp"}  # the default on a bench without acc
    assert best["worst_rms_error_pct"] <= 3.0


def test_the_iterated_drive_with_its_force_recovers_the_bench_road(iterated):
    exact, target, run = iterated
    drive = read_record(run / "drive.csv")
    assert "FL/active_force" in drive
    start = int(round(-drive.start_time * drive.rate))  # the lead-in before the target's first sample
    span = slice(start, start + target.n_samples)
    played = replay(exact, drive).record
    assert relative_error(played["FL/actuator_disp"][span], target["FL/actuator_disp"], target.rate, SWEEP) < 2.0
    assert relative_error(played["FL/sprung_disp"][span], target["FL/sprung_disp"], target.rate, SWEEP) < 3.0
    alone = replay(exact, drive.select(["FL/drive"])).record
    assert relative_error(alone["FL/sprung_disp"][span], target["FL/sprung_disp"], target.rate, SWEEP) > 10.0
