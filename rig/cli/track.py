"""``rig track``: a vehicle driven over a road at constant speed (the virtual test track)."""

from __future__ import annotations

import argparse

from rig.cli.options import NON_NEGATIVE, POSITIVE, add_rerun, add_vehicle, out_record, review
from rig.cli.replay import print_airborne
from rig.road.roads import RoadError

ROAD_HELP = ("road spec (iso8608:class=C,length=500 | bar:sides=right | plywood | sweep | step | crg:path=F.crg | "
             "profile:path=F.txt) or a .crg / profile file")


def add_parser(commands: argparse._SubParsersAction) -> None:
    track = commands.add_parser("track", help="drive a vehicle over a road at constant speed")
    add_vehicle(track)
    track.add_argument("--road", metavar="SPEC", required=True, help=ROAD_HELP)
    track.add_argument("--speed", metavar="M_PER_S", required=True, type=POSITIVE, help="m/s")
    track.add_argument("--duration", metavar="S", type=POSITIVE,
                       help="s (default: until the front axle reaches the road's end)")
    track.add_argument("--out", type=out_record, metavar="R", required=True,
                       help="record (.csv, RPC III .rsp or MDF .mf4)")
    track.add_argument("--rate", metavar="HZ", type=POSITIVE, default=512.0,
                       help="sample rate in Hz (default: %(default)s)")
    track.add_argument("--envelope", metavar="M", type=NON_NEGATIVE, default=0.0,
                       help="tyre-enveloping moving-average base in m")
    track.add_argument("--rolling-radius", nargs="+", metavar="M|CORNER=M",
                       help="rolling radius of the wheels in m, one for all or per corner (FL=0.2978 FR=0.2985 ...; "
                            "default: the vehicle's tyre): each wheel's angle turns at speed / radius")
    track.add_argument("--plot", metavar="P.png", help="also write a PNG of the responses")
    add_rerun(track)
    track.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from rig.io.files import write_record
    from rig.report.plots import plot_responses, save_figure
    from rig.report.review_runs import present_track
    from rig.road.roads import road_from_spec
    from rig.signal.comfort import comfort_summary
    from rig.sim.track import track_run
    from rig.vehicle.vehicle_file import load_vehicle

    vehicle = load_vehicle(args.vehicle)
    road = road_from_spec(args.road)
    result = track_run(vehicle, road, args.speed, args.duration, args.rate, args.envelope,
                       rolling_radius=rolling_radius(args.rolling_radius))
    record = result.record
    print_airborne(result.airborne_time())
    comfort = comfort_summary(record)
    print("ISO 2631-1 Wk-weighted RMS of body acceleration: "
          + ", ".join(f"{name.split('/')[0]} {value:.3f} m/s²" for name, value in comfort.items()))
    write_record(args.out, record)
    if args.plot:
        save_figure(plot_responses(record), args.plot)
    print(f"wrote {args.out}: {record.duration:.1f} s at {args.speed:g} m/s over {road.provenance}")
    review(args, f"{vehicle.name} over {road.provenance} at {args.speed:g} m/s", lambda rec: present_track(
        rec, result, road.provenance, args.speed, comfort, args.rerun_magnify))
    return 0


def rolling_radius(items: list[str] | None) -> float | dict[str, float] | None:
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
