"""Where the shipped assets (MJCF, vehicle files) are, in a checkout and in an installed wheel."""

from __future__ import annotations

from pathlib import Path


def asset_dir() -> Path:
    """The assets folder: ``rig/assets`` in an installed wheel, ``<repo>/assets`` in a checkout."""
    package = Path(__file__).resolve().parents[1]  # rig/
    for candidate in (package / "assets", package.parent / "assets"):
        if (candidate / "mjcf").is_dir():
            return candidate
    raise FileNotFoundError(f"rig assets not found beside {package}; reinstall the package")


def mjcf_path(name: str) -> Path:
    """Path of a shipped MJCF file, e.g. ``mjcf_path('four_poster.xml')``."""
    return asset_dir() / "mjcf" / name


def vehicle_dir() -> Path:
    return asset_dir() / "vehicles"
