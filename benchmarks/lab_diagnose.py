"""The diagnosis of the lab quarter-car bench (tests/lab_rig.py's SciPy bench, 0.02 mm encoders, a correlated
actuator force): per case the verdict, each named cause's held-out gain and values, the recalibration's factors and
the held-out TDDI of the baseline, recalibrated and extended models, and the wall time.

Cases: ``exact`` (nothing hidden), ``weak_actuator`` (force constant 0.8), ``friction`` (0.4 N body bearing) and
``pair`` (both). 30 s measured and 15 s held out at 500 Hz, seed 3.
Run: python benchmarks/lab_diagnose.py [case ...]
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from lab_rig import lab_records

from rig.diagnosis.rig_test.diagnose import diagnose
from rig.vehicle.vehicle_file import load_vehicle

CASES = {"exact": {}, "weak_actuator": {"force_constant": 0.8}, "friction": {"bearing_friction": 0.4},
         "pair": {"force_constant": 0.8, "bearing_friction": 0.4}}


def main(names: list[str]) -> None:
    vehicle = load_vehicle("lab_quarter")
    for name in names or list(CASES):
        measured, holdout, _ = lab_records(vehicle, 3, duration=30.0, holdout=15.0, **CASES[name])
        start = time.perf_counter()
        diagnosis = diagnose(vehicle, measured, holdout)
        seconds = time.perf_counter() - start
        named = "; ".join(f"{c.effect} gain {c.gain:.3f} " + ", ".join(f"{k} {v:.3g}" for k, v in c.params.items())
                          for c in diagnosis.named)
        factors = ", ".join(f"{k} {v:.3f}" for k, v in diagnosis.recalibration.values.items())
        print(f"{name}: verdict {diagnosis.verdict_text}; {named or 'nothing named'}\n"
              f"  recalibration: {factors}\n"
              f"  held-out TDDI: baseline {diagnosis.baseline_tddi:.3g}, "
              f"recalibrated {diagnosis.recalibrated_tddi:.3g}, "
              f"extended {diagnosis.extended_tddi:.3g}, noise floor {diagnosis.noise_floor:.3g}; {seconds:.0f} s",
              flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
