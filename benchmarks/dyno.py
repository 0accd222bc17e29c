"""Damper dynamometer: coefficients recovered from generated records, the law chosen, the fit's time, and the
written vehicle file's damper simulated on the dyno.

Records of the generator written for the tests (tests/dyno_cases.py: sine tests at six speeds and triangle tests at
three, 25 mm, 1 kHz, 1 % noise on displacement and force, a 20 degC rise over the programme), one programme per
known law. Prints per law: the law chosen among all 40 by BIC, the largest coefficient error of the true law's fit,
the residual, the fit's wall time, and how the law written into proton_x's front axle (motion ratio 0.7)
reproduces the law and the measured loops on the simulated dyno. ``--plot PATH`` draws the README figure (the
force-velocity plot of the last law), ``--records DIR`` writes that law's records as CSV files to try ``rig dyno``.
Run: python benchmarks/dyno.py [--plot PATH] [--records DIR] [--laws NAME ...] [--seed 0]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from dyno_cases import LAWS, T_REF, dyno_records

from rig.diagnosis.dyno.damper_in_vehicle import damper_in_vehicle, reproduction
from rig.diagnosis.dyno.damper_choice import fit_damper
from rig.diagnosis.dyno.dyno_test import dyno_test
from rig.io.files import write_record
from rig.vehicle.vehicle_file import load_vehicle

MOTION_RATIO = 0.7


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--laws", nargs="+", default=list(LAWS), choices=list(LAWS))
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--plot", help="PNG of the last law's force-velocity fit (the README figure)")
    parser.add_argument("--records", help="folder to write the last law's records to, as CSV (displacement in mm)")
    args = parser.parse_args()
    print("| law | chosen | largest coefficient error | residual | fit time | written: law | written: loops |")
    print("|---|---|---|---|---|---|---|")
    for name in args.laws:
        records = dyno_records(LAWS[name], seed=args.seed)
        test = dyno_test(records)
        started = time.perf_counter()
        fit = fit_damper(test, reference_temperature=T_REF)
        elapsed = time.perf_counter() - started
        truth = fit.form(name)
        worst = max(abs(truth.law.coefficients[k] / v - 1) for k, v in LAWS[name].items())
        speeds = (max(r.velocity.max() for r in test.runs), max(-r.velocity.min() for r in test.runs))
        written = damper_in_vehicle(load_vehicle("proton_x"), "front", truth.law, MOTION_RATIO, speeds=speeds)
        check = reproduction(written, truth.law, test)
        print(f"| {name} | {fit.chosen.law.name} | {100 * worst:.2f} % | {truth.residual_rms_pct:.2f} % | "
              f"{elapsed:.1f} s | {check.law_rms_pct:.2f} % | {check.loop_rms_pct:.2f} % |")
    if args.records:
        for run_name, record in records:
            write_record(Path(args.records) / f"{run_name}.csv", record, units={"damper/displacement": "mm"})
        print(f"wrote {len(records)} records to {args.records}")
    if args.plot:
        from rig.report.dyno_plots import plot_force_velocity
        from rig.report.plots import save_figure

        temperature = test.joined("temperature")
        save_figure(plot_force_velocity(fit, (float(temperature.min()), float(temperature.max()))), args.plot)
        print(f"wrote {args.plot}")


if __name__ == "__main__":
    main()
