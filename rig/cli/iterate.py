"""``rig iterate``: post drives iterated until the virtual rig reproduces a target record (RPC / TWR)."""

from __future__ import annotations

import argparse
import math
from pathlib import Path

from rig.cli.options import (COUNT, NON_NEGATIVE, add_map, add_rerun, add_resample, add_vehicle, in_file, out_folder,
                             progress_line, read, review)
from rig.io.record import Record, RecordError


def add_parser(commands: argparse._SubParsersAction) -> None:
    iterate = commands.add_parser("iterate", help="iterate post drives until the rig reproduces a target record")
    add_vehicle(iterate)
    iterate.add_argument("--target", metavar="T", required=True, type=in_file,
                         help="target record (.csv, RPC III .rsp, MDF .mf4, TDMS .tdms)")
    iterate.add_argument("--out", type=out_folder, metavar="DIR", required=True,
                         help="output folder (history.json, drive.csv, drive.drv, plots)")
    iterate.add_argument("--iterations", metavar="N", type=COUNT, default=8,
                         help="most iterations (default: %(default)s)")
    iterate.add_argument("--channels", metavar="CHANNEL", nargs="+",
                         help="target channels to reproduce (default: every sprung_acc and unsprung_acc channel, "
                              "else every sprung_disp and unsprung_disp channel: a lab bench's encoders)")
    iterate.add_argument("--scheme", choices=("adaptive", "fixed"), default="adaptive",
                         help="adaptive: FRF updated from each iteration, gain adapted; fixed: the identified FRF "
                              "and gain 0.5 throughout (default: %(default)s)")
    iterate.add_argument("--match", choices=("rms", "peak", "damage"), default="rms",
                         help="what to match: the time history (RMS error), its peaks (peak error) or its fatigue "
                              "damage (rainflow damage ratio) (default: %(default)s)")
    iterate.add_argument("--target-error", metavar="PCT", type=NON_NEGATIVE, default=None,
                         help="stop when every channel's error under --match is at most this %% (default: 3 for rms, "
                              "5 for peak, 25 for damage: a damage ratio within 0.8-1.25)")
    iterate.add_argument("--initial", default="frf", metavar="{frf,narx,inverse-model,FILE}",
                         help="first drive: the one-shot FRF inverse (default), an estimate (rig estimate-drive's "
                              "methods) or a drive record")
    iterate.add_argument("--train", metavar="R", type=in_file,
                         help="measured drive/response record: the FRF's identification (instead of a run "
                                         "on the virtual rig) and the NARX's training data")
    iterate.add_argument("--resume", action="store_true", help="continue the run saved in --out")
    iterate.add_argument("--quiet", action="store_true", help="no progress bar")
    add_resample(iterate)
    add_map(iterate)
    add_rerun(iterate)
    iterate.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from controllers import IterationError

    earlier = [name for name in ("state.npz", "history.json") if (Path(args.out) / name).exists()]
    if earlier and not args.resume:  # before any work: nothing of the earlier run is overwritten
        raise IterationError(f"{args.out} holds an earlier drive iteration ({', '.join(earlier)}): continue it with "
                             f"--resume, or give another --out folder")
    from controllers.rpc import DriveIteration, IterationSettings
    from rig.report.plots import IterationPlots
    from rig.vehicle.vehicle_file import load_vehicle

    vehicle = load_vehicle(args.vehicle)
    target = read(args, args.target)
    channels = args.channels or _default_channels(target, vehicle.corners)
    missing = [n for n in channels if n not in target]
    if not channels or missing:
        wanted = ', '.join(missing) or 'sprung_acc/unsprung_acc or sprung_disp/unsprung_disp'
        raise RecordError(f"target has no channel(s) {wanted} (it has: {', '.join(target.names)}); use --channels or "
                          f"--map")
    settings = IterationSettings(scheme=args.scheme, iterations=args.iterations, target_error_pct=args.target_error,
                                 match=args.match)
    train = read(args, args.train) if args.train else None
    initial = None
    if args.initial != "frf" and not args.resume:
        initial = _initial_drive(args, vehicle, target, train)
    job = DriveIteration(vehicle, target, channels, args.out, settings, initial=initial, identification=train)
    if job.settings.band != settings.band:
        low, high = job.settings.band
        print(f"iterating in {low:.3g}-{high:.3g} Hz: what a {target.duration:.3g} s target at {target.rate:g} Hz "
              f"supports")
    callbacks = [IterationPlots(args.out, f"{vehicle.name}: {settings.scheme} drive iteration", job.target, job.span,
                                job.rate, channels, settings.target_error_pct)]
    if not args.quiet:
        callbacks.append(_say)
    if args.rerun or args.rerun_spawn:
        from rig.report.review_iteration import IterationLog

        callbacks.append(IterationLog())

    def each(step) -> None:
        for callback in callbacks:
            callback(step)

    result = job.run(resume=args.resume, progress=False, callback=each)
    best = result.best
    print(f"{result.stop_reason}; best iteration {best.iteration}: worst channel {best.worst_rms_error_pct:.2f} % "
          f"RMS error (" + ", ".join(f"{n} {m.rms_error_pct:.2f}" for n, m in best.channels.items()) + ")")
    for demand in best.unreachable:
        print(f"  beyond the model: {demand.describe()}")
    if args.match != "rms":
        print("damage ratio: " + ", ".join(f"{n} {m.damage_ratio:.2f}" for n, m in best.channels.items())
              + "; peak error: " + ", ".join(f"{n} {m.peak_error_pct:.1f} %" for n, m in best.channels.items()))
    if best.road_recovery_rms_error_pct is not None:
        print("road recovery, RMS error of the post motion against the road: " + "; ".join(
            f"{c} " + ", ".join(f"{e:.1f} % ({band})" for band, e in parts.items())
            for c, parts in best.road_recovery_rms_error_pct.items()))
    print(f"wrote {args.out}/drive.csv, drive.drv, history.json, convergence.png")
    from rig.report.review_iteration import log_drive_iteration

    review(args, f"drives for {args.target} on {vehicle.name}", lambda rec: log_drive_iteration(
        rec, result, callbacks[-1], job.target, float(job.time[0]), channels, settings, job.target_record,
        args.rerun_magnify))
    return 0


def _default_channels(target: Record, corners: tuple[str, ...]) -> list[str]:
    """The target's accelerations at the vehicle's corners, else its displacements (a lab bench's encoders)."""
    for quantities in (("sprung_acc", "unsprung_acc"), ("sprung_disp", "unsprung_disp")):
        found = [n for n in target.names if n.split("/")[0] in corners and n.split("/")[-1] in quantities]
        if found:
            return found
    return []


def _say(step) -> None:
    """One line per iteration as it ends, and every post limit the iteration's drive met."""
    entry = step.record
    worst = max(entry.channels, key=lambda n: entry.channels[n].rms_error_pct)
    damage = [m.damage_ratio for m in entry.channels.values() if not math.isnan(m.damage_ratio)]
    spread = f"damage ratio {min(damage):.3g}-{max(damage):.3g}, " if damage else ""
    print(f"iteration {entry.iteration}: worst channel {entry.worst_rms_error_pct:.2f} % RMS error ({worst}), "
          f"{spread}gain {entry.gain:.2f}", flush=True)
    for hit in entry.limit_hits:
        print(f"  post limit: {hit}", flush=True)


def _initial_drive(args: argparse.Namespace, vehicle, target: Record, train: Record | None) -> Record:
    """The first drive ``--initial`` names: an estimate of rig estimate-drive's methods, or a drive record."""
    from controllers.drive_estimation import METHODS, estimate_drive

    if args.initial in METHODS:
        estimate = estimate_drive(vehicle, target, args.initial, train, progress=None if args.quiet else progress_line)
        print(f"initial drive: {estimate.detail}")
        if estimate.coverage is not None and not estimate.coverage.covered:
            print(f"warning: {estimate.coverage.describe()}")
        return estimate.drive
    if not Path(args.initial).is_file():
        raise RecordError(f"--initial must be frf, narx, inverse-model or a drive record; no file {args.initial}")
    return read(args, args.initial)
