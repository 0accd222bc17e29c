"""Model extensions beyond the baseline ride model, as vehicle-file sections named after their cause.

Each extension is a TOML table named after its cause in the DESIGN.md vocabulary, with one sub-table per
axle for per-corner effects, for example::

    [bump_stop.front]
    gap = 0.030          # m of compression from static ride height before the stop touches
    rate = 150000.0      # N/m once in contact

    [damper_asymmetry.rear]
    compression = 1800.0 # N s/m, replaces [rear] damping in compression
    rebound = 3200.0     # N s/m, replaces [rear] damping in rebound

The MuJoCo realisation of each (rig/model.py) stays inside mj_step: a bump stop is a dead-band spring
tendon beside the suspension, an asymmetric damper two sign-clamped affine actuators on it.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

AXLES = ("front", "rear")


@dataclass(frozen=True)
class BumpStop:
    gap: float   # m, compression from static ride height to contact
    rate: float  # N/m in contact

    LIMITS = {"gap": (0.0, 0.3), "rate": (1e3, 1e8)}


@dataclass(frozen=True)
class DamperAsymmetry:
    compression: float  # N s/m
    rebound: float      # N s/m

    LIMITS = {"compression": (0.0, 1e5), "rebound": (0.0, 1e5)}


#: cause name -> parameter class of its per-axle sub-tables
AXLE_EXTENSIONS = {"bump_stop": BumpStop, "damper_asymmetry": DamperAsymmetry}


def parse_extensions(data: dict, where: str, axles: tuple[str, ...]) -> dict[str, dict[str, object]]:
    """Read the extension sections of a parsed vehicle file: cause -> axle -> parameters."""
    result: dict[str, dict[str, object]] = {}
    for cause, kind in AXLE_EXTENSIONS.items():
        if cause not in data:
            continue
        section = data[cause]
        unknown_axles = sorted(set(section) - set(axles))
        if unknown_axles:
            raise ValueError(f"{where}: [{cause}] has sub-table(s) {', '.join(unknown_axles)}; "
                             f"expected {' or '.join(f'[{cause}.{a}]' for a in axles)}")
        result[cause] = {axle: _parameters(kind, table, f"{where}: [{cause}.{axle}]") for axle, table in section.items()}
    return result


def _parameters(kind: type, table: dict, where: str) -> object:
    names = [f.name for f in fields(kind)]
    unknown = sorted(set(table) - set(names))
    missing = [n for n in names if n not in table]
    if unknown or missing:
        raise ValueError(f"{where}: " + "; ".join(
            ([f"unknown key(s) {', '.join(unknown)}"] if unknown else []) + ([f"missing {', '.join(missing)}"] if missing else [])
        ) + f" (keys: {', '.join(names)})")
    for name in names:
        value = table[name]
        low, high = kind.LIMITS[name]
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not low <= value <= high:
            raise ValueError(f"{where}: {name} = {value!r} is outside the plausible range {low:g}..{high:g} (SI units)")
    return kind(**{n: float(table[n]) for n in names})


def to_tables(extensions: dict[str, dict[str, object]]) -> dict:
    """The extension sections as TOML-ready tables (inverse of parse_extensions)."""
    return {cause: {axle: {f.name: getattr(p, f.name) for f in fields(p)} for axle, p in per_axle.items()}
            for cause, per_axle in extensions.items()}
