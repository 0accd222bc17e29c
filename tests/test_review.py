"""Rerun review: recordings of a replay, a track run and a drive iteration, read back from the .rrd file and
checked against the records, the simulation's kinematics and the iteration's own results."""

from __future__ import annotations

import json
import shutil
from collections import defaultdict

import numpy as np
import pyarrow as pa
import pytest
from rerun.chunk import RrdReader

from controllers.rpc import DriveIteration, IterationSettings
from rig.cli.demo import demo_drive
from rig.cli.main import main
from rig.io.files import write_record
from rig.report.review import IterationLog, default_blueprint, log_drive_iteration, log_iteration, log_replay, recording
from rig.road.roads import iso8608_road
from rig.sim.replay import replay
from rig.sim.track import track_run
from rig.vehicle.vehicle_file import load_vehicle

CHANNELS = [f"{c}/{q}" for c in ("FL", "FR", "RL", "RR") for q in ("sprung_acc", "unsprung_acc")]
FLOAT32 = 2e-7  # m: positions and quaternions are stored as float32


def _numbers(column: pa.Array) -> np.ndarray:
    """A column of (nested) lists of numbers as rows x values."""
    rows = len(column)
    while pa.types.is_list(column.type) or pa.types.is_fixed_size_list(column.type):
        column = column.flatten()
    return np.asarray(column.to_numpy(zero_copy_only=False), float).reshape(rows, -1)


class Rrd:
    """The recording in a .rrd file: per entity, its timelines and components (temporal rows sorted by time)."""

    def __init__(self, path):
        reader = RrdReader(path)
        self.blueprints = reader.blueprints()
        self.static: dict[str, dict[str, pa.Array]] = defaultdict(dict)
        parts: dict[str, dict[str, list[pa.Array]]] = defaultdict(lambda: defaultdict(list))
        for chunk in reader.store().stream():
            batch = chunk.to_record_batch()
            names = [n for n in batch.schema.names if not n.startswith("rerun.controls")]
            for name in names:
                if chunk.is_static:
                    self.static[chunk.entity_path][name] = batch.column(name)
                else:
                    parts[chunk.entity_path][name].append(batch.column(name))
        self.temporal = {path: {name: pa.concat_arrays(arrays) for name, arrays in columns.items()}
                         for path, columns in parts.items()}

    def timelines(self, entity: str) -> set[str]:
        return {n for n in self.temporal[entity] if ":" not in n}

    def index(self, entity: str, timeline: str) -> np.ndarray:
        values = self.temporal[entity][timeline]
        if pa.types.is_duration(values.type):
            return values.cast(pa.int64()).to_numpy() / 1e9  # s
        return values.to_numpy()

    def values(self, entity: str, component: str, timeline: str = "time") -> np.ndarray:
        """Rows x values of a temporal component, in timeline order."""
        order = np.argsort(self.index(entity, timeline), kind="stable")
        return _numbers(self.temporal[entity][component])[order]

    def scalars(self, entity: str, timeline: str = "time") -> tuple[np.ndarray, np.ndarray]:
        order = np.argsort(self.index(entity, timeline), kind="stable")
        return self.index(entity, timeline)[order], self.values(entity, "Scalars:scalars", timeline)[:, 0]


def _rotate_z(quaternion_xyzw: np.ndarray) -> np.ndarray:
    """The z axis rotated by a unit quaternion in Rerun's order (x, y, z, w)."""
    x, y, z, w = quaternion_xyzw
    return np.array([2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)])


@pytest.fixture(scope="module")
def vehicle():
    return load_vehicle("proton_x")


@pytest.fixture(scope="module")
def replayed(vehicle, tmp_path_factory):
    result = replay(vehicle, demo_drive(vehicle.corners, duration=2.0))
    path = tmp_path_factory.mktemp("review") / "replay.rrd"
    with recording(path, blueprint=default_blueprint(vehicle.corners)) as stream:
        log_replay(stream, result)
    return result, Rrd(path)


def test_replay_channels_are_series_per_corner_on_the_time_timeline(replayed):
    result, rrd = replayed
    record = result.record
    assert rrd.blueprints, "the file carries its default layout"
    for name in record.names:
        entity = f"/run/{name}"
        assert rrd.timelines(entity) == {"time"}
        time, values = rrd.scalars(entity)
        assert values.size == record.n_samples == 1024
        np.testing.assert_allclose(time, record.time, atol=1e-9)
        np.testing.assert_array_equal(values, record[name])  # float64 end to end
        assert rrd.static[entity]["SeriesLines:names"].to_pylist() == [[f"{name} [{record.units[name]}]"]]
    assert {e for e in rrd.temporal if e.startswith("/run/")} == {f"/run/{n}" for n in record.names}


def test_replay_animation_follows_the_record(replayed):
    """The posts' poses reproduce the achieved post displacement and the suspension tendon drawn between its
    sites reproduces the suspension travel, sample by sample: the animation is the simulated motion."""
    result, rrd = replayed
    record, model = result.record, result.model
    for corner in ("FL", "RR"):
        post = f"/rig/{corner}/post"
        assert rrd.timelines(post) == {"time"}
        translation = rrd.values(post, "Transform3D:translation")
        assert translation.shape == (record.n_samples, 3)
        np.testing.assert_allclose(np.sort(rrd.index(post, "time")), record.time, atol=1e-9)
        rest = model.body_pos[model.body(f"{corner}/post").id]
        np.testing.assert_allclose(translation[:, :2], np.broadcast_to(rest[:2], (record.n_samples, 2)), atol=FLOAT32)
        np.testing.assert_allclose(translation[:, 2] - rest[2], record[f"{corner}/actuator_disp"], atol=FLOAT32)
        strips = rrd.values(f"/rig/tendons/car.{corner}/suspension", "LineStrips3D:strips").reshape(-1, 2, 3)
        length = np.linalg.norm(strips[:, 0] - strips[:, 1], axis=1)
        np.testing.assert_allclose(length[0] - length, record[f"{corner}/susp_travel"], atol=1e-6)
        assert np.ptp(record[f"{corner}/susp_travel"]) > 5e-3  # the check above is not trivially met
    body = rrd.values("/rig/car.body", "Transform3D:quaternion")
    assert body.shape == (record.n_samples, 4)
    assert np.all(body[:, 3] > 0.999)  # w last: the body only pitches and rolls a little
    assert np.ptp(body[:, 1]) > 1e-4  # ...but it does pitch


def test_replay_geometry_has_the_models_proportions(replayed):
    result, rrd = replayed
    model = result.model
    wheel = rrd.static["/rig/car.FL/wheel/cylinders"]
    geom = model.geom("car.FL/wheel").id
    assert _numbers(wheel["Cylinders3D:radii"])[0, 0] == pytest.approx(model.geom_size[geom, 0], rel=1e-6)
    assert _numbers(wheel["Cylinders3D:lengths"])[0, 0] == pytest.approx(2 * model.geom_size[geom, 1], rel=1e-6)
    axis = _rotate_z(_numbers(wheel["Cylinders3D:quaternions"])[0])
    np.testing.assert_allclose(np.abs(axis), [0, 1, 0], atol=1e-6)  # the wheel's axle is lateral
    box = rrd.static["/rig/car.body/boxes"]
    np.testing.assert_allclose(_numbers(box["Boxes3D:half_sizes"])[0], model.geom_size[model.geom("car.body").id],
                               rtol=1e-6)
    assert "/rig/world/boxes" in rrd.static  # the pit floor


@pytest.fixture(scope="module")
def iteration(vehicle, tmp_path_factory):
    target = track_run(vehicle, iso8608_road("B", 300.0, seed=3), 20.0, duration=6.0).record
    folder = tmp_path_factory.mktemp("iterate")
    job = DriveIteration(vehicle, target, CHANNELS, folder, IterationSettings(iterations=3, target_error_pct=0.0))
    plays = IterationLog()
    result = job.run(progress=False, callback=plays)
    with recording(folder / "iterate.rrd", blueprint=default_blueprint(vehicle.corners, CHANNELS)) as stream:
        log_drive_iteration(stream, result, plays, job.target, float(job.time[0]), CHANNELS, job.settings.band)
    return job, result, Rrd(folder / "iterate.rrd")


def test_iteration_series_match_the_iterations_own_results(iteration):
    job, result, rrd = iteration
    assert [h.iteration for h in result.history] == [0, 1, 2]
    best = result.best.iteration
    n = job.target.shape[0]
    for j, name in enumerate(CHANNELS):
        time, target = rrd.scalars(f"/iterate/target/{name}")
        assert target.size == n
        np.testing.assert_allclose(time, job.time, atol=1e-9)
        assert time[0] < 0  # the drive's lead-in: the target record starts at 0
        np.testing.assert_array_equal(target, job.target[:, j])
        assert rrd.timelines(f"/iterate/response/{name}") == {"time"}
        response = rrd.values(f"/iterate/response/{name}", "Scalars:scalars")  # samples x iterations
        error = rrd.values(f"/iterate/error/{name}", "Scalars:scalars")
        assert response.shape == error.shape == (n, 3)
        np.testing.assert_allclose(error, target[:, None] - response, atol=1e-12)
        # the best iteration's response is the one the iteration kept, band-passed alike
        np.testing.assert_allclose(response[:, best], result.response[:, j],
                                   atol=1e-9 * np.abs(result.response[:, j]).max())
        assert rrd.static[f"/iterate/response/{name}"]["SeriesLines:names"].to_pylist() == [
            ["iteration 0", "iteration 1", "iteration 2"]]
    for i, corner in enumerate(job.corners):
        drives = rrd.values(f"/iterate/drive/{corner}", "Scalars:scalars")
        np.testing.assert_array_equal(drives[:, best], result.drive[:, i])


def test_iteration_metrics_are_on_the_iteration_timeline(iteration):
    job, result, rrd = iteration
    history = json.loads((job.out_dir / "history.json").read_text())["iterations"]
    for name in CHANNELS:
        for key in ("rms_error_pct", "tddi", "damage_ratio"):
            entity = f"/iterate/{key}/{name}"
            assert rrd.timelines(entity) == {"iteration"}
            sequence, values = rrd.scalars(entity, "iteration")
            np.testing.assert_array_equal(sequence, [0, 1, 2])
            np.testing.assert_allclose(values, [h["channels"][name][key] for h in history], rtol=1e-12)
    worst = rrd.scalars("/iterate/worst_rms_error_pct", "iteration")[1]
    np.testing.assert_allclose(worst, [h["worst_rms_error_pct"] for h in history], rtol=1e-12)
    assert worst[-1] < worst[0]  # it converges
    summary = rrd.temporal["/iterate/summary"]["TextDocument:text"].to_pylist()
    assert len(summary) == 3 and all(name in summary[0][0] for name in CHANNELS)


def test_frf_is_logged_against_frequency_with_the_quarter_car_magnitude(iteration):
    """Well below wheel hop the wheel follows its own post: |unsprung_acc / drive| = (2 pi f)^2 (44 dB at 2 Hz),
    and the other posts reach it only through the body, far weaker."""
    job, _, rrd = iteration
    for name in CHANNELS:
        entity = f"/frf/coherence/{name}"
        assert rrd.timelines(entity) == {"frequency_mHz"}
        millihertz, coherence = rrd.scalars(entity, "frequency_mHz")
        assert millihertz[0] >= 1000 * job.settings.band[0] and millihertz[-1] <= 1000 * job.settings.band[1]
        assert np.all((coherence >= 0) & (coherence <= 1)) and np.median(coherence) > 0.9
    millihertz, direct = rrd.scalars("/frf/magnitude_db/FL/unsprung_acc/FL/drive", "frequency_mHz")
    cross = rrd.scalars("/frf/magnitude_db/FL/unsprung_acc/RR/drive", "frequency_mHz")[1]
    for hertz in (2.0, 3.0):
        line = np.flatnonzero(millihertz == 1000 * hertz)[0]
        assert direct[line] == pytest.approx(20 * np.log10((2 * np.pi * hertz) ** 2), abs=1.0)
        assert cross[line] < direct[line] - 20


def test_iteration_best_drive_is_replayed_for_the_rig_view(iteration):
    job, result, rrd = iteration
    time, drive = rrd.scalars("/run/FL/drive")
    np.testing.assert_array_equal(drive, result.drive[:, 0])
    np.testing.assert_allclose(time, job.time, atol=1e-9)
    assert rrd.timelines("/rig/car.body") == {"time"}


def test_cli_replay_and_track_write_recordings(vehicle, tmp_path, capsys):
    drive = tmp_path / "drive.csv"
    write_record(drive, demo_drive(vehicle.corners, duration=2.0))
    assert main(["replay", "--vehicle", "proton_x", "--drive", str(drive), "--out", str(tmp_path / "r.csv"),
                 "--rerun", str(tmp_path / "replay.rrd")]) == 0
    rrd = Rrd(tmp_path / "replay.rrd")
    assert rrd.scalars("/run/RR/tyre_force")[1].size == 1024
    assert main(["track", "--vehicle", "proton_x", "--road", "iso8608:class=B,length=100,seed=1", "--speed", "20",
                 "--duration", "1", "--out", str(tmp_path / "t.csv"), "--rerun", str(tmp_path / "track.rrd")]) == 0
    rrd = Rrd(tmp_path / "track.rrd")
    assert rrd.scalars("/run/FL/road")[1].size == 512
    assert "/rig/FL/post" in rrd.static and "/rig/FL/post" not in rrd.temporal  # ideal posts: pans stay put
    assert rrd.timelines("/rig/car.FL/wheel") == {"time"}
    assert "open it with: rerun" in capsys.readouterr().out


def test_resumed_iterations_are_labelled_by_their_own_iteration_numbers(tmp_path):
    """A resumed run logs responses only for its own iterations: the last entries of the history."""
    history = [{"iteration": k, "gain": 1.0, "worst_rms_error_pct": 10.0 / (k + 1),
                "channels": {"FL/sprung_acc": {"rms_error_pct": 10.0 / (k + 1), "tddi": 0.1, "damage_ratio": 1.0}}}
               for k in range(3)]
    target = np.linspace(0.0, 1.0, 64)[:, None]
    responses = [0.5 * target, 0.9 * target]  # iterations 1 and 2
    with recording(tmp_path / "resumed.rrd") as stream:
        log_iteration(stream, history, target, responses, 64.0, ["FL/sprung_acc"], start_time=-0.5)
    rrd = Rrd(tmp_path / "resumed.rrd")
    assert rrd.static["/iterate/response/FL/sprung_acc"]["SeriesLines:names"].to_pylist() == [
        ["iteration 1", "iteration 2"]]
    time, _ = rrd.scalars("/iterate/target/FL/sprung_acc")
    np.testing.assert_allclose(time, -0.5 + np.arange(64) / 64.0, atol=1e-9)
    np.testing.assert_allclose(rrd.values("/iterate/error/FL/sprung_acc", "Scalars:scalars"),
                               np.column_stack([0.5 * target[:, 0], 0.1 * target[:, 0]]), atol=1e-12)
    assert rrd.scalars("/iterate/worst_rms_error_pct", "iteration")[1].tolist() == [10.0, 5.0, 10.0 / 3]


def test_cli_iterate_resumed_writes_a_recording(iteration, tmp_path):
    """``rig iterate --resume --rerun``: the resumed iteration's series, every iteration's metrics, the FRF."""
    job, _, _ = iteration
    folder = tmp_path / "iterate"
    shutil.copytree(job.out_dir, folder)
    target = tmp_path / "target.csv"
    write_record(target, job.target_record)
    assert main(["iterate", "--vehicle", "proton_x", "--target", str(target), "--out", str(folder), "--channels",
                 *CHANNELS, "--iterations", "4", "--target-error", "0", "--resume", "--quiet",
                 "--rerun", str(tmp_path / "resumed.rrd")]) == 0
    rrd = Rrd(tmp_path / "resumed.rrd")
    assert rrd.static["/iterate/response/FL/sprung_acc"]["SeriesLines:names"].to_pylist() == [["iteration 3"]]
    assert rrd.values("/iterate/drive/RR", "Scalars:scalars").shape == (job.target.shape[0], 1)
    assert rrd.scalars("/iterate/rms_error_pct/RR/unsprung_acc", "iteration")[0].tolist() == [0, 1, 2, 3]
    assert rrd.timelines("/frf/coherence/RR/unsprung_acc") == {"frequency_mHz"}
    assert rrd.timelines("/rig/car.body") == {"time"}
