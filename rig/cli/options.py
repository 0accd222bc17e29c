"""Options and steps every command shares: the vehicle, reading records through ``--map`` / ``--resample``,
and the Rerun recording that ``--rerun`` / ``--rerun-spawn`` ask for."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable
from typing import TYPE_CHECKING

from rig.io.record import Record

if TYPE_CHECKING:
    from rig.report.review import Review


def add_vehicle(command: argparse.ArgumentParser, example: str = "proton_x") -> None:
    command.add_argument("--vehicle", metavar="V", required=True, help=f"built-in name ({example}) or vehicle file")


def add_resample(command: argparse.ArgumentParser) -> None:
    command.add_argument("--resample", action="store_true",
                         help="interpolate a log with irregular time stamps (a CSV time column, an MDF group, "
                              "a TDMS time channel) onto a uniform grid (rounded stamps need no option)")


def add_map(command: argparse.ArgumentParser) -> None:
    command.add_argument("--map", nargs="+", metavar="MAP.toml|FROM=TO",
                         help="read the records through a channel map: a TOML file ([channels] \"DAQ name\" = "
                              "\"FL/sprung_acc\" or {name, unit, scale}) or FROM=TO pairs, FROM a channel name "
                              "or a unique part of one (e.g. LF_=FL/unsprung_acc); unmapped channels are ignored")


def add_rerun(command: argparse.ArgumentParser, scene: bool = True) -> None:
    command.add_argument("--rerun", metavar="FILE.rrd", help="also write a Rerun recording (open it: rerun FILE.rrd)")
    command.add_argument("--rerun-spawn", action="store_true", help="also stream the run to a new Rerun viewer")
    if scene:
        command.add_argument("--rerun-magnify", metavar="K", type=positive, default=1.0,
                             help="scale the motion of the rig in the recording's 3D view by K (default: true scale)")


def read(args: argparse.Namespace, path: str) -> Record:
    """Read a record as ``--resample`` and ``--map`` allow, saying what was resampled and what was left out."""
    from rig.io.channel_map import map_from_option
    from rig.io.files import read_record

    record = read_record(path, resample=args.resample, channel_map=map_from_option(args.map))
    for key in ("resampled", "unmapped"):
        if key in record.metadata:
            print(f"{path}: {key}: {record.metadata[key]}", file=sys.stderr)
    return record


def review(args: argparse.Namespace, title: str, log: Callable[[Review], None]) -> None:
    """Write the recording that ``--rerun`` / ``--rerun-spawn`` ask for, if any: ``log(review)`` logs the run
    and its result, the overview says which command ran with which options (``title``: what ran, in words)."""
    if not (args.rerun or args.rerun_spawn):
        return
    from rig.report.review import recording, what_ran

    options = {k: v for k, v in vars(args).items() if k not in ("command", "run") and not k.startswith("rerun")}
    with recording(args.rerun, args.rerun_spawn, f"rig {args.command}: {title}") as rec:
        rec.ran = what_ran(args.command, options)
        log(rec)
    if args.rerun:
        print(f"wrote {args.rerun} (open it with: rerun {args.rerun})")


def positive(text: str) -> float:
    """An option's value that must be a positive number."""
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not value > 0 or value == float("inf"):
        raise argparse.ArgumentTypeError(f"a positive number is needed, got {text}")
    return value


def progress_line(text: str) -> None:
    """A long computation's progress, on stderr."""
    print(f"  {text}", file=sys.stderr)
