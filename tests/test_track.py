"""Track runs: wheelbase delay between axles, road channels in the record, real OpenCRG surface."""

import numpy as np
import pytest

from rig.cli.main import main
from rig.io.files import read_record
from rig.road.roads import RoadError, crg_road, iso8608_road, road_from_spec
from rig.sim.track import track_run
from rig.vehicle.mjcf import build_model
from rig.vehicle.vehicle_file import load_vehicle


@pytest.fixture(scope="module")
def proton_x():
    return load_vehicle("proton_x")


def test_rear_road_is_the_front_road_one_wheelbase_later(proton_x):
    speed, rate = 20.0, 512.0
    result = track_run(proton_x, iso8608_road("C", 400.0, seed=5), speed, duration=15.0, rate=rate)
    front, rear = result.record["FL/road"], result.record["RL/road"]
    lags = np.arange(-200, 201)
    correlation = [np.dot(front[200:-200], np.roll(rear, -lag)[200:-200]) for lag in lags]
    expected = proton_x.wheelbase / speed * rate  # 66.56 samples
    assert abs(lags[int(np.argmax(correlation))] - expected) <= 1.0


def test_track_record_carries_road_and_responses_not_posts(proton_x):
    result = track_run(proton_x, iso8608_road("B", 120.0, seed=1), 25.0)
    names = set(result.record.names)
    assert {"FL/road", "RR/road", "FL/sprung_acc", "RR/tyre_force"} <= names
    assert not any("actuator" in n for n in names)
    assert result.record.metadata["test"] == "track"
    assert result.record.duration == pytest.approx(120.0 / 25.0, abs=1 / 512)


def test_duration_beyond_the_road_is_refused(proton_x):
    with pytest.raises(RoadError, match=r"road is 50.00 m long: at 20 m/s it lasts 2.50 s, not 10 s"):
        track_run(proton_x, iso8608_road("C", 50.0), 20.0, duration=10.0)


def test_enveloping_filter_smooths_a_sharp_obstacle(proton_x):
    from rig.road.roads import bar_obstacle

    sharp = track_run(proton_x, bar_obstacle(), 10.0)
    enveloped = track_run(proton_x, bar_obstacle(), 10.0, envelope_base=0.3)
    assert enveloped.record["FL/road"].max() < 0.8 * sharp.record["FL/road"].max()
    assert np.abs(enveloped.record["FL/unsprung_acc"]).max() < np.abs(sharp.record["FL/unsprung_acc"]).max()


def test_belgian_block_crg_run_at_20_kmh(real_data, proton_x):
    with pytest.warns(UserWarning, match="CR byte"):  # the shared copy lost bytes to a CRLF conversion
        road = crg_road(real_data / "belgian_block.crg", left_offset=proton_x.track_front / 2,
                        right_offset=-proton_x.track_front / 2)
    assert road.length == pytest.approx(10.0)
    result = track_run(proton_x, road, 20 / 3.6)
    record = result.record
    assert all(np.all(np.isfinite(v)) for v in record.channels.values())
    for corner in proton_x.corners:
        assert record[f"{corner}/tyre_force"].min() >= 0.0


def test_cli_track_writes_the_record(tmp_path, capsys):
    out = tmp_path / "track.csv"
    assert main(["track", "--vehicle", "proton_x", "--road", "iso8608:class=C,length=150,seed=2",
                 "--speed", "20", "--out", str(out)]) == 0
    record = read_record(out)
    assert "RL/road" in record.names and record.metadata["test"] == "track"
    assert "Wk-weighted" in capsys.readouterr().out


def test_a_road_that_falls_by_a_metre_keeps_the_car_on_it(proton_x):
    """A 1 m descent over 100 m (grade 1 %): the tyres never leave the road and are back at their static load
    at the bottom (the road used to pass the tyre tendon's lower end and let the car fall)."""
    road = road_from_spec("step:height=-1.0,position=10,rise=100,length=200")
    record = track_run(proton_x, road, 20.0, duration=9.0).record
    assert record["FL/road"][-1] == pytest.approx(-1.0, abs=1e-3)
    for corner in ("FL", "RR"):
        load = record[f"{corner}/tyre_force"] / record[f"{corner}/tyre_force"][0]
        assert load.min() > 0.5 and load[-1] == pytest.approx(1.0, abs=1e-3), corner


def test_only_the_rig_draws_its_tyre_tendons(proton_x):
    """With servo posts the tyre tendon runs from the wheel pan to the hub, a short line worth drawing; on the
    road (ideal posts) its lower end is 100 m below the surface, so it is not drawn (Rerun and the viewer draw
    only visible tendons)."""
    for posts, alpha in (("servo", 1.0), ("ideal", 0.0)):
        model = build_model(proton_x, 512.0, posts).model
        assert model.tendon_rgba[model.tendon("FL/tyre_spring").id, 3] == alpha, posts
