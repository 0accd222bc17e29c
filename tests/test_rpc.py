"""RPC-style drive iteration on the virtual rig: the fixed-gain reference, the default scheme on a nonlinear
car, limits, divergence handling, resuming, and the command line."""

import json

import numpy as np
import pytest

from controllers.rpc import DriveIteration, IterationSettings
from rig.signal.metrics import ChannelMetrics
from rig.cli.main import main
from rig.io.files import read_record, write_record
from rig.road.roads import iso8608_road
from rig.sim.track import track_run
from rig.vehicle.vehicle_file import load_vehicle

CHANNELS = [f"{c}/{q}" for c in ("FL", "FR", "RL", "RR") for q in ("sprung_acc", "unsprung_acc")]


@pytest.fixture(scope="module")
def linear_target():
    """proton_x over an ISO 8608 class B road at 20 m/s: no tyre leaves the ground, so the car is linear."""
    vehicle = load_vehicle("proton_x")
    result = track_run(vehicle, iso8608_road("B", 400.0, seed=3), 20.0, duration=12.0)
    assert not any(result.airborne_time().values())
    return vehicle, result.record


def errors(history):
    return np.array([h.worst_rms_error_pct for h in history])


def test_fixed_scheme_converges_as_one_minus_gain_to_the_k(linear_target, tmp_path):
    vehicle, target = linear_target
    settings = IterationSettings(scheme="fixed", iterations=6, target_error_pct=0.0)
    history = DriveIteration(vehicle, target, CHANNELS, tmp_path, settings).run(progress=False).history
    measured = errors(history)
    expected = 100 * 0.5 ** (np.arange(len(measured)) + 1)  # drive_0 = g H+ target already leaves (1 - g)
    considered = expected >= 1.0
    ratio = measured[considered] / expected[considered]
    assert np.all((ratio > 0.5) & (ratio < 2.0)), (measured, expected)


def test_default_scheme_reaches_3_percent_on_a_nonlinear_car_within_limits(tmp_path):
    """proton_x_nonlinear (bump stops, asymmetric dampers, tyres that lift off), 30 s of ISO 8608 class C
    at 20 m/s as the 8-channel target."""
    vehicle = load_vehicle("proton_x_nonlinear")
    run = track_run(vehicle, iso8608_road("C", 700.0, seed=1), 20.0, duration=30.0)
    assert any(run.airborne_time().values())  # the target itself has lift-off
    result = DriveIteration(vehicle, run.record, CHANNELS, tmp_path,
                            IterationSettings(iterations=8)).run(progress=False)
    assert result.status == "converged" and result.stop_reason.startswith("target reached")
    last = result.history[-1]
    assert last.worst_rms_error_pct <= 3.0 and len(result.history) <= 8
    assert all(h.limit_hits == [] for h in result.history)
    assert np.abs(result.drive).max() < vehicle.rig.stroke
    recovery = last.road_recovery_rms_error_pct
    assert all(parts["2-50 Hz"] < 10.0 for parts in recovery.values())


def test_history_is_written_every_iteration_with_the_contract_keys(linear_target, tmp_path):
    vehicle, target = linear_target
    DriveIteration(vehicle, target, CHANNELS, tmp_path,
                   IterationSettings(iterations=2, target_error_pct=0.0)).run(progress=False)
    document = json.loads((tmp_path / "history.json").read_text())
    assert len(document["iterations"]) == 2
    for entry in document["iterations"]:
        for name in CHANNELS:
            assert set(entry["channels"][name]) == {"rms_error_pct", "tddi", "damage_ratio", "peak_error_pct"}
    drive = read_record(tmp_path / "drive.drv")
    assert drive.names == ["FL/drive", "FR/drive", "RL/drive", "RR/drive"]


def test_resuming_after_iteration_2_gives_the_uninterrupted_result(linear_target, tmp_path):
    """Stopped after iteration 2 of 4 (its state written), resumed to 4: the drive and errors of 4 uninterrupted
    iterations."""
    vehicle, target = linear_target

    def settings(iterations):
        return IterationSettings(iterations=iterations, target_error_pct=0.0)

    straight = DriveIteration(vehicle, target, CHANNELS, tmp_path / "straight", settings(4)).run(progress=False)
    DriveIteration(vehicle, target, CHANNELS, tmp_path / "stopped", settings(2)).run(progress=False)
    resumed = DriveIteration(vehicle, target, CHANNELS, tmp_path / "stopped", settings(4)).run(
        resume=True, progress=False)
    # equal up to floating-point summation order in the linear algebra (1e-12 of the drive's peak)
    np.testing.assert_allclose(resumed.drive, straight.drive, rtol=0, atol=1e-12 * np.abs(straight.drive).max())
    np.testing.assert_allclose(errors(resumed.history), errors(straight.history), rtol=1e-9)


def test_resume_refuses_other_settings(linear_target, tmp_path):
    vehicle, target = linear_target
    DriveIteration(vehicle, target, CHANNELS, tmp_path, IterationSettings(iterations=1)).run(progress=False)
    with pytest.raises(ValueError, match="other settings"):
        DriveIteration(vehicle, target, CHANNELS, tmp_path,
                       IterationSettings(iterations=2, scheme="fixed")).run(resume=True, progress=False)


def test_a_diverging_step_is_cut_and_the_best_drive_kept(linear_target, tmp_path):
    vehicle, target = linear_target
    settings = IterationSettings(iterations=5, gain=3.0, target_error_pct=0.0)  # overshoots by 200 %
    result = DriveIteration(vehicle, target, CHANNELS, tmp_path, settings).run(progress=False)
    gains = [h.gain for h in result.history]
    assert min(gains) < 3.0
    totals = [h.total_error_pct for h in result.history]
    best = min(totals)
    kept = DriveIteration(vehicle, target, CHANNELS, tmp_path / "check", IterationSettings(iterations=1))
    response = kept.rig.play(result.drive)[0][0]
    from rig.signal.filters import band_pass

    replayed = band_pass(response, kept.rate, kept.settings.band)
    weighted = (kept.weight * replayed + (1 - kept.weight) * kept.target)[kept.span]
    error = np.sqrt(np.mean((weighted - kept.target[kept.span]) ** 2, axis=0)) / kept.target_rms * 100
    assert np.sqrt(np.mean(error**2)) == pytest.approx(best, rel=1e-6)


def test_cli_iterate_with_channel_map(linear_target, tmp_path, capsys):
    _vehicle, target = linear_target
    renamed = target.select(["FL/unsprung_acc", "FR/unsprung_acc", "RL/unsprung_acc", "RR/unsprung_acc"])
    renamed.channels = {n.replace("/unsprung_acc", "_wheel"): v for n, v in renamed.channels.items()}
    renamed.units = {n: "m/s^2" for n in renamed.channels}
    path = tmp_path / "target.csv"
    write_record(path, renamed)
    out = tmp_path / "run"
    code = main(["iterate", "--vehicle", "proton_x", "--target", str(path), "--out", str(out), "--iterations", "2",
                 "--quiet", "--map", "FL_=FL/unsprung_acc", "FR_=FR/unsprung_acc", "RL_=RL/unsprung_acc",
                 "RR_=RR/unsprung_acc"])
    assert code == 0
    for name in ("drive.csv", "drive.drv", "history.json", "convergence.png", "psd/iteration_01.png"):
        assert (out / name).stat().st_size > 0
    assert "RMS error" in capsys.readouterr().out
    assert main(["iterate", "--vehicle", "proton_x", "--target", str(path), "--out", str(tmp_path / "again"),
                 "--quiet", "--map", "wheel=FL/unsprung_acc"]) == 2
    assert "matches 4 channels" in capsys.readouterr().err


def test_a_run_saved_before_iterations_had_a_status_resumes(linear_target, tmp_path):
    vehicle, target = linear_target
    settings = IterationSettings(iterations=1, target_error_pct=0.0)
    DriveIteration(vehicle, target, CHANNELS, tmp_path, settings).run(progress=False)
    path = tmp_path / "history.json"
    document = json.loads(path.read_text())
    del document["status"]  # history.json as the previous version wrote it
    path.write_text(json.dumps(document))
    resumed = DriveIteration(vehicle, target, CHANNELS, tmp_path, IterationSettings(iterations=2, target_error_pct=0.0))
    result = resumed.run(resume=True, progress=False)
    assert [h.iteration for h in result.history] == [0, 1] and result.status == "out_of_iterations"


def test_the_command_line_says_each_iteration_and_every_post_limit_as_it_happens(capsys):
    from controllers.rpc import IterationRecord, IterationStep
    from rig.cli.iterate import _say

    entry = IterationRecord(3, 0.5, 4.2, 3.1, {"FL/sprung_acc": ChannelMetrics.from_json({"rms_error_pct": 4.2}),
                                               "FR/sprung_acc": ChannelMetrics.from_json({"rms_error_pct": 1.0})},
                            ["FL: velocity limit ±2.38 m/s exceeded, peak 2.9 m/s at 12.31 s"])
    _say(IterationStep(entry, [entry], np.zeros((1, 4)), np.zeros((1, 2))))
    assert capsys.readouterr().out.splitlines() == [
        "iteration 3: worst channel 4.20 % RMS error (FL/sprung_acc), gain 0.50",
        "  post limit: FL: velocity limit ±2.38 m/s exceeded, peak 2.9 m/s at 12.31 s"]
