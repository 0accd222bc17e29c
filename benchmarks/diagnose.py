"""Diagnosis: verdicts, gains and wall time for a fixed set of hidden-cause cases.

Each case is a synthetic rig test of proton_x (rig/diagnosis/synthetic.py): 60 s measured and 30 s held out at
512 Hz, linear parameters off by up to 3 %, 2 % noise, one hidden cause (or none). Prints the verdict, the
held-out gain of the named cause, the held-out TDDI of the recalibrated and extended models, and the
wall time per diagnosis (target: at most 10 min on 2 cores).
Run: python benchmarks/diagnose.py [cause ...]
"""

from __future__ import annotations

import sys
import time

from rig.diagnosis.diagnose import diagnose
from rig.diagnosis.synthetic import hidden_cause_records
from rig.vehicle.vehicle_file import load_vehicle

CASES = ("none", "damper_asymmetry", "bump_stop", "anti_roll_bar", "actuator_lag", "sensor_delay")


def main(causes: tuple[str, ...]) -> None:
    vehicle = load_vehicle("proton_x")
    print(f"{'hidden cause':22s} {'verdict':22s} {'gain':>6s} {'recalibrated':>12s} {'extended':>9s} {'time':>7s}")
    for seed, cause in enumerate(causes, start=11):
        measured, holdout, _ = hidden_cause_records(vehicle, cause, seed, duration=60.0, holdout_duration=30.0)
        start = time.perf_counter()
        result = diagnose(vehicle, measured, holdout)
        wall = time.perf_counter() - start
        gain = result.causes[0].gain if result.verdict != "none" else 0.0
        print(f"{cause:22s} {result.verdict:22s} {gain:6.3f} {result.recalibrated_tddi:12.4g} "
              f"{result.extended_tddi:9.4g} {wall:6.0f}s", flush=True)


if __name__ == "__main__":
    main(tuple(sys.argv[1:]) or CASES)
