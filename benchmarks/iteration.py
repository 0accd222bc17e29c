"""Drive iteration: the default (adaptive) scheme against the fixed-gain reference on the same case.

Case (the acceptance case of the iteration issue): proton_x_nonlinear (bump stops, asymmetric dampers,
tyres that lift off), target = 8-channel track run, ISO 8608 class C, 20 m/s, 30 s. Prints per iteration
the worst channel's RMS error of each scheme, the iterations each needs to reach 5 %, and the wall time
of each run (identification, 8 rig runs and the per-iteration files and plots).
Run: python benchmarks/iteration.py
"""

from __future__ import annotations

import tempfile
import time

from controllers.rpc import DriveIteration, IterationSettings
from rig.road.roads import iso8608_road
from rig.sim.track import track_run
from rig.vehicle.vehicle_file import load_vehicle

CHANNELS = [f"{c}/{q}" for c in ("FL", "FR", "RL", "RR") for q in ("sprung_acc", "unsprung_acc")]
ITERATIONS = 8


def main() -> None:
    vehicle = load_vehicle("proton_x_nonlinear")
    target = track_run(vehicle, iso8608_road("C", 700.0, seed=1), 20.0, duration=30.0).record
    runs = {}
    for scheme in ("fixed", "adaptive"):
        settings = IterationSettings(scheme=scheme, iterations=ITERATIONS, target_error_pct=0.0)
        with tempfile.TemporaryDirectory() as folder:
            start = time.perf_counter()
            result = DriveIteration(vehicle, target, CHANNELS, folder, settings).run(progress=False)
            runs[scheme] = (result.history, time.perf_counter() - start)
    print("iteration   worst channel RMS error [%]")
    print("            fixed     adaptive")
    for k in range(ITERATIONS):
        row = [runs[s][0][k].worst_rms_error_pct if k < len(runs[s][0]) else float("nan") for s in runs]
        print(f"{k:9d}   {row[0]:7.2f}   {row[1]:8.2f}")
    for scheme, (history, wall) in runs.items():
        reached = next((h.iteration + 1 for h in history if h.worst_rms_error_pct <= 5.0), None)
        print(f"{scheme:9s}: {reached or f'>{ITERATIONS}'} iterations to reach 5 %, "
              f"{history[-1].worst_rms_error_pct:.2f} % after {len(history)}, wall time {wall:.1f} s")


if __name__ == "__main__":
    main()
