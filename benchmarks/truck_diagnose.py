"""The truck diagnosis per hidden truck cause: verdict, the named cause's parameters against the hidden ones, held-out
TDDIs, and the CPU and wall time of each case with the machine's load; with each parameter, its 95 % interval.

Each case is a rig test of 20 s fitted and 10 s held out at 256 Hz, 2 % noise, the truth's linear parameters off by up
to 3 % (rig/diagnosis/rig_test/synthetic.py ``truth_vehicle``), seed 1:
- ``frame_flexibility`` and ``frame_leaf_friction``: records of the project's own model of truck_6x4 with its
  flexible frame (the independent simulator has a rigid frame), the hidden frame or leaf friction;
- the others: records of the independent truck simulator (tests/independent_truck.py) of a rigid-frame truck_6x4
  (tractor_4x2 for ``cab_air_spring``), the model the same file with a rigid frame.
CPU time is over all threads (on two cores, a case's wall time on an idle machine is about half of it); the load
average is the machine's over the last minute when the case ends (a shared machine's wall times are not comparable).
Run: python benchmarks/truck_diagnose.py [--timing] [case ...] (``--timing``: each step's and fit's time)
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from diagnose import stage_table  # benchmarks/diagnose.py
from independent_truck import rig_test_records

from rig.diagnosis.rig_test.diagnose import diagnose
from rig.diagnosis.rig_test.synthetic import hidden_cause_records, truth_vehicle
from rig.vehicle.vehicle_file import load_vehicle

RATE, DURATION, HOLDOUT, SEED = 256.0, 20.0, 10.0, 1
#: case -> (vehicle, hidden cause, records from the independent simulator)
CASES = {
    "frame_flexibility": ("truck_6x4", "frame_flexibility", False),
    "frame_leaf_friction": ("truck_6x4", "leaf_friction", False),
    "leaf_friction": ("truck_6x4", "leaf_friction", True),
    "air_spring_law": ("truck_6x4", "air_spring_law", True),
    "cab_mounts": ("truck_6x4", "cab_mounts", True),
    "driveline_mounts": ("truck_6x4", "driveline_mounts", True),
    "mass_error": ("truck_6x4", "mass_error", True),
    "cab_air_spring": ("tractor_4x2", "cab_air_spring", True),
}


def case_records(name: str):
    """The model, the measured and held-out records, and the truth of a case."""
    vehicle, cause, independent = CASES[name]
    if not independent:
        model = load_vehicle(vehicle)
        measured, holdout, truth = hidden_cause_records(model, cause, SEED, DURATION, HOLDOUT, RATE)
        return model, measured, holdout, truth
    model = dataclasses.replace(load_vehicle(vehicle), frame=None)
    rng = np.random.default_rng(SEED)
    truth = truth_vehicle(model, cause, rng)
    measured, holdout = rig_test_records(truth, rng, DURATION, HOLDOUT, RATE)
    return model, measured, holdout, truth


def flat(value) -> dict[str, float]:
    """A hidden cause's parameters as the fit names them (``front_friction``, ``middle_volume``...)."""
    if isinstance(value, dict):
        return {f"{axle}_{k}": v for axle, law in value.items() for k, v in dataclasses.asdict(law).items()}
    return dataclasses.asdict(value)


def run(name: str, timing: bool = False) -> None:
    model, measured, holdout, truth = case_records(name)
    cause = CASES[name][1]
    wall, cpu = time.perf_counter(), time.process_time()
    result = diagnose(model, measured, holdout)
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    hidden = flat(truth.extensions[cause])
    found = result.named[0].params if result.named else {}
    spread = result.named[0].intervals if result.named else {}
    errors = ", ".join(f"{k} {v:.5g} (hidden {hidden[k]:.5g}, {100 * (v / hidden[k] - 1):+.2f} %; 95 % "
                       f"{spread[k][0]:.4g}..{spread[k][1]:.4g})" for k, v in found.items() if k in hidden)
    print(f"{name}: verdict {result.verdict_text}; {errors or 'nothing named'}; held-out TDDI recalibrated "
          f"{result.recalibrated_tddi:.3g}, extended {result.extended_tddi:.3g}, floor {result.noise_floor:.3g}; "
          f"CPU {cpu:.0f} s, wall {wall:.0f} s, load {os.getloadavg()[0]:.1f}", flush=True)
    if timing:
        print(stage_table(result.stage_times), flush=True)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description="Truck diagnosis: verdict, parameters and time per hidden cause.")
    parser.add_argument("cases", nargs="*", metavar="case", help=f"cases to run (default: all): {', '.join(CASES)}")
    parser.add_argument("--timing", action="store_true", help="print each case's step and fit times")
    args = parser.parse_args()
    asked = args.cases
    unknown = [c for c in asked if c not in CASES]
    if unknown:
        parser.error(f"unknown case(s) {', '.join(unknown)} (known: {', '.join(CASES)})")
    for case in asked or list(CASES):
        run(case, args.timing)
