"""Rerun review: the recording of every command that writes one (replay, track, control, iterate, diagnose of a rig
and a track test, demo --quick), read back from its .rrd file: every view of its default layout shows logged
data, the overview says what ran and the result, the plotted peaks are the record's; and the details checked
against the records, the simulation's kinematics and the iteration's own results."""

from __future__ import annotations

import argparse
import itertools
import json
import shutil
from collections import defaultdict
from types import SimpleNamespace

import numpy as np
import pytest
from rrd_file import FLOAT32_RESOLUTION, Rrd, numbers, selected, text

from controllers.rpc import DriveIteration, IterationSettings
from rig.signal.metrics import ChannelMetrics
from rig.causes import CAUSES, with_extension
from rig.causes.wheel_unbalance import WheelUnbalance
from rig.cli.main import main
from rig.cli.options import review
from rig.diagnosis.rig_test.force_laws import measure_force_laws
from rig.diagnosis.core.validation import mean_tddi
from rig.io.files import read_record, write_record
from rig.io.record import Record
from rig.report.review import recording
from rig.report.review_diagnosis import log_diagnosis
from rig.report.review_iteration import IterationLog, log_drive_iteration, log_metrics, log_time_series
from rig.report.review_runs import present_replay
from rig.report.style import CORNER_COLORS, MODEL_COLORS, REFERENCE_COLOR, display_unit
from rig.road.roads import iso8608_road
from rig.sim.broadband import broadband_drive
from rig.sim.replay import replay
from rig.sim.track import track_run
from rig.vehicle.vehicle_file import load_vehicle, vehicle_to_toml

CORNERS = ("FL", "FR", "RL", "RR")
CHANNELS = [f"{c}/{q}" for c in CORNERS for q in ("sprung_acc", "unsprung_acc")]


@pytest.fixture(scope="module")
def vehicle():
    return load_vehicle("proton_x")


# ---- one recording per command ------------------------------------------------------------------------------
HELD_OUT_START = 20.0  # s: the stub diagnosis's held-out part starts here in its record
def _stub_diagnosis(vehicle, rng):
    """A diagnosis result built from real records (a diagnosis itself takes minutes): the held-out test of a car
    with asymmetric dampers against the data sheet's model and the model extended by the cause."""
    truth = CAUSES["damper_asymmetry"].hidden(vehicle, rng)
    drive = broadband_drive(vehicle.corners, 6.0)
    measured, baseline = replay(truth, drive).record, replay(vehicle, drive).record
    names = [f"{c}/{q}" for c in vehicle.corners for q in ("sprung_acc", "unsprung_acc", "susp_travel", "tyre_force")]
    compared = {"measured": measured.select(names), "baseline": baseline.select(names),
                "recalibrated": baseline.select(names), "extended": measured.select(names)}
    tddi = mean_tddi(*(np.column_stack([compared[k][n] for n in names]) for k in ("measured", "baseline")))
    cause = SimpleNamespace(effect="damper_asymmetry", gain=0.97, tddi_holdout=1e-5, params={"ratio": 2.0},
                            units={"ratio": "-"}, intervals={"ratio": (1.9986, 2.0014)})
    other = SimpleNamespace(effect="anti_roll_bar", gain=-6e-6, tddi_holdout=0.03, params={"front_rate": 2.828e-13},
                            units={"front_rate": "N/m"}, intervals={"front_rate": (-673.7, 679.1)})  # optimiser noise
    held_out = SimpleNamespace(holdout=SimpleNamespace(start=HELD_OUT_START, end=HELD_OUT_START + 6.0))
    return SimpleNamespace(verdict="damper_asymmetry", compared=compared, baseline_tddi=tddi, recalibrated_tddi=tddi,
                           extended_tddi=1e-5, noise_floor=1e-5, causes=[cause, other], unexplained=None,
                           force_laws=measure_force_laws(measured, vehicle), data_sheet=vehicle, split=held_out)


@pytest.fixture(scope="module")
def stub(vehicle):
    return _stub_diagnosis(vehicle, np.random.default_rng(4))


@pytest.fixture(scope="module")
def recordings(vehicle, stub, tmp_path_factory):
    """command -> (the recording, the record it shows under ``run/`` or as the last series of
    ``diagnosis/compared/``, words the overview must hold)."""
    folder = tmp_path_factory.mktemp("commands")
    drive = folder / "drive.csv"
    write_record(drive, broadband_drive(vehicle.corners, duration=2.0))
    done = {}
    assert main(["replay", "--vehicle", "proton_x", "--drive", str(drive), "--out", str(folder / "r.csv"),
                 "--rerun", str(folder / "replay.rrd"), "--rerun-magnify", "10"]) == 0
    done["replay"] = ("replay.rrd", read_record(folder / "r.csv"), ["rig replay", "proton_x", "post limits"])
    assert main(["track", "--vehicle", "proton_x", "--road", "iso8608:class=B,length=100,seed=1", "--speed", "20",
                 "--duration", "1", "--out", str(folder / "t.csv"), "--rerun", str(folder / "track.rrd")]) == 0
    done["track"] = ("track.rrd", read_record(folder / "t.csv"), ["rig track", "ISO 2631-1 a_w"])
    assert main(["control", "--vehicle", "proton_x_quarter", "--road", "iso8608:class=C,length=10,seed=1",
                 "--speed", "20", "--controller", "skyhook", "--out", str(folder / "control"),
                 "--rerun", str(folder / "control.rrd")]) == 0
    metrics = json.loads((folder / "control" / "metrics.json").read_text())
    done["control"] = ("control.rrd", read_record(folder / "control" / "record.csv"),
                       ["rig control", "skyhook", f"a_w {metrics['a_w']:.3f} m/s²"])
    assert main(["demo", "--quick", "--duration", "3", "--out", str(folder / "demo"),
                 "--rerun", str(folder / "demo.rrd")]) == 0
    done["demo --quick"] = ("demo.rrd", read_record(folder / "demo" / "response.csv"), ["rig demo", "post limits"])
    args = argparse.Namespace(command="diagnose", run=None, vehicle="proton_x", measured=["m.csv"], holdout=None,
                              out="d", rerun=str(folder / "diagnose.rrd"), rerun_spawn=False)
    review(args, "proton_x against m.csv", lambda rec: log_diagnosis(rec, stub))
    done["diagnose rig"] = ("diagnose.rrd", stub.compared["measured"], ["rig diagnose", "verdict: damper_asymmetry"])
    car = folder / "unbalanced.toml"
    car.write_text(vehicle_to_toml(with_extension(vehicle, "wheel_unbalance", WheelUnbalance("RL", 0.012, -120.0))))
    for name, seed, speed in (("m.csv", 4, 30.0), ("h.csv", 5, 25.0)):
        assert main(["track", "--vehicle", str(car), "--road", f"iso8608:class=A,length=400,seed={seed}",
                     "--speed", str(speed), "--duration", "8", "--out", str(folder / name)]) == 0
        driven = read_record(folder / name)  # as measured on the road: without the road itself
        write_record(folder / name, driven.select([n for n in driven.names if not n.endswith("/road")]))
    assert main(["diagnose", "--vehicle", "proton_x", "--measured", str(folder / "m.csv"), "--holdout",
                 str(folder / "h.csv"), "--out", str(folder / "td"),
                 "--rerun", str(folder / "track_diagnose.rrd")]) == 0
    done["diagnose track"] = ("track_diagnose.rrd", read_record(folder / "m.csv"),
                              ["verdict: wheel_unbalance", "unbalance at RL"])
    return {command: (Rrd(folder / path), record, words) for command, (path, record, words) in done.items()}


COMMANDS = ("replay", "track", "control", "demo --quick", "diagnose rig", "diagnose track")


@pytest.mark.parametrize("command", COMMANDS)
def test_every_view_shows_logged_data_and_the_layout_opens_on_the_overview(recordings, command):
    """Each view of the layout stored in the file selects logged entities; on screen when the recording opens
    (first tabs, timeline ``time``): the overview first, and only views with data on ``time`` or static."""
    rrd = recordings[command][0]
    layout = rrd.layout
    assert layout.timeline == "time"
    for view in layout.views.values():
        assert selected(rrd, view), (command, view["name"])
    assert layout.on_screen[0]["origin"] == "/overview"
    for view in layout.on_screen:
        assert any(e in rrd.static or "time" in rrd.timelines(e) for e in selected(rrd, view)), view["name"]


@pytest.mark.parametrize("command", COMMANDS)
def test_the_overview_says_what_ran_and_the_result(recordings, command):
    rrd, _, words = recordings[command]
    overview = text(rrd, "/overview")
    assert "## Result" in overview and "## What was run" in overview
    for word in words:
        assert word in overview, (command, word)


@pytest.mark.parametrize("command", COMMANDS)
def test_plotted_peaks_are_the_records(recordings, command):
    """Each channel's recorded series reaches the record's own peak (in the unit the panel gives), and keeps
    its peaks when a pixel holds several samples (min/max aggregation)."""
    rrd, record, _ = recordings[command]
    for name in record.names:
        entity = f"/diagnosis/compared/{name}" if command == "diagnose rig" else f"/run/{name}"
        scale = display_unit(name.split("/")[1])[1]
        values = rrd.values(entity, "Scalars:scalars")[:, -1]  # the measurement is the last series
        assert values.size == record.n_samples
        assert np.max(np.abs(values)) == pytest.approx(np.max(np.abs(record[name])) * scale, rel=1e-9)
        assert rrd.static[entity]["SeriesLines:aggregation_policy"].to_pylist() == [[5]]  # MinMax


def test_panel_titles_state_their_unit_and_promise_only_logged_lines(recordings):
    for command in COMMANDS:
        rrd = recordings[command][0]
        for view in rrd.layout.of_class("TimeSeries"):
            assert any(f"({unit}" in view["name"] for unit in ("mm", "m/s²", "m/s", "kN", "%", "-")), view["name"]
            if "target grey" in view["name"]:
                assert any("/target" in e for e in selected(rrd, view)), view["name"]


def drawn(rrd: Rrd, view: dict) -> list[tuple[str, str, tuple[int, int, int]]]:
    """The lines a time-series view draws, in the viewer's order (entities in the order of their paths' parts, each
    entity's series in order; a later line lies over an earlier one): (entity, series name, colour)."""
    lines = []
    for entity in sorted(selected(rrd, view), key=lambda e: e.strip("/").split("/")):
        style = rrd.static.get(entity, {})
        if "SeriesLines:colors" in style:
            lines += [(entity, n, c) for n, c in zip(style["SeriesLines:names"].to_pylist()[0], rrd.colors(entity))]
    return lines


def assert_references_on_top(rrd: Rrd) -> None:
    """In every time-series view, the grey lines (a measurement, a target, the road, the passive car) come after
    every coloured line: drawn last, over the runs and models (a noise band is not a reference: it may lie under)."""
    for view in rrd.layout.of_class("TimeSeries"):
        colours = [c for _, name, c in drawn(rrd, view) if not name.startswith("noise")]
        grey = [i for i, c in enumerate(colours) if c == REFERENCE_COLOR]
        assert grey == list(range(len(colours) - len(grey), len(colours))), (view["name"], drawn(rrd, view))


@pytest.mark.parametrize("command", COMMANDS)
def test_references_are_drawn_last_over_runs_and_models(recordings, command):
    assert_references_on_top(recordings[command][0])


def test_track_posts_stand_at_the_road_under_each_wheel(recordings):
    """A track run's posts have no joint (the road is fed to the tyre): the scene lifts each post to the road height
    under its wheel, so that the hub stands one loaded tyre radius above the pan, R - F / k_t."""
    rrd, record, _ = recordings["track"]
    vehicle = load_vehicle("proton_x")
    for corner in CORNERS:
        post = rrd.values(f"/rig/{corner}/post", "Transform3D:translation")[:, 2]
        np.testing.assert_allclose(post, record[f"{corner}/road"], atol=1e-6)  # float32 of centimetres
        hub = rrd.values(f"/rig/car.{corner}/wheel", "Transform3D:translation")[:, 2]
        loaded = vehicle.wheel_radius - record[f"{corner}/tyre_force"] / vehicle.axle(corner).tyre_rate
        np.testing.assert_allclose(hub - post, loaded, atol=1e-5)


def test_control_run_draws_the_passive_car_over_it_and_states_its_metrics(recordings):
    rrd, record, _ = recordings["control"]
    panel = next(v for v in rrd.layout.views.values() if v["name"].startswith("FL body acceleration"))
    assert selected(rrd, panel) == ["/run/FL/sprung_acc", "/without_controller/FL/sprung_acc"]
    assert "passive grey, thin, on top" in panel["name"]
    assert rrd.colors("/without_controller/FL/sprung_acc") == [REFERENCE_COLOR]
    passive = rrd.scalars("/without_controller/FL/sprung_acc")[1]
    assert passive.size == record.n_samples and not np.allclose(passive, record["FL/sprung_acc"])
    row = next(line for line in text(rrd, "/overview").splitlines() if line.startswith("| a_w, ISO 2631-1"))
    controlled, reference, change = (float(cell.split()[0]) for cell in row.split("|")[2:5])
    assert change == pytest.approx(100 * (controlled / reference - 1), abs=0.15)  # the table's own numbers


def test_demo_recording_shows_the_baseline_models_drive_beside_the_extended_ones(vehicle, stub, tmp_path):
    """The demo's story on the real car: the extended model's drive (``run/``), the baseline model's (``before/``,
    a tint of the corner's colour, under it) and the target (grey, on top), with each channel's error before and
    after in the overview."""
    from rig.cli.demo_story import StoryResult
    from rig.cli.demo import _review_story

    drive = broadband_drive(vehicle.corners, 2.0)
    real = CAUSES["damper_asymmetry"].hidden(vehicle, np.random.default_rng(2))
    after, before = replay(real, drive), replay(vehicle, drive)
    errors_before = {n: 20.0 + i for i, n in enumerate(CHANNELS)}
    story = StoryResult(vehicle, 27.0, 1.8, stub,
                        after.record.select(CHANNELS), after, after.record, before, errors_before,
                        dict.fromkeys(CHANNELS, 1.8))
    with recording(tmp_path / "demo.rrd") as rec:
        _review_story(rec, story, argparse.Namespace(rerun_magnify=1.0))
    rrd = Rrd(tmp_path / "demo.rrd")
    panel = next(v for v in rrd.layout.views.values() if v["name"].startswith("FL body acceleration"))
    assert selected(rrd, panel) == ["/before/FL/sprung_acc", "/run/FL/sprung_acc", "/target/FL/sprung_acc"]
    assert "the baseline model's drive light" in panel["name"]
    np.testing.assert_array_equal(rrd.scalars("/before/FL/sprung_acc")[1], before.record["FL/sprung_acc"])
    (faint,) = rrd.colors("/before/FL/sprung_acc")
    assert _delta_e(faint, CORNER_COLORS["FL"]) > 15 and faint != REFERENCE_COLOR
    assert_references_on_top(rrd)
    assert "| RR/unsprung_acc | 27.0 % | 1.8 % |" in text(rrd, "/overview")


# ---- replay: series, animation, geometry ---------------------------------------------------------------------
@pytest.fixture(scope="module")
def replayed(vehicle, tmp_path_factory):
    result = replay(vehicle, broadband_drive(vehicle.corners, duration=2.0))
    path = tmp_path_factory.mktemp("review") / "replay.rrd"
    with recording(path) as rec:
        present_replay(rec, result, magnification=10.0)
    return result, Rrd(path)


def test_replay_channels_are_series_per_corner_in_display_units(replayed):
    result, rrd = replayed
    record = result.record
    for name in record.names:
        entity = f"/run/{name}"
        assert rrd.timelines(entity) == {"time"}
        time, values = rrd.scalars(entity)
        np.testing.assert_allclose(time, record.time, atol=1e-9)
        unit, scale = display_unit(name.split("/")[1])
        np.testing.assert_array_equal(values, record[name] * scale)  # float64 end to end
        assert rrd.static[entity]["SeriesLines:names"].to_pylist() == [[f"{name} [{unit}]"]]
    assert {e for e in rrd.temporal if e.startswith("/run/")} == {f"/run/{n}" for n in record.names}
    assert display_unit("actuator_disp") == ("mm", 1e3) and display_unit("tyre_force") == ("kN", 1e-3)


def test_replay_animation_is_the_motion_magnified(replayed):
    """Magnified 10 times about the settled pose: the posts move 10 times the achieved post displacement, and
    the suspension tendon's length changes by 10 times the suspension travel (to first order)."""
    result, rrd = replayed
    record, model = result.record, result.model
    for corner in ("FL", "RR"):
        post = f"/rig/{corner}/post"
        translation = rrd.values(post, "Transform3D:translation")
        rest = model.body_pos[model.body(f"{corner}/post").id]
        np.testing.assert_allclose(translation[:, :2], np.broadcast_to(rest[:2], (record.n_samples, 2)),
                                   atol=FLOAT32_RESOLUTION)
        np.testing.assert_allclose(translation[:, 2] - rest[2], 10 * record[f"{corner}/actuator_disp"], atol=1e-6)
        strips = rrd.values(f"/rig/tendons/car.{corner}/suspension", "LineStrips3D:strips").reshape(-1, 2, 3)
        length = np.linalg.norm(strips[:, 0] - strips[:, 1], axis=1)
        travel = record[f"{corner}/susp_travel"]
        np.testing.assert_allclose(length[0] - length, 10 * travel, atol=0.02 * 10 * np.ptp(travel))
        scale = rrd.values(f"/rig/springs/{corner}", "Transform3D:scale")  # the coil stretches with it
        np.testing.assert_allclose(scale[:, 2], length, rtol=1e-5)
    assert rrd.layout.of_class("3D")[0]["name"] == "Rig (3D): motion magnified ×10"
    assert rrd.static["/rig/magnification"]["Points3D:labels"].to_pylist() == [["motion ×10"]]


def test_replay_wheels_take_their_corner_colours_and_labels_and_the_front_is_marked(replayed):
    result, rrd = replayed
    model = result.model
    for corner in CORNERS:
        wheel = rrd.static[f"/rig/car.{corner}/wheel/cylinders"]
        geom = model.geom(f"car.{corner}/wheel").id
        assert numbers(wheel["Cylinders3D:radii"])[0, 0] == pytest.approx(model.geom_size[geom, 0], rel=1e-6)
        packed = int(wheel["Cylinders3D:colors"].to_pylist()[0][0])
        assert tuple((packed >> s) & 0xFF for s in (24, 16, 8)) == CORNER_COLORS[corner]
        assert wheel["Cylinders3D:labels"].to_pylist() == [[corner]]
    front = rrd.static["/rig/car.body/front"]
    assert numbers(front["Arrows3D:vectors"])[0, 0] > 0  # points forward (x)
    assert "/rig/world/boxes" in rrd.static  # the pit floor


# ---- drive iteration -------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def iteration(vehicle, tmp_path_factory):
    target = track_run(vehicle, iso8608_road("B", 300.0, seed=3), 20.0, duration=6.0).record
    folder = tmp_path_factory.mktemp("iterate")
    settings = IterationSettings(iterations=3, target_error_pct=0.5)
    job = DriveIteration(vehicle, target, CHANNELS, folder, settings)
    plays = IterationLog()
    result = job.run(progress=False, callback=plays)
    with recording(folder / "iterate.rrd") as rec:
        log_drive_iteration(rec, result, plays, job.target, float(job.time[0]), CHANNELS, settings, job.target_record)
    return job, result, Rrd(folder / "iterate.rrd")


def test_iteration_layout_shows_logged_data_and_the_stop_reason(iteration):
    _, result, rrd = iteration
    for view in rrd.layout.views.values():
        assert selected(rrd, view), view["name"]
    overview = text(rrd, "/overview")
    assert result.stop_reason in overview and "against a target of 0.5 %" in overview
    assert ("(met)" if result.best.worst_rms_error_pct <= 0.5 else "(missed)") in overview
    assert [v["origin"] for v in rrd.layout.on_screen] == ["/overview", "/rig", "/iterate/convergence/plot",
                                                           "/iterate/convergence/table"]
    tolerance = rrd.scalars("/iterate/target_error_pct", "iteration")[1]
    assert tolerance.tolist() == [0.5, 0.5, 0.5]


def test_iteration_series_match_the_iterations_own_results(iteration):
    job, result, rrd = iteration
    best = result.best.iteration
    n = job.target.shape[0]
    for j, name in enumerate(CHANNELS):
        time, target = rrd.scalars(f"/iterate/target/{name}")
        np.testing.assert_allclose(time, job.time, atol=1e-9)
        assert time[0] < 0  # the drive's lead-in: the target record starts at 0
        np.testing.assert_array_equal(target, job.target[:, j])  # m/s²: SI is the display unit
        response = rrd.values(f"/iterate/response/{name}", "Scalars:scalars")  # samples x iterations
        error = rrd.values(f"/iterate/error/{name}", "Scalars:scalars")
        assert response.shape == error.shape == (n, 3)
        np.testing.assert_allclose(error, target[:, None] - response, atol=1e-12)
        np.testing.assert_allclose(response[:, best], result.response[:, j],
                                   atol=1e-9 * np.abs(result.response[:, j]).max())
    for i, corner in enumerate(job.corners):
        drives = rrd.values(f"/iterate/drive/{corner}", "Scalars:scalars")
        np.testing.assert_allclose(drives[:, best], 1e3 * result.drive[:, i], rtol=1e-12)  # mm


def test_iteration_metrics_are_on_the_iteration_timeline_with_the_worst_marked(iteration):
    job, _, rrd = iteration
    history = json.loads((job.out_dir / "history.json").read_text())["iterations"]
    for name in CHANNELS:
        for key in ("rms_error_pct", "damage_ratio"):
            sequence, values = rrd.scalars(f"/iterate/{key}/{name}", "iteration")
            np.testing.assert_array_equal(sequence, [0, 1, 2])
            np.testing.assert_allclose(values, [h["channels"][name][key] for h in history], rtol=1e-12)
        np.testing.assert_allclose(rrd.scalars(f"/iterate/log10_tddi/{name}", "iteration")[1],
                                   np.log10([h["channels"][name]["tddi"] for h in history]), rtol=1e-12)
    worst = rrd.scalars("/iterate/worst_rms_error_pct", "iteration")[1]
    np.testing.assert_allclose(worst, [h["worst_rms_error_pct"] for h in history], rtol=1e-12)
    assert "SeriesPoints:markers" in rrd.static["/iterate/worst_rms_error_pct"]  # dots: the line under them shows
    table = text(rrd, "/iterate/convergence/table")
    assert f"| 2 | {history[2]['gain']:.3g} | {history[2]['worst_rms_error_pct']:.3g} |" in table


def test_frf_and_convergence_are_images_that_open_on_every_timeline(iteration):
    """Plots against frequency or iteration are PNG images (static: shown whatever the time panel's timeline)."""
    _, _, rrd = iteration
    for entity in ("/iterate/convergence/plot", *(f"/iterate/frf/{c}" for c in CORNERS)):
        png = bytes(rrd.static[entity]["EncodedImage:blob"].to_pylist()[0][0])
        assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 20_000
    frf = [v for v in rrd.layout.of_class("2D") if v["origin"].startswith("/iterate/frf/")]
    assert len(frf) == 4 and all("dB re 1 unit/m" in v["name"] for v in frf)


def test_iteration_best_drive_is_replayed_for_the_rig_view(iteration):
    job, result, rrd = iteration
    time, drive = rrd.scalars("/run/FL/drive")
    np.testing.assert_allclose(drive, 1e3 * result.drive[:, 0], rtol=1e-12)
    np.testing.assert_allclose(time, job.time, atol=1e-9)
    for entity in ("/rig/car.body", "/rig/car.RR/wheel", "/rig/FL/post"):
        assert rrd.timelines(entity) == {"time", "iteration"}
        last = rrd.values(entity, "Transform3D:translation")[-1]
        assert rrd.index(entity, "iteration").tolist() == [0]
        np.testing.assert_array_equal(rrd.values(entity, "Transform3D:translation", "iteration")[0], last)
    for corner in job.corners:  # a track target: the road under each wheel, grey beside the achieved post
        np.testing.assert_allclose(rrd.scalars(f"/target/{corner}/road")[1], 1e3 * job.target_record[f"{corner}/road"])
        post = next(v for v in rrd.layout.views.values() if v["name"].startswith(f"{corner} post or road (mm)"))
        assert {f"/run/{corner}/actuator_disp", f"/target/{corner}/road"} <= set(selected(rrd, post))
        assert "target grey" in post["name"]


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


def test_one_colour_per_corner_a_tint_for_the_drive_and_a_grey_reference(iteration):
    """Every plotted line of a corner has that corner's colour (iterations fade by opacity only; the drive a
    light tint, told apart from the achieved post); corners differ; targets and the road share one neutral
    grey, far from every corner colour and readable on the light and on the dark theme."""
    _, _, rrd = iteration
    colours: dict[str | None, set] = defaultdict(set)
    for view in rrd.layout.of_class("TimeSeries"):
        for entity in selected(rrd, view):
            if "SeriesLines:colors" not in rrd.static[entity]:
                continue
            parts = entity.strip("/").split("/")
            reference = parts[0] == "target" or parts[1] in ("target", "target_error_pct", "gain") \
                or parts[-1] == "road"
            corner = None if reference else next(p for p in parts if p in CORNERS)
            key = f"{corner} drive" if parts[0] == "run" and parts[-1] == "drive" else corner
            colours[key].update(rrd.colors(entity))
    assert colours.pop(None) == {REFERENCE_COLOR}
    for corner in CORNERS:
        (drive,) = colours.pop(f"{corner} drive")
        assert _delta_e(drive, CORNER_COLORS[corner]) > 15 and _contrast(drive, NEAR_BLACK) >= 3
    assert {c: s for c, s in colours.items()} == {c: {CORNER_COLORS[c]} for c in CORNERS}
    for a, b in itertools.combinations(CORNER_COLORS.values(), 2):
        assert _delta_e(a, b) > 30  # told apart at a glance
    assert np.ptp(REFERENCE_COLOR) < 10  # neutral: no hue to mistake for a corner
    for corner in CORNER_COLORS.values():
        assert _delta_e(corner, REFERENCE_COLOR) > 30
        assert min(_contrast(corner, WHITE), _contrast(corner, NEAR_BLACK)) >= 3
    assert min(_contrast(REFERENCE_COLOR, WHITE), _contrast(REFERENCE_COLOR, NEAR_BLACK)) >= 3


def test_resumed_iterations_are_labelled_by_their_own_iteration_numbers(tmp_path):
    """A resumed run logs responses only for its own iterations: the last entries of the history."""
    tddi = [0.1, 1.2345e-3, 1.2345e-5]  # near the noise floor a fixed number of decimals shows nothing
    history = [SimpleNamespace(iteration=k, gain=1.0, worst_rms_error_pct=10.0 / (k + 1), total_error_pct=1.0,
                               limit_hits=[], channels={"FL/sprung_acc": ChannelMetrics.from_json(
                                   {"rms_error_pct": 10.0 / (k + 1), "tddi": tddi[k], "damage_ratio": 1.0})})
               for k in range(3)]
    target = np.linspace(0.0, 1.0, 64)[:, None]
    with recording(tmp_path / "resumed.rrd") as rec:
        log_time_series(rec, history, target, [0.5 * target, 0.9 * target], 64.0, ["FL/sprung_acc"], start_time=-0.5)
        log_metrics(rec, history, 3.0)
    rrd = Rrd(tmp_path / "resumed.rrd")
    assert rrd.static["/iterate/response/FL/sprung_acc"]["SeriesLines:names"].to_pylist() == [
        ["iteration 1", "iteration 2"]]
    np.testing.assert_allclose(rrd.scalars("/iterate/target/FL/sprung_acc")[0], -0.5 + np.arange(64) / 64.0, atol=1e-9)
    np.testing.assert_allclose(rrd.values("/iterate/error/FL/sprung_acc", "Scalars:scalars"),
                               np.column_stack([0.5 * target[:, 0], 0.1 * target[:, 0]]), atol=1e-12)
    summary = rrd.temporal["/iterate/summary"]["TextDocument:text"].to_pylist()
    for entry, shown in zip(summary, ("| 0.1 |", "| 0.00123 |", "| 1.23e-05 |")):  # three significant figures
        assert "| FL/sprung_acc | " in entry[0] and shown in entry[0]


def test_cli_iterate_resumed_writes_a_recording(iteration, tmp_path):
    """``rig iterate --resume --rerun``: the resumed iteration's series, every iteration's metrics, the FRF."""
    job, _, _ = iteration
    folder = tmp_path / "iterate"
    shutil.copytree(job.out_dir, folder)
    target = tmp_path / "target.csv"
    write_record(target, job.target_record)
    assert main(["iterate", "--vehicle", "proton_x", "--target", str(target), "--out", str(folder), "--channels",
                 *CHANNELS, "--iterations", "4", "--target-error", "0.5", "--resume", "--quiet",
                 "--rerun", str(tmp_path / "resumed.rrd")]) == 0
    rrd = Rrd(tmp_path / "resumed.rrd")
    assert rrd.static["/iterate/response/FL/sprung_acc"]["SeriesLines:names"].to_pylist() == [["iteration 3"]]
    assert rrd.scalars("/iterate/rms_error_pct/RR/unsprung_acc", "iteration")[0].tolist() == [0, 1, 2, 3]
    assert "/iterate/frf/RR" in rrd.static
    for view in rrd.layout.views.values():
        assert selected(rrd, view), view["name"]
    assert "RMS error against a target of 0.5 %" in text(rrd, "/overview")


# ---- diagnosis ------------------------------------------------------------------------------------------------
def test_diagnosis_draws_the_measurement_on_top_of_models_told_apart_with_residuals_on_its_own_time(recordings):
    """Each compared channel is one entity whose series the viewer draws in order: the models, each in its own
    colour (far from each other and from the grey), then the measurement, grey: on top. The residual panel draws
    the noise band first and the extended model's residual last. The held-out part keeps the time of its record."""
    rrd, measured, _ = recordings["diagnose rig"]
    models = ["baseline", "recalibrated", "extended"]
    for name in measured.names:
        panel = next(v for v in rrd.layout.views.values() if v["name"].startswith(f"{name} ("))
        entity = f"/diagnosis/compared/{name}"
        assert selected(rrd, panel) == [entity] and panel["legend"]
        names = rrd.static[entity]["SeriesLines:names"].to_pylist()[0]
        assert [n.split(" [")[0] for n in names] == [*models, "measured"]
        colours = rrd.colors(entity)
        assert colours == [MODEL_COLORS[m] for m in models] + [REFERENCE_COLOR]
        assert all(_delta_e(a, b) > 30 for a, b in itertools.combinations(colours, 2))
        time, values = rrd.index(entity, "time"), rrd.values(entity, "Scalars:scalars")
        np.testing.assert_allclose(time, HELD_OUT_START + measured.time, atol=1e-9)
        residual = next(v for v in rrd.layout.views.values() if v["name"].startswith(f"{name} residual"))
        assert selected(rrd, residual) == [f"/diagnosis/residual/{name}"]
        labels = rrd.static[f"/diagnosis/residual/{name}"]["SeriesLines:names"].to_pylist()[0]
        assert [n.split(" [")[0] for n in labels] == ["noise +2 RMS", "noise -2 RMS", "measured - recalibrated",
                                                      "measured - extended"]
        residuals = rrd.values(f"/diagnosis/residual/{name}", "Scalars:scalars")
        np.testing.assert_allclose(residuals[:, 2], values[:, 3] - values[:, 1], atol=1e-12)
        assert np.all(residuals[:, 3] == 0)  # the stub's extended model is the measurement itself
    assert "/diagnosis/force_laws" in rrd.static


def test_diagnosis_overview_puts_the_named_cause_first_with_units_and_no_optimiser_noise(recordings):
    overview = text(recordings["diagnose rig"][0], "/overview")
    result = overview[overview.index("## Result"):]
    assert result.index("named **damper_asymmetry**: ratio = 2.0000 ± 0.0014") < result.index("| held-out TDDI |")
    assert "| **damper_asymmetry** | 0.970 |" in overview
    assert "front_rate = 0 ± 680 N/m" in overview and "e-13" not in overview
    assert overview.index("## Result") < overview.index("## What was run")


def test_track_diagnosis_shows_the_order_spectra_and_the_unbalance(recordings):
    rrd = recordings["diagnose track"][0]
    pictures = {v["origin"] for v in rrd.layout.of_class("2D")}
    assert {"/diagnosis/order_spectra", "/diagnosis/unbalance", "/diagnosis/transmissibility"} <= pictures
    assert "| RL | " in text(rrd, "/overview")


def test_magnification_must_be_positive(tmp_path, capsys):
    (tmp_path / "d.csv").write_text("time [s]\n0\n")  # the options are read in turn: the drive must exist
    with pytest.raises(SystemExit) as stop:
        main(["replay", "--vehicle", "proton_x", "--drive", str(tmp_path / "d.csv"), "--out", str(tmp_path / "r.csv"),
              "--rerun-magnify", "-2"])
    assert stop.value.code == 2
    assert "a positive number is needed, got -2" in capsys.readouterr().err


def test_record_without_corners_is_shown_without_corner_tabs(tmp_path):
    record = Record(100.0, {"speed": np.linspace(0, 1, 100)})
    with recording(tmp_path / "plain.rrd") as rec:
        from rig.report.review import log_record

        log_record(rec, record)
    rrd = Rrd(tmp_path / "plain.rrd")
    assert [v["origin"] for v in rrd.layout.views.values()] == ["/overview"]


def test_a_figure_shown_as_an_image_is_laid_out_as_the_report_files_are(tmp_path):
    """A figure of two rows whose lower titles take two lines: the image logged is laid out (tight, as the report's PNG
    files), not drawn with matplotlib's default margins, where those titles ran into the upper row's axis labels."""
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(2, 2)
    for ax in axes[1]:
        ax.set_title("largest binned departure 12.3 N,\n1.4 % of the model's c v")
    default = (figure.subplotpars.hspace, figure.subplotpars.top)
    with recording(tmp_path / "image.rrd") as review:
        review.image("figure", figure)
    assert (figure.subplotpars.hspace, figure.subplotpars.top) != default
    assert figure.subplotpars.hspace > default[0]
