"""``rig kc``: kinematics & compliance tests of a vehicle on the rig (contract: docs/contracts.md), and hardpoint fits.

    rig kc --vehicle V --test travel|roll|steer|lateral|longitudinal|aligning --out DIR [--range R] [--steps N]
           [--fit MEASURED.csv --free NAME,... [--method lm|nelder-mead]] [--rerun FILE.rrd]
    rig kc --vehicle V --lasers FILE [--calibration CAL.csv ...] --out DIR

Writes ``DIR/kc.csv`` (rig/io/kc_record.py) and ``DIR/kc.png`` (every curve), for a travel test also
``DIR/camber_toe.png``; with ``--fit``, the hardpoints fitted to measured K&C records
(rig/diagnosis/kc/hardpoint_fit.py) or
the bushing rates fitted to compliance records (rig/diagnosis/kc/bushing_fit.py) in ``DIR/fit.json`` and the vehicle
with them in ``DIR/<vehicle>_fitted.toml``; with ``--lasers``, a measured laser record read into angles
(rig/diagnosis/kc/laser_records.py) in ``DIR/lasers.csv`` and ``DIR/lasers.png``.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from rig.cli.options import add_rerun, add_vehicle, in_file, out_folder, review
from rig.io.kc_record import FACTORS, SWEEP_UNITS, SWEEPS, TESTS, write_kc_csv


def add_parser(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser("kc", help="kinematics & compliance tests on the rig: body held, wheels moved "
                                              "quasi-statically; curves per corner (kc.csv) and plots")
    add_vehicle(parser, "fs_car")
    parser.add_argument("--test", choices=TESTS, help="the K&C test to run (needed unless --fit or --lasers)")
    parser.add_argument("--out", metavar="DIR", type=out_folder, required=True,
                        help="output folder (kc.csv, kc.png)")
    parser.add_argument("--range", type=float,
                        help="half range of the sweep in the first column's unit: m of travel or rack, deg of roll, "
                             "N of force, N m of moment (default: 0.06 m, 3 deg, 0.02 m, 1000 N, 100 N m)")
    parser.add_argument("--steps", type=int, default=41, help="points of the sweep (default: %(default)s)")
    parser.add_argument("--fit", metavar="MEASURED.csv", nargs="+", type=in_file,
                        help="fit hardpoints to these measured K&C records (travel, roll, steer tests), or bushing "
                             "rates (lateral, longitudinal, aligning tests)")
    parser.add_argument("--free", metavar="NAME,...",
                        help="hardpoints to fit: [front.|rear.]point[.x|.y|.z], e.g. "
                             "front.upper_outer,tie_rod_outer.z; or bushing rates: "
                             "<axle>.bushings.<joint>[.radial|.axial|.conical|.torsional], e.g. "
                             "front.bushings.lower_front.radial")
    parser.add_argument("--method", choices=("lm", "nelder-mead"), default="lm",
                        help="least squares by Levenberg-Marquardt, or Nelder-Mead as the paper (default: %(default)s)")
    parser.add_argument("--lasers", metavar="FILE", type=in_file,
                        help="read a measured laser record (<corner>/laser_1..7 columns of a K&C record) into the "
                             "wishbones' and the wheel carrier's angles (DIR/lasers.csv, DIR/lasers.png)")
    parser.add_argument("--calibration", metavar="CAL.csv", nargs="+", type=in_file,
                        help="with --lasers: calibrate the lasers first on these laser records of sweeps the rig set "
                             "(each corner's travel; the rack in a steer test): a travel and a steer test")
    add_rerun(parser)
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from rig.report.kc_plots import plot_camber_toe, plot_kc
    from rig.report.plots import save_figure
    from rig.sim.kc import KcRig, run_kc
    from rig.vehicle.suspensions.hardpoints import KinematicsError
    from rig.vehicle.vehicle_file import load_vehicle

    if (args.fit is None) != (args.free is None):
        raise KinematicsError("--fit and --free go together")
    if args.calibration and not args.lasers:
        raise KinematicsError("--calibration goes with --lasers")
    if args.test is None and not (args.lasers or args.fit):
        raise KinematicsError("--test is needed (unless --fit fits measured records or --lasers reads one)")
    vehicle = load_vehicle(args.vehicle)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    if args.lasers:
        return _lasers(args, vehicle, out)
    if args.fit:
        return _fit(args, vehicle, out)
    name = SWEEPS[args.test][0]
    half_range = None if args.range is None else args.range * FACTORS[SWEEP_UNITS[name]]
    start = time.perf_counter()
    rig = KcRig(vehicle)
    result = run_kc(vehicle, args.test, half_range, args.steps, rig=rig)
    write_kc_csv(out / "kc.csv", result)
    save_figure(plot_kc(result), out / "kc.png")
    if args.test == "travel":
        save_figure(plot_camber_toe(result), out / "camber_toe.png")
    print(f"rig kc: {vehicle.name} {args.test} test, {args.steps} points in {time.perf_counter() - start:.1f} s; "
          f"wrote {out / 'kc.csv'} and plots")
    sliders = [axle for axle in vehicle.axle_names if vehicle.axle_named(axle).kinematics is None]
    if sliders:
        print(f"note: {vehicle.name}'s {' and '.join(sliders)} axle(s) have no linkage ([<axle>.kinematics]): their "
              f"wheels slide vertically, so camber, toe, caster, kingpin, scrub, trail and track change are zero by "
              f"construction there; travel, wheel load, wheel rate and motion ratio hold (linkage cars: fs_car, "
              f"kc_car)")
    from rig.report.review_kc import log_kc_test

    review(args, f"{vehicle.name} {args.test} test",
           lambda rec: log_kc_test(rec, rig.model, result, args.rerun_magnify))
    return 0


def _fit(args: argparse.Namespace, vehicle, out: Path) -> int:
    from rig.diagnosis.kc.bushing_fit import fit_bushings, is_rate_name, parse_free_rates
    from rig.diagnosis.kc.hardpoint_fit import fit_hardpoints, parse_free
    from rig.io.atomic import write_text_atomic
    from rig.io.kc_record import read_kc_csv
    from rig.vehicle.suspensions.hardpoints import KinematicsError
    from rig.vehicle.vehicle_file import vehicle_to_toml

    measured = [read_kc_csv(path) for path in args.fit]
    rates = [is_rate_name(item) for item in args.free.split(",") if item.strip()]
    if any(rates) and not all(rates):
        raise KinematicsError("--free: fit hardpoints (to travel, roll and steer tests) and bushing rates (to "
                              "compliance tests) apart")
    if any(rates):
        fit = fit_bushings(vehicle, measured, parse_free_rates(args.free, vehicle))
    else:
        fit = fit_hardpoints(vehicle, measured, parse_free(args.free, vehicle), method=args.method)
    write_text_atomic(out / "fit.json", fit.to_json())
    write_text_atomic(out / f"{vehicle.name}_fitted.toml", vehicle_to_toml(
        fit.vehicle, comment=f"{vehicle.name} with hardpoints fitted to {', '.join(args.fit)}"))
    print(fit.summary())
    print(f"wrote {out / 'fit.json'} and {out / (vehicle.name + '_fitted.toml')}")
    return 0


def _lasers(args: argparse.Namespace, vehicle, out: Path) -> int:
    from rig.diagnosis.kc.laser_records import read_lasers
    from rig.io.kc_record import read_kc_csv
    from rig.report.kc_plots import plot_kc
    from rig.report.plots import save_figure

    calibration = [read_kc_csv(path) for path in args.calibration or ()]
    angles = read_lasers(vehicle, read_kc_csv(args.lasers), calibration)
    write_kc_csv(out / "lasers.csv", angles)
    save_figure(plot_kc(angles), out / "lasers.png")
    quantities = dict.fromkeys(name.split("/")[1] for name in angles.curves)
    calibrated = f", the lasers calibrated on {', '.join(args.calibration)}" if calibration else ""
    print(f"rig kc: {args.lasers} read into {', '.join(quantities)} of {', '.join(angles.corners)}{calibrated}; "
          f"wrote {out / 'lasers.csv'} and lasers.png")
    return 0


def diagnose(args: argparse.Namespace) -> int:
    """``rig diagnose`` on K&C records: the kinematic causes ``hardpoint_error`` and ``bushing_compliance``, or
    ``none`` (rig/diagnosis/kc/kinematic_diagnosis.py); writes DIR/diagnosis.json, DIR/vehicle_extended.toml,
    DIR/report.md and a figure per record (rig/report/kc_report.py)."""
    from rig.diagnosis.kc.kinematic_diagnosis import diagnose_kc
    from rig.io.kc_record import is_kc_record, read_kc_csv
    from rig.io.record import RecordError
    from rig.report.kc_report import write_kc_diagnosis
    from rig.report.review_kc import log_kc_diagnosis
    from rig.vehicle.vehicle_file import load_vehicle

    others = [p for p in args.measured if not is_kc_record(p)]
    if others:
        raise RecordError(f"{', '.join(others)}: not a K&C record ('# test: kc'); K&C and rig tests are diagnosed "
                          f"apart")
    vehicle = load_vehicle(args.vehicle)
    result = diagnose_kc(vehicle, [read_kc_csv(p) for p in args.measured])
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    write_kc_diagnosis(result, out)
    print(f"verdict: {result.verdict}")
    for line in _finding_summary(result):
        print(line)
    print(f"wrote {out / 'diagnosis.json'}, vehicle_extended.toml, report.md and a figure per record")
    review(args, f"{vehicle.name} against {', '.join(args.measured)}", lambda rec: log_kc_diagnosis(rec, result))
    return 0


def _finding_summary(result) -> list[str]:
    """What the K&C diagnosis found, in lines for the terminal."""
    from rig.report.kc_report import NO_BUSHINGS
    from rig.sim.kc import COMPLIANCE_TESTS

    lines = []
    if result.hardpoints is not None:
        finding = result.hardpoints
        lines.append(f"hardpoints ({'per corner' if finding.per_corner else 'axle-wide'}): F = "
                     f"{finding.significance.f_statistic:.3g}, p = {finding.significance.p_value:.3g}")
        lines.append(finding.fit.summary())
        lines += [f"  {a.sentence()}" for a in finding.aliases]
    if result.bushings is not None:
        lines.append(f"bushings: F = {result.bushings.significance.f_statistic:.3g}, p = "
                     f"{result.bushings.significance.p_value:.3g}")
        lines.append(result.bushings.fit.summary())
    elif any(r.test in COMPLIANCE_TESTS for r in result.records):
        lines.append(NO_BUSHINGS)
    return lines
