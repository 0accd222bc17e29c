"""``rig sweep --engine ray`` on a local Ray (2 CPUs): the local engine's table, and a killed worker's chunk retried."""

import os
import sys

import numpy as np
import pytest

ray = pytest.importorskip("ray", reason="the Ray engine needs the optional extra [scale] (pip install 'ray>=2.9')")

from rig.cli import main  # noqa: E402
from rig.road.roads import road_from_spec  # noqa: E402
from rig.sweep.design import make_design, parse_vary, vehicle_tables  # noqa: E402
from rig.sweep.evaluate import SweepCase, evaluate_chunk  # noqa: E402
from rig.sweep.ray_engine import RayEngine  # noqa: E402
from rig.sweep.run import run_sweep  # noqa: E402
from rig.vehicle.vehicle_file import load_vehicle  # noqa: E402

ROAD = "iso8608:class=C,length=100,seed=4"
GRID = ["--vary", "front.damping=1500:3000:4", "speed=10:20:3"]  # 12 points


@pytest.fixture(scope="module")
def local_ray():
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    ray.cloudpickle.register_pickle_by_value(sys.modules[__name__])  # workers get this module's functions by value
    yield
    ray.shutdown()


def test_ray_gives_the_local_engines_table_row_for_row(local_ray, tmp_path):
    common = ["sweep", "--vehicle", "proton_x_quarter", "--road", ROAD, "--speed", "20", *GRID, "--quiet"]
    assert main([*common, "--out", str(tmp_path / "local")]) == 0
    assert main([*common, "--engine", "ray", "--out", str(tmp_path / "ray")]) == 0
    local = (tmp_path / "local" / "results.csv").read_text()
    assert local.count("\n") == 13
    assert (tmp_path / "ray" / "results.csv").read_text() == local


def _dies_once(marker, case, keys, points, values):
    """evaluate_chunk, except that the first worker to run chunk 1 dies hard (no exception: the process ends)."""
    if points[0] == 3 and not os.path.exists(marker):
        open(marker, "w").close()
        os._exit(1)
    return evaluate_chunk(case, keys, points, values)


def test_a_killed_worker_loses_and_duplicates_nothing(local_ray, tmp_path):
    import functools

    case = SweepCase(vehicle_tables(load_vehicle("proton_x_quarter")), road_from_spec(ROAD), 20.0)
    design = make_design([parse_vary("front.damping=1500:3000:4"), parse_vary("speed=10:20:3")], [], {})
    marker = tmp_path / "killed"
    engine = RayEngine(function=functools.partial(_dies_once, str(marker)))
    result = run_sweep(case, design, tmp_path / "ray", engine=engine, chunk_size=3)
    assert marker.exists()  # the worker did die
    reference = run_sweep(case, design, tmp_path / "local", chunk_size=3)
    assert result.rows()[:, 0].tolist() == list(range(12))
    assert np.array_equal(result.rows(), reference.rows())


def test_an_error_in_a_chunk_comes_back_as_itself(local_ray, tmp_path, capsys):
    assert main(["sweep", "--vehicle", "proton_x_quarter", "--road", ROAD, "--speed", "20", "--engine", "ray",
                 "--vary", "front.damping=1500:300000:2", "--quiet", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip()
    assert "front] body damping ratio = 46.7 (damping = 300000 N s/m" in err and "\n" not in err


def test_tasks_larger_than_the_cluster_are_refused_not_left_waiting(local_ray, tmp_path):
    from rig.sweep.design import SweepError

    case = SweepCase(vehicle_tables(load_vehicle("proton_x_quarter")), road_from_spec(ROAD), 20.0)
    design = make_design([parse_vary("front.damping=1500:3000:2")], [], {})
    with pytest.raises(SweepError, match=r"asks for 4 CPUs .* the cluster has 2"):
        run_sweep(case, design, tmp_path, engine=RayEngine(threads=4))
