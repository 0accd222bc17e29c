"""``rig causes``: the causes the diagnosis knows (the cause registry), with their vehicle-file keys."""

from __future__ import annotations

import argparse
import math


def add_parser(commands: argparse._SubParsersAction) -> None:
    causes = commands.add_parser("causes", help="list the causes the diagnosis knows, with their vehicle-file keys")
    causes.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from rig.causes import CAUSES, Cause

    for name, cause in CAUSES.items():
        layouts = "" if set(cause.layouts) == set(Cause.layouts) else f"; layout {' or '.join(cause.layouts)} only"
        print(f"{name} ({cause.subsystem}{layouts}): {cause.meaning}")
        for key, unit, low, high, meaning in cause.parameters():
            span = "" if math.isnan(low) else f" {low:g}..{high:g}"  # a choice (a corner) has no range
            print(f"    {key} [{unit}]{span}: {meaning}")
    return 0
