"""``rig sweep``: a design sweep or a Monte-Carlo of parameter scatter, locally or on Ray."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from rig.cli.control import actuator_bounds, add_actuator_bounds
from rig.cli.options import COUNT, POSITIVE, add_map, add_resample, add_vehicle, in_file, out_folder, read


def add_parser(commands: argparse._SubParsersAction) -> None:
    sweep = commands.add_parser("sweep", help="run a design sweep or a Monte-Carlo of parameter scatter, "
                                              "locally or on Ray")
    add_vehicle(sweep)
    sweep.add_argument("--road", metavar="SPEC", help="road spec as for 'rig track' (with --speed)")
    sweep.add_argument("--speed", metavar="M_PER_S", type=POSITIVE, help="m/s (with --road)")
    sweep.add_argument("--drive", metavar="D", type=in_file,
                       help="drive record to replay at every point (instead of --road)")
    sweep.add_argument("--duration", metavar="S", type=POSITIVE, help="s (default: the whole road or drive)")
    sweep.add_argument("--rate", metavar="HZ", type=POSITIVE, default=512.0,
                       help="road sample rate in Hz (default: %(default)s)")
    sweep.add_argument("--vary", nargs="+", action="extend", metavar="KEY=START:STOP[:COUNT]",
                       help="vehicle-file key (front.damping, sprung.mass) or speed: a grid of COUNT values, "
                            "or sampled uniformly with --samples")
    sweep.add_argument("--samples", metavar="N", type=COUNT,
                       help="draw N points (Latin hypercube or Monte-Carlo) instead of a grid")
    sweep.add_argument("--scatter", nargs="+", action="extend", metavar="KEY=PCT",
                       help="normal scatter of a key about its nominal value, standard deviation PCT %% "
                            "(with --samples)")
    sweep.add_argument("--sampling", choices=("lhs", "random"), default="lhs",
                       help="Latin hypercube or plain Monte-Carlo (default: %(default)s)")
    sweep.add_argument("--seed", metavar="S", type=int, default=0,
                       help="random seed of the samples (default: %(default)s)")
    sweep.add_argument("--measured", metavar="M", type=in_file,
                       help="measured record whose PSDs are drawn over the scatter band")
    sweep.add_argument("--controller", metavar="NAME[:k=v,...]", help="run every point under this controller "
                                                                       "(as 'rig control'; road only)")
    add_actuator_bounds(sweep)
    sweep.add_argument("--out", type=out_folder, metavar="DIR", required=True,
                       help="output folder (results.csv, results.parquet, plots, chunks/)")
    sweep.add_argument("--engine", choices=("local", "ray"), default="local",
                       help="local: chunks one after another, each a threaded rollout; ray: chunks as Ray tasks "
                            "(extra [scale]) (default: %(default)s)")
    sweep.add_argument("--address", metavar="ADDR",
                       help="Ray cluster to join ('auto', 'ray://HOST:10001'); default: a local Ray")
    sweep.add_argument("--num-cpus", metavar="N", type=COUNT, help="CPUs of the local Ray (default: all)")
    sweep.add_argument("--threads", metavar="N", type=COUNT, default=1,
                       help="rollout threads (and CPUs) per Ray task (default: 1)")
    sweep.add_argument("--chunk-size", metavar="N", type=COUNT, default=4,
                       help="points per chunk (default: %(default)s)")
    sweep.add_argument("--resume", action="store_true", help="reuse the finished chunks of this sweep in --out")
    sweep.add_argument("--quiet", action="store_true", help="no progress bar")
    add_resample(sweep)
    add_map(sweep)
    sweep.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from tqdm import tqdm

    from rig.road.roads import road_from_spec
    from rig.sweep.design import SweepError, make_design, nominal_value, parse_scatter, parse_vary, vehicle_tables
    from rig.sweep.evaluate import SweepCase
    from rig.sweep.run import run_sweep
    from rig.vehicle.vehicle_file import load_vehicle

    if (args.road is None) == (args.drive is None):
        raise SweepError("give either --road (with --speed) or --drive")
    if args.road and args.speed is None:
        raise SweepError("--road needs --speed (m/s; --vary speed=... then varies it)")
    if args.scatter and args.samples is None:
        raise SweepError("--scatter needs --samples N (the number of Monte-Carlo samples)")
    vehicle = load_vehicle(args.vehicle)
    tables = vehicle_tables(vehicle)
    vary = [parse_vary(v) for v in args.vary or []]
    scatter = [parse_scatter(s) for s in args.scatter or []]
    nominal = {key: nominal_value(tables, key, args.speed if args.road else None)
               for key in [f.key for f in vary] + [k for k, _ in scatter]}
    design = make_design(vary, scatter, nominal, args.samples, args.sampling, args.seed)
    case = SweepCase(tables, road_from_spec(args.road) if args.road else None, args.speed if args.road else None,
                     read(args, args.drive) if args.drive else None, args.duration, args.rate,
                     *_controller(args), psd=args.samples is not None or args.measured is not None)
    with tqdm(total=design.n_points, desc="sweep", unit="point", disable=args.quiet, leave=False) as bar:
        result = run_sweep(case, design, args.out, _engine(args), args.chunk_size, args.resume, bar.update)
    written = _present(args, result, vehicle.name, Path(args.out))
    reused = f", {result.chunks_reused} chunk(s) reused" if result.chunks_reused else ""
    print(f"{design.n_points} points ({design.kind}) in {result.chunks_run + result.chunks_reused} chunk(s){reused}; "
          f"a_w {result.column('a_w').min():.3f}-{result.column('a_w').max():.3f} m/s²")
    print(f"wrote {', '.join(written)} in {Path(args.out).resolve()}")
    return 0


def _controller(args: argparse.Namespace) -> tuple:
    """The sweep points' controller (``--controller``) and its description, or (None, "")."""
    if not args.controller:
        return None, ""
    import functools

    from controllers import ControllerError
    from controllers.controlled_runs import sweep_episode
    from controllers.suspension_laws import parse_controller

    try:
        parse_controller(args.controller)
    except ValueError as err:
        raise ControllerError(str(err)) from None
    bounds = actuator_bounds(args)
    return functools.partial(sweep_episode, args.controller, bounds), repr((args.controller, bounds))


def _engine(args: argparse.Namespace):
    """The engine ``--engine`` names (Ray imported only here, when asked for)."""
    from rig.sweep.design import SweepError

    if args.engine == "local":
        if args.address:
            raise SweepError("--address joins a Ray cluster: use it with --engine ray")
        return None
    from rig.sweep.ray_engine import RayEngine

    return RayEngine(address=args.address, num_cpus=args.num_cpus, threads=args.threads)


def _present(args: argparse.Namespace, result, vehicle_name: str, out: Path) -> list[str]:
    """The table, the plots and the measured record's place in the scatter band; the files written."""
    from rig.io.atomic import write_text_atomic
    from rig.report.plots import save_figure
    from rig.report.sweep_plots import plot_psd_band, plot_response_surfaces, plot_sweep_pareto
    from rig.sweep.evaluate import channel_psds
    from rig.sweep.design import SweepError
    from rig.sweep.results import band_coverage, write_parquet, write_table

    write_table(result, out / "results.csv")
    written = ["results.csv"] + (["results.parquet"] if write_parquet(result, out / "results.parquet") else [])
    what = f"drive {args.drive}"
    if args.road:
        speeds = result.column("speed") if "speed" in result.design.keys else [args.speed]
        at = f"{min(speeds):g} m/s" if min(speeds) == max(speeds) else f"{min(speeds):g}-{max(speeds):g} m/s"
        what = f"{args.road} at {at}"
    title = f"{vehicle_name}, {what}" + (f", {args.controller}" if args.controller else "")
    if result.design.keys:
        save_figure(plot_response_surfaces(result, title), out / "response_surfaces.png")
        save_figure(plot_sweep_pareto(result, title), out / "pareto.png")
        written += ["response_surfaces.png", "pareto.png"]
    if result.psd_band is None:
        return written
    measured = None
    if args.measured:
        record = read(args, args.measured)
        common = tuple(c for c in result.psd_band.channels if c in record)
        if not common:
            raise SweepError(f"{args.measured} has none of the channels {', '.join(result.psd_band.channels)}")
        frequency, psd = channel_psds(record, common)
        measured = {c: (frequency, p) for c, p in zip(common, psd)}
    save_figure(plot_psd_band(result.psd_band, measured, title), out / "psd_band.png")
    written.append("psd_band.png")
    if measured:
        coverage = band_coverage(result.psd_band, measured)
        write_text_atomic(out / "scatter.json", json.dumps({"measured_inside_band": coverage}, indent=2))
        written.append("scatter.json")
        print("measured PSD inside the simulated 5-95 % band: "
              + ", ".join(f"{c} {100 * v:.0f} %" for c, v in coverage.items()) + " of the frequencies")
    return written
