"""Options and steps every command shares: the vehicle, reading records through ``--map`` / ``--resample``,
and the Rerun recording that ``--rerun`` / ``--rerun-spawn`` ask for."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable
from types import ModuleType

from rig.io.record import Record


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


def add_rerun(command: argparse.ArgumentParser) -> None:
    command.add_argument("--rerun", metavar="FILE.rrd", help="also write a Rerun recording (open it: rerun FILE.rrd)")
    command.add_argument("--rerun-spawn", action="store_true", help="also stream the run to a new Rerun viewer")


def read(args: argparse.Namespace, path: str) -> Record:
    """Read a record as ``--resample`` and ``--map`` allow, saying what was resampled and what was left out."""
    from rig.io.channel_map import map_from_option
    from rig.io.files import read_record

    record = read_record(path, resample=args.resample, channel_map=map_from_option(args.map))
    for key in ("resampled", "unmapped"):
        if key in record.metadata:
            print(f"{path}: {key}: {record.metadata[key]}", file=sys.stderr)
    return record


def review(args: argparse.Namespace, corners: tuple[str, ...], log: Callable[[ModuleType, object], None],
           iteration_channels: list[str] | tuple[str, ...] = ()) -> None:
    """Open the recording that ``--rerun`` / ``--rerun-spawn`` ask for, if any, and ``log(rig.review, stream)``."""
    if not (args.rerun or args.rerun_spawn):
        return
    from rig.report import review as rerun_review

    blueprint = rerun_review.default_blueprint(corners, iteration_channels)
    with rerun_review.recording(args.rerun, args.rerun_spawn, blueprint) as stream:
        log(rerun_review, stream)
    if args.rerun:
        print(f"wrote {args.rerun} (open it with: rerun {args.rerun})")


def progress_line(text: str) -> None:
    """A long computation's progress, on stderr."""
    print(f"  {text}", file=sys.stderr)
