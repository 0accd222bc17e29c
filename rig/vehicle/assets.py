"""Where the shipped assets (MJCF, vehicle files), examples and data are, in a checkout and in an installed wheel."""

from __future__ import annotations

import os
from pathlib import Path


def shipped_dir(name: str, marker: str) -> Path:
    """A folder the wheel ships inside the package (``rig/<name>``) and a checkout holds at its top (``<repo>/<name>``),
    found by a file or folder ``marker`` in it: ``assets``, ``examples``, ``data``."""
    package = Path(__file__).resolve().parents[1]  # rig/
    for candidate in (package / name, package.parent / name):
        if (candidate / marker).exists():
            return candidate
    raise FileNotFoundError(f"rig's {name} not found beside {package}; reinstall the package")


def asset_dir() -> Path:
    """The assets folder: ``rig/assets`` in an installed wheel, ``<repo>/assets`` in a checkout."""
    return shipped_dir("assets", "mjcf")


def mjcf_path(name: str) -> Path:
    """Path of a shipped MJCF file, e.g. ``mjcf_path('four_poster.xml')``."""
    return asset_dir() / "mjcf" / name


def vehicle_dir() -> Path:
    return asset_dir() / "vehicles"


def builtin_vehicles() -> list[str]:
    """Names of the vehicle files shipped in assets/vehicles."""
    return sorted(p.stem for p in vehicle_dir().glob("*.toml"))


def vehicle_path(name_or_path: str | os.PathLike) -> Path | None:
    """A vehicle file's path: the given path where it names a file (a ``.toml`` or an existing path), else the
    built-in vehicle of that name; None where neither exists."""
    path = Path(name_or_path)
    if path.suffix == ".toml" or path.exists():
        return path if path.is_file() else None
    builtin = vehicle_dir() / f"{name_or_path}.toml"
    return builtin if builtin.is_file() else None
