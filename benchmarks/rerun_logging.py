"""Rerun logging cost of a drive iteration against the simulation time of that iteration.

A 60 s, 8-channel target (proton_x over ISO 8608 class C at 20 m/s) is iterated 8 times on the virtual rig
(fixed scheme: it never stops early). Prints:
- the simulation time of the 8 iterations (the time spent in the rig's rollouts, drives of 70 s with the
  lead-in and lead-out) and of the whole iteration run (with the 120 s identification and the FRF work);
- the logging time of everything ``rig iterate --rerun`` writes (8 iterations of target, response, error and
  drive series, the metrics, the convergence and FRF images, the best drive's record and 3D animation, the
  overview and the layout), through the file's flush;
- the ratio logging / simulation (target <= 0.10) and the file size (the best drive's replay comes from
  the iteration itself: ``--rerun`` simulates nothing more).
Run: python benchmarks/rerun_logging.py
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

from controllers.rpc import DriveIteration, IterationSettings
from rig.report.review import recording
from rig.report.review_iteration import IterationLog, log_drive_iteration
from rig.road.roads import iso8608_road
from rig.sim.track import track_run
from rig.vehicle.vehicle_file import load_vehicle

DURATION = 60.0  # s
ITERATIONS = 8
REPEATS = 3  # logging is timed best of 3
CHANNELS = [f"{c}/{q}" for c in ("FL", "FR", "RL", "RR") for q in ("sprung_acc", "unsprung_acc")]


def main() -> None:
    vehicle = load_vehicle("proton_x")
    target = track_run(vehicle, iso8608_road("C", 1300.0, seed=4), 20.0, duration=DURATION).record
    with tempfile.TemporaryDirectory() as folder:
        settings = IterationSettings(scheme="fixed", iterations=ITERATIONS, target_error_pct=0.0)
        job = DriveIteration(vehicle, target, CHANNELS, folder, settings)
        simulated: list[float] = []
        play = job.rig.play

        def timed(*args) -> tuple:
            start = time.perf_counter()
            out = play(*args)
            simulated.append(time.perf_counter() - start)
            return out

        job.rig.play = timed
        plays = IterationLog()
        start = time.perf_counter()
        result = job.run(progress=False, callback=plays)
        run_time = time.perf_counter() - start
        assert len(result.history) == ITERATIONS, result.stop_reason
        simulation = sum(simulated[-ITERATIONS:])  # the first play is the identification

        path = Path(folder) / "iterate.rrd"
        times = []
        for _ in range(REPEATS):
            start = time.perf_counter()
            with recording(path) as review:
                log_drive_iteration(review, result, plays, job.target, float(job.time[0]), CHANNELS, settings,
                                    job.target_record)
            times.append(time.perf_counter() - start)
        logging = min(times)
        size = path.stat().st_size

    samples = job.target.shape[0]
    print(f"{ITERATIONS} iterations of a {DURATION:g} s, {len(CHANNELS)}-channel target "
          f"({samples} samples per series with the lead-in and lead-out, {job.rate:g} Hz)")
    print(f"simulation of the {ITERATIONS} iterations: {simulation:.2f} s  (whole iteration run: {run_time:.2f} s)")
    print(f"Rerun logging, all of it:     {logging:.3f} s  (best of {REPEATS}: {', '.join(f'{t:.3f}' for t in times)}; "
          f"{size / 1e6:.0f} MB .rrd)")
    print(f"logging / simulation:         {logging / simulation:.3f}   (target <= 0.10)")
    print(f"logging / whole run:          {logging / run_time:.3f}")


if __name__ == "__main__":
    main()
