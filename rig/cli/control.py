"""``rig control``: a vehicle driven over a road under a suspension controller, its ride metrics, and with
``--sweep`` every controller placed against the passive comfort / road-holding front."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from rig.cli.options import NON_NEGATIVE, POSITIVE, add_rerun, add_vehicle, out_folder, review
from rig.cli.track import ROAD_HELP


def add_parser(commands: argparse._SubParsersAction) -> None:
    control = commands.add_parser("control", help="drive a vehicle over a road under a suspension controller")
    add_vehicle(control, "proton_x_quarter")
    control.add_argument("--road", metavar="SPEC", required=True, help=ROAD_HELP)
    control.add_argument("--speed", metavar="M_PER_S", required=True, type=POSITIVE, help="m/s")
    control.add_argument("--duration", metavar="S", type=POSITIVE,
                         help="s (default: until the front axle reaches the road's end)")
    control.add_argument("--controller", required=True, metavar="NAME[:k=v,...]",
                         help="passive, skyhook, skyhook_onoff, skyhook_active, groundhook, hybrid or lqr, with "
                              "parameters, e.g. passive:scale=0.7 or skyhook:c_sky=6000")
    control.add_argument("--out", type=out_folder, metavar="DIR", required=True,
                         help="output folder (record.csv, metrics.json, pareto.png)")
    control.add_argument("--rate", metavar="HZ", type=POSITIVE, default=512.0,
                         help="control and sample rate in Hz (default: %(default)s)")
    add_actuator_bounds(control)
    control.add_argument("--sweep", action="store_true",
                         help="also run the passive damper scaled 0.2-1.0 and every controller, and plot them "
                              "(pareto.png, sweep.json)")
    add_rerun(control)
    control.set_defaults(run=run)


def add_actuator_bounds(command: argparse.ArgumentParser) -> None:
    command.add_argument("--force-limit", metavar="N", type=POSITIVE, default=5000.0,
                         help="active force limit in N (default: %(default)s)")
    command.add_argument("--c-min", metavar="C", type=NON_NEGATIVE, default=1000.0,
                         help="semi-active damping minimum, N s/m (default: %(default)s)")
    command.add_argument("--c-max", metavar="C", type=POSITIVE, default=8000.0,
                         help="semi-active damping maximum, N s/m (default: %(default)s)")


def actuator_bounds(args: argparse.Namespace):
    from controllers.controlled_runs import ActuatorBounds

    return ActuatorBounds(args.force_limit, args.c_min, args.c_max)


def run(args: argparse.Namespace) -> int:
    from controllers.controlled_runs import compare_with_front, controlled_episode
    from rig.io.atomic import write_text_atomic
    from rig.io.files import write_record
    from rig.report.review_runs import present_control
    from rig.vehicle.vehicle_file import load_vehicle

    vehicle = load_vehicle(args.vehicle)
    env_kwargs = {"vehicle": vehicle, "road": args.road, "speed": args.speed, "duration": args.duration,
                  "rate": args.rate}
    bounds = actuator_bounds(args)
    run = controlled_episode(args.controller, bounds, env_kwargs)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    write_record(out / "record.csv", run.record)
    write_text_atomic(out / "metrics.json", json.dumps({**run.metrics, "controller": args.controller}, indent=2))
    m = run.metrics
    print(f"{args.controller}: a_w {m['a_w']:.3f} m/s², tyre load RMS {m['tyre_load_rms']:.3f} of "
          f"static, travel RMS {m['travel_rms'] * 1e3:.1f} mm, power {m['power_w']:.0f} W")
    written = ["record.csv", "metrics.json"]
    front = None
    if args.sweep:
        comparison = compare_with_front(args.controller, run, bounds, env_kwargs)
        written += _sweep(args, comparison, vehicle.name, out)
        front = comparison.below_front
    print(f"wrote {', '.join(written)} in {out.resolve()}")
    passive = None  # the recording's reference: the same car and road without the controller
    if (args.rerun or args.rerun_spawn) and args.controller != "passive":
        passive = controlled_episode("passive", bounds, env_kwargs)
    review(args, f"{vehicle.name} under {args.controller} over {args.road} at {args.speed:g} m/s",
           lambda rec: present_control(rec, run, args.controller, args.rerun_magnify, front, passive))
    return 0


def _sweep(args: argparse.Namespace, comparison, vehicle_name: str, out: Path) -> list[str]:
    """Print and write the controllers' places against the passive front; the files written."""
    from rig.io.atomic import write_text_atomic
    from rig.report.pareto_plot import plot_pareto
    from rig.report.plots import save_figure

    for name, reason in comparison.left_out.items():
        print(f"  {name}: left out ({reason})")
    for name, gain in comparison.below_front.items():
        where = "no passive setting holds the road as well" if gain is None else f"{100 * gain:+.1f} % below the front"
        metrics = comparison.metrics[name]
        print(f"  {name}: a_w {metrics['a_w']:.3f}, tyre load {metrics['tyre_load_rms']:.3f}: {where}")
    sweep = {"passive": [{"scale": p.scale, **p.metrics} for p in comparison.front],
             "controllers": {n: {**m, "below_front": comparison.below_front[n]} for n, m in comparison.metrics.items()}}
    write_text_atomic(out / "sweep.json", json.dumps(sweep, indent=2))
    save_figure(plot_pareto(comparison.front, comparison.metrics, f"{vehicle_name}, {args.road}, {args.speed:g} m/s",
                            highlight=args.controller), out / "pareto.png")
    return ["sweep.json", "pareto.png"]
