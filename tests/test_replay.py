"""Replay: drive limits are refused or clipped and reported, never silently; servo vs ideal posts agree;
the command line writes contract records and fails in one line without touching existing files."""

import dataclasses

import numpy as np
import pytest

from rig.sim.broadband import broadband_drive
from rig.cli.main import main
from rig.io.channels import CORNERS, RESPONSE_QUANTITIES, channel
from rig.io.files import read_record, write_record
from rig.io.record import Record, RecordError
from rig.sim.drive_limits import DriveLimitError
from rig.sim.replay import replay
from rig.vehicle.vehicle_file import load_vehicle


@pytest.fixture(scope="module")
def proton_x():
    return load_vehicle("proton_x")


def drive_record(values, rate=512.0):
    return Record(rate, {channel(c, "drive"): values[:, i] for i, c in enumerate(CORNERS)})


def sine_drive(amplitude, frequency, duration=2.0, rate=512.0):
    t = np.arange(int(duration * rate)) / rate
    values = amplitude * np.sin(2 * np.pi * frequency * t)
    return drive_record(np.column_stack([values] * 4), rate)


def test_response_record_has_every_contract_channel_at_the_drive_rate(proton_x):
    drive = broadband_drive(proton_x.corners, duration=3.0)
    result = replay(proton_x, drive)
    expected = {channel(c, q) for c in CORNERS for q in (*RESPONSE_QUANTITIES, "drive")}
    assert set(result.record.names) == expected
    assert result.record.rate == drive.rate and result.record.n_samples == drive.n_samples
    assert result.record.metadata["posts"] == "servo"


def test_beyond_stroke_is_refused_naming_corner_and_limit(proton_x):
    with pytest.raises(DriveLimitError, match=r"FL: stroke limit ±0.075 m exceeded, peak 0.08 m"):
        replay(proton_x, sine_drive(0.08, 0.5))


def test_beyond_velocity_is_refused(proton_x):
    with pytest.raises(DriveLimitError, match=r"velocity limit ±2.38 m/s exceeded"):
        replay(proton_x, sine_drive(0.02, 25.0))  # 3.1 m/s peak


def test_clip_clips_and_reports_every_corner(proton_x):
    result = replay(proton_x, sine_drive(0.08, 0.5), clip=True)
    stroke_hits = [h for h in result.limit_hits if h.limit == "stroke"]
    assert {h.corner for h in stroke_hits} == set(CORNERS)
    assert np.abs(result.record["FL/drive"]).max() <= 0.075 + 1e-12
    # the post meets its end stop (a soft joint limit): reported, and held within 0.1 mm
    assert np.abs(result.record["FL/actuator_disp"]).max() <= 0.075 + 1e-4
    assert len(stroke_hits) == 8  # four clipped drives, four posts at their end stops


def test_force_saturation_is_refused_then_reported_with_clip(proton_x):
    weak = dataclasses.replace(proton_x, rig=dataclasses.replace(proton_x.rig, force_limit=5000.0))
    drive = sine_drive(0.01, 12.0)
    with pytest.raises(DriveLimitError, match=r"FL: force limit ±5000 N reached, peak 5000 N"):
        replay(weak, drive)
    result = replay(weak, drive, clip=True)
    assert {h.limit for h in result.limit_hits} == {"force"}
    assert np.abs(result.record["FL/actuator_force"]).max() <= 5000.0 + 1e-6


def test_drive_must_start_at_zero(proton_x):
    values = np.full((1024, 4), 0.002)
    with pytest.raises(DriveLimitError, match=r"drive must start at 0 m.*FL starts at 2.00 mm"):
        replay(proton_x, drive_record(values))


def test_missing_corner_is_named(proton_x):
    drive = broadband_drive(proton_x.corners, duration=1.0)
    partial = drive.select([n for n in drive.names if not n.startswith("RR/")])
    with pytest.raises(RecordError, match=r"missing RR/drive"):
        replay(proton_x, partial)


def test_ideal_replay_of_the_achieved_post_motion_reproduces_the_servo_run(proton_x):
    """The car only feels the posts: replaying the servo run's measured actuator_disp on ideal posts
    must give the same car responses (this is how validation replays measured rig data)."""
    servo = replay(proton_x, broadband_drive(proton_x.corners, duration=6.0)).record
    measured = servo.select([channel(c, "actuator_disp") for c in CORNERS])
    ideal = replay(proton_x, measured).record
    assert ideal.metadata["posts"] == "ideal"
    for quantity in ("sprung_acc", "unsprung_acc", "susp_travel", "tyre_force"):
        a, b = servo.quantity(quantity), ideal.quantity(quantity)
        relative = np.sqrt(np.mean((a - b) ** 2)) / np.sqrt(np.mean((a - a.mean()) ** 2))
        assert relative < 0.005, (quantity, relative)


def test_batch_of_vehicle_variants_equals_single_runs(proton_x):
    from rig.sim.replay import replay_batch

    soft = dataclasses.replace(proton_x, front=dataclasses.replace(proton_x.front, damping=2000.0))
    drive = broadband_drive(proton_x.corners, duration=2.0)
    together = replay_batch([proton_x, soft], [drive, drive], nthread=2)
    for vehicle, result in zip([proton_x, soft], together):
        alone = replay(vehicle, drive).record
        np.testing.assert_array_equal(result.record["FL/sprung_acc"], alone["FL/sprung_acc"])


def test_cli_replay_writes_a_contract_csv(tmp_path, capsys):
    drive = tmp_path / "drive.csv"
    write_record(drive, broadband_drive(CORNERS, duration=2.0))
    out = tmp_path / "response.csv"
    assert main(["replay", "--vehicle", "proton_x", "--drive", str(drive), "--out", str(out)]) == 0
    record = read_record(out)
    assert record.rate == 512.0 and "RR/tyre_force" in record.names
    assert "posts" in capsys.readouterr().out


def test_cli_bad_input_is_one_line_and_keeps_existing_output(tmp_path, capsys):
    drive = tmp_path / "drive.csv"
    write_record(drive, sine_drive(0.09, 0.5))
    out = tmp_path / "response.csv"
    out.write_text("previous result\n")
    assert main(["replay", "--vehicle", "proton_x", "--drive", str(drive), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "stroke" in err and "Traceback" not in err
    assert out.read_text() == "previous result\n"


def test_cli_model_export_loads_in_mujoco_at_rest(tmp_path):
    import mujoco

    path = tmp_path / "proton_x.xml"
    assert main(["model", "--vehicle", "proton_x", "--export", str(path)]) == 0
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key("static_ride_height").id)
    mujoco.mj_forward(model, data)
    assert np.abs(data.qacc).max() < 1e-2  # at rest up to the XML's printed precision


def test_cli_demo_writes_records_and_plots(tmp_path):
    out = tmp_path / "demo"
    assert main(["demo", "--quick", "--out", str(out), "--duration", "3"]) == 0
    for name in ("drive.csv", "response.csv", "responses.png", "psd.png"):
        assert (out / name).stat().st_size > 0


def test_joint_positions_at_sample_times_match_the_channels(proton_x):
    result = replay(proton_x, broadband_drive(proton_x.corners, duration=2.0))
    assert result.qpos.shape == (result.record.n_samples, result.model.nq)
    for corner in proton_x.corners:
        post = result.model.jnt_qposadr[result.model.joint(f"{corner}/post").id]
        np.testing.assert_allclose(result.qpos[:, post], result.record[f"{corner}/actuator_disp"], atol=1e-12)


def test_a_replay_without_joint_positions_gives_the_same_records_and_still_refuses_a_run_that_diverged(proton_x):
    """A batch that keeps no states (a fit's: ``qpos=False``) gives the records bit for bit; a run that diverged
    (front dampers pushing: -60 000 N s/m) is refused although a later run on the same thread cleared MuJoCo's
    warnings and MuJoCo reset it to finite values, since its time stops where MuJoCo stopped it (the clock sensor)."""
    from rig.sim.replay import replay_batch
    from rig.sim.simulate import SimulationError

    measured = replay(proton_x, broadband_drive(proton_x.corners, duration=2.0)).record
    posts = measured.select([channel(c, "actuator_disp") for c in CORNERS])
    soft = dataclasses.replace(proton_x, front=dataclasses.replace(proton_x.front, damping=2000.0))
    kept = replay_batch([proton_x, soft], [posts, posts], limits=False, longest=2e-3)
    lean = replay_batch([proton_x, soft], [posts, posts], limits=False, longest=2e-3, qpos=False)
    for a, b in zip(kept, lean):
        assert b.qpos is None and a.qpos is not None
        for name in a.record.names:
            np.testing.assert_array_equal(a.record[name], b.record[name])
    diverging = dataclasses.replace(proton_x, front=dataclasses.replace(proton_x.front, damping=-60000.0))
    for qpos in (True, False):
        with pytest.raises(SimulationError, match="unstable"):
            replay_batch([diverging, proton_x], [posts, posts], nthread=1, limits=False, longest=2e-3, qpos=qpos)
