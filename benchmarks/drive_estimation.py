"""Drive estimation from a measured response: our counterpart of Nurhadiyanto's Tables 6.1 (Eq 5.1) and 6.3 (NARX).

Cases (tests/drive_estimation_case.py): proton_x (a) as it is and (b) with asymmetric dampers (rebound 2.2 x
compression) and progressive springs, both measured by the independent simulator (tests/independent_rig.py,
0.5 % noise): a 60 s pink-noise identification run (the FRF's H1 and the NARX's training data) and an unseen
20 s road target. For each method it prints the drive error per corner (Nurhadiyanto's measure: RMS of estimate
minus true drive over the true drive's RMS, 0.5-50 Hz) and the worst response error (RMS % of the target's,
body and wheel accelerations, 0.5-50 Hz) when the estimate is replayed on the car's model; then, for (b), the
worst-channel error of each iteration started from each estimate, and the plays needed to reach 5 %.
Run: python benchmarks/drive_estimation.py
"""

from __future__ import annotations

import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from drive_estimation_case import RATE, measured_records, nonlinear_vehicle

from controllers.drive_estimation import METHODS, drive_errors, estimate_drive
from controllers.rpc import DriveIteration, IterationSettings
from rig.constants import ANALYSIS_BAND
from rig.signal.filters import band_pass
from rig.signal.metrics import rms_error_pct
from rig.sim.virtual_rig import VirtualRig
from rig.vehicle.vehicle_file import load_vehicle

CHANNELS = [f"{c}/{q}" for c in ("FL", "FR", "RL", "RR") for q in ("sprung_acc", "unsprung_acc")]
ITERATIONS = 6


def response_error(car, target, estimate) -> float:
    """Worst channel's RMS error (%) of the estimate replayed on ``car`` against the target, in the band."""
    played = VirtualRig(car, RATE, CHANNELS).play(estimate.values)[0][0]
    measured = np.column_stack([target[n] for n in CHANNELS])
    a, b = (band_pass(x, RATE, ANALYSIS_BAND) for x in (measured, played))
    return max(rms_error_pct(a[:, i], b[:, i]) for i in range(len(CHANNELS)))


def main() -> None:
    baseline = load_vehicle("proton_x")
    for label, nonlinear in (("(a) linear proton_x", False), ("(b) asymmetric dampers, progressive springs", True)):
        car = nonlinear_vehicle(baseline) if nonlinear else baseline
        train, target = measured_records(baseline, nonlinear=nonlinear)
        print(f"{label}")
        estimates = {}
        for method in METHODS:
            start = time.perf_counter()
            estimates[method] = estimate = estimate_drive(baseline, target, method, train)
            errors = drive_errors(target, estimate)
            print(f"  {method:14s} drive error " + ", ".join(f"{c} {e:6.2f} %" for c, e in errors.items())
                  + f"; response error (worst) {response_error(car, target, estimate):6.2f} %"
                  + f"; {time.perf_counter() - start:.1f} s  [{estimate.detail}]", flush=True)
            if estimate.narx is not None:
                for structure, validation in estimate.narx.validation_error_pct.items():
                    print(f"      NARX {structure.describe()}: validation (free run) drive error worst "
                          f"{np.max(validation):.2f} %")
        if not nonlinear:
            continue
        for method in METHODS:
            settings = IterationSettings(iterations=ITERATIONS, target_error_pct=5.0)
            initial = None if method == "frf" else estimates[method].drive
            with tempfile.TemporaryDirectory() as folder:
                result = DriveIteration(car, target, CHANNELS, folder, settings, initial=initial).run(progress=False)
            worst = [h.worst_rms_error_pct for h in result.history]
            reached = next((k + 1 for k, e in enumerate(worst) if e <= 5.0), None)
            print(f"  iteration from {method:14s}: " + ", ".join(f"{e:.1f}" for e in worst)
                  + f" %; plays to 5 %: {reached or f'more than {ITERATIONS}'}", flush=True)


if __name__ == "__main__":
    main()
