"""``rig examples``: copy the shipped example inputs and real data into a folder, where the documented commands run
as written (``examples/run_042.mf4``, ``data/belgian_block_20kph_wheel_acc.rsp``...)."""

from __future__ import annotations

import argparse
import shutil
from pathlib import Path

from rig.cli.options import out_folder

SHIPPED = (("examples", "README.md"), ("data", "README.md"))  # the folders copied, and a file each holds


def add_parser(commands: argparse._SubParsersAction) -> None:
    examples = commands.add_parser("examples", help="copy the example inputs and the real data the documentation's "
                                                    "commands use into a folder")
    examples.add_argument("out", metavar="DIR", nargs="?", type=out_folder, default="rig_examples",
                          help="folder to copy them into, as DIR/examples and DIR/data (default: %(default)s)")
    examples.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from rig.errors import RigError
    from rig.vehicle.assets import shipped_dir

    out = Path(args.out)
    copies = [(source, out / name / source.relative_to(folder)) for name, marker in SHIPPED
              for folder in [shipped_dir(name, marker)] for source in sorted(folder.rglob("*"))
              if source.is_file() and "__pycache__" not in source.parts]
    clashes = [str(target) for source, target in copies
               if target.exists() and target.read_bytes() != source.read_bytes()]
    if clashes:  # nothing already written is lost
        raise RigError(f"{', '.join(clashes[:3])}{' ...' if len(clashes) > 3 else ''} already hold(s) other "
                       f"content; give another folder")
    for source, target in copies:
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(source, target)
    print(f"copied {len(copies)} files into {out.resolve()} (examples/, data/, each with its README)")
    print(f"from there the documented commands run as written: cd {args.out} && rig validate --vehicle proton_x "
          f"--measured examples/run_042.mf4 --map examples/daq.toml --out validation")
    return 0
