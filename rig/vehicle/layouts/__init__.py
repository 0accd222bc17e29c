"""The layout registry: one module per layout, each holding one ``LAYOUT`` (rig/vehicle/layouts/_base.py), found on
first use. A vehicle file's ``layout`` value is looked up here (``layout_named``); code asks the layout what it needs
(its corners per axle, where its axles come from, its body's motions, its frame), never its name."""

from __future__ import annotations

import functools

from rig.registries import held_by_modules
from rig.vehicle.layouts._base import Layout

__all__ = ["DEFAULT", "Layout", "layout_named", "layouts"]

DEFAULT = "full"  # a vehicle file without a ``layout`` key


@functools.cache
def layouts() -> dict[str, Layout]:
    """Layout name -> layout, alphabetical, found among this package's modules (those holding a ``LAYOUT``)."""
    return dict(sorted(held_by_modules(__name__, __path__, "LAYOUT").items()))


def layout_named(name: str) -> Layout:
    """The layout called ``name``; ValueError lists the known ones."""
    known = layouts()
    if not isinstance(name, str) or name not in known:
        raise ValueError(f"layout must be one of {', '.join(known)}, got {name!r}")
    return known[name]
