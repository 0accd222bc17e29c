"""``rig replay``: drive (or measured post displacement) channels played on the virtual rig."""

from __future__ import annotations

import argparse
import sys

from rig.cli.options import add_map, add_rerun, add_resample, add_vehicle, in_file, out_record, read, review


def add_parser(commands: argparse._SubParsersAction) -> None:
    replay = commands.add_parser("replay", help="replay drive (or measured post displacement) channels")
    add_vehicle(replay)
    replay.add_argument("--drive", metavar="D", required=True, type=in_file,
                        help="record with <corner>/drive or <corner>/actuator_disp")
    replay.add_argument("--out", type=out_record, metavar="R", required=True,
                        help="response record (.csv, RPC III .rsp or MDF .mf4)")
    replay.add_argument("--clip", action="store_true", help="clip a drive beyond the post limits and report it")
    replay.add_argument("--plot", metavar="P.png", help="also write a PNG of the responses")
    add_resample(replay)
    add_map(replay)
    add_rerun(replay)
    replay.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from rig.constants import ANALYSIS_BAND, TOP_SHARE_OF_RATE
    from rig.io.files import write_record
    from rig.report.review_runs import present_replay
    from rig.report.plots import plot_responses, save_figure
    from rig.sim.replay import replay
    from rig.vehicle.vehicle_file import load_vehicle

    vehicle = load_vehicle(args.vehicle)
    drive = read(args, args.drive)
    top = TOP_SHARE_OF_RATE * drive.rate
    if top < ANALYSIS_BAND[1]:
        print(f"note: the drive is sampled at {drive.rate:g} Hz: the response record holds up to {top:.3g} Hz "
              f"(the analysis band's {ANALYSIS_BAND[1]:g} Hz needs {ANALYSIS_BAND[1] / TOP_SHARE_OF_RATE:g} Hz)",
              file=sys.stderr)
    result = replay(vehicle, drive, clip=args.clip)
    for hit in result.limit_hits:
        print(f"clipped: {hit.describe()}", file=sys.stderr)
    print_airborne(result.airborne_time())
    write_record(args.out, result.record)
    if args.plot:
        save_figure(plot_responses(result.record), args.plot)
    print(f"wrote {args.out}: {len(result.record.names)} channels, {result.record.duration:.1f} s at "
          f"{result.record.rate:g} Hz ({result.record.metadata['posts']} posts)")
    review(args, f"{args.drive} replayed on {vehicle.name}",
           lambda rec: present_replay(rec, result, args.rerun_magnify))
    return 0


def print_airborne(airborne_time: dict[str, float]) -> None:
    """Say which tyres left the ground and for how long (s)."""
    airborne = {c: t for c, t in airborne_time.items() if t > 0}
    if airborne:
        print("tyres left the ground: " + ", ".join(f"{c} {t:.3f} s" for c, t in airborne.items()))
