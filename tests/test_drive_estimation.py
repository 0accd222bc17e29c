"""Drive estimation from a measured response (Nurhadiyanto's chapters 5-6): band-limited integration against its
closed form, Eq 5.1 through the servo model against the drive that made a linear car's response, iteration
started from an estimate, and the command line with its refusals of bad training records."""

import json

import numpy as np
import pytest
from drive_estimation_case import measured_records, nonlinear_vehicle

from controllers.drive_estimation import METHODS, drive_errors, estimate_drive
from controllers.narx import NarxStructure
from controllers.rpc import DriveIteration, IterationSettings
from rig.cli.main import main
from rig.io.files import read_record, write_record
from rig.io.record import Record
from rig.road.roads import iso8608_road
from rig.signal.filters import band_limited_noise, integrate
from rig.sim.replay import replay
from rig.sim.track import track_run
from rig.vehicle.vehicle_file import load_vehicle

RATE = 512.0
CHANNELS = [f"{c}/{q}" for c in ("FL", "FR", "RL", "RR") for q in ("sprung_acc", "unsprung_acc")]


@pytest.fixture(scope="module")
def linear_rig_test():
    """proton_x on the servo rig, 20 s of pink-noise drives: a rig record whose drives are the truth."""
    vehicle = load_vehicle("proton_x")
    drive = band_limited_noise(20.0, RATE, (0.5, 30.0), 0.003, 4, seed=1, slope=1.0)
    record = replay(vehicle, Record(RATE, {f"{c}/drive": drive[:, i] for i, c in enumerate(vehicle.corners)})).record
    return vehicle, record


def test_band_limited_integration_matches_the_closed_form():
    t = np.arange(int(20 * RATE)) / RATE
    omega = 2 * np.pi * 3.0  # a whole number of periods: the periodic transform is exact
    acceleration = -omega**2 * np.sin(omega * t)
    np.testing.assert_allclose(integrate(acceleration, RATE, 0.25), omega * np.cos(omega * t),
                               atol=1e-9)
    np.testing.assert_allclose(integrate(acceleration, RATE, 0.25, times=2), np.sin(omega * t), atol=1e-9)
    assert np.allclose(integrate(np.ones(1024), RATE, 0.25), 0.0)  # nothing below the lower limit


def test_eq_5_1_through_the_servo_recovers_the_drive_of_a_linear_car(linear_rig_test):
    """Noise-free and linear: what is left is leakage at the band's lower edge (measured 0.25-0.37 %)."""
    vehicle, record = linear_rig_test
    estimate = estimate_drive(vehicle, record, "inverse-model")
    errors = drive_errors(record, estimate)
    assert max(errors.values()) < 0.5, errors


def test_iteration_starts_from_the_estimate_where_it_belongs(tmp_path):
    """The inverse-model start on a track target: its first play is within 10 % (measured 9.6 %, then 5.1 and
    3.2 %); placed a second late it would miss by far more. What the first play misses lies in the target's
    first and last second, where the track run is already in motion and the drive is faded to rest: inside
    them, the estimate replayed is within 0.6-5.6 % per channel."""
    vehicle = load_vehicle("proton_x")
    target = track_run(vehicle, iso8608_road("B", 400.0, seed=3), 20.0, duration=12.0).record
    estimate = estimate_drive(vehicle, target, "inverse-model").drive
    settings = IterationSettings(iterations=1, target_error_pct=0.0)
    placed = DriveIteration(vehicle, target, CHANNELS, tmp_path / "a", settings, initial=estimate).run(progress=False)
    late = Record(estimate.rate, estimate.channels, start_time=1.0)
    shifted = DriveIteration(vehicle, target, CHANNELS, tmp_path / "b", settings, initial=late).run(progress=False)
    assert placed.history[0].worst_rms_error_pct < 10.0
    assert shifted.history[0].worst_rms_error_pct > 5 * placed.history[0].worst_rms_error_pct


def test_frf_estimate_from_a_measured_record_equals_the_first_drive_of_iteration(linear_rig_test):
    vehicle, record = linear_rig_test
    train = record.select([n for n in record.names if n.split("/")[1] in ("drive", "sprung_acc", "unsprung_acc")])
    longer = Record(RATE, {n: np.tile(v, 2) for n, v in train.channels.items()})  # 40 s: 5 FRF segments
    estimate = estimate_drive(vehicle, record, "frf", longer)
    job = DriveIteration(vehicle, record, CHANNELS, None, IterationSettings(), identification=longer)
    np.testing.assert_array_equal(estimate.values, job.first_drive()[job.span])
    assert max(drive_errors(record, estimate).values()) < 50.0


def test_cli_estimate_drive_and_its_refusals(linear_rig_test, tmp_path, capsys):
    _vehicle, record = linear_rig_test
    target = tmp_path / "target.csv"
    write_record(target, record)
    out = tmp_path / "drive.csv"
    assert main(["estimate-drive", "--vehicle", "proton_x", "--target", str(target), "--method", "inverse-model",
                 "--out", str(out)]) == 0
    assert "drive error" in capsys.readouterr().out
    written = read_record(out)
    assert written.names == ["FL/drive", "FR/drive", "RL/drive", "RR/drive"]
    assert main(["replay", "--vehicle", "proton_x", "--drive", str(out), "--out", str(tmp_path / "r.csv")]) == 0
    run = tmp_path / "iterate"
    assert main(["iterate", "--vehicle", "proton_x", "--target", str(target), "--out", str(run), "--initial", str(out),
                 "--iterations", "1", "--quiet"]) == 0
    first = json.loads((run / "history.json").read_text())["iterations"][0]
    assert first["worst_rms_error_pct"] < 2.0  # the estimate in its place: measured 0.83 %

    no_drive = tmp_path / "no_drive.csv"
    write_record(no_drive, record.select([n for n in record.names if "drive" not in n]))
    slow = tmp_path / "slow.csv"
    write_record(slow, Record(RATE / 2, {n: v[::2] for n, v in record.channels.items()}))
    short = tmp_path / "short.csv"
    write_record(short, Record(RATE, {n: v[:1024] for n, v in record.channels.items()}))
    for method, train, message in (("narx", no_drive, "no 'drive' channel"), ("frf", slow, "sampled at 256 Hz"),
                                   ("narx", short, "the training record has 1024 samples"),
                                   ("frf", short, "the identification record is 2 s long")):
        code = main(["estimate-drive", "--vehicle", "proton_x", "--target", str(target), "--method", method,
                     "--train", str(train), "--out", str(tmp_path / "x.csv"), "--quiet"])
        err = capsys.readouterr().err
        assert code == 2 and message in err and len(err.strip().splitlines()) == 1, err


def test_a_linear_narx_recovers_an_unseen_drive_of_a_linear_car(linear_rig_test):
    """Trained on one pink-noise record, run free on another: with no tanh neuron the network is a linear
    filter of the accelerations and their integrals, which holds Eq 5.1 through the servo (measured 0.31-0.51 %)."""
    vehicle, train = linear_rig_test
    drive = band_limited_noise(10.0, RATE, (0.5, 30.0), 0.003, 4, seed=2, slope=1.0)
    target = replay(vehicle, Record(RATE, {f"{c}/drive": drive[:, i] for i, c in enumerate(vehicle.corners)})).record
    linear = NarxStructure((-2, -1, 0, 1, 2), 0, 1, 0, True)
    estimate = estimate_drive(vehicle, target, "narx", train, candidates=(linear,))
    errors = drive_errors(target, estimate)
    assert max(errors.values()) < 2.0, errors


@pytest.mark.slow
def test_narx_is_the_best_start_on_a_nonlinear_car_measured_by_the_independent_simulator(tmp_path):
    """The acceptance case (tests/drive_estimation_case.py): asymmetric dampers and progressive springs, a 60 s
    pink-noise identification run for training and an unseen 20 s road target, both from the independent
    simulator. The NARX has the lowest worst-corner drive error of the three methods and meets the 5 % aimed at
    (measured 4.50 %, against 11.0 % for Eq 5.1 and 35.1 % for the FRF inverse), and iteration
    on that car reaches 5 % in fewer plays from it than from the FRF start (measured 2 against 4)."""
    baseline = load_vehicle("proton_x")
    train, target = measured_records(baseline)
    estimates = {method: estimate_drive(baseline, target, method, train) for method in METHODS}
    worst = {method: max(drive_errors(target, estimate).values()) for method, estimate in estimates.items()}
    assert worst["narx"] <= 5.0 and worst["narx"] == min(worst.values()), worst
    plays = {}
    for method in ("frf", "narx"):
        initial = None if method == "frf" else estimates[method].drive
        settings = IterationSettings(iterations=6, target_error_pct=5.0)
        history = DriveIteration(nonlinear_vehicle(baseline), target, CHANNELS, tmp_path / method, settings,
                                 initial=initial).run(progress=False).history
        plays[method] = next((k + 1 for k, h in enumerate(history) if h.worst_rms_error_pct <= 5.0), 99)
    assert plays["narx"] < plays["frf"], plays


@pytest.mark.slow
def test_narx_generalises_to_large_road_events_when_its_training_covers_them():
    """The large-event case (tests/drive_estimation_case.py: the nonlinear car, 1 % noise, six large road events in a
    60 s training run and in an unseen 20 s target, all from the independent simulator). With the case's own
    training the NARX is the best of the three and says where the target goes beyond its training (measured: NARX
    10.2 %, Eq 5.1 22.4 %, FRF 40.7 %; before the measured travel and the coverage check, 13.5 %); trained on a run
    designed from the target to cover it, it meets the 10 % asked (measured 7.7 %)."""
    from drive_estimation_case import CUBIC, RATE, RATIO, large_event_records
    from independent_rig import Car, Hidden, Simulator, rig_record

    from controllers.training_coverage import training_drive

    baseline = load_vehicle("proton_x")
    train, target = large_event_records(baseline)
    estimates = {method: estimate_drive(baseline, target, method, train) for method in METHODS}
    worst = {method: max(drive_errors(target, estimate).values()) for method, estimate in estimates.items()}
    assert worst["narx"] == min(worst.values()) and worst["narx"] < 11.0, worst
    assert not estimates["narx"].coverage.covered
    simulator = Simulator(Car.from_vehicle(baseline), Hidden(cubic_spring=CUBIC, damper_ratio=RATIO))
    designed = rig_record(simulator, training_drive(baseline, target), RATE, np.random.default_rng(7), 0.01)
    narx = estimate_drive(baseline, target, "narx", designed)
    assert max(drive_errors(target, narx).values()) <= 10.0
