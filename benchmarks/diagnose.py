"""Diagnosis: verdicts, gains and wall time per hidden-effect case.

Two sets of cases, each a rig test at 512 Hz with the truth car's linear parameters off by up to 3 % and
2 % noise on the measured channels:
- ``own``: the project's synthetic tests (rig/diagnosis/synthetic.py), hiding the diagnosis's own laws;
  60 s measured and 30 s held out;
- ``independent``: records of a second simulator written from the equations (tests/independent_rig.py),
  hiding laws the diagnosis does not fit; 30 s measured and 30 s held out.
Prints per case the verdict (and whether it is one the hidden effect allows), the held-out gain of the
named cause (of the generic extension for ``unexplained``), the held-out TDDI of the recalibrated and extended models,
the noise floor and the wall time.
Run: python benchmarks/diagnose.py [own|independent] [--vehicle proton_x] [case ...]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from independent_rig import Hidden, independent_records

from rig.diagnosis.diagnose import diagnose
from rig.diagnosis.synthetic import hidden_cause_records
from rig.vehicle.vehicle_file import load_vehicle

OWN = ("none", "damper_asymmetry", "bump_stop", "anti_roll_bar", "actuator_lag", "sensor_delay")
#: case -> (hidden effects, verdicts that name it rightly)
INDEPENDENT = {
    "none": (Hidden(), {"none"}),
    "duffing_spring": (Hidden(cubic_spring=3.0e7), {"progressive_spring"}),
    "smooth_bump_stop": (Hidden(smooth_bump=(0.010, 4.0e6)), {"bump_stop", "progressive_spring"}),
    "smooth_rebound_stop": (Hidden(smooth_rebound=(0.010, 4.0e6)), {"rebound_stop", "progressive_spring"}),
    "tanh_friction": (Hidden(tanh_friction=(250.0, 0.01)), {"strut_friction"}),
    "hydraulic_compliance": (Hidden(hydraulic_compliance=2.0e5), {"top_mount_compliance"}),
    "payload": (Hidden(payload=(180.0, -1.0, 0.2)), {"mass_error"}),
    "engine_on_mounts": (Hidden(secondary_mass=(150.0, 1.2, 0.0, 11.0, 0.08)), {"secondary_mass", "unexplained"}),
    "anti_roll_bar": (Hidden(anti_roll_bar=(15000.0, 7000.0)), {"anti_roll_bar"}),
    "tyre_damping": (Hidden(tyre_damping=300.0), {"tyre_damping"}),
    "second_order_valve": (Hidden(valve=(14.0, 0.7, 0.006)), {"actuator_lag"}),
    "sensor_gain": (Hidden(sensor_gain={"FR/sprung_acc": 1.1}), {"sensor_gain"}),
    "sensor_delay": (Hidden(sensor_delay={"RL/sprung_acc": 0.005, "RL/unsprung_acc": 0.005}), {"sensor_delay"}),
    "digressive_damper": (Hidden(digressive_damper=(0.1, 0.4)), {"unexplained"}),
}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("set", nargs="?", choices=("own", "independent"), default="independent")
    parser.add_argument("cases", nargs="*")
    parser.add_argument("--vehicle", default="proton_x")
    args = parser.parse_args()
    vehicle = load_vehicle(args.vehicle)
    cases = args.cases or (OWN if args.set == "own" else list(INDEPENDENT))
    print(f"{args.set} cases on {vehicle.name}")
    print(f"{'hidden':22s} {'verdict':22s} {'right':5s} {'gain':>6s} {'recalibrated':>12s} {'extended':>9s} "
          f"{'floor':>8s} {'time':>6s}")
    right = 0
    for seed, case in enumerate(cases, start=11):
        if args.set == "own":
            measured, holdout, _ = hidden_cause_records(vehicle, case, seed, duration=60.0, holdout_duration=30.0)
            allowed = {case}
        else:
            hidden, allowed = INDEPENDENT[case]
            measured, holdout, _ = independent_records(vehicle, hidden, seed, 30.0, 30.0)
        start = time.perf_counter()
        result = diagnose(vehicle, measured, holdout)
        wall = time.perf_counter() - start
        # the named cause's held-out gain; for 'unexplained', the generic extension's
        generic = (result.unexplained or {}).get("generic_extension", {})
        gain = result.named[0].gain if result.named else generic.get("gain", 0.0)
        right += result.verdict in allowed
        print(f"{case:22s} {result.verdict:22s} {'yes' if result.verdict in allowed else 'NO':5s} {gain:6.3f} "
              f"{result.recalibrated_tddi:12.4g} {result.extended_tddi:9.4g} {result.noise_floor:8.2g} {wall:5.0f}s",
              flush=True)
    print(f"{right}/{len(cases)} verdicts right")


if __name__ == "__main__":
    main()
