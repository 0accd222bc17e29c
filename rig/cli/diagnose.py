"""``rig diagnose``: name the cause of the model's discrepancy with a measured test, extend the model."""

from __future__ import annotations

import argparse
from pathlib import Path

from rig.cli.options import (add_map, add_rerun, add_resample, add_vehicle, command_line, in_file, out_folder,
                             progress_line, read, review)


def add_parser(commands: argparse._SubParsersAction) -> None:
    diagnose = commands.add_parser("diagnose", help="name the cause of the model's discrepancy, extend the model")
    add_vehicle(diagnose)
    diagnose.add_argument("--measured", metavar="M", required=True, nargs="+", type=in_file,
                          help="measured record to fit: a rig test, track tests (one or more constant speeds), or "
                               "K&C records (rig kc's kc.csv)")
    diagnose.add_argument("--holdout", metavar="H", type=in_file,
                          help="held-out record to score on (default: the last third of --measured)")
    diagnose.add_argument("--out", type=out_folder, metavar="DIR", required=True,
                          help="output folder (diagnosis.json, vehicle_extended.toml, report)")
    add_resample(diagnose)
    add_map(diagnose)
    add_rerun(diagnose, scene=False)
    diagnose.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from rig.cli import kc
    from rig.diagnosis.dispatch import diagnose_records
    from rig.diagnosis.track.track_diagnosis import TrackDiagnosis
    from rig.io.kc_record import is_kc_record
    from rig.vehicle.vehicle_file import load_vehicle

    if any(is_kc_record(path) for path in args.measured):  # K&C records: the kinematic diagnosis
        return kc.diagnose(args)
    vehicle = load_vehicle(args.vehicle)
    records = [read(args, path) for path in args.measured]
    holdout = read(args, args.holdout) if args.holdout else None
    result = diagnose_records(vehicle, records, holdout, [*args.measured, *([args.holdout] if holdout else [])],
                              progress=progress_line)
    if isinstance(result, TrackDiagnosis):
        _present_track(args, result, vehicle, records[0])
    else:
        _present_rig(args, result, vehicle)
    return 0


def _present_rig(args: argparse.Namespace, result, vehicle) -> None:
    from rig.report.diagnosis_report import next_steps, write_diagnosis

    write_diagnosis(result, args.out, command_line(args))
    print(f"verdict: {result.verdict}; held-out TDDI {result.baseline_tddi:.4g} (baseline) -> "
          f"{result.recalibrated_tddi:.4g} (recalibrated) -> {result.extended_tddi:.4g} (extended)")
    if result.unexplained is not None:
        left = result.unexplained
        amplitude = left.where.amplitude_dependence
        print(f"unexplained: {left.floor_multiple:.1f} times the noise floor left, the residual {left.where.text()}"
              + (f"; amplitude dependence {amplitude:.2f}" if amplitude is not None else ""))
    print(f"wrote {args.out}/diagnosis.json, vehicle_extended.toml, report.md")
    for step in next_steps(result, Path(args.out)):
        print(f"next: {step[2:]}")

    from rig.report.review_diagnosis import log_diagnosis

    review(args, f"{vehicle.name} against {', '.join(args.measured)}", lambda rec: log_diagnosis(rec, result))


def _present_track(args: argparse.Namespace, result, vehicle, first) -> None:
    from rig.report.track_report import write_track_diagnosis

    write_track_diagnosis(result, args.out)
    named = result.unbalance.named
    print(f"verdict: {result.verdict}" + (f"; {named.corner}: m e {named.unbalance_kgm * 1e3:.2f} ± "
                                          f"{named.std_kgm * 1e3:.2f} g·m at {named.angle_deg:.1f} ± "
                                          f"{named.std_deg:.1f} deg from the mark" if named else ""))
    threshold = next(iter(result.unbalance.wheels.values())).threshold
    print(f"unbalance per wheel (g·m, T² against {threshold:.1f}): "
          + ", ".join(f"{w.corner} {w.unbalance_kgm * 1e3:.2f} ± {w.std_kgm * 1e3:.2f} (T² {w.t2:.1f})"
                      for w in result.unbalance.wheels.values()))
    if result.road is not None:
        print(f"road part (rig-style, on the measured road): {result.road.verdict}")
    print(f"wrote {args.out}/diagnosis.json, vehicle_extended.toml, report.md")
    from rig.report.review_diagnosis import log_track_diagnosis

    review(args, f"{vehicle.name} against {', '.join(args.measured)} (track)",
           lambda rec: log_track_diagnosis(rec, result, first))
