"""``rig sweep``: designs, chunks written once and resumable, the nominal Monte-Carlo, metrics, one-line errors."""

import json
import sys

import numpy as np
import pytest

from rig.cli import main
from rig.io.units import STANDARD_GRAVITY
from rig.road.roads import road_from_spec
from rig.sim.track import track_run
from rig.sweep.design import (
    Factor,
    SweepError,
    make_design,
    nominal_value,
    parse_scatter,
    parse_vary,
    vehicle_at,
    vehicle_tables,
)
from rig.sweep.evaluate import SweepCase, evaluate_chunk, ride_metrics
from rig.sweep.results import band_coverage, pareto_mask, psd_band
from rig.sweep.run import LocalEngine, run_sweep
from rig.vehicle.vehicle_file import VehicleError, load_vehicle

ROAD = "iso8608:class=C,length=100,seed=4"


@pytest.fixture(scope="module")
def quarter():
    return load_vehicle("proton_x_quarter")


@pytest.fixture(scope="module")
def case(quarter):
    return SweepCase(vehicle_tables(quarter), road_from_spec(ROAD), 20.0)


def test_grid_is_every_combination_last_key_fastest():
    design = make_design([parse_vary("front.damping=1000:3000:3"), parse_vary("speed=10:20:2")], [], {})
    assert design.keys == ("front.damping", "speed")
    assert design.values.tolist() == [[1000, 10], [1000, 20], [2000, 10], [2000, 20], [3000, 10], [3000, 20]]


def test_latin_hypercube_draws_every_stratum_of_every_key_once():
    nominal = {"sprung.mass": 300.0}
    design = make_design([Factor("front.damping", 1000.0, 2000.0)], [parse_scatter("sprung.mass=5")], nominal,
                         samples=20, seed=3)
    strata = np.floor((design.values[:, 0] - 1000.0) / 1000.0 * 20).astype(int)
    assert sorted(strata) == list(range(20))
    from scipy.stats import norm

    z = (design.values[:, 1] / 300.0 - 1.0) / 0.05
    assert sorted(np.floor(norm.cdf(z) * 20).astype(int)) == list(range(20))


def test_zero_scatter_is_the_nominal_value_exactly():
    design = make_design([], [("sprung.mass", 0.0)], {"sprung.mass": 317.5}, samples=5, sampling="random")
    assert design.values[:, 0].tolist() == [317.5] * 5


@pytest.mark.parametrize("text, message", [
    ("front.damping=1:2:x", "COUNT an integer"),
    ("front.damping", "KEY=START:STOP:COUNT"),
    ("front.damping=1:2:0", "COUNT at least 1"),
])
def test_bad_vary_is_refused(text, message):
    with pytest.raises(SweepError, match=message):
        parse_vary(text)


def test_keys_are_vehicle_file_paths_and_bad_values_are_refused_as_in_a_file(quarter):
    tables = vehicle_tables(quarter)
    assert nominal_value(tables, "front.damping") == quarter.front.damping
    assert vehicle_at(tables, {"front.damping": 1234.0}).front.damping == 1234.0
    with pytest.raises(SweepError, match=r"unknown key 'front.dampng': front has no 'dampng'"):
        nominal_value(tables, "front.dampng")
    with pytest.raises(VehicleError, match=r"body damping ratio = 156 \(damping = 1e\+06 N s/m"):
        vehicle_at(tables, {"front.damping": 1e6})


def test_monte_carlo_with_zero_scatter_gives_the_nominal_run(quarter, case, tmp_path):
    design = make_design([], [("sprung.mass", 0.0), ("front.damping", 0.0)],
                         {"sprung.mass": quarter.sprung_mass, "front.damping": quarter.front.damping}, samples=3)
    result = run_sweep(case, design, tmp_path, chunk_size=2)
    nominal = ride_metrics(track_run(quarter, case.road, 20.0).record)
    for name, value in nominal.items():
        assert result.column(name).tolist() == [value] * 3


def test_tyre_load_is_relative_to_the_static_load(quarter, case):
    record = track_run(quarter, case.road, 20.0).record
    static = (quarter.sprung_mass + quarter.front.unsprung_mass) * STANDARD_GRAVITY
    assert record["FL/tyre_force"][0] == pytest.approx(static, rel=1e-9)
    expected = np.sqrt(np.mean((record["FL/tyre_force"] / static - 1.0) ** 2))
    assert ride_metrics(record)["tyre_load_rms"] == pytest.approx(expected, rel=1e-9)


def test_a_point_does_not_depend_on_its_chunk(case, tmp_path):
    design = make_design([parse_vary("front.tyre_damping=0:400:3"), parse_vary("speed=15:20:2")], [], {})
    single = run_sweep(case, design, tmp_path / "one", chunk_size=1)
    batched = run_sweep(case, design, tmp_path / "all", chunk_size=6)
    assert np.array_equal(single.rows(), batched.rows())
    assert len(set(single.column("a_w"))) == 6  # every point differs: a chunk really mixes variants


def test_resume_runs_only_the_missing_chunks_and_gives_the_same_table(case, tmp_path):
    design = make_design([parse_vary("front.damping=1500:3000:4")], [], {})
    first = run_sweep(case, design, tmp_path, chunk_size=1)
    (tmp_path / "chunks" / "chunk_00002.npz").unlink()
    seen = []
    resumed = run_sweep(case, design, tmp_path, chunk_size=1, resume=True, progress=seen.append)
    assert (resumed.chunks_run, resumed.chunks_reused) == (1, 3)
    assert seen == [3, 1]
    assert np.array_equal(first.rows(), resumed.rows())
    other = make_design([parse_vary("front.damping=1500:3000:5")], [], {})
    with pytest.raises(SweepError, match="holds another sweep"):
        run_sweep(case, other, tmp_path, chunk_size=1, resume=True)


class _Twice(LocalEngine):
    """An engine that hands every chunk back twice (as a retried task might)."""

    def run(self, case, keys, chunks):
        for index, result in super().run(case, keys, chunks):
            yield index, result
            yield index, result


def test_a_chunk_handed_back_twice_is_written_once(case, tmp_path):
    design = make_design([parse_vary("front.damping=1500:3000:3")], [], {})
    result = run_sweep(case, design, tmp_path, engine=_Twice(), chunk_size=2)
    assert result.rows()[:, 0].tolist() == [0, 1, 2]
    assert len(list((tmp_path / "chunks").glob("*.npz"))) == 2


def test_drive_replays_report_rms_and_damage_per_channel(tmp_path):
    from rig.sim.broadband import broadband_drive

    vehicle = load_vehicle("proton_x")
    drive = broadband_drive(vehicle.corners, 5.0, seed=1)
    case = SweepCase(vehicle_tables(vehicle), drive=drive)
    result = evaluate_chunk(case, ("front.damping",), np.arange(2), np.array([[3000.0], [5000.0]]))
    names = dict(zip(result.metric_names, result.metrics.T))
    assert names["limit_hits"].tolist() == [0, 0]
    assert np.all(names["FL/sprung_acc rms"] > 0) and np.all(names["RR/tyre_force damage"] > 0)
    # more damping at the front, less front travel; the rear barely changes
    assert names["FL/susp_travel rms"][1] < names["FL/susp_travel rms"][0]


def test_pareto_mask_keeps_only_the_undominated_points():
    assert pareto_mask([1, 2, 3, 2], [3, 2, 1, 3]).tolist() == [True, True, True, False]


def test_sweep_writes_table_and_plots(tmp_path):
    out = tmp_path / "sweep"
    assert main(["sweep", "--vehicle", "proton_x_quarter", "--road", ROAD, "--speed", "20", "--quiet",
                 "--vary", "front.damping=1500:3000:3", "--vary", "speed=15:20:2", "--out", str(out)]) == 0
    lines = (out / "results.csv").read_text().splitlines()
    assert lines[0] == "point,front.damping [N s/m],speed [m/s],a_w [m/s^2],tyre_load_rms [-],travel_rms [m]"
    assert len(lines) == 7
    for name in ("response_surfaces.png", "pareto.png"):
        assert (out / name).stat().st_size > 10_000
    pytest.importorskip("pyarrow", reason="Parquet is written only with pyarrow")
    import pyarrow.parquet as pq

    table = pq.read_table(out / "results.parquet")
    assert table.column("a_w").to_pylist() == [float(line.split(",")[3]) for line in lines[1:]]


def test_monte_carlo_writes_the_psd_band_with_the_measured_overlay(tmp_path):
    measured = tmp_path / "measured.csv"
    assert main(["track", "--vehicle", "proton_x_quarter", "--road", ROAD, "--speed", "20",
                 "--out", str(measured)]) == 0
    out = tmp_path / "mc"
    assert main(["sweep", "--vehicle", "proton_x_quarter", "--road", ROAD, "--speed", "20", "--quiet",
                 "--samples", "4", "--scatter", "sprung.mass=5", "--measured", str(measured), "--out", str(out)]) == 0
    assert (out / "psd_band.png").stat().st_size > 10_000
    # the measurement is the nominal car: inside the scatter of a 5 % mass scatter nearly everywhere
    coverage = json.loads((out / "scatter.json").read_text())["measured_inside_band"]
    assert set(coverage) == {"FL/sprung_acc", "FL/unsprung_acc", "FL/susp_travel", "FL/tyre_force"}
    assert min(coverage.values()) > 0.5


def test_band_coverage_counts_the_frequencies_inside_the_band():
    band = psd_band(("a",), np.array([1.0, 2.0, 3.0, 4.0]), np.array([[[1.0, 1, 1, 1]], [[3.0, 3, 3, 3]]]))
    measured = {"a": (np.array([1.0, 2.0, 3.0, 4.0]), np.array([0.5, 2.0, 2.5, 4.0]))}
    assert band_coverage(band, measured) == {"a": 0.5}


@pytest.mark.parametrize("extra, message", [
    (["--vary", "front.damping=1:2"], "a grid needs KEY=START:STOP:COUNT"),
    (["--scatter", "sprung.mass=5"], "--scatter needs --samples N"),
    (["--vary", "front.nothing=1:2:2"], "unknown key 'front.nothing'"),
    (["--vary", "front.damping=1000:2000:2", "--address", "auto"], "use it with --engine ray"),
    (["--controller", "nonsense"], "unknown controller 'nonsense'"),
])
def test_bad_sweeps_exit_with_one_line(tmp_path, capsys, extra, message):
    assert main(["sweep", "--vehicle", "proton_x_quarter", "--road", ROAD, "--speed", "20",
                 "--out", str(tmp_path), *extra]) == 2
    err = capsys.readouterr().err.strip()
    assert message in err and "\n" not in err


def test_ray_engine_without_ray_says_how_to_install_it(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "ray", None)  # import ray now raises ImportError
    assert main(["sweep", "--vehicle", "proton_x_quarter", "--road", ROAD, "--speed", "20", "--engine", "ray",
                 "--vary", "front.damping=1000:2000:2", "--out", str(tmp_path)]) == 2
    assert "pip install 'virtual-four-poster[scale]'" in capsys.readouterr().err


def test_the_passive_controller_episode_agrees_with_the_batched_run(tmp_path):
    """The same car two ways: one episode per point stepped under ``passive`` (damping as a semi-active
    actuator), and the chunk batched in C (the damper in the model): the same metrics to rounding."""
    tables = {}
    for label, extra in (("batched", []), ("episodes", ["--controller", "passive"])):
        out = tmp_path / label
        assert main(["sweep", "--vehicle", "proton_x_quarter", "--road", ROAD, "--speed", "20", "--quiet",
                     "--vary", "front.damping=1500:3000:2", "--out", str(out), *extra]) == 0
        lines = (out / "results.csv").read_text().splitlines()
        tables[label] = np.array([[float(v) for v in line.split(",")[2:5]] for line in lines[1:]])
    assert tables["episodes"] == pytest.approx(tables["batched"], rel=1e-12)
