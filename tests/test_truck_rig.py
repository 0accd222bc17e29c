"""A truck on the multi-post rig (docs/trucks.md): the MuJoCo model against an independent simulator written from the
equations (tests/independent_truck.py), and the commands on a three-axle truck: replay, track, validate, sweep."""

import dataclasses

import numpy as np
import pytest
from independent_truck import Truck

from rig import Record, load_vehicle, replay, tddi
from rig.cli.main import main
from rig.diagnosis.rig_test.synthetic import event_drive
from rig.diagnosis.core.validation import validate
from rig.io.files import read_record, write_record
from rig.io.units import STANDARD_GRAVITY
from rig.road.roads import iso8608_road
from rig.sim.track import track_run

RATE = 256.0


@pytest.fixture(scope="module")
def truck():
    return load_vehicle("truck_6x4")


@pytest.fixture(scope="module")
def drive(truck):
    values = event_drive(truck.corners, 3.0, RATE, np.random.default_rng(1))
    return Record(RATE, {f"{c}/drive": values[:, i] for i, c in enumerate(truck.corners)})


def test_rigid_frame_truck_replay_matches_the_independent_simulator_on_every_channel(truck, drive):
    """Beam axles on leaf springs with Fancher's friction and on air springs with the polytropic law itself (not the
    realised cubic), twin tyres, the cab and driveline on their mounts, six servo posts: TDDI <= 1e-3 per channel."""
    rigid = dataclasses.replace(truck, frame=None)
    values = drive.quantity("drive", rigid.corners)
    independent = Truck(rigid).run(values, RATE)
    model = replay(rigid, drive).record
    worst = {}
    for quantity, out in independent.items():
        if quantity == "seat_acc":
            worst["cab/seat_acc"] = tddi(model["cab/seat_acc"], out)
            continue
        for i, corner in enumerate(rigid.corners):
            worst[f"{corner}/{quantity}"] = tddi(model[f"{corner}/{quantity}"], out[:, i])
    assert len(worst) == 6 * 6 + 1
    assert max(worst.values()) <= 1e-3, sorted(worst.items(), key=lambda kv: -kv[1])[:3]
    assert np.ptp(model["FL/unsprung_acc"]) > 20.0  # the events shake the axles


def test_cli_replay_of_a_truck_writes_every_station_and_the_seat(truck, drive, tmp_path):
    path, out = tmp_path / "drive.csv", tmp_path / "response.csv"
    write_record(path, drive)
    assert main(["replay", "--vehicle", "truck_6x4", "--drive", str(path), "--out", str(out)]) == 0
    record = read_record(out)
    assert record.corners_with("tyre_force") == ["FL", "FR", "ML", "MR", "RL", "RR"]
    weight = (truck.sprung_mass + truck.cab.mass + truck.driveline.mass
              + sum(2 * a.unsprung_mass for a in truck.axles)) * STANDARD_GRAVITY
    at_rest = sum(record[f"{c}/tyre_force"][0] for c in truck.corners)
    assert at_rest == pytest.approx(weight, rel=1e-6)
    assert np.std(record["cab/seat_acc"]) > 0.01


def test_track_run_puts_each_axle_on_the_road_as_far_behind_as_it_is(truck):
    """At 9.6 m/s and 256 Hz the middle axle (3.60 m back) is 96 samples behind the front one, the rear (4.95 m)
    132: each sees the front axle's road that many samples later."""
    road = iso8608_road("C", length=60.0, seed=3)
    run = track_run(truck, road, 9.6, duration=4.0, rate=RATE).record
    for corner, samples in (("ML", 96), ("RL", 132)):
        np.testing.assert_allclose(run[f"{corner}/road"][samples:], run["FL/road"][:-samples], rtol=0, atol=1e-12)
    assert np.ptp(run["FL/road"]) > 0.005
    assert run.corners_with("wheel_angle") == list(truck.corners)


def test_validating_a_truck_on_its_own_rig_test_finds_no_discrepancy(truck, drive):
    """The model's servo replay, validated against its ideal-post replay of the achieved post motion."""
    measured = replay(truck, drive).record
    report = validate(truck, measured, "own replay")
    assert report.mean_tddi < 1e-4
    assert {name.split("/")[0] for name in report.channels} == set(truck.corners) | {"cab"}  # the seat compared
    assert report.indices.ride is not None and abs(report.indices.ride) < 1e-3  # Forsén's eq. 10 on the seat


def test_cli_sweep_over_a_truck_axle_key_damps_its_travel(tmp_path, drive):
    path = tmp_path / "drive.csv"
    write_record(path, drive)
    out = tmp_path / "sweep"
    assert main(["sweep", "--vehicle", "truck_6x4", "--drive", str(path), "--vary", "axles.1.damping=5000:40000:2",
                 "--out", str(out), "--quiet"]) == 0
    import csv

    rows = list(csv.DictReader((out / "results.csv").open()))
    assert [float(r["axles.1.damping [N s/m]"]) for r in rows] == [5000.0, 40000.0]
    travel = "ML/susp_travel rms [m]"
    assert float(rows[1][travel]) < 0.8 * float(rows[0][travel])


def test_rerun_review_of_a_truck_replay_has_a_tab_per_station(drive, tmp_path):
    from rrd_file import Rrd, selected

    path = tmp_path / "drive.csv"
    write_record(path, drive)
    assert main(["replay", "--vehicle", "truck_6x4", "--drive", str(path), "--out", str(tmp_path / "r.csv"),
                 "--rerun", str(tmp_path / "truck.rrd")]) == 0
    rrd = Rrd(tmp_path / "truck.rrd")
    names = [view["name"] for view in rrd.layout.views.values()]
    for corner in ("FL", "FR", "ML", "MR", "RL", "RR"):
        assert any(name.startswith(f"{corner} ") for name in names), (corner, names)
    for view in rrd.layout.views.values():
        assert selected(rrd, view), view["name"]
    record = read_record(tmp_path / "r.csv")
    for name in ("ML/unsprung_acc", "cab/seat_acc"):
        np.testing.assert_allclose(rrd.scalars(f"/run/{name}")[1], record[name], rtol=1e-6, atol=1e-4)


def test_the_cab_on_its_mounts_keeps_the_wk_weighted_seat_acceleration_far_below_the_frames(truck):
    """On an ISO 8608 class C road at 20 m/s: the seat's ISO 2631-1 a_w is a fraction of the frame's above the front
    axle on the 1.5 Hz cab mounts, and more than twice as high with mounts a hundred times stiffer (a cab bolted
    down)."""
    from rig.signal.comfort import comfort_summary

    road = iso8608_road("C", length=300.0, seed=2)
    stiff = dataclasses.replace(truck, cab=dataclasses.replace(truck.cab, stiffness=100 * truck.cab.stiffness,
                                                               damping=10 * truck.cab.damping))
    soft_run, stiff_run = (comfort_summary(track_run(v, road, 20.0, duration=8.0, rate=RATE).record)
                           for v in (truck, stiff))
    assert soft_run["cab/seat_acc"] < 0.3 * soft_run["FL/sprung_acc"]
    assert stiff_run["cab/seat_acc"] > 2 * soft_run["cab/seat_acc"]
