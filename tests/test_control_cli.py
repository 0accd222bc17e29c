"""``rig control``: contract record, metrics.json, the sweep and its plot, one-line errors."""

import json

import pytest

from rig.cli import main
from rig.io.files import read_record
from rig.signal.comfort import weighted_rms

ROAD = "iso8608:class=C,length=20,seed=4"


def test_control_writes_a_contract_record_and_the_metrics(tmp_path):
    out = tmp_path / "skyhook"
    assert main(["control", "--vehicle", "proton_x_quarter", "--road", ROAD, "--speed", "20",
                 "--controller", "skyhook:c_sky=5000", "--out", str(out)]) == 0
    record = read_record(out / "record.csv")
    metrics = json.loads((out / "metrics.json").read_text())
    assert {"a_w", "tyre_load_rms", "travel_rms", "power_w"} <= set(metrics)
    assert metrics["controller"] == "skyhook:c_sky=5000"
    for name in ("FL/road", "FL/sprung_acc", "FL/susp_travel", "FL/tyre_force", "FL/control_force"):
        assert name in record
    assert record.metadata["controller"] == "skyhook:c_sky=5000"
    # the CSV keeps 6-7 significant digits: a_w from the file agrees with the run's to that resolution
    assert weighted_rms(record["FL/sprung_acc"], record.rate) == pytest.approx(metrics["a_w"], rel=1e-5)


def test_sweep_places_every_controller_on_the_passive_curve(tmp_path):
    out = tmp_path / "sweep"
    assert main(["control", "--vehicle", "proton_x_quarter", "--road", ROAD, "--speed", "20",
                 "--controller", "passive:scale=0.7", "--out", str(out), "--sweep"]) == 0
    sweep = json.loads((out / "sweep.json").read_text())
    assert next(p["scale"] for p in sweep["passive"]) == 0.2
    assert {"skyhook", "lqr", "hybrid", "passive:scale=0.7"} <= set(sweep["controllers"])
    seven = next(p for p in sweep["passive"] if p["scale"] == 0.7)
    assert sweep["controllers"]["passive:scale=0.7"]["a_w"] == pytest.approx(seven["a_w"], rel=1e-12)
    assert (out / "pareto.png").stat().st_size > 10_000


@pytest.mark.parametrize("controller, message", [
    ("magic", "unknown controller 'magic'"),
    ("skyhook:c_sky=fast", "'c_sky=fast' is not key=number"),
    ("hybrid:alpha=2", "alpha must lie in"),
    ("passive:scale=0.2", "outside the damper's range [1000, 8000] N s/m"),  # 792 N s/m: c_min would clip it
])
def test_bad_controllers_get_a_one_line_error(tmp_path, capsys, controller, message):
    assert main(["control", "--vehicle", "proton_x_quarter", "--road", ROAD, "--speed", "20",
                 "--controller", controller, "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip()
    assert message in err and "\n" not in err


@pytest.mark.parametrize("option, message", [
    (["--force-limit", "-5", "--controller", "lqr"], "force_limit must be positive"),
    (["--c-min", "-1", "--controller", "skyhook"], "c_min must be >= 0"),
    (["--speed", "0", "--controller", "skyhook"], "speed must be positive"),
])
def test_bad_bounds_and_speeds_get_a_one_line_error(tmp_path, capsys, option, message):
    argv = ["control", "--vehicle", "proton_x_quarter", "--road", ROAD, "--speed", "20", "--out", str(tmp_path)]
    assert main(argv + option) == 2
    err = capsys.readouterr().err.strip()
    assert message in err and "\n" not in err
