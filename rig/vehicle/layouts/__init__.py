"""The layout registry: one module per layout, each holding one ``LAYOUT`` (rig/vehicle/layouts/_base.py), found on
first use. A vehicle file's ``layout`` value is looked up here (``layout_named``); code asks the layout what it needs
(its corners per axle, where its axles come from, its body's motions, its frame), never its name."""

from __future__ import annotations

import functools
import importlib
import pkgutil

from rig.vehicle.layouts._base import Layout

__all__ = ["DEFAULT", "Layout", "layout_named", "layouts"]

DEFAULT = "full"  # a vehicle file without a ``layout`` key


@functools.cache
def layouts() -> dict[str, Layout]:
    """Layout name -> layout, alphabetical, found among this package's modules (those holding a ``LAYOUT``)."""
    found = {}
    for info in pkgutil.iter_modules(__path__):
        module = importlib.import_module(f"{__name__}.{info.name}")
        if hasattr(module, "LAYOUT"):
            found[module.LAYOUT.name] = module.LAYOUT
    return dict(sorted(found.items()))


def layout_named(name: str) -> Layout:
    """The layout called ``name``; ValueError lists the known ones."""
    known = layouts()
    if not isinstance(name, str) or name not in known:
        raise ValueError(f"layout must be one of {', '.join(known)}, got {name!r}")
    return known[name]
