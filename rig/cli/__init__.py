"""The ``rig`` command line."""

from rig.cli.main import main

__all__ = ["main"]
