"""A test matrix with repeats (rig/diagnosis/track/test_matrix.py, rig/diagnosis/track/scatter.py): the repeats'
scatter is the
accuracy a model must reach (Forsén 1999). A truck whose cab mounts are softer than its model says is outside the
scatter on the seat until the cause is added to the model; the scatter and verdict against values computed by hand;
the command over roads x speeds, with measured records as repeats, its figures and its Rerun view."""

import dataclasses
import json

import numpy as np
import pytest
from rrd_file import Rrd, selected

from rig import Record, load_vehicle
from rig.causes import CAUSES
from rig.cli.main import main
from rig.diagnosis.track.scatter import case_scatter
from rig.diagnosis.track.test_matrix import MatrixCase, run_matrix
from rig.io.files import write_record
from rig.signal.filters import band_pass
from rig.signal.metrics import tddi

ROAD = "iso8608:class=C,length=60,seed=3"


def test_the_seat_turns_from_outside_to_inside_the_scatter_when_the_hidden_cab_mounts_are_added():
    """truck_6x4's cab on mounts 0.52 times as stiff as its file says, four repeats over a class C road at 12 m/s (1 %
    speed scatter, 2 % noise): the model without the cause is outside on the seat, 130 times the repeats' scatter;
    with the cause every channel is inside."""
    truck = load_vehicle("truck_6x4")
    truth = CAUSES["cab_mounts"].hidden(truck, np.random.default_rng(2))
    assert truth.extensions["cab_mounts"].stiffness < 0.6 * truck.cab.stiffness
    cases = [MatrixCase(ROAD, 12.0)]
    without = run_matrix(truck, cases, repeats=4, repeats_of=truth, rate=256.0, seed=1).cases[0]
    with_cause = run_matrix(truth, cases, repeats=4, repeats_of=truth, rate=256.0, seed=1).cases[0]
    seat = "cab/seat_acc"
    assert seat in without.outside and without.channels[seat].model > 50 * without.channels[seat].scatter
    assert with_cause.outside == []
    assert with_cause.channels[seat].scatter == without.channels[seat].scatter  # the same repeats
    assert len(without.names) == 6 * 4 + 1 and without.repeats.shape[0] == 4


def test_the_scatter_and_the_verdict_are_the_mean_tddi_of_the_pairs_and_of_the_model_against_the_runs():
    rate, n = 256.0, 2048
    time = np.arange(n) / rate
    rng = np.random.default_rng(0)
    runs = [np.sin(2 * np.pi * 3 * time + phase) + 0.05 * rng.standard_normal(n) for phase in (0.0, 0.1, 0.25)]
    model = np.sin(2 * np.pi * 3 * time + 0.6)
    records = [Record(rate, {"FL/sprung_acc": r}) for r in runs]
    case = case_scatter("sines", Record(rate, {"FL/sprung_acc": model}), records)
    band = [band_pass(r, rate, (0.5, 50.0)) for r in runs]
    modelled = band_pass(model, rate, (0.5, 50.0))
    pairs = [tddi(band[0], band[1]), tddi(band[0], band[2]), tddi(band[1], band[2])]
    score = case.channels["FL/sprung_acc"]
    assert score.scatter == pytest.approx(np.mean(pairs), rel=1e-12)
    assert score.scatter_max == pytest.approx(max(pairs), rel=1e-12)
    assert score.model == pytest.approx(np.mean([tddi(b, modelled) for b in band]), rel=1e-12)
    assert not score.inside  # a 0.6 rad phase is beyond runs within 0.25 rad of each other
    np.testing.assert_allclose(case.low[:, 0], np.min(band, axis=0))
    np.testing.assert_allclose(case.high[:, 0], np.max(band, axis=0))


def test_the_command_runs_roads_by_speeds_with_repeats_and_takes_measured_records_as_repeats(tmp_path, capsys):
    out = tmp_path / "matrix"
    assert main(["track", "--vehicle", "proton_x", "--road", ROAD, "iso8608:class=B,length=40,seed=4",
                 "--speed", "10", "15", "--repeats", "3", "--rate", "256", "--out", str(out),
                 "--rerun", str(tmp_path / "matrix.rrd")]) == 0
    printed = capsys.readouterr().out
    document = json.loads((out / "matrix.json").read_text())
    assert len(document["cases"]) == 4 and printed.count("channels outside the scatter of 3 repeats") == 4
    assert all((out / f"band_{i}.png").is_file() for i in range(1, 5)) and (out / "verdicts.png").is_file()
    assert document["cases"][0]["outside"] == []  # the model is its own repeats' vehicle: inside
    rrd = Rrd(tmp_path / "matrix.rrd")
    names = [view["name"] for view in rrd.layout.views.values()]
    assert any(n.startswith("FL/sprung_acc") and "inside" in n for n in names), names
    for view in rrd.layout.views.values():
        assert selected(rrd, view), view["name"]
    band = rrd.values("/matrix/case_1/FL/sprung_acc/band", "Scalars:scalars")
    model = rrd.scalars("/matrix/case_1/FL/sprung_acc/model")[1]
    assert np.all(band[:, 0] <= band[:, 1]) and band.shape[0] == model.shape[0]
    # two measured records (softer front springs than the model's) as the repeats of one case
    softer = dataclasses.replace(load_vehicle("proton_x"), front=dataclasses.replace(
        load_vehicle("proton_x").front, spring_rate=0.7 * load_vehicle("proton_x").front.spring_rate))
    measured = run_matrix(softer, [MatrixCase(ROAD, 10.0)], repeats=2, rate=256.0, seed=3)
    for i, record in enumerate(measured.cases[0].repeats):
        names = measured.cases[0].names
        write_record(tmp_path / f"run_{i}.csv", Record(256.0, {n: record[:, k] for k, n in enumerate(names)}))
    (tmp_path / "cases.toml").write_text(f'[[case]]\nroad = "{ROAD}"\nspeed = 10.0\nrecords = ["run_0.csv", '
                                         f'"run_1.csv"]\n')
    assert main(["track", "--vehicle", "proton_x", "--cases", str(tmp_path / "cases.toml"), "--out",
                 str(tmp_path / "measured")]) == 0
    case = json.loads((tmp_path / "measured" / "matrix.json").read_text())["cases"][0]
    assert json.loads((tmp_path / "measured" / "matrix.json").read_text())["repeats_of"] == "measured records"
    assert "FL/susp_travel" in case["outside"]  # the model's stiffer front springs


@pytest.mark.parametrize("arguments, named", [
    (["--road", ROAD, "--speed", "10", "15", "--out", "m"], "--repeats of at least 2"),
    (["--road", ROAD, "--speed", "10", "--repeats", "3", "--out", "m.csv"], "writes a folder"),
    (["--road", ROAD, "--out", "r.csv"], "needs --road and --speed"),
])
def test_a_matrix_without_repeats_or_with_a_record_for_its_folder_is_refused_in_one_line(arguments, named, capsys,
                                                                                           tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["track", "--vehicle", "proton_x", *arguments]) == 2
    err = capsys.readouterr().err
    assert named in err and err.count("\n") == 1
