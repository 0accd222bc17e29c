"""``rig dyno``: fit a damper's force law to dynamometer records, plot it, and write it into a vehicle file.

    rig dyno --record R [R ...] --out DIR [--map MAP.toml] [--law NAME]
             [--vehicle V --axle front --motion-ratio MR --write V2.toml] [--simulate]

Writes ``DIR/damper.json`` (docs/contracts.md; rig/report/dyno_report.py), ``DIR/force_velocity.png``,
``DIR/loops.png`` and ``DIR/residual_tests.png`` (the residual's whiteness: the chosen law, the best static law and
the best with dynamics); with ``--write`` the vehicle file and ``DIR/written_loops.png`` (the written damper simulated
on the dyno); with ``--simulate`` the vehicle's own damper on the dyno beside the records (``DIR/vehicle_loops.png``).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import sys
from pathlib import Path

from rig.cli.options import add_map, add_resample, in_file, read


def add_parser(commands: argparse._SubParsersAction) -> None:
    """Register ``rig dyno`` on the ``rig`` command's sub-parsers."""
    dyno = commands.add_parser("dyno", help="fit a damper's force law to dynamometer records; write it into a "
                                            "vehicle file")
    dyno.add_argument("--record", nargs="+", required=True, metavar="R", type=in_file,
                      help="dyno records (CSV, RPC III, MDF, TDMS; sine or triangle tests, one or more files) with "
                           "damper/displacement (m, extension positive), damper/force (N, positive resisting "
                           "extension), optionally damper/temperature (degC)")
    dyno.add_argument("--out", metavar="DIR", required=True,
                      help="output folder (damper.json, force_velocity.png, loops.png)")
    add_map(dyno)
    add_resample(dyno)
    dyno.add_argument("--law", metavar="NAME",
                      help="fit only this law (e.g. quadratic, digressive+preload), not all of them by BIC")
    dyno.add_argument("--reference-temperature", type=float, metavar="DEGC",
                      help="temperature at which a drifting law's coefficients are stated (default: the test's mean)")
    dyno.add_argument("--vehicle", metavar="V", help="vehicle file (or built-in name) for --write and --simulate")
    dyno.add_argument("--axle", default="front", choices=("front", "rear"), help="axle of --vehicle (default: front)")
    dyno.add_argument("--motion-ratio", type=float, default=1.0, metavar="MR",
                      help="damper travel over wheel travel (default 1.0): the dyno measures the damper, vehicle "
                           "files hold it at the wheel (wheel force = damper force x MR, wheel damping = c x MR^2)")
    dyno.add_argument("--write", metavar="V2.toml", help="write --vehicle with the fitted law as --axle's damper")
    dyno.add_argument("--temperature", type=float, metavar="DEGC",
                      help="for --write: the temperature whose coefficients a drifting law writes (default: its "
                           "reference)")
    dyno.add_argument("--simulate", action="store_true",
                      help="simulate --vehicle's damper on the dyno (MuJoCo) with each record's displacement and "
                           "put it beside the records")
    dyno.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Read, fit, plot, write; one line per result on stdout."""
    from rig.diagnosis.dyno.damper_choice import fit_damper
    from rig.diagnosis.dyno.damper_law import candidate_names
    from rig.diagnosis.dyno.dynamic_damper_fit import dynamic_names
    from rig.diagnosis.dyno.dyno_test import DynoError, dyno_test
    from rig.io.atomic import write_text_atomic

    if (args.write or args.simulate) and not args.vehicle:
        raise DynoError("--write and --simulate need --vehicle (a vehicle file or a built-in name)")
    known = candidate_names(True) + dynamic_names(True) + dynamic_names(False)
    if args.law and args.law not in known:
        raise DynoError(f"unknown law '{args.law}' (known: {', '.join(dict.fromkeys(known))})")
    test = dyno_test([(path, read(args, path)) for path in args.record])
    for note in test.notes:
        print(f"note: {note}", file=sys.stderr)
    fit = fit_damper(test, [args.law] if args.law else None, args.reference_temperature)
    out = Path(args.out)
    plots = _fit_plots(fit, out)
    extra = _vehicle_parts(args, fit, out, plots)
    from rig.report.dyno_report import damper_document

    document = damper_document(fit, test.notes, plots, **extra)
    write_text_atomic(out / "damper.json", json.dumps(document, indent=2))
    chosen = fit.chosen
    print(f"law: {chosen.law.name}, residual (force minus fit, RMS) {chosen.residual_rms_pct:.2f} % of the RMS force "
          f"({len(fit.forms)} form(s) fitted; {out / 'damper.json'})")
    from rig.diagnosis.dyno.damper_law import UNITS

    if chosen.tests is not None:
        print(f"  {chosen.tests.describe()}")
    print_table(("coefficient", "value", "95 % interval", "unit"),
                [(name, f"{value:.6g}", "{:.6g} .. {:.6g}".format(*chosen.intervals[name]), UNITS.get(name, "-"))
                 for name, value in chosen.law.coefficients.items()])
    return 0


def print_table(header: tuple[str, ...], rows: list[tuple[str, ...]]) -> None:
    """Rows under their header, in columns as wide as their widest cell, indented."""
    widths = [max(len(str(cell)) for cell in column) for column in zip(header, *rows)]
    for row in (header, *rows):
        print("  " + "  ".join(str(cell).ljust(width) for cell, width in zip(row, widths)).rstrip())


def _fit_plots(fit, out: Path) -> dict[str, str]:
    from rig.report.dyno_plots import plot_force_velocity, plot_loops
    from rig.report.plots import save_figure

    law = fit.chosen.law
    temperatures = ()
    if law.temperature:
        values = fit.test.joined("temperature")
        temperatures = (float(values.min()), float(values.max()))
    save_figure(plot_force_velocity(fit, temperatures), out / "force_velocity.png")
    fitted = [law.along(run) for run in fit.test.runs]
    save_figure(plot_loops(fit.test, fitted, f"fit ({law.name})"), out / "loops.png")
    plots = {"force_velocity": "force_velocity.png", "loops": "loops.png"}
    tests = [f.tests for f in _tested(fit) if f.tests is not None]
    if tests:
        from rig.report.residual_report import plot_residual_tests

        save_figure(plot_residual_tests(tests, "damper laws' residuals"), out / "residual_tests.png")
        plots["residual_tests"] = "residual_tests.png"
    return plots


def _tested(fit) -> list:
    """The laws whose residual tests are drawn: the chosen, the best static one and the best with dynamics."""
    best_static = next((f for f in fit.forms if not f.law.dynamic), None)
    best_dynamic = next((f for f in fit.forms if f.law.dynamic), None)
    return list({id(f): f for f in (fit.chosen, best_static, best_dynamic) if f is not None}.values())


def _vehicle_parts(args: argparse.Namespace, fit, out: Path, plots: dict[str, str]) -> dict:
    """``--simulate`` and ``--write``: the vehicle's damper beside the records, and the law written and checked."""
    from rig.report.dyno_plots import plot_loops
    from rig.report.plots import save_figure
    from rig.vehicle.vehicle_file import load_vehicle

    parts: dict = {}
    if not args.vehicle:
        return parts
    vehicle = load_vehicle(args.vehicle)
    if args.simulate:
        parts["simulated"], figure = _simulated(vehicle, args, fit)
        save_figure(figure, out / "vehicle_loops.png")
        plots["vehicle_loops"] = "vehicle_loops.png"
    if args.write:
        written, reproduced = _write(vehicle, args, fit)
        parts.update(written=written, written_path=args.write, reproduced=reproduced)
        save_figure(plot_loops(fit.test, [s.force for s in reproduced.simulated], f"{Path(args.write).name} (MuJoCo)",
                               "the written damper simulated on the dyno"), out / "written_loops.png")
        plots["written_loops"] = "written_loops.png"
        print(f"wrote {args.write}: {', '.join(written.sections)}; simulated on the dyno it is "
              f"{reproduced.law_rms_pct:.2f} % off the law, {reproduced.loop_rms_pct:.2f} % off the measured loops")
        for note in written.notes:
            print(f"note: {note}", file=sys.stderr)
    return parts


def _simulated(vehicle, args: argparse.Namespace, fit):
    import numpy as np

    from rig.report.dyno_plots import plot_loops
    from rig.sim.dyno import simulate_dyno

    sims = [simulate_dyno(vehicle, args.axle, run.displacement, run.rate, velocity=run.velocity,
                          motion_ratio=args.motion_ratio) for run in fit.test.runs]
    per_run = {run.name: round(float(100 * np.sqrt(np.mean((s.force - run.force) ** 2) / np.mean(run.force ** 2))), 4)
               for run, s in zip(fit.test.runs, sims, strict=True)}
    label = f"{vehicle.name} {args.axle} (MuJoCo)"
    summary = {"vehicle": vehicle.name, "axle": args.axle, "motion_ratio": args.motion_ratio,
               "rms_difference_pct": per_run,
               "meaning": "the vehicle file's damper simulated on the dyno with each record's displacement: RMS of "
                          "measured minus simulated force, in percent of the measured RMS"}
    print(f"simulated {label} on the dyno with each record's displacement:")
    print_table(("record", "RMS of measured minus simulated force, % of the measured RMS"),
                [(name, f"{value:.1f} %") for name, value in per_run.items()])
    return summary, plot_loops(fit.test, [s.force for s in sims], label)


def _write(vehicle, args: argparse.Namespace, fit):
    from rig.diagnosis.dyno.damper_in_vehicle import damper_in_vehicle, reproduction
    from rig.io.atomic import write_text_atomic
    from rig.vehicle.vehicle_file import load_vehicle, vehicle_to_toml

    law = fit.chosen.law
    speeds = (max(float(run.velocity.max()) for run in fit.test.runs),
              max(float(-run.velocity.min()) for run in fit.test.runs))
    written = damper_in_vehicle(vehicle, args.axle, law, args.motion_ratio, args.temperature, speeds)
    comment = (f"{vehicle.name} with the {args.axle} damper measured on a dynamometer (rig dyno: {law.name}, "
               f"motion ratio {args.motion_ratio:g})\n" + "\n".join(written.notes))
    write_text_atomic(args.write, vehicle_to_toml(written.vehicle, comment))
    written = dataclasses.replace(written, vehicle=load_vehicle(args.write))  # the file as a user loads it
    return written, reproduction(written, law, fit.test)
