"""Rerun review: recordings of a replay, a track run and a drive iteration, read back from the .rrd file and
checked against the records, the simulation's kinematics and the iteration's own results."""

from __future__ import annotations

import itertools
import json
import shutil
import uuid
from collections import defaultdict

import numpy as np
import pyarrow as pa
import pytest
from rerun.chunk import RrdReader

from controllers.rpc import DriveIteration, IterationSettings
from rig.sim.broadband import broadband_drive
from rig.cli.main import main
from rig.io.files import read_record, write_record
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
    """The recording in a .rrd file: per entity, its timelines and components (temporal rows sorted by time;
    rows of chunks on other timelines left out), and its default layout (``Layout``)."""

    def __init__(self, path):
        reader = RrdReader(path)
        self.blueprints = reader.blueprints()
        self.layout = Layout(reader) if self.blueprints else None
        self.static: dict[str, dict[str, pa.Array]] = defaultdict(dict)
        parts: dict[str, list[pa.Table]] = defaultdict(list)
        for chunk in reader.store().stream():
            batch = chunk.to_record_batch()
            names = [n for n in batch.schema.names if not n.startswith("rerun.controls")]
            if chunk.is_static:
                self.static[chunk.entity_path].update({name: batch.column(name) for name in names})
            else:
                parts[chunk.entity_path].append(pa.Table.from_batches([batch.select(names)]))
        self.temporal: dict[str, dict[str, pa.Array]] = {}
        for entity, tables in parts.items():  # chunks on other timelines: their timeline columns are null
            table = pa.concat_tables(tables, promote_options="default")
            self.temporal[entity] = {name: table.column(name).combine_chunks() for name in table.column_names}

    def timelines(self, entity: str) -> set[str]:
        return {n for n in self.temporal[entity] if ":" not in n}

    def _rows(self, entity: str, timeline: str) -> np.ndarray:
        """The entity's rows on ``timeline``, in its order."""
        values = self.temporal[entity][timeline]
        rows = np.flatnonzero(values.is_valid().to_numpy(zero_copy_only=False))
        return rows[np.argsort(self._times(values.take(rows)), kind="stable")]

    @staticmethod
    def _times(values: pa.Array) -> np.ndarray:
        if pa.types.is_duration(values.type):
            return values.cast(pa.int64()).to_numpy() / 1e9  # s
        return values.to_numpy()

    def index(self, entity: str, timeline: str) -> np.ndarray:
        """The entity's times (s) or sequence numbers on ``timeline``, in order."""
        return self._times(self.temporal[entity][timeline].take(self._rows(entity, timeline)))

    def values(self, entity: str, component: str, timeline: str = "time") -> np.ndarray:
        """Rows x values of a temporal component, in timeline order."""
        return _numbers(self.temporal[entity][component].take(self._rows(entity, timeline)))

    def scalars(self, entity: str, timeline: str = "time") -> tuple[np.ndarray, np.ndarray]:
        return self.index(entity, timeline), self.values(entity, "Scalars:scalars", timeline)[:, 0]

    def entities(self, query: str) -> list[str]:
        """Logged entities (static or temporal) that a view's ``+ path`` query (``**``: and everything below)
        selects."""
        path = "/" + query.removeprefix("+ ")
        below = path.endswith("/**")
        base = path.removesuffix("/**")
        return sorted(e for e in set(self.static) | set(self.temporal)
                      if e == base or (below and e.startswith(base + "/")))

    def colors(self, entity: str) -> list[tuple[int, int, int]]:
        """The RGB colour of each series of an entity (its static SeriesLines)."""
        packed = np.asarray(self.static[entity]["SeriesLines:colors"].to_pylist()[0], np.uint32)
        return [tuple(int(v >> shift) & 0xFF for shift in (24, 16, 8)) for v in packed]


def _union_kinds(array: pa.Array) -> list[str]:
    """The variant names of a dense union array, e.g. TimeRangeBoundary's 'Infinite'."""
    names = {code: array.type.field(i).name for i, code in enumerate(array.type.type_codes)}
    return [names[code] for code in array.type_codes.to_numpy()]


def _one(column: pa.Array):
    """The single value of a blueprint component (its last row)."""
    return column[len(column) - 1].as_py()[0]


class Layout:
    """A recording's default blueprint: its views (class, name, origin, content queries, time ranges, x axis,
    legend) and the views on screen when it opens (every container's content, but only a tab container's
    first tab)."""

    def __init__(self, reader: RrdReader):
        parts: dict[str, dict[str, pa.Array]] = defaultdict(dict)
        for chunk in reader.store(store=reader.blueprints()[0]).stream():
            batch = chunk.to_record_batch()
            parts[chunk.entity_path].update({n: batch.column(n) for n in batch.schema.names if ":" in n})
        self.parts = parts = dict(parts)
        self.views = {}
        for path, columns in parts.items():
            if path.count("/") == 2 and path.startswith("/view/"):
                view = {"class": _one(columns["ViewBlueprint:class_identifier"]),
                        "name": _one(columns["ViewBlueprint:display_name"]),
                        "origin": _one(columns["ViewBlueprint:space_origin"]),
                        "contents": parts[f"{path}/ViewContents"]["ViewContents:query"][0].as_py()}
                ranges = parts.get(f"{path}/VisibleTimeRanges", {}).get("VisibleTimeRanges:ranges")
                if ranges is not None:
                    items = ranges[0].values
                    view["ranges"] = dict(zip(items.field("timeline").to_pylist(), zip(
                        _union_kinds(items.field("range").field("start")),
                        _union_kinds(items.field("range").field("end")))))
                axis = parts.get(f"{path}/TimeAxis")
                if axis:
                    view_range = axis["TimeAxis:view_range"][0].values
                    view["axis"] = (_union_kinds(view_range.field("start"))[0],
                                    _union_kinds(view_range.field("end"))[0], _one(axis["TimeAxis:link"]))
                legend = parts.get(f"{path}/PlotLegend")
                view["legend"] = _one(legend["PlotLegend:visible"]) if legend else True
                self.views[path.removeprefix("/")] = view
        root = _one(parts["/viewport"]["ViewportBlueprint:root_container"])  # a UUID as 16 bytes
        self.on_screen = self._visible(f"container/{uuid.UUID(bytes=bytes(root))}")
        self.timeline = _one(parts["/time_panel"]["TimePanelBlueprint:timeline"])

    def _visible(self, item: str) -> list[dict]:
        if item.startswith("view/"):
            return [self.views[item]]
        columns = self.parts[f"/{item}"]
        contents = columns["ContainerBlueprint:contents"][0].as_py()
        if _one(columns["ContainerBlueprint:container_kind"]) == 1:  # tabs: the first one shows
            contents = contents[:1]
        return [view for child in contents for view in self._visible(child)]

    def of_class(self, kind: str) -> list[dict]:
        return [view for view in self.views.values() if view["class"] == kind]


def _rotate_z(quaternion_xyzw: np.ndarray) -> np.ndarray:
    """The z axis rotated by a unit quaternion in Rerun's order (x, y, z, w)."""
    x, y, z, w = quaternion_xyzw
    return np.array([2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)])


@pytest.fixture(scope="module")
def vehicle():
    return load_vehicle("proton_x")


@pytest.fixture(scope="module")
def replayed(vehicle, tmp_path_factory):
    result = replay(vehicle, broadband_drive(vehicle.corners, duration=2.0))
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
        log_drive_iteration(stream, result, plays, job.target, float(job.time[0]), CHANNELS, job.settings.band,
                            job.target_record)
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
    job, _, rrd = iteration
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
    for name in CHANNELS:
        np.testing.assert_allclose(rrd.scalars(f"/iterate/log10_tddi/{name}", "iteration")[1],
                                   np.log10([h["channels"][name]["tddi"] for h in history]), rtol=1e-12)
    bars = rrd.static["/iterate/convergence/worst_rms_error_pct"]  # static: on every timeline
    np.testing.assert_allclose(bars["BarChart:values"].to_pylist()[0][0]["buffer"], worst)
    start = np.array(bars["BarChart:abscissa"].to_pylist()[0][0]["buffer"])
    np.testing.assert_allclose(start + _numbers(bars["BarChart:widths"])[0] / 2, [0, 1, 2], atol=1e-7)  # centred
    table = rrd.static["/iterate/convergence/table"]["TextDocument:text"].to_pylist()[0][0]
    assert f"| 2 | {history[2]['gain']:.3g} | {history[2]['worst_rms_error_pct']:.3g} |" in table


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
    """The best drive moves the rig on ``time``; on the iteration and frequency timelines the rig stands in
    its last pose (it would fall apart into the model's body frames without one)."""
    job, result, rrd = iteration
    time, drive = rrd.scalars("/run/FL/drive")
    np.testing.assert_array_equal(drive, result.drive[:, 0])
    np.testing.assert_allclose(time, job.time, atol=1e-9)
    for entity in ("/rig/car.body", "/rig/car.RR/wheel", "/rig/FL/post"):
        assert rrd.timelines(entity) == {"time", "iteration", "frequency_mHz"}
        last = rrd.values(entity, "Transform3D:translation")[-1]
        for timeline in ("iteration", "frequency_mHz"):
            assert rrd.index(entity, timeline).tolist() == [0]
            np.testing.assert_array_equal(rrd.values(entity, "Transform3D:translation", timeline)[0], last)
    strips = rrd.values("/rig/tendons/car.FL/suspension", "LineStrips3D:strips", "iteration")
    np.testing.assert_array_equal(strips[0], rrd.values("/rig/tendons/car.FL/suspension", "LineStrips3D:strips")[-1])


def test_iteration_post_panel_shows_the_targets_post_motion(iteration):
    """A track target carries the road under each wheel: it is logged grey beside the achieved post motion."""
    job, _, rrd = iteration
    for corner in job.corners:
        time, road = rrd.scalars(f"/target/{corner}/road")
        np.testing.assert_array_equal(road, job.target_record[f"{corner}/road"])
        np.testing.assert_allclose(time, job.target_record.time, atol=1e-9)
        post = next(v for v in rrd.layout.views.values() if v["name"].startswith(f"{corner} post (m)"))
        assert {f"/run/{corner}/actuator_disp", f"/target/{corner}/road"} <= {
            e for query in post["contents"] for e in rrd.entities(query)}


def _queries(view: dict) -> list[str]:
    return [q.replace("$origin", view["origin"]) for q in view["contents"]]


def _selected(rrd: Rrd, view: dict) -> list[str]:
    return sorted({e for query in _queries(view) for e in rrd.entities(query)})


def test_layout_opens_on_panels_with_data(iteration):
    """Every panel on screen when the recording opens (first tabs, timeline ``time``) shows data: its entities
    are static or on ``time``. Every panel of every tab selects logged entities."""
    _, _, rrd = iteration
    layout = rrd.layout
    assert layout.timeline == "time"
    kinds = {v["class"] for v in layout.on_screen}
    assert {"3D", "BarChart", "TextDocument", "TimeSeries"} <= kinds
    for view in layout.on_screen:
        selected = _selected(rrd, view)
        assert selected, view["name"]
        assert any(e in rrd.static or "time" in rrd.timelines(e) for e in selected), view["name"]
    for view in layout.views.values():
        assert _selected(rrd, view), view["name"]


def test_layout_views_cover_the_whole_of_every_timeline(iteration):
    """Plots open on the whole timeline (FRFs on every line, not +-1 Hz about the cursor), each on its own x
    axis; one FRF panel per iterated channel; suspension velocity has a panel per corner."""
    _, _, rrd = iteration
    layout = rrd.layout
    plots = layout.of_class("TimeSeries")
    for view in plots:
        assert view["ranges"] == {t: ("Infinite", "Infinite") for t in ("time", "iteration", "frequency_mHz")}
        assert view["axis"] == ("Infinite", "Infinite", 1)  # 1: independent of the other plots
    frf = [v for v in plots if any(q.startswith("+ frf/magnitude_db/") for q in v["contents"])]
    assert sorted(q for v in frf for q in v["contents"]) == sorted(f"+ frf/magnitude_db/{n}/**" for n in CHANNELS)
    assert [v["origin"] for v in layout.of_class("3D")] == ["rig"]
    assert [v["origin"] for v in layout.of_class("BarChart")] == ["iterate/convergence/worst_rms_error_pct"]
    assert {v["origin"] for v in layout.of_class("TextDocument")} == {"iterate/convergence/table", "iterate/summary"}
    for corner in ("FL", "FR", "RL", "RR"):
        assert sum(f"+ run/{corner}/susp_velocity" in v["contents"] for v in plots) == 1
        assert "time" in rrd.timelines(f"/run/{corner}/susp_velocity")


def test_layout_legends_fit(iteration):
    """A plot with a legend names at most four lines (more overflow the panel): busier plots hide it."""
    _, _, rrd = iteration
    for view in rrd.layout.of_class("TimeSeries"):
        lines = sum(len(rrd.static[e]["SeriesLines:names"].to_pylist()[0]) for e in _selected(rrd, view))
        assert lines <= 4 or not view["legend"], (view["name"], lines)


def _luminance(rgb) -> float:
    """WCAG 2 relative luminance of an sRGB colour (0-255)."""
    c = np.asarray(rgb, float) / 255
    linear = np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
    return float(linear @ [0.2126, 0.7152, 0.0722])


def _contrast(a, b) -> float:
    high, low = sorted((_luminance(a), _luminance(b)), reverse=True)
    return (high + 0.05) / (low + 0.05)


def _delta_e(a, b) -> float:
    """CIE76 colour difference of two sRGB colours (0-255): about 2 is just noticeable, above 30 obvious."""
    def lab(rgb):
        c = np.asarray(rgb, float) / 255
        linear = np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
        xyz = np.array([[0.4124, 0.3576, 0.1805], [0.2126, 0.7152, 0.0722], [0.0193, 0.1192, 0.9505]]) @ linear
        f = np.cbrt(xyz / [0.9505, 1.0, 1.089])  # D65 white; all colours here are far above the linear toe
        return np.array([116 * f[1] - 16, 500 * (f[0] - f[1]), 200 * (f[1] - f[2])])
    return float(np.linalg.norm(lab(a) - lab(b)))


WHITE, NEAR_BLACK = (255, 255, 255), (18, 18, 18)  # the viewer's light and dark plot backgrounds, about


def _corner_of(entity: str) -> str | None:
    """The corner whose colour a plotted entity takes (a FRF: its input's), None for a reference (targets, the
    road, run-wide metrics)."""
    parts = entity.strip("/").split("/")
    if parts[0] == "target" or parts[:2] == ["iterate", "target"] or parts[-1] == "road":
        return None
    if parts[:2] == ["frf", "magnitude_db"]:
        return parts[-2]
    return next((p for p in parts if p in ("FL", "FR", "RL", "RR")), None)


def test_one_colour_per_corner_in_every_panel_and_a_grey_reference(iteration):
    """Every plotted line of a corner has that corner's colour (iterations fade by opacity only); corners
    differ; targets, the road and run-wide metrics share one neutral grey, far from every corner colour and
    readable on the light and on the dark theme (WCAG contrast >= 3 against both backgrounds)."""
    _, _, rrd = iteration
    colours: dict[str | None, set] = defaultdict(set)
    for view in rrd.layout.of_class("TimeSeries"):
        for entity in _selected(rrd, view):
            colours[_corner_of(entity)].update(rrd.colors(entity))
    assert set(colours) == {"FL", "FR", "RL", "RR", None}
    corners = {}
    for corner in ("FL", "FR", "RL", "RR"):
        assert len(colours[corner]) == 1, (corner, colours[corner])
        corners[corner] = np.array(colours[corner].pop(), float)
    (reference,) = colours[None]
    for a, b in itertools.combinations(corners.values(), 2):
        assert _delta_e(a, b) > 30  # told apart at a glance
    assert np.ptp(reference) < 10  # neutral: no hue to mistake for a corner
    for corner in corners.values():
        assert _delta_e(corner, reference) > 30
        assert min(_contrast(corner, WHITE), _contrast(corner, NEAR_BLACK)) >= 3
    assert min(_contrast(reference, WHITE), _contrast(reference, NEAR_BLACK)) >= 3


def test_cli_replay_and_track_write_recordings(vehicle, tmp_path, capsys):
    drive = tmp_path / "drive.csv"
    write_record(drive, broadband_drive(vehicle.corners, duration=2.0))
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


def test_cli_control_recording_fills_the_corner_panels(tmp_path):
    """``rig control --rerun`` logs the run where the layout's corner panels look: each selects the run's series."""
    path = tmp_path / "control.rrd"
    assert main(["control", "--vehicle", "proton_x_quarter", "--road", "iso8608:class=C,length=10,seed=1",
                 "--speed", "20", "--controller", "skyhook", "--out", str(tmp_path / "out"), "--rerun", str(path)]) == 0
    rrd = Rrd(path)
    record = read_record(tmp_path / "out" / "record.csv")
    assert {e for e in rrd.temporal if e.startswith("/run/")} == {f"/run/{n}" for n in record.names}
    panels = [v for v in rrd.layout.views.values() if v["name"].startswith("FL ") and v["class"] == "TimeSeries"]
    assert len(panels) == 7
    for view in panels:
        assert any(e.startswith("/run/FL/") for e in _selected(rrd, view)), view["name"]


def test_resumed_iterations_are_labelled_by_their_own_iteration_numbers(tmp_path):
    """A resumed run logs responses only for its own iterations: the last entries of the history."""
    tddi = [0.1, 1.2345e-3, 1.2345e-5]  # near the noise floor a fixed number of decimals shows nothing
    history = [{"iteration": k, "gain": 1.0, "worst_rms_error_pct": 10.0 / (k + 1),
                "channels": {"FL/sprung_acc": {"rms_error_pct": 10.0 / (k + 1), "tddi": tddi[k], "damage_ratio": 1.0}}}
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
    summary = rrd.temporal["/iterate/summary"]["TextDocument:text"].to_pylist()
    for text, shown in zip(summary, ("| 0.1 |", "| 0.00123 |", "| 1.23e-05 |")):  # three significant figures
        assert "| FL/sprung_acc | " in text[0] and shown in text[0]
    table = rrd.static["/iterate/convergence/table"]["TextDocument:text"].to_pylist()[0][0]
    assert "| 2 | 1 | 3.33 | " in table and table.endswith("| 1.23e-05 | 1.23e-05 |")
    np.testing.assert_allclose(rrd.scalars("/iterate/log10_tddi/FL/sprung_acc", "iteration")[1], np.log10(tddi))


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
    assert rrd.scalars("/target/RR/road")[1].size == job.target_record.n_samples
    assert rrd.scalars("/iterate/rms_error_pct/RR/unsprung_acc", "iteration")[0].tolist() == [0, 1, 2, 3]
    assert rrd.timelines("/frf/coherence/RR/unsprung_acc") == {"frequency_mHz"}
    assert rrd.timelines("/rig/car.body") == {"time", "iteration", "frequency_mHz"}
