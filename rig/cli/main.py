"""The ``rig`` command line (DESIGN.md contract for commands and options)."""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Callable
from pathlib import Path
from types import ModuleType

from rig.cli import dyno
from rig.io.record import Record as RecordType
from rig.io.record import RecordError
from rig.io.units import UnitError
from rig.road.roads import RoadError
from rig.sim.drive_limits import DriveLimitError
from rig.sim.simulate import SimulationError
from rig.sweep.design import SweepError
from rig.vehicle.statics import EquilibriumError
from rig.vehicle.vehicle_file import VehicleError, load_vehicle


class ControlError(ValueError):
    """A controller or environment argument of ``rig control`` that cannot be used."""


#: Errors that mean bad input: reported in one line, exit status 2, no traceback.
USER_ERRORS = (RecordError, VehicleError, DriveLimitError, SimulationError, EquilibriumError, UnitError, RoadError,
               ControlError, SweepError, FileNotFoundError, PermissionError, IsADirectoryError)


def main(argv: list[str] | None = None) -> int:
    parser = _parser()
    args = parser.parse_args(argv)
    try:
        return args.run(args)
    except USER_ERRORS as err:
        print(f"rig {args.command}: error: {err}", file=sys.stderr)
        return 2


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="rig", description="Virtual four-poster test rig")
    commands = parser.add_subparsers(dest="command", required=True)

    demo = commands.add_parser("demo", help="the whole story on built-in data: iterate, miss on the real car, "
                                            "diagnose, extend, iterate again (a few minutes)")
    demo.add_argument("--out", default="rig_demo_output", help="output folder (default: %(default)s)")
    demo.add_argument("--quick", action="store_true",
                      help="only replay a built-in broadband drive on proton_x and plot it (seconds)")
    demo.add_argument("--duration", type=float, default=20.0, help="--quick drive length in s (default: %(default)s)")
    _add_rerun_options(demo)
    demo.set_defaults(run=_demo)

    causes = commands.add_parser("causes", help="list the causes the diagnosis knows, with their vehicle-file keys")
    causes.set_defaults(run=_causes)

    model = commands.add_parser("model", help="write the assembled MJCF model of a vehicle on the rig")
    model.add_argument("--vehicle", required=True, help="built-in name (proton_x) or vehicle file")
    model.add_argument("--export", required=True, help="output .xml, loadable in MuJoCo's viewer")
    model.add_argument("--posts", choices=("servo", "ideal"), default="servo")
    model.set_defaults(run=_model)

    replay = commands.add_parser("replay", help="replay drive (or measured post displacement) channels")
    replay.add_argument("--vehicle", required=True, help="built-in name (proton_x) or vehicle file")
    replay.add_argument("--drive", required=True, help="record with <corner>/drive or <corner>/actuator_disp")
    replay.add_argument("--out", required=True, help="response record (.csv, RPC III .rsp or MDF .mf4)")
    replay.add_argument("--clip", action="store_true", help="clip a drive beyond the post limits and report it")
    replay.add_argument("--plot", help="also write a PNG of the responses")
    _add_resample_option(replay)
    _add_map_option(replay)
    _add_rerun_options(replay)
    replay.set_defaults(run=_replay)

    track = commands.add_parser("track", help="drive a vehicle over a road at constant speed")
    track.add_argument("--vehicle", required=True, help="built-in name (proton_x) or vehicle file")
    track.add_argument("--road", required=True,
                       help="road spec (iso8608:class=C,length=500 | bar:sides=right | plywood | sweep | step | "
                            "crg:path=F.crg | profile:path=F.txt) or a .crg / profile file")
    track.add_argument("--speed", required=True, type=float, help="m/s")
    track.add_argument("--duration", type=float, help="s (default: until the front axle reaches the road's end)")
    track.add_argument("--out", required=True, help="record (.csv, RPC III .rsp or MDF .mf4)")
    track.add_argument("--rate", type=float, default=512.0, help="sample rate in Hz (default: %(default)s)")
    track.add_argument("--envelope", type=float, default=0.0, help="tyre-enveloping moving-average base in m")
    track.add_argument("--rolling-radius", nargs="+", metavar="M|CORNER=M",
                       help="rolling radius of the wheels in m, one for all or per corner (FL=0.2978 FR=0.2985 ...; "
                            "default: the vehicle's tyre): each wheel's angle turns at speed / radius")
    track.add_argument("--plot", help="also write a PNG of the responses")
    _add_rerun_options(track)
    track.set_defaults(run=_track)

    control = commands.add_parser("control", help="drive a vehicle over a road under a suspension controller")
    control.add_argument("--vehicle", required=True, help="built-in name (proton_x_quarter) or vehicle file")
    control.add_argument("--road", required=True, help="road spec as for 'rig track' (iso8608:class=C,length=500 ...)")
    control.add_argument("--speed", required=True, type=float, help="m/s")
    control.add_argument("--duration", type=float, help="s (default: until the front axle reaches the road's end)")
    control.add_argument("--controller", required=True, metavar="NAME[:k=v,...]",
                         help="passive, skyhook, skyhook_onoff, skyhook_active, groundhook, hybrid or lqr, with "
                              "parameters, e.g. passive:scale=0.7 or skyhook:c_sky=6000")
    control.add_argument("--out", required=True, help="output folder (record.csv, metrics.json, pareto.png)")
    control.add_argument("--rate", type=float, default=512.0, help="control and sample rate in Hz (default: %(default)s)")
    control.add_argument("--force-limit", type=float, default=5000.0, help="active force limit in N (default: %(default)s)")
    control.add_argument("--c-min", type=float, default=1000.0, help="semi-active damping minimum, N s/m (default: %(default)s)")
    control.add_argument("--c-max", type=float, default=8000.0, help="semi-active damping maximum, N s/m (default: %(default)s)")
    control.add_argument("--sweep", action="store_true",
                         help="also run the passive damper scaled 0.2-1.0 and every controller, and plot them "
                              "(pareto.png, sweep.json)")
    _add_rerun_options(control)
    control.set_defaults(run=_control)

    sweep = commands.add_parser("sweep", help="run a design sweep or a Monte-Carlo of parameter scatter, "
                                              "locally or on Ray")
    sweep.add_argument("--vehicle", required=True, help="built-in name (proton_x) or vehicle file")
    sweep.add_argument("--road", help="road spec as for 'rig track' (with --speed)")
    sweep.add_argument("--speed", type=float, help="m/s (with --road)")
    sweep.add_argument("--drive", help="drive record to replay at every point (instead of --road)")
    sweep.add_argument("--duration", type=float, help="s (default: the whole road or drive)")
    sweep.add_argument("--rate", type=float, default=512.0, help="road sample rate in Hz (default: %(default)s)")
    sweep.add_argument("--vary", nargs="+", action="extend", metavar="KEY=START:STOP[:COUNT]",
                       help="vehicle-file key (front.damping, sprung.mass) or speed: a grid of COUNT values, "
                            "or sampled uniformly with --samples")
    sweep.add_argument("--samples", type=int, help="draw N points (Latin hypercube or Monte-Carlo) instead of a grid")
    sweep.add_argument("--scatter", nargs="+", action="extend", metavar="KEY=PCT",
                       help="normal scatter of a key about its nominal value, standard deviation PCT %% "
                            "(with --samples)")
    sweep.add_argument("--sampling", choices=("lhs", "random"), default="lhs",
                       help="Latin hypercube or plain Monte-Carlo (default: %(default)s)")
    sweep.add_argument("--seed", type=int, default=0, help="random seed of the samples (default: %(default)s)")
    sweep.add_argument("--measured", help="measured record whose PSDs are drawn over the scatter band")
    sweep.add_argument("--controller", metavar="NAME[:k=v,...]", help="run every point under this controller "
                                                                       "(as 'rig control'; road only)")
    sweep.add_argument("--force-limit", type=float, default=5000.0, help="active force limit in N (default: 5000)")
    sweep.add_argument("--c-min", type=float, default=1000.0, help="semi-active damping minimum, N s/m (default: 1000)")
    sweep.add_argument("--c-max", type=float, default=8000.0, help="semi-active damping maximum, N s/m (default: 8000)")
    sweep.add_argument("--out", required=True, help="output folder (results.csv, results.parquet, plots, chunks/)")
    sweep.add_argument("--engine", choices=("local", "ray"), default="local",
                       help="local: chunks one after another, each a threaded rollout; ray: chunks as Ray tasks "
                            "(extra [scale]) (default: %(default)s)")
    sweep.add_argument("--address", help="Ray cluster to join ('auto', 'ray://HOST:10001'); default: a local Ray")
    sweep.add_argument("--num-cpus", type=int, help="CPUs of the local Ray (default: all)")
    sweep.add_argument("--threads", type=int, default=1, help="rollout threads (and CPUs) per Ray task (default: 1)")
    sweep.add_argument("--chunk-size", type=int, default=4, help="points per chunk (default: %(default)s)")
    sweep.add_argument("--resume", action="store_true", help="reuse the finished chunks of this sweep in --out")
    sweep.add_argument("--quiet", action="store_true", help="no progress bar")
    _add_resample_option(sweep)
    _add_map_option(sweep)
    sweep.set_defaults(run=_sweep)

    iterate = commands.add_parser("iterate", help="iterate post drives until the rig reproduces a target record")
    iterate.add_argument("--vehicle", required=True, help="built-in name (proton_x) or vehicle file")
    iterate.add_argument("--target", required=True, help="target record (.csv, RPC III .rsp, MDF .mf4, TDMS .tdms)")
    iterate.add_argument("--out", required=True, help="output folder (history.json, drive.csv, drive.drv, plots)")
    iterate.add_argument("--iterations", type=int, default=8, help="most iterations (default: %(default)s)")
    iterate.add_argument("--channels", nargs="+",
                         help="target channels to reproduce (default: every sprung_acc and unsprung_acc channel)")
    iterate.add_argument("--scheme", choices=("adaptive", "seed002"), default="adaptive")
    iterate.add_argument("--target-error", type=float, default=3.0, help="stop at this RMS error %% (default: 3)")
    iterate.add_argument("--initial", default="frf", metavar="{frf,narx,inverse-model,FILE}",
                         help="first drive: the one-shot FRF inverse (default), an estimate (rig estimate-drive's "
                              "methods) or a drive record")
    iterate.add_argument("--train", help="measured drive/response record: the FRF's identification (instead of a run "
                                         "on the virtual rig) and the NARX's training data")
    iterate.add_argument("--resume", action="store_true", help="continue the run saved in --out")
    iterate.add_argument("--quiet", action="store_true", help="no progress bar")
    _add_resample_option(iterate)
    _add_map_option(iterate)
    _add_rerun_options(iterate)
    iterate.set_defaults(run=_iterate)

    estimate = commands.add_parser("estimate-drive", help="estimate post drives straight from a measured response "
                                                          "(seed 002: inverse model, FRF inverse, NARX)")
    estimate.add_argument("--vehicle", required=True, help="built-in name (proton_x) or vehicle file")
    estimate.add_argument("--target", required=True, help="target record with body and wheel accelerations")
    estimate.add_argument("--method", required=True, choices=("inverse-model", "frf", "narx"))
    estimate.add_argument("--train", help="measured drive/response record: the FRF's H1 or the NARX's training data "
                                          "(default: an identification run of the virtual rig)")
    estimate.add_argument("--out", required=True, help="drive record (.csv, RPC III .drv, MDF .mf4)")
    estimate.add_argument("--quiet", action="store_true", help="no progress lines")
    _add_resample_option(estimate)
    _add_map_option(estimate)
    estimate.set_defaults(run=_estimate_drive)

    validate = commands.add_parser("validate", help="compare a measured rig test with the model's simulation of it")
    validate.add_argument("--vehicle", required=True, help="built-in name (proton_x) or vehicle file")
    validate.add_argument("--measured", required=True, help="measured rig record (actuator_disp, responses, drive)")
    validate.add_argument("--out", default="validation", help="output folder (default: %(default)s)")
    _add_resample_option(validate)
    _add_map_option(validate)
    validate.set_defaults(run=_validate)

    diagnose = commands.add_parser("diagnose", help="name the cause of the model's discrepancy, extend the model")
    diagnose.add_argument("--vehicle", required=True, help="built-in name (proton_x) or vehicle file")
    diagnose.add_argument("--measured", required=True, nargs="+",
                          help="measured record to fit: a rig test, or track tests (one or more constant speeds)")
    diagnose.add_argument("--holdout", help="held-out record to score on (default: the last third of --measured)")
    diagnose.add_argument("--out", required=True, help="output folder (diagnosis.json, vehicle_extended.toml, report)")
    _add_resample_option(diagnose)
    _add_map_option(diagnose)
    _add_rerun_options(diagnose)
    diagnose.set_defaults(run=_diagnose)
    dyno.add_parser(commands)
    return parser


def _add_resample_option(command: argparse.ArgumentParser) -> None:
    command.add_argument("--resample", action="store_true",
                         help="interpolate a log with irregular time stamps (a CSV time column, an MDF group, "
                              "a TDMS time channel) onto a uniform grid (rounded stamps need no option)")


def _add_map_option(command: argparse.ArgumentParser) -> None:
    command.add_argument("--map", nargs="+", metavar="MAP.toml|FROM=TO",
                         help="read the records through a channel map: a TOML file ([channels] \"DAQ name\" = "
                              "\"FL/sprung_acc\" or {name, unit, scale}) or FROM=TO pairs, FROM a channel name "
                              "or a unique part of one (e.g. LF_=FL/unsprung_acc); unmapped channels are ignored")


def _read(args: argparse.Namespace, path: str) -> RecordType:
    """Read a record as ``--resample`` and ``--map`` allow, saying what was resampled and what was left out."""
    from rig.io.channel_map import map_from_option
    from rig.io.files import read_record

    record = read_record(path, resample=args.resample, channel_map=map_from_option(args.map))
    for key in ("resampled", "unmapped"):
        if key in record.metadata:
            print(f"{path}: {key}: {record.metadata[key]}", file=sys.stderr)
    return record


def _add_rerun_options(command: argparse.ArgumentParser) -> None:
    command.add_argument("--rerun", metavar="FILE.rrd", help="also write a Rerun recording (open it: rerun FILE.rrd)")
    command.add_argument("--rerun-spawn", action="store_true", help="also stream the run to a new Rerun viewer")


def _review(args: argparse.Namespace, corners: tuple[str, ...], log: Callable[[ModuleType, object], None],
            iteration_channels: list[str] | tuple[str, ...] = ()) -> None:
    """Open the recording that ``--rerun`` / ``--rerun-spawn`` ask for, if any, and ``log(rig.review, stream)``."""
    if not (args.rerun or args.rerun_spawn):
        return
    from rig.report import review

    blueprint = review.default_blueprint(corners, iteration_channels)
    with review.recording(args.rerun, args.rerun_spawn, blueprint) as stream:
        log(review, stream)
    if args.rerun:
        print(f"wrote {args.rerun} (open it with: rerun {args.rerun})")


def _demo(args: argparse.Namespace) -> int:
    from rig.cli.demo import run_demo, run_story

    if args.quick:
        files = run_demo(args.out, duration=args.duration, rerun=args.rerun, rerun_spawn=args.rerun_spawn)
        print(f"wrote {', '.join(p.name for p in files.values())} in {Path(args.out).resolve()}")
    else:
        errors = run_story(args.out, rerun=args.rerun, rerun_spawn=args.rerun_spawn)
        print(f"played on the real car, the worst channel's RMS error went from {errors['worst_error_before_pct']:.1f} % "
              f"(drive iterated on the baseline model) to {errors['worst_error_after_pct']:.1f} % (extended model)")
        print(f"report: {Path(args.out).resolve() / 'diagnosis' / 'report.md'}")
    if args.rerun:
        print(f"wrote {args.rerun} (open it with: rerun {args.rerun})")
    return 0


def _causes(args: argparse.Namespace) -> int:
    from rig.causes import CAUSES

    for name, cause in CAUSES.items():
        print(f"{name} ({cause.subsystem}): {cause.meaning}")
        for key, unit, low, high, meaning in cause.parameters():
            span = "" if math.isnan(low) else f" {low:g}..{high:g}"  # a choice (a corner) has no range
            print(f"    {key} [{unit}]{span}: {meaning}")
    return 0


def _model(args: argparse.Namespace) -> int:
    from rig.io.atomic import write_text_atomic
    from rig.vehicle.statics import settled_mjcf

    vehicle = load_vehicle(args.vehicle)
    xml, dofs = settled_mjcf(vehicle, args.posts)
    write_text_atomic(args.export, xml)
    print(f"wrote {args.export}: {vehicle.name} on the four-poster ({args.posts} posts), "
          f"{dofs} DOF; keyframe 'static_ride_height' is the settled state")
    return 0


def _replay(args: argparse.Namespace) -> int:
    from rig.io.files import write_record
    from rig.report.plots import plot_responses
    from rig.sim.replay import replay

    vehicle = load_vehicle(args.vehicle)
    drive = _read(args, args.drive)
    result = replay(vehicle, drive, clip=args.clip)
    for hit in result.limit_hits:
        print(f"clipped: {hit.describe()}", file=sys.stderr)
    airborne = {c: t for c, t in result.airborne_time().items() if t > 0}
    if airborne:
        print("tyres left the ground: " + ", ".join(f"{c} {t:.3f} s" for c, t in airborne.items()))
    write_record(args.out, result.record)
    if args.plot:
        plot_responses(result.record, args.plot)
    print(f"wrote {args.out}: {len(result.record.names)} channels, {result.record.duration:.1f} s at "
          f"{result.record.rate:g} Hz ({result.record.metadata['posts']} posts)")
    _review(args, vehicle.corners, lambda review, stream: review.log_replay(stream, result))
    return 0


def _track(args: argparse.Namespace) -> int:
    from rig.io.files import write_record
    from rig.report.plots import plot_responses
    from rig.road.roads import road_from_spec
    from rig.signal.comfort import comfort_summary
    from rig.sim.track import track_run

    vehicle = load_vehicle(args.vehicle)
    road = road_from_spec(args.road)
    result = track_run(vehicle, road, args.speed, args.duration, args.rate, args.envelope,
                       rolling_radius=_rolling_radius(args.rolling_radius))
    record = result.record
    airborne = {c: t for c, t in result.airborne_time().items() if t > 0}
    if airborne:
        print("tyres left the ground: " + ", ".join(f"{c} {t:.3f} s" for c, t in airborne.items()))
    comfort = comfort_summary(record)
    print("ISO 2631-1 Wk-weighted RMS of body acceleration: "
          + ", ".join(f"{name.split('/')[0]} {value:.3f} m/s²" for name, value in comfort.items()))
    write_record(args.out, record)
    if args.plot:
        plot_responses(record, args.plot)
    print(f"wrote {args.out}: {record.duration:.1f} s at {args.speed:g} m/s over {road.provenance}")
    _review(args, vehicle.corners, lambda review, stream: review.log_replay(stream, result))
    return 0


def _rolling_radius(items: list[str] | None) -> float | dict[str, float] | None:
    """``--rolling-radius``: one radius in m, or CORNER=M pairs."""
    if not items:
        return None
    try:
        if len(items) == 1 and "=" not in items[0]:
            return float(items[0])
        pairs = [item.split("=", 1) for item in items]
        if any(len(p) != 2 for p in pairs):
            raise ValueError
        return {corner: float(value) for corner, value in pairs}
    except ValueError:
        raise RoadError(f"--rolling-radius takes one radius in m or CORNER=M pairs, got {' '.join(items)}") from None


def _control(args: argparse.Namespace) -> int:
    import json

    from controllers.suspension import CONTROLLERS
    from rig.envs.pareto import below_front, passive_front
    from rig.io.atomic import write_text_atomic
    from rig.io.files import write_record
    from rig.report.pareto_plot import plot_pareto

    vehicle = load_vehicle(args.vehicle)
    env_kwargs = {"vehicle": vehicle, "road": args.road, "speed": args.speed, "duration": args.duration, "rate": args.rate}
    run = _controlled_run(args.controller, args, env_kwargs)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    write_record(out / "record.csv", run.record)
    write_text_atomic(out / "metrics.json", json.dumps({**run.metrics, "controller": args.controller}, indent=2))
    print(f"{args.controller}: a_w {run.metrics['a_w']:.3f} m/s², tyre load RMS {run.metrics['tyre_load_rms']:.3f} of "
          f"static, travel RMS {run.metrics['travel_rms'] * 1e3:.1f} mm, power {run.metrics['power_w']:.0f} W")
    written = ["record.csv", "metrics.json"]
    if args.sweep:
        front = passive_front(**env_kwargs)
        placed = {}
        for name in CONTROLLERS:
            if name == "passive":
                continue
            try:
                placed[name] = _controlled_run(name, args, env_kwargs).metrics
            except ControlError as err:  # e.g. the LQR, designed for quarter cars only
                print(f"  {name}: left out ({err})")
        placed[args.controller] = run.metrics
        gains = {name: below_front(front, m) for name, m in placed.items()}
        for name, gain in gains.items():
            where = "no passive setting holds the road as well" if gain is None else f"{100 * gain:+.1f} % below the front"
            print(f"  {name}: a_w {placed[name]['a_w']:.3f}, tyre load {placed[name]['tyre_load_rms']:.3f}: {where}")
        sweep = {"passive": [{"scale": p.scale, **p.metrics} for p in front],
                 "controllers": {n: {**m, "below_front": gains[n]} for n, m in placed.items()}}
        write_text_atomic(out / "sweep.json", json.dumps(sweep, indent=2))
        plot_pareto(front, placed, out / "pareto.png", f"{vehicle.name}, {args.road}, {args.speed:g} m/s",
                    highlight=args.controller)
        written += ["sweep.json", "pareto.png"]
    print(f"wrote {', '.join(written)} in {out.resolve()}")
    _review(args, vehicle.corners, lambda review, stream: review.log_record(stream, run.record))
    return 0


def _controlled_run(spec: str, args: argparse.Namespace, env_kwargs: dict):
    """One episode of ``spec``'s environment (active or semi-active, as the controller needs) under it."""
    return _controlled_episode(spec, args.force_limit, args.c_min, args.c_max, env_kwargs)


def _controlled_episode(spec: str, force_limit: float, c_min: float, c_max: float, env_kwargs: dict):
    """``_controlled_run`` with the actuator bounds given (N; N s/m): a plain function, for sweep workers."""
    from controllers.suspension import make_controller, needs
    from rig.envs.policy_run import run_policy
    from rig.envs.suspension import ActiveSuspensionEnv, SemiActiveSuspensionEnv

    try:
        if needs(spec) == "force":
            env = ActiveSuspensionEnv(force_limit=force_limit, physical_actions=True, **env_kwargs)
        else:
            env = SemiActiveSuspensionEnv(c_min=c_min, c_max=c_max, physical_actions=True, **env_kwargs)
        controller = make_controller(spec, env)
    except ValueError as err:  # bad controller, bounds or road: one line
        raise ControlError(str(err)) from None
    controller.reset()
    metadata = {"vehicle": env_kwargs["vehicle"].name, "test": "track", "speed": f"{env_kwargs['speed']:g} m/s",
                "road": getattr(env_kwargs["road"], "provenance", env_kwargs["road"]), "controller": spec}
    return run_policy(env, controller, metadata)


def _sweep_episode(spec: str, force_limit: float, c_min: float, c_max: float, vehicle, road, speed: float,
                   duration: float | None, rate: float):
    """A sweep point under a controller: its metrics and record (rig/sweep/evaluate.py's ``controller``)."""
    env_kwargs = {"vehicle": vehicle, "road": road, "speed": speed, "duration": duration, "rate": rate}
    run = _controlled_episode(spec, force_limit, c_min, c_max, env_kwargs)
    return run.metrics, run.record


def _sweep(args: argparse.Namespace) -> int:
    import functools
    import json

    from rig.io.atomic import write_text_atomic
    from rig.report.sweep_plots import plot_psd_band, plot_response_surfaces, plot_sweep_pareto
    from rig.road.roads import road_from_spec
    from rig.sweep.design import make_design, nominal_value, parse_scatter, parse_vary, vehicle_tables
    from rig.sweep.evaluate import SweepCase, channel_psds
    from rig.sweep.results import band_coverage, write_parquet, write_table
    from rig.sweep.run import run_sweep

    if (args.road is None) == (args.drive is None):
        raise SweepError("give either --road (with --speed) or --drive")
    if args.road and args.speed is None:
        raise SweepError("--road needs --speed (m/s; --vary speed=... then varies it)")
    vehicle = load_vehicle(args.vehicle)
    tables = vehicle_tables(vehicle)
    vary = [parse_vary(v) for v in args.vary or []]
    scatter = [parse_scatter(s) for s in args.scatter or []]
    nominal = {key: nominal_value(tables, key, args.speed if args.road else None)
               for key in [f.key for f in vary] + [k for k, _ in scatter]}
    design = make_design(vary, scatter, nominal, args.samples, args.sampling, args.seed)
    controller = None
    if args.controller:
        from controllers.suspension import parse_controller

        try:
            parse_controller(args.controller)
        except ValueError as err:
            raise ControlError(str(err)) from None
        controller = functools.partial(_sweep_episode, args.controller, args.force_limit, args.c_min, args.c_max)
    case = SweepCase(tables, road_from_spec(args.road) if args.road else None, args.speed if args.road else None,
                     _read(args, args.drive) if args.drive else None, args.duration, args.rate, controller,
                     psd=args.samples is not None or args.measured is not None)
    engine = _sweep_engine(args)
    from tqdm import tqdm

    with tqdm(total=design.n_points, desc="sweep", unit="point", disable=args.quiet, leave=False) as bar:
        result = run_sweep(case, design, args.out, engine, args.chunk_size, args.resume, bar.update)
    out = Path(args.out)
    write_table(result, out / "results.csv")
    written = ["results.csv"] + (["results.parquet"] if write_parquet(result, out / "results.parquet") else [])
    what = f"drive {args.drive}"
    if args.road:
        speeds = result.column("speed") if "speed" in design.keys else [args.speed]
        at = f"{min(speeds):g} m/s" if min(speeds) == max(speeds) else f"{min(speeds):g}-{max(speeds):g} m/s"
        what = f"{args.road} at {at}"
    title = f"{vehicle.name}, {what}" + (f", {args.controller}" if args.controller else "")
    if result.design.keys:
        plot_response_surfaces(result, out / "response_surfaces.png", title)
        plot_sweep_pareto(result, out / "pareto.png", title)
        written += ["response_surfaces.png", "pareto.png"]
    if result.psd_band is not None:
        measured = None
        if args.measured:
            record = _read(args, args.measured)
            common = tuple(c for c in result.psd_band.channels if c in record)
            if not common:
                raise SweepError(f"{args.measured} has none of the channels {', '.join(result.psd_band.channels)}")
            frequency, psd = channel_psds(record, common)
            measured = {c: (frequency, p) for c, p in zip(common, psd)}
        plot_psd_band(result.psd_band, out / "psd_band.png", measured, title)
        written.append("psd_band.png")
        if measured:
            coverage = band_coverage(result.psd_band, measured)
            write_text_atomic(out / "scatter.json", json.dumps({"measured_inside_band": coverage}, indent=2))
            written.append("scatter.json")
            print("measured PSD inside the simulated 5-95 % band: "
                  + ", ".join(f"{c} {100 * v:.0f} %" for c, v in coverage.items()) + " of the frequencies")
    reused = f", {result.chunks_reused} chunk(s) reused" if result.chunks_reused else ""
    print(f"{design.n_points} points ({design.kind}) in {result.chunks_run + result.chunks_reused} chunk(s){reused}; "
          f"a_w {result.column('a_w').min():.3f}-{result.column('a_w').max():.3f} m/s²")
    print(f"wrote {', '.join(written)} in {out.resolve()}")
    return 0


def _sweep_engine(args: argparse.Namespace):
    """The engine ``--engine`` names (Ray imported only here, when asked for)."""
    if args.engine == "local":
        if args.address:
            raise SweepError("--address joins a Ray cluster: use it with --engine ray")
        return None
    from rig.sweep.ray_engine import RayEngine

    return RayEngine(address=args.address, num_cpus=args.num_cpus, threads=args.threads)


def _iterate(args: argparse.Namespace) -> int:
    from controllers.rpc import DriveIteration, IterationSettings
    from rig.report.plots import IterationPlots

    vehicle = load_vehicle(args.vehicle)
    target = _read(args, args.target)
    channels = args.channels or [n for n in target.names if n.split("/")[0] in vehicle.corners
                                 and n.split("/")[-1] in ("sprung_acc", "unsprung_acc")]
    missing = [n for n in channels if n not in target]
    if not channels or missing:
        raise RecordError(f"target has no channel(s) {', '.join(missing) or 'sprung_acc/unsprung_acc'} "
                          f"(it has: {', '.join(target.names)}); use --channels or --map")
    settings = IterationSettings(scheme=args.scheme, iterations=args.iterations, target_error_pct=args.target_error)
    train = _read(args, args.train) if args.train else None
    initial = None
    if args.initial != "frf" and not args.resume:
        initial = _initial_drive(args, vehicle, target, train)
    job = DriveIteration(vehicle, target, channels, args.out, settings, initial=initial, identification=train)
    callbacks = [IterationPlots(args.out, f"{vehicle.name}: {settings.scheme} drive iteration", job.target, job.span,
                                job.rate, channels)]
    if args.rerun or args.rerun_spawn:
        from rig.report.review import IterationLog

        callbacks.append(IterationLog())

    def each(step) -> None:
        for callback in callbacks:
            callback(step)

    result = job.run(resume=args.resume, progress=not args.quiet, callback=each)
    best = result.best
    print(f"{result.stop_reason}; best iteration {best.iteration}: worst channel {best.worst_rms_error_pct:.2f} % "
          f"RMS error (" + ", ".join(f"{n} {m['rms_error_pct']:.2f}" for n, m in best.channels.items()) + ")")
    if best.road_recovery_rms_error_pct is not None:
        print("road recovery, RMS error of the post motion against the road: " + "; ".join(
            f"{c} " + ", ".join(f"{e:.1f} % ({band})" for band, e in parts.items())
            for c, parts in best.road_recovery_rms_error_pct.items()))
    print(f"wrote {args.out}/drive.csv, drive.drv, history.json, convergence.png")

    _review(args, vehicle.corners, lambda review, stream: review.log_drive_iteration(
        stream, result, callbacks[-1], job.target, float(job.time[0]), channels, settings.band, job.target_record),
        channels)
    return 0


def _initial_drive(args: argparse.Namespace, vehicle, target: RecordType, train: RecordType | None) -> RecordType:
    """The first drive ``--initial`` names: an estimate of rig estimate-drive's methods, or a drive record."""
    from controllers.drive_estimation import METHODS, estimate_drive

    if args.initial in METHODS:
        estimate = estimate_drive(vehicle, target, args.initial, train, progress=None if args.quiet else _progress_line)
        print(f"initial drive: {estimate.detail}")
        return estimate.drive
    if not Path(args.initial).is_file():
        raise RecordError(f"--initial must be frf, narx, inverse-model or a drive record; no file {args.initial}")
    return _read(args, args.initial)


def _progress_line(text: str) -> None:
    print(f"  {text}", file=sys.stderr)


def _estimate_drive(args: argparse.Namespace) -> int:
    from controllers.drive_estimation import drive_errors, estimate_drive
    from rig.io.files import write_record

    vehicle = load_vehicle(args.vehicle)
    target = _read(args, args.target)
    train = _read(args, args.train) if args.train else None
    estimate = estimate_drive(vehicle, target, args.method, train, progress=None if args.quiet else _progress_line)
    write_record(args.out, estimate.at_rest())
    print(f"{args.method}: {estimate.detail}")
    if target.corners_with("drive") == list(vehicle.corners):  # a rig record: its own drive is the truth
        print("drive error against the target's own drive (RMS, in the drive band): "
              + ", ".join(f"{c} {e:.2f} %" for c, e in drive_errors(target, estimate).items()))
    print(f"wrote {args.out}: {len(vehicle.corners)} drive channels, {estimate.drive.duration:.1f} s at "
          f"{estimate.drive.rate:g} Hz")
    return 0


def _validate(args: argparse.Namespace) -> int:
    from rig.diagnosis.validation import validate
    from rig.report.validation_report import write_validation

    vehicle = load_vehicle(args.vehicle)
    report = validate(vehicle, _read(args, args.measured))
    write_validation(report, args.out)
    low, high = report.band_hz
    print(f"mean TDDI {report.mean_tddi:.4g} over {len(report.channels)} channels ({low:g}-{high:g} Hz); worst: "
          + ", ".join(f"{n} {m.rms_error_pct:.1f} %" for n, m in
                      sorted(report.channels.items(), key=lambda kv: -kv[1].tddi)[:4]))
    print(f"wrote {args.out}/validation.json, psd_overlay.png, pattern_frfs.png")
    return 0


def _diagnose(args: argparse.Namespace) -> int:
    from rig.diagnosis.diagnose import diagnose
    from rig.diagnosis.unbalance import is_track_record
    from rig.report.diagnosis_report import write_diagnosis

    vehicle = load_vehicle(args.vehicle)
    records = [_read(args, path) for path in args.measured]
    holdout = _read(args, args.holdout) if args.holdout else None

    def progress(step: str) -> None:
        print(f"  {step}", file=sys.stderr)

    if any(is_track_record(r) for r in records):
        return _diagnose_track(args, vehicle, records, holdout, progress)
    if len(records) > 1:
        raise RecordError("a rig test is one --measured record "
                          "(several are taken only as track tests at several speeds)")
    result = diagnose(vehicle, records[0], holdout, progress=progress)
    write_diagnosis(result, args.out)
    print(f"verdict: {result.verdict}; held-out TDDI {result.baseline_tddi:.4g} (baseline) -> "
          f"{result.recalibrated_tddi:.4g} (recalibrated) -> {result.extended_tddi:.4g} (extended)")
    if result.unexplained is not None:
        where = result.unexplained
        print(f"unexplained: the residual lives on {', '.join(where['channels'])} in {where['band_hz'][0]:.1f}-"
              f"{where['band_hz'][1]:.1f} Hz (peak {where['peak_hz']:.2f} Hz); amplitude dependence "
              f"{where['amplitude_dependence']:.2f}")
    print(f"wrote {args.out}/diagnosis.json, vehicle_extended.toml, report.md")

    def log(review, stream) -> None:  # held-out data: measured against the recalibrated and extended models
        for label, record in result.compared.items():
            review.log_record(stream, record, prefix=f"diagnosis/{label}")

    _review(args, vehicle.corners, log)
    return 0


def _diagnose_track(args: argparse.Namespace, vehicle, records: list, holdout, progress) -> int:
    """``rig diagnose`` on track records: the wheels' unbalance from their order content (and, with the road
    measured, the rig-style diagnosis of the rest)."""
    from rig.diagnosis.track_diagnosis import diagnose_track
    from rig.diagnosis.unbalance import is_track_record
    from rig.report.track_report import write_track_diagnosis

    mixed = [path for path, r in zip(args.measured + ([args.holdout] if holdout else []), records + [holdout])
             if r is not None and not is_track_record(r)]
    if mixed:
        raise RecordError(f"{', '.join(mixed)}: not a track record ('# test: track'); rig and track tests are "
                          f"diagnosed apart")
    result = diagnose_track(vehicle, records, holdout, progress=progress)
    write_track_diagnosis(result, args.out)
    named = result.unbalance.named
    print(f"verdict: {result.verdict}" + (f"; {named.corner}: m e {named.unbalance_kgm * 1e3:.2f} ± "
                                          f"{named.std_kgm * 1e3:.2f} g·m at {named.angle_deg:.1f} ± "
                                          f"{named.std_deg:.1f} deg from the mark" if named else ""))
    print("unbalance per wheel (g·m, T² against " + f"{next(iter(result.unbalance.wheels.values())).threshold:.1f}): "
          + ", ".join(f"{w.corner} {w.unbalance_kgm * 1e3:.2f} ± {w.std_kgm * 1e3:.2f} (T² {w.t2:.1f})"
                      for w in result.unbalance.wheels.values()))
    if result.road is not None:
        print(f"road part (rig-style, on the measured road): {result.road.verdict}")
    print(f"wrote {args.out}/diagnosis.json, vehicle_extended.toml, report.md")
    _review(args, vehicle.corners, lambda review, stream: review.log_record(stream, records[0], prefix="measured"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
