"""Sweep throughput: design points per second, the local engine against Ray on this machine, and an estimate
for N nodes.

Workload: proton_x over an ISO 8608 class C road, 200 m at 20 m/s (10 s at 512 Hz per point), a grid of
front x rear damping, chunks of 4 points. Measured in the same run:
- the local engine (chunks one after another, each a rollout on all cores) and the Ray engine on a local Ray
  with as many CPUs (one rollout thread per task), started beforehand (its start-up is reported apart);
  the ratio of their times is Ray's overhead at one node (aimed at: <= 15 %);
- the time of one chunk on one thread, and Ray's cost per task (round trips of empty tasks);
- Ray's time against the ideal: the one-thread chunk time x the chunks each core runs;
- an estimate for a large design (``--estimate-points``) on N nodes like this one: each node runs ``cores``
  chunks at once, the driver hands out tasks one at a time, so
  T(N) = max(ceil(chunks / (N cores)) (t_chunk + t_task), chunks t_task). It leaves out the nodes' start-up and
  the network (a chunk's case and result are a few kB), and assumes nodes as fast as this one.
Written to ``--out`` (JSON) and printed. Run: python benchmarks/sweep.py [--points 32] [--out sweep_benchmark.json]
"""

from __future__ import annotations

import argparse
import json
import math
import os
import tempfile
import time

import numpy as np

from rig.road.roads import road_from_spec
from rig.sweep.design import make_design, parse_vary, vehicle_tables
from rig.sweep.evaluate import SweepCase, evaluate_chunk
from rig.sweep.ray_engine import RayEngine, import_ray
from rig.sweep.run import chunk_design, run_sweep
from rig.vehicle.vehicle_file import load_vehicle

CHUNK = 4
NODES = (1, 2, 4, 8, 16, 64)


def timed(function) -> float:
    start = time.perf_counter()
    function()
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=32, help="design points (default: %(default)s)")
    parser.add_argument("--estimate-points", type=int, default=10_000,
                        help="design size of the N-node estimate (default: %(default)s)")
    parser.add_argument("--out", default="sweep_benchmark.json", help="JSON result (default: %(default)s)")
    args = parser.parse_args()
    cores = os.cpu_count() or 1
    road = road_from_spec("iso8608:class=C,length=200,seed=1")
    case = SweepCase(vehicle_tables(load_vehicle("proton_x")), road, 20.0)
    side = int(math.ceil(math.sqrt(args.points)))
    design = make_design([parse_vary(f"front.damping=2500:5500:{side}"), parse_vary(f"rear.damping=1500:3500:{side}")],
                         [], {})
    design = type(design)(design.keys, design.values[:args.points], design.kind)
    chunks = chunk_design(design, CHUNK)
    ray = import_ray()
    with tempfile.TemporaryDirectory() as tmp:
        run_sweep(case, design, f"{tmp}/warm", chunk_size=CHUNK)  # imports, caches
        results = {}
        local = timed(lambda: results.update(local=run_sweep(case, design, f"{tmp}/local", chunk_size=CHUNK)))
        _, points, values = chunks[0]
        one_thread = SweepCase(**{**case.__dict__, "nthread": 1})
        t_chunk = min(timed(lambda: evaluate_chunk(one_thread, design.keys, points, values)) for _ in range(2))
        startup = timed(lambda: ray.init(num_cpus=cores, include_dashboard=False, log_to_driver=False))
        try:
            noop = ray.remote(num_cpus=1)(lambda: None)
            ray.get([noop.remote() for _ in range(20)])
            t_task = timed(lambda: ray.get([noop.remote() for _ in range(200)])) / 200
            run_sweep(case, design, f"{tmp}/ray_warm", engine=RayEngine(), chunk_size=CHUNK)  # workers import rig
            on_ray = timed(lambda: results.update(ray=run_sweep(case, design, f"{tmp}/ray", engine=RayEngine(),
                                                                 chunk_size=CHUNK)))
        finally:
            ray.shutdown()
    if not np.array_equal(results["local"].rows(), results["ray"].rows()):
        raise SystemExit("the Ray engine's table differs from the local engine's")
    ideal = math.ceil(len(chunks) / cores) * t_chunk  # the chunks on every core, nothing else
    n_chunks = math.ceil(args.estimate_points / CHUNK)
    estimate = {n: args.estimate_points / max(math.ceil(n_chunks / (n * cores)) * (t_chunk + t_task), n_chunks * t_task)
                for n in NODES}
    report = {
        "workload": f"proton_x, ISO 8608 class C 200 m at 20 m/s (10 s at 512 Hz), {design.n_points} points, "
                    f"chunks of {CHUNK}, {cores} cores",
        "local_points_per_s": design.n_points / local,
        "ray_points_per_s": design.n_points / on_ray,
        "ray_over_local_time": on_ray / local,
        "ray_over_ideal_time": on_ray / ideal,
        "ray_startup_s": startup,
        "chunk_one_thread_s": t_chunk,
        "ray_task_overhead_s": t_task,
        "estimate_points": args.estimate_points,
        "estimated_points_per_s_by_nodes": {str(n): v for n, v in estimate.items()},
    }
    with open(args.out, "w", encoding="utf-8") as file:
        json.dump(report, file, indent=2)
    print(report["workload"])
    print(f"local engine:  {report['local_points_per_s']:.2f} points/s")
    print(f"Ray engine:    {report['ray_points_per_s']:.2f} points/s  (Ray time / local time {on_ray / local:.3f}; "
          f"Ray start-up {startup:.1f} s, not included)")
    print(f"one chunk of {CHUNK} on one thread: {t_chunk:.3f} s; Ray task overhead {t_task * 1e3:.2f} ms; "
          f"Ray time / ideal (chunk time x chunks per core) {on_ray / ideal:.3f}")
    print(f"estimate for {args.estimate_points} points on N nodes of this size: "
          + ", ".join(f"{n}: {v:.0f}" for n, v in estimate.items()) + " points/s")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
