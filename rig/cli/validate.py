"""``rig validate``: a measured rig test against the model's simulation of it."""

from __future__ import annotations

import argparse

from rig.cli.options import add_map, add_resample, add_vehicle, command_line, in_file, out_folder, read


def add_parser(commands: argparse._SubParsersAction) -> None:
    validate = commands.add_parser("validate", help="compare a measured rig test with the model's simulation of it")
    add_vehicle(validate)
    validate.add_argument("--measured", metavar="M", required=True, type=in_file,
                          help="measured rig record (actuator_disp, responses, drive)")
    validate.add_argument("--out", type=out_folder, metavar="DIR", default="validation",
                          help="output folder (default: %(default)s)")
    add_resample(validate)
    add_map(validate)
    validate.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from rig.diagnosis.core.validation import validate
    from rig.report.validation_report import indices_line, next_step, write_validation
    from rig.vehicle.vehicle_file import load_vehicle

    vehicle = load_vehicle(args.vehicle)
    report = validate(vehicle, read(args, args.measured), args.measured)
    ran = command_line(args)
    write_validation(report, args.out, ran)
    low, high = report.band_hz
    for note in report.notes:
        print(f"note: {note}")
    print(f"mean TDDI {report.mean_tddi:.4g} over {len(report.channels)} channels ({low:.3g}-{high:.3g} Hz); worst "
          f"RMS error: " + ", ".join(f"{n} {m.rms_error_pct:.1f} %" for n, m in
                                     sorted(report.channels.items(), key=lambda kv: -kv[1].tddi)[:4]))
    print(indices_line(report.indices))
    print(report.verdict())
    print(f"next: {next_step(report, ran)}")
    print(f"wrote {args.out}/report.md, validation.json, psd_overlay.png, pattern_frfs.png")
    return 0
