"""Options and steps every command shares: the vehicle, numbers and output paths checked as they are parsed,
reading records through ``--map`` / ``--resample``, and the Rerun recording that ``--rerun`` / ``--rerun-spawn``
ask for."""

from __future__ import annotations

import argparse
import math
import os
import shlex
import sys
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from rig.io.record import Record
    from rig.report.review import Review


class Parser(argparse.ArgumentParser):
    """An argument parser whose errors are one line: ``rig iterate: error: argument --iterations: ...``."""

    def error(self, message: str):
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def number(low: float = -math.inf, *, above: bool = False, integer: bool = False) -> Callable[[str], float]:
    """An option type: a finite number at least ``low`` (greater than ``low`` with ``above``; whole with
    ``integer``), refused at parse time with what it must be."""
    def parse(text: str) -> float:
        try:
            value = int(text) if integer else float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected {'a whole number' if integer else 'a number'}, "
                                             f"got {text!r}") from None
        if not math.isfinite(value) or value < low or (above and value == low):
            raise argparse.ArgumentTypeError(f"must be {'greater than' if above else 'at least'} {low:g}, "
                                             f"got {text}")
        return value
    return parse


POSITIVE = number(0.0, above=True)
NON_NEGATIVE = number(0.0)
COUNT = number(1, integer=True)


def out_folder(text: str) -> str:
    """An output folder: it may exist (files in it are replaced one by one), but not as a file, and it or the folder
    it would be made in must be writable: refused as the options are read, before any work."""
    if Path(text).exists() and not Path(text).is_dir():
        raise argparse.ArgumentTypeError(f"{text} is a file; give a folder")
    _writable(text, Path(text))
    return text


def out_record(text: str) -> str:
    """An output record file, of a type the writers know, not an existing folder, in a folder it can be written to."""
    from rig.io.files import writable_suffixes

    if Path(text).suffix.lower() not in writable_suffixes():
        raise argparse.ArgumentTypeError(f"{text}: cannot write a record of type '{Path(text).suffix}' "
                                         f"(use {', '.join(sorted(writable_suffixes()))})")
    if Path(text).is_dir():
        raise argparse.ArgumentTypeError(f"{text} is a folder; give a file")
    _writable(text, Path(text).parent)
    return text


def _writable(text: str, folder: Path) -> None:
    """Refuse ``text`` unless ``folder``, or the nearest of its parents that exists, is a folder this process may
    write in (one under a regular file, or a read-only one, named)."""
    existing = next(p for p in (folder.absolute(), *folder.absolute().parents) if p.exists())
    if not existing.is_dir():
        raise argparse.ArgumentTypeError(f"{text}: {existing} is a file, not a folder")
    if not os.access(existing, os.W_OK | os.X_OK):
        raise argparse.ArgumentTypeError(f"{text}: cannot write in {existing} (permission denied)")


def in_file(text: str) -> str:
    """An input file that exists: refused as the options are read, before any work."""
    path = Path(text)
    if not path.exists():
        raise argparse.ArgumentTypeError(f"no such file: {text}")
    if path.is_dir():
        raise argparse.ArgumentTypeError(f"{text} is a folder; give a file")
    return text


def vehicle_option(text: str) -> str:
    """A built-in vehicle's name or a vehicle file that exists."""
    from rig.vehicle.assets import builtin_vehicles, vehicle_path

    if vehicle_path(text) is None:
        raise argparse.ArgumentTypeError(f"{text!r} is neither a vehicle file nor a built-in vehicle "
                                         f"({', '.join(builtin_vehicles())})")
    return text


def add_vehicle(command: argparse.ArgumentParser, example: str = "proton_x") -> None:
    command.add_argument("--vehicle", metavar="V", required=True, type=vehicle_option,
                         help=f"built-in name ({example}) or vehicle file")


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
    for key in ("resampled", "unmapped", "events", "truncated"):
        if key in record.metadata:
            print(f"{path}: {key}: {record.metadata[key]}", file=sys.stderr)
    return record


def review(args: argparse.Namespace, title: str, log: Callable[[Review], None]) -> None:
    """Write the recording that ``--rerun`` / ``--rerun-spawn`` ask for, if any: ``log(review)`` logs the run
    and its result, the overview says which command ran with which options (``title``: what ran, in words)."""
    if not (args.rerun or args.rerun_spawn):
        return
    from rig.report.review import recording, what_ran

    options = {k: v for k, v in vars(args).items() if k not in ("command", "run", "argv") and not k.startswith("rerun")}
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


def command_line(args: argparse.Namespace) -> str:
    """The command as it was run (shell-quoted), for a report to say what it answers."""
    return " ".join(["rig", *map(shlex.quote, args.argv)])


def progress_line(text: str) -> None:
    """A long computation's progress, on stderr."""
    print(f"  {text}", file=sys.stderr)
