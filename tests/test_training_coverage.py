"""Whether a training record covers a target: the excess a linear car shows when its drive is scaled, a designed
training run that covers a target with large events, and the command that writes it."""

import numpy as np
import pytest

from controllers.drive_estimation import rig_record
from controllers.training_coverage import coverage, training_drive
from rig.cli.main import main
from rig.io.files import read_record, write_record
from rig.io.record import Record
from rig.signal.filters import band_limited_noise
from rig.sim.drive_limits import check_drive
from rig.vehicle.vehicle_file import load_vehicle

RATE = 512.0
BAND = (0.5, 50.0)


@pytest.fixture(scope="module")
def car():
    return load_vehicle("proton_x")


@pytest.fixture(scope="module")
def training(car):
    drive = band_limited_noise(20.0, RATE, (0.5, 30.0), 0.0015, 4, seed=1, slope=1.0)
    return drive, rig_record(car, drive, RATE, "pink noise", travel=True)


def test_a_linear_car_driven_harder_leaves_the_training_by_the_drive_scale(car, training):
    """proton_x with its tyres on the posts is linear: the same drive twice as large gives responses twice as large,
    so every quantity of every corner leaves the training's range, by exactly that factor (to 3e-5, measured; at
    2.5 times a 2 mm drive a rear tyre starts to leave its post and the factor is off by 0.5 %); the same drive at
    0.8 stays inside."""
    drive, train = training
    louder = rig_record(car, 2.0 * drive, RATE, "louder", travel=True)
    found = coverage(train, louder, car.corners, BAND, measured_travel=True)
    assert {(e.corner, e.quantity) for e in found.excesses} == {
        (c, q) for c in car.corners for q in ("sprung_acc", "unsprung_acc", "travel", "travel_rate")}
    for excess in found.excesses:
        np.testing.assert_allclose(excess.target_range, 2.0 * np.array(excess.training_range), rtol=1e-4)
        assert excess.duration > 0
    assert found.beyond.any(axis=0).all() and not found.covered
    assert "the NARX extrapolates there: FL body acceleration: the target reaches" in found.describe()
    quieter = rig_record(car, 0.8 * drive, RATE, "quieter", travel=True)
    assert coverage(train, quieter, car.corners, BAND, measured_travel=True).covered


def test_a_designed_training_run_covers_a_target_with_large_events(car):
    """A target whose events reach 30 mm on single posts: the pink-noise training above does not cover it; a run
    designed from the target (its Eq 5.1 estimate sets the level, events climb to 1.25 times its largest excursion)
    does, and stays within the posts' stroke and velocity."""
    rng = np.random.default_rng(3)
    drive = band_limited_noise(20.0, RATE, (0.5, 30.0), 0.003, 4, seed=5, slope=1.0)
    time = np.arange(drive.shape[0]) / RATE
    for start, corner in zip((4.0, 9.0, 14.0), rng.permutation(4)[:3]):
        drive[:, corner] += 0.03 * np.sin(np.pi * np.clip((time - start) / 0.15, 0, 1))
    target = rig_record(car, drive, RATE, "target with events", travel=True)
    pink = rig_record(car, band_limited_noise(60.0, RATE, (0.5, 30.0), 0.003, 4, seed=6, slope=1.0), RATE, "pink",
                      travel=True)
    assert not coverage(pink, target, car.corners, BAND, measured_travel=True).covered
    design = training_drive(car, target, 60.0, BAND)
    check_drive(design, RATE, car.rig, car.corners, np.arange(design.shape[0]) / RATE)  # raises beyond the limits
    designed = rig_record(car, design, RATE, "designed", travel=True)
    found = coverage(designed, target, car.corners, BAND, measured_travel=True)
    assert found.covered, found.describe()


def test_cli_writes_the_designed_training_drive(car, training, tmp_path, capsys):
    _drive, train = training
    target = tmp_path / "target.csv"
    write_record(target, train)
    out, design = tmp_path / "drive.csv", tmp_path / "training.csv"
    assert main(["estimate-drive", "--vehicle", "proton_x", "--target", str(target), "--method", "inverse-model",
                 "--out", str(out), "--training-drive", str(design), "--quiet"]) == 0
    assert "a 60 s training drive covering the target's amplitudes" in capsys.readouterr().out
    written = read_record(design)
    assert written.names == [f"{c}/drive" for c in car.corners] and written.duration == pytest.approx(60.0, abs=0.01)
    assert isinstance(written, Record) and np.abs(written.quantity("drive", car.corners)).max() <= car.rig.stroke


def test_a_drive_is_bridged_below_its_estimate_where_the_tyre_was_off():
    """A post going down a bump's far side (a half-sine) while the wheel flies: the estimate there is the touching
    position, above the post; the bridge is the flattest drive below it and comes back towards the post."""
    from controllers.lift_off_bridge import airborne, bridged

    rate = 512.0
    time = np.arange(int(2 * rate)) / rate
    post = 0.03 * np.sin(np.pi * np.clip((time - 0.5) / 0.3, 0, 1))  # m: up 0.5-0.65 s, down 0.65-0.8 s
    off = (time > 0.7) & (time < 0.76)
    touching = np.where(off, post + 5.6 * (time - 0.7) * (0.76 - time), post)  # the flying wheel: 5 mm above at most
    force = np.where(off, 0.0, 3000.0) + np.random.default_rng(0).normal(0, 30.0, time.size)
    record = Record(rate, {"FL/tyre_force": force})
    found = airborne(record, ("FL",))
    assert found[:, 0].sum() == pytest.approx(off.sum(), abs=2)
    result = bridged(touching[:, None], found, rate)[:, 0]
    assert np.all(result <= touching + 1e-12)
    np.testing.assert_array_equal(result[~found[:, 0]], touching[~found[:, 0]])
    assert np.sqrt(np.mean((result - post)[off] ** 2)) < 0.3 * np.sqrt(np.mean((touching - post)[off] ** 2))
    assert airborne(Record(rate, {"FL/drive": post}), ("FL",)) is None
