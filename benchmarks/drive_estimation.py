"""Drive estimation from a measured response: our counterpart of Nurhadiyanto's Tables 6.1 (Eq 5.1) and 6.3 (NARX).

Cases (tests/drive_estimation_case.py), all measured by the independent simulator (tests/independent_rig.py):
proton_x (a) as it is and (b) with asymmetric dampers (rebound 2.2 x compression) and progressive springs, 0.5 %
noise, a 60 s pink-noise identification run (the FRF's H1 and the NARX's training data) and an unseen 20 s road
target; (c) the car of (b) with 1 % noise, both records a broadband drive with six large road events (a 60 s
training run, an unseen 20 s target: tyres off the posts, springs deep in their cubic range). For each method it
prints the drive error per corner (Nurhadiyanto's measure: RMS of estimate minus true drive over the true drive's
RMS, 0.5-50 Hz) and the worst response error (RMS % of the target's, body and wheel accelerations, 0.5-50 Hz)
when the estimate is replayed on the car's model, and what the training does not cover; for (c) also the NARX
trained on a run designed to cover the target (controllers/training_coverage.py) and the NARX of the car's model
without a measured training record (designed identification run, refitted on its own plays); then, for (b) and
(c), the worst-channel error of each iteration started from each estimate, and the plays needed to reach 5 %.
Run: python benchmarks/drive_estimation.py
"""

from __future__ import annotations

import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from drive_estimation_case import CUBIC, RATE, RATIO, large_event_records, measured_records, nonlinear_vehicle
from independent_rig import Car, Hidden, Simulator, rig_record

from controllers.drive_estimation import METHODS, drive_errors, estimate_drive
from controllers.rpc import DriveIteration, IterationSettings
from controllers.training_coverage import training_drive
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


def report(label: str, car, baseline, target, train):
    """One estimate's drive error per corner, its response error, its time and how it was made."""
    start = time.perf_counter()
    estimate = estimate_drive(baseline, target, label.split()[0], train)
    errors = drive_errors(target, estimate)
    print(f"  {label:24s} drive error " + ", ".join(f"{c} {e:6.2f} %" for c, e in errors.items())
          + f"; worst {max(errors.values()):6.2f} %; response error (worst) "
          f"{response_error(car, target, estimate):6.2f} %; {time.perf_counter() - start:.0f} s  [{estimate.detail}]",
          flush=True)
    if estimate.narx is not None:
        for structure, validation in estimate.narx.validation_error_pct.items():
            print(f"      NARX {structure.describe()}: validation (free run) drive error worst "
                  f"{np.max(validation):.2f} %")
        print(f"      {estimate.coverage.describe()}")
    return estimate


def iterate_from(car, target, estimates) -> None:
    for method in METHODS:
        settings = IterationSettings(iterations=ITERATIONS, target_error_pct=5.0)
        initial = None if method == "frf" else estimates[method].drive
        with tempfile.TemporaryDirectory() as folder:
            result = DriveIteration(car, target, CHANNELS, folder, settings, initial=initial).run(progress=False)
        worst = [h.worst_rms_error_pct for h in result.history]
        reached = next((k + 1 for k, e in enumerate(worst) if e <= 5.0), None)
        print(f"  iteration from {method:14s}: " + ", ".join(f"{e:.1f}" for e in worst)
              + f" %; plays to 5 %: {reached or f'more than {ITERATIONS}'}", flush=True)


def main() -> None:
    baseline = load_vehicle("proton_x")
    cases = (("(a) linear proton_x", measured_records(baseline, nonlinear=False), baseline),
             ("(b) asymmetric dampers, progressive springs", measured_records(baseline), nonlinear_vehicle(baseline)),
             ("(c) the car of (b), six large road events, 1 % noise", large_event_records(baseline),
              nonlinear_vehicle(baseline)))
    for label, (train, target), car in cases:
        print(label)
        estimates = {method: report(method, car, baseline, target, train) for method in METHODS}
        if label.startswith("(c)"):
            simulator = Simulator(Car.from_vehicle(baseline), Hidden(cubic_spring=CUBIC, damper_ratio=RATIO))
            designed = rig_record(simulator, training_drive(baseline, target), RATE, np.random.default_rng(7), 0.01)
            report("narx (designed training run)", car, baseline, target, designed)
            report("narx (the car's model, no training record)", car, car, target, None)
        if car is not baseline:
            iterate_from(car, target, estimates)


if __name__ == "__main__":
    main()
