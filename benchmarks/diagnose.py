"""Diagnosis: verdicts, gains and wall time per hidden-effect case.

Two sets of cases, each a rig test at 512 Hz with the truth car's linear parameters off by up to 3 % and
2 % noise on the measured channels:
- ``own``: the project's synthetic tests (rig/diagnosis/rig_test/synthetic.py), hiding the diagnosis's own laws;
  60 s measured and 30 s held out;
- ``independent``: records of a second simulator written from the equations (tests/independent_rig.py),
  hiding laws the diagnosis does not fit; 30 s measured and 30 s held out.
- ``pairs``: the independent simulator with two hidden effects at once; a verdict is right when it names both.
Each case keeps its seed whichever cases are run (11 + its place in its set), so cases can be run one at a time.
Prints per case the verdict (and whether it is one the hidden effect allows), the held-out gain of the named cause (of
the generic extension for ``unexplained``), the held-out TDDI of the recalibrated and extended models, the noise
floor, the wall and CPU time (over all threads) and the machine's load average over the last minute when the case ends
(a shared machine's wall times are not comparable); with ``--timing``, each case's steps and the fits inside them
(wall seconds: fits that ran beside each other add up to more than their step), its CPU time over all threads, and the
median wall and CPU times over the cases run (the CPU time drifts less with a shared machine's speed than the wall
clock). Run: python benchmarks/diagnose.py [own|independent|pairs] [--vehicle proton_x] [--out DIR] [--timing] [case
...] [--without QUANTITY ...] (the cases before ``--without``, which takes every name after it; ``--out``: each case's
diagnosis.json, report.md and plots in DIR/<set>/<vehicle>/<case>/; ``--without tyre_force susp_travel``: the records as
a rig without wheel-pan load cells, or without travel sensors too, records them). ``--time-domain``: the recalibration
and the first round's linear causes fitted by time stepping even where the car stays linear (by default on its frequency
response there: rig/diagnosis/rig_test/frequency_fit.py); ``--rate HZ``: records at HZ instead of 512 Hz (a record at
1000 Hz or more is decimated first: rig/diagnosis/core/working_rate.py); ``--events M``: the independent cases' road
events M m high (35 mm by default, where a rear tyre can lift off and the car is then not linear; the cases tried
at 15 mm stayed linear)
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from independent_rig import Hidden, independent_records

from rig.diagnosis.rig_test.diagnose import diagnose
from rig.diagnosis.rig_test.synthetic import hidden_cause_records
from rig.io.record import Record
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
#: case -> (two hidden effects, for each the verdict names that name it rightly)
PAIRS = {
    "asymmetric_damper+friction": (Hidden(damper_ratio=2.5, tanh_friction=(250.0, 0.01)),
                                   ({"damper_asymmetry"}, {"strut_friction"})),
    "duffing_spring+payload": (Hidden(cubic_spring=3.0e7, payload=(180.0, -1.0, 0.2)),
                               ({"progressive_spring"}, {"mass_error"})),
    "anti_roll_bar+tyre_damping": (Hidden(anti_roll_bar=(15000.0, 7000.0), tyre_damping=300.0),
                                   ({"anti_roll_bar"}, {"tyre_damping"})),
    "smooth_bump_stop+sensor_gain": (Hidden(smooth_bump=(0.010, 4.0e6), sensor_gain={"FR/sprung_acc": 1.1}),
                                     ({"bump_stop", "progressive_spring"}, {"sensor_gain"})),
    "hydraulic_compliance+payload": (Hidden(hydraulic_compliance=2.0e5, payload=(180.0, -1.0, 0.2)),
                                     ({"top_mount_compliance"}, {"mass_error"})),
    "asymmetric_damper+sensor_delay": (Hidden(damper_ratio=2.5, sensor_delay={"RL/sprung_acc": 0.005,
                                                                               "RL/unsprung_acc": 0.005}),
                                       ({"damper_asymmetry"}, {"sensor_delay"})),
    "second_order_valve+duffing_spring": (Hidden(valve=(14.0, 0.7, 0.006), cubic_spring=3.0e7),
                                          ({"actuator_lag"}, {"progressive_spring"})),
    "anti_roll_bar+friction": (Hidden(anti_roll_bar=(15000.0, 7000.0), tanh_friction=(250.0, 0.01)),
                               ({"anti_roll_bar"}, {"strut_friction"})),
}


def verdict_names(verdict) -> tuple[str, ...]:
    """The names a verdict holds ('a+b' or a tuple of names)."""
    return tuple(verdict.split("+")) if isinstance(verdict, str) else tuple(verdict)


def is_right(names: tuple[str, ...], allowed: tuple[set[str], ...]) -> bool:
    """Every hidden effect named by one of its names, and nothing else named but the remainder ``unexplained``
    (a single effect's ``unexplained`` is right only where that is what it allows)."""
    causes = [n for n in names if n != "unexplained"] or list(names)
    return len(causes) == len(allowed) and all(any(n in a for n in causes) for a in allowed)


def cases_of(which: str) -> dict[str, tuple[object, tuple[set[str], ...]]]:
    if which == "own":
        return {case: (case, ({case},)) for case in OWN}
    if which == "independent":
        return {case: (hidden, (allowed,)) for case, (hidden, allowed) in INDEPENDENT.items()}
    return dict(PAIRS)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("set", nargs="?", choices=("own", "independent", "pairs"), default="independent")
    parser.add_argument("cases", nargs="*")
    parser.add_argument("--vehicle", default="proton_x")
    parser.add_argument("--out", help="write each case's diagnosis (report, JSON, plots) under this folder")
    parser.add_argument("--timing", action="store_true", help="print each case's step and fit times")
    parser.add_argument("--time-domain", action="store_true",
                        help="linear fits by time stepping where the car stays linear "
                             "(diagnose(frequency_domain=False))")
    parser.add_argument("--rate", type=float, default=512.0, metavar="HZ",
                        help="the records' sample rate (a DAQ's 1000 or 2048 Hz: decimated to the working rate)")
    parser.add_argument("--events", type=float, default=0.035, metavar="M",
                        help="independent cases: the road events' height in m (at 35 mm a rear tyre can lift off)")
    parser.add_argument("--without", nargs="+", default=[], metavar="QUANTITY",
                        help="leave these quantities out of the records (tyre_force: a rig without load cells)")
    args = parser.parse_intermixed_args()
    vehicle = load_vehicle(args.vehicle)
    known = cases_of(args.set)
    unknown = [c for c in args.cases if c not in known]
    if unknown:
        parser.error(f"unknown case(s) {', '.join(unknown)} (known: {', '.join(known)})")
    without_note = f", records without {', '.join(args.without)}" if args.without else ""
    print(f"{args.set} cases on {vehicle.name} at {args.rate:g} Hz{without_note}")
    print(f"{'hidden':34s} {'verdict':40s} {'right':5s} {'gains':>13s} {'recalibrated':>12s} {'extended':>9s} "
          f"{'floor':>8s} {'wall':>6s} {'CPU':>6s} {'load':>5s}")
    right, walls, cpus = 0, [], []
    cases = args.cases or list(known)
    for case in cases:
        seed = 11 + list(known).index(case)
        hidden, allowed = known[case]
        if args.set == "own":
            measured, holdout, _ = hidden_cause_records(vehicle, case, seed, duration=60.0, holdout_duration=30.0,
                                                           rate=args.rate)
        else:
            measured, holdout, _ = independent_records(vehicle, hidden, seed, 30.0, 30.0, rate=args.rate,
                                                           events=args.events)
        measured, holdout = (without(r, args.without) for r in (measured, holdout))
        start, cpu_start = time.perf_counter(), time.process_time()
        result = diagnose(vehicle, measured, holdout, frequency_domain=not args.time_domain)
        wall, cpu = time.perf_counter() - start, time.process_time() - cpu_start
        walls.append(wall)
        cpus.append(cpu)
        names = verdict_names(result.verdict)
        # the named causes' held-out gains; for 'unexplained' alone, the generic extension's
        gains = [c.gain for c in result.named] or [generic_gain(result)]
        ok = is_right(names, allowed)
        if args.out:
            from rig.report.diagnosis_report import write_diagnosis

            write_diagnosis(result, Path(args.out) / args.set / vehicle.name / case)
        right += ok
        print(f"{case:34s} {'+'.join(names):40s} {'yes' if ok else 'NO':5s} {' '.join(f'{g:.3f}' for g in gains):>13s} "
              f"{result.recalibrated_tddi:12.4g} {result.extended_tddi:9.4g} {result.noise_floor:8.2g} {wall:5.0f}s "
              f"{cpu:5.0f}s {os.getloadavg()[0]:5.1f}", flush=True)
        if args.timing:
            print(stage_table(result.stage_times), flush=True)
            print(f"    CPU time, all threads {cpu:46.1f} s ({cpu / wall:.2f} cores busy)", flush=True)
    print(f"{right}/{len(cases)} verdicts right")
    if args.timing:
        print(f"median wall {statistics.median(walls):.1f} s, median CPU time {statistics.median(cpus):.1f} s over "
              f"{len(walls)} case(s)")


def without(record: Record, quantities: list[str]) -> Record:
    """``record`` without the channels of ``quantities``."""
    return dataclasses.replace(record, channels={n: v for n, v in record.channels.items()
                                                 if n.partition("/")[2] not in quantities})


def stage_table(times) -> str:
    """Each step's wall time, the fits inside it indented below it (repeated fits of one name summed)."""
    lines = []
    for step in (t for t in times if t.within is None):
        lines.append(f"    {step.stage:60s} {step.seconds:7.1f} s")
        parts: dict[str, list[float]] = {}
        for part in (t for t in times if t.within == step.stage):
            parts.setdefault(part.stage, []).append(part.seconds)
        lines += [f"      {name[:58]:58s} {sum(seconds):7.1f} s" + (f" ({len(seconds)}x)" if len(seconds) > 1 else "")
                  for name, seconds in parts.items()]
    return "\n".join(lines)


def generic_gain(result) -> float:
    """The generic extension's held-out gain of an 'unexplained' verdict (0 when none was fitted)."""
    where = result.unexplained
    if where is None:
        return 0.0
    generic = where.get("generic_extension") if isinstance(where, dict) else where.generic_extension
    if generic is None:
        return 0.0
    return generic["gain"] if isinstance(generic, dict) else generic.gain


if __name__ == "__main__":
    main()
