"""The ``rig`` command line (docs/cli.md): one module per command in this package, each parsing its options,
calling the library and presenting the result. Bad input ends in one line on stderr and exit status 2."""

from __future__ import annotations

import argparse
import os
import sys
import warnings

from rig import __version__
from rig.cli import (causes, control, demo, diagnose, dyno, estimate_drive, examples, iterate, kc, model, replay,
                     sweep, track, validate)
from rig.cli.options import Parser
from rig.errors import RigError

#: the commands, in the order ``rig --help`` lists them
COMMANDS = (demo, examples, causes, model, replay, track, control, sweep, iterate, estimate_drive, validate, diagnose,
            kc, dyno)

#: Errors that mean bad input: reported in one line, exit status 2, no traceback. The project's own derive from
#: RigError (rig/errors.py); a file or folder the system refuses is the user's to mend too.
USER_ERRORS = (RigError, FileNotFoundError, PermissionError, IsADirectoryError, NotADirectoryError)


def build_parser() -> argparse.ArgumentParser:
    parser = Parser(prog="rig", description="Virtual four-poster test rig")
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    commands = parser.add_subparsers(dest="command", required=True)
    for command in COMMANDS:
        command.add_parser(commands)
    return parser


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    args = build_parser().parse_args(argv)
    args.argv = argv  # what was run, for the reports: rig/cli/options.py command_line
    _warnings_as_notes(args.command)
    try:
        return args.run(args)
    except USER_ERRORS as err:
        print(f"rig {args.command}: error: {err}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:  # files are written atomically: what was written stands, nothing is half-written
        print(f"rig {args.command}: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # the reader of our output went away (rig causes | head)
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0


def _warnings_as_notes(command: str) -> None:
    """A library's warning reaches the user as one line, ``rig <command>: note: ...``, not as Python's two-line
    report of the code that raised it."""
    def show(message, category, filename, lineno, file=None, line=None) -> None:
        print(f"rig {command}: note: {message}", file=sys.stderr)
    warnings.showwarning = show


if __name__ == "__main__":
    sys.exit(main())
