"""What the registries that find their modules share: the object each module of a package holds under one name (a
suspension type's ``SUSPENSION``, a layout's ``LAYOUT``, a cause's ``CAUSE``), found by importing the package's
modules."""

from __future__ import annotations

import importlib
import pkgutil
from collections.abc import Iterable


def held_by_modules(package: str, path: Iterable[str], attribute: str) -> dict[str, object]:
    """Name -> the ``attribute`` of each module of ``package`` (at ``path``, its ``__path__``) that holds one, keyed by
    that object's ``name``."""
    found = {}
    for info in pkgutil.iter_modules(path):
        module = importlib.import_module(f"{package}.{info.name}")
        if hasattr(module, attribute):
            held = getattr(module, attribute)
            found[held.name] = held
    return found
