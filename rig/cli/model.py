"""``rig model``: the assembled MJCF of a vehicle on the rig, with its static ride height as a keyframe."""

from __future__ import annotations

import argparse

from rig.cli.options import add_vehicle


def add_parser(commands: argparse._SubParsersAction) -> None:
    model = commands.add_parser("model", help="write the assembled MJCF model of a vehicle on the rig")
    add_vehicle(model)
    model.add_argument("--export", metavar="OUT.xml", required=True, help="output .xml, loadable in MuJoCo's viewer")
    model.add_argument("--posts", choices=("servo", "ideal"), default="servo")
    model.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from rig.io.atomic import write_text_atomic
    from rig.vehicle.statics import settled_mjcf
    from rig.vehicle.vehicle_file import load_vehicle

    vehicle = load_vehicle(args.vehicle)
    xml, dofs = settled_mjcf(vehicle, args.posts)
    write_text_atomic(args.export, xml)
    print(f"wrote {args.export}: {vehicle.name} on the rig ({len(vehicle.corners)} {args.posts} posts), "
          f"{dofs} DOF; keyframe 'static_ride_height' is the settled state")
    return 0
