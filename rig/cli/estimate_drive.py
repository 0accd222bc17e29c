"""``rig estimate-drive``: post drives estimated straight from a measured response (Nurhadiyanto's thesis:
inverse model, FRF inverse, NARX; the neuro form of the neuro-model paper; or the method its checks choose)."""

from __future__ import annotations

import argparse

from rig.cli.options import add_map, add_resample, add_vehicle, in_file, out_record, progress_line, read


def add_parser(commands: argparse._SubParsersAction) -> None:
    estimate = commands.add_parser("estimate-drive", help="estimate post drives straight from a measured response "
                                                          "(inverse model, FRF inverse, NARX)")
    add_vehicle(estimate)
    estimate.add_argument("--target", metavar="T", required=True, type=in_file,
                          help="target record with body and wheel accelerations")
    estimate.add_argument("--method", required=True, choices=("inverse-model", "frf", "narx", "neuro", "auto"),
                          help="neuro: Eq 5.1 with the suspension force learned by the neuro-model paper's network; "
                               "auto: the method with the lowest drive error and the whitest residual on the "
                               "training's held-out part, the car's structure first where the target leaves the "
                               "training")
    estimate.add_argument("--train", metavar="R", type=in_file,
                          help="measured drive/response record: the FRF's H1 or the NARX's training data "
                                          "(default: an identification run of the virtual rig)")
    estimate.add_argument("--out", type=out_record, metavar="D", required=True,
                          help="drive record (.csv, RPC III .drv, MDF .mf4)")
    estimate.add_argument("--training-drive", type=out_record, metavar="TD",
                          help="also write a training drive designed to cover the target's amplitudes: play it on "
                               "the rig and record the responses, the --train record a NARX needs")
    estimate.add_argument("--summary", metavar="DIR",
                          help="write DIR/summary.json (the method, its checks on the training's held-out part: drive "
                               "error and residual tests per corner, the coverage) and DIR/residual_tests.png")
    estimate.add_argument("--quiet", action="store_true", help="no progress lines")
    add_resample(estimate)
    add_map(estimate)
    estimate.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from controllers.drive_estimation import drive_errors, estimate_drive
    from rig.io.channels import channel
    from rig.io.files import write_record
    from rig.io.record import Record
    from rig.vehicle.vehicle_file import load_vehicle

    vehicle = load_vehicle(args.vehicle)
    target = read(args, args.target)
    train = read(args, args.train) if args.train else None
    estimate = estimate_drive(vehicle, target, args.method, train, progress=None if args.quiet else progress_line)
    write_record(args.out, estimate.at_rest())
    print(f"{estimate.method}: {estimate.detail}")
    if estimate.choice:
        print(f"chosen: {estimate.choice}")
    for check in estimate.checks:
        print(f"held out ({check.method}): worst corner {check.worst:.2f} %, residual white against the responses "
              f"at {check.white} of {len(check.tests)} corners")
    if estimate.coverage is not None and not estimate.coverage.covered:
        print(f"warning: {estimate.coverage.describe()}")
    if args.summary:
        _write_summary(estimate, args.summary)
    if target.corners_with("drive") == list(vehicle.corners):  # a rig record: its own drive is the truth
        print("drive error against the target's own drive (RMS, in the drive band): "
              + ", ".join(f"{c} {e:.2f} %" for c, e in drive_errors(target, estimate).items()))
    print(f"wrote {args.out}: {len(vehicle.corners)} drive channels, {estimate.drive.duration:.1f} s at "
          f"{estimate.drive.rate:g} Hz")
    if args.training_drive:
        from controllers.training_coverage import training_drive

        values = training_drive(vehicle, target, band=estimate.band)
        write_record(args.training_drive, Record(target.rate, {channel(c, "drive"): values[:, i] for i, c in
                                                              enumerate(vehicle.corners)},
                                                 metadata={"vehicle": vehicle.name, "test": "rig",
                                                           "signal": "training drive covering the target"}))
        print(f"wrote {args.training_drive}: a {values.shape[0] / target.rate:.0f} s training drive covering the "
              f"target's amplitudes")
    return 0


def _write_summary(estimate, folder: str) -> None:
    """summary.json and the residual tests' figure of the estimate's checks."""
    import json
    from pathlib import Path

    from rig.io.atomic import write_text_atomic
    from rig.report.plots import save_figure
    from rig.report.residual_report import plot_residual_tests

    out = Path(folder)
    write_text_atomic(out / "summary.json", json.dumps(estimate.summary(), indent=1))
    chosen = next((c for c in estimate.checks if c.method == estimate.method), None)
    if chosen is not None:
        save_figure(plot_residual_tests(chosen.tests, f"{estimate.method} drive: held-out residual"),
                    out / "residual_tests.png")
    print(f"wrote {out / 'summary.json'}")
