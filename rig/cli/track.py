"""``rig track``: a vehicle driven over a road at constant speed (the virtual test track); over several roads and
speeds, or with repeats, a test matrix whose repeats' scatter is the accuracy the model must reach
(rig/diagnosis/track/test_matrix.py)."""

from __future__ import annotations

import argparse
import tomllib
from pathlib import Path

from rig.cli.options import (
    COUNT,
    NON_NEGATIVE,
    POSITIVE,
    add_map,
    add_rerun,
    add_resample,
    add_vehicle,
    out_folder,
    out_record,
    review,
)
from rig.cli.replay import print_airborne
from rig.io.record import RecordError
from rig.road.roads import RoadError

ROAD_HELP = ("road spec (iso8608:class=C,length=500 | bar:sides=right | plywood | sweep | step | crg:path=F.crg | "
             "profile:path=F.txt) or a .crg / profile file")


def add_parser(commands: argparse._SubParsersAction) -> None:
    track = commands.add_parser("track", help="drive a vehicle over a road at constant speed; over several roads and "
                                               "speeds with repeats, a test matrix against the repeats' scatter")
    add_vehicle(track)
    track.add_argument("--road", metavar="SPEC", nargs="+", help=ROAD_HELP + "; several: a test matrix")
    track.add_argument("--speed", metavar="M_PER_S", nargs="+", type=POSITIVE, help="m/s; several: a test matrix")
    track.add_argument("--duration", metavar="S", type=POSITIVE,
                       help="s (default: until the front axle reaches the road's end)")
    track.add_argument("--out", type=record_or_folder, metavar="R|DIR", required=True,
                       help="record (.csv, RPC III .rsp or MDF .mf4); a test matrix's output folder")
    matrix = track.add_argument_group("test matrix (Forsén's repeats: the model inside or outside their scatter)")
    matrix.add_argument("--repeats", metavar="N", type=COUNT,
                        help="seeded repeats per road and speed (at least 2): runs of --repeats-of at speeds scattered "
                             "by --speed-scatter, with measurement noise")
    matrix.add_argument("--repeats-of", metavar="V", help="the vehicle whose runs are the repeats (default: --vehicle)")
    matrix.add_argument("--speed-scatter", metavar="SHARE", type=NON_NEGATIVE, default=0.01,
                        help="a repeat's speed scatter, a normal share clipped at twice it (default: %(default)s)")
    matrix.add_argument("--noise", metavar="SHARE", type=NON_NEGATIVE, default=0.02,
                        help="a repeat's measurement noise, of each channel's RMS (default: %(default)s)")
    matrix.add_argument("--seed", metavar="N", type=int, default=0, help="seed of the repeats (default: %(default)s)")
    matrix.add_argument("--cases", metavar="FILE.toml",
                        help="the matrix as [[case]] tables of road, speed and records (measured repeats, files)")
    add_resample(matrix)
    add_map(matrix)
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


def record_or_folder(text: str) -> str:
    """``--out``: a record file (a single run) or a folder (a test matrix)."""
    return out_record(text) if _is_record(text) else out_folder(text)


def _is_record(path: str) -> bool:
    """Whether ``path`` names a record file (its suffix one the writers know): the record formats are imported when
    the arguments are read, not with the command line."""
    from rig.io.files import writable_suffixes

    return Path(path).suffix.lower() in writable_suffixes()


def run(args: argparse.Namespace) -> int:
    if args.cases or args.repeats or len(args.road or ()) > 1 or len(args.speed or ()) > 1:
        return run_matrix(args)
    if not args.road or not args.speed:
        raise RoadError("rig track needs --road and --speed (or --cases)")
    if not _is_record(args.out):
        raise RecordError(f"--out {args.out}: a single run writes a record (.csv, .rsp or .mf4)")
    args.road, args.speed = args.road[0], args.speed[0]
    return run_single(args)


def run_single(args: argparse.Namespace) -> int:
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


def matrix_cases(args: argparse.Namespace) -> list:
    """The cases of ``--cases`` ([[case]] road, speed, records) or of --road x --speed."""
    from rig.diagnosis.track.test_matrix import MatrixCase

    if not args.cases:
        if not args.road or not args.speed:
            raise RoadError("a test matrix needs --road and --speed, or --cases")
        if not args.repeats or args.repeats < 2:
            raise RecordError("a test matrix needs --repeats of at least 2 (or measured repeats in --cases)")
        return [MatrixCase(road, speed) for road in args.road for speed in args.speed]
    try:
        tables = tomllib.loads(Path(args.cases).read_text()).get("case")
    except tomllib.TOMLDecodeError as err:
        raise RoadError(f"{args.cases}: not a TOML file ({err})") from None
    if not isinstance(tables, list) or not tables:
        raise RoadError(f"{args.cases}: give the cases as [[case]] tables with road, speed and records")
    cases = []
    for number, table in enumerate(tables, 1):
        road, speed, records = table.get("road"), table.get("speed"), table.get("records", [])
        if not isinstance(road, str) or not isinstance(speed, (int, float)) or speed <= 0 or not isinstance(
                records, list):
            raise RoadError(f"{args.cases}: [[case]] {number} needs road (a spec), speed (m/s > 0) and records "
                            f"(a list)")
        if not records and (not args.repeats or args.repeats < 2):
            raise RecordError(f"{args.cases}: [[case]] {number} has no records: give them, or --repeats of at "
                              f"least 2")
        base = Path(args.cases).parent
        cases.append(MatrixCase(road, float(speed), tuple(str(base / r) for r in records)))
    return cases


def run_matrix(args: argparse.Namespace) -> int:
    """A test matrix: each case's repeats and the model's run, the verdict per channel, figures and Rerun."""
    from rig.cli.options import read
    from rig.diagnosis.track.test_matrix import run_matrix as matrix
    from rig.report.matrix_report import write_matrix
    from rig.report.review_matrix import present_matrix
    from rig.vehicle.vehicle_file import load_vehicle

    if _is_record(args.out):
        raise RecordError(f"--out {args.out}: a test matrix writes a folder, not a record")
    vehicle = load_vehicle(args.vehicle)
    repeats_of = load_vehicle(args.repeats_of) if args.repeats_of else None
    result = matrix(vehicle, matrix_cases(args), args.repeats or 0, repeats_of, args.rate, args.duration,
                    args.speed_scatter, args.noise, args.seed, read=lambda path: read(args, path))
    for number, case in enumerate(result.cases, 1):
        print(f"case {number}, {case.label}: {len(case.outside)} of {len(case.names)} channels outside the scatter "
              f"of {case.repeats.shape[0]} repeats" + (f" ({', '.join(case.outside)})" if case.outside else ""))
    written = write_matrix(result, args.out)
    print(f"wrote {args.out}/" + ", ".join(written))
    review(args, f"{vehicle.name}: a test matrix of {len(result.cases)} case(s)",
           lambda rec: present_matrix(rec, result))
    return 0
