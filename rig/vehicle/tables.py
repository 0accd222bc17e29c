"""The baseline tables of a vehicle file (docs/contracts.md): their keys with units and plausible ranges, and how a
table is read, unknown, missing, non-numeric and implausible values refused naming the key. Cars and quarter cars
(rig/vehicle/vehicle_file.py) and trucks (rig/vehicle/truck_file.py) read theirs with it."""

from __future__ import annotations

from rig.errors import RigError


class VehicleError(RigError):
    """A vehicle file that is missing, malformed or implausible."""


# key: (unit, low, high, required). The ranges only hold what no vehicle or rig has (a negative mass, a rate of a
# TN/m); units are checked by what the numbers make of each corner (rig/vehicle/plausibility.py), so that lab
# benches and trucks load alike.
AXLE_KEYS = {
    "unsprung_mass": ("kg", 0.01, 1e5, True),
    "spring_rate": ("N/m", 1.0, 1e9, True),
    "parasitic_rate": ("N/m", 0.0, 1e9, False),
    "damping": ("N s/m", 0.0, 1e8, True),
    "tyre_rate": ("N/m", 1.0, 1e10, True),
    "tyre_damping": ("N s/m", 0.0, 1e7, False),
}
GEOMETRY_KEYS = {
    "wheelbase": ("m", 0.05, 30.0, True),
    "cg_to_front_axle": ("m", 0.0, 30.0, True),
    "track_front": ("m", 0.05, 5.0, True),
    "track_rear": ("m", 0.05, 5.0, True),
    "cg_height": ("m", 0.01, 5.0, False),
    "wheel_radius": ("m", 0.01, 2.0, False),
}
SPRUNG_KEYS = {
    "mass": ("kg", 0.1, 1e6, True),
    "pitch_inertia": ("kg m^2", 1e-4, 1e8, True),
    "roll_inertia": ("kg m^2", 1e-4, 1e8, True),
    "yaw_inertia": ("kg m^2", 1e-4, 1e8, False),
}


_DEFAULTS = {"parasitic_rate": 0.0, "tyre_damping": 0.0, "cg_height": 0.55, "wheel_radius": 0.30}

def read_section(data: dict, section: str, keys: dict, where: str, required: bool = True, label: str = "",
                 defaults: dict | None = None) -> dict:
    """The numbers of table ``section`` of ``data``: keys {name: (unit, low, high, required)}, unknown, missing,
    non-numeric and implausible values refused naming the key; ``label`` names the table in messages (default
    ``[section]``), ``defaults`` fill keys that are not required."""
    shown = label or f"[{section}]"
    defaults = _DEFAULTS if defaults is None else defaults
    table = data.get(section)
    if table is None:
        if required:
            raise VehicleError(f"{where}: missing section {shown}")
        table = {}
    if not isinstance(table, dict):
        raise VehicleError(f"{where}: {shown} must be a table")
    unknown = sorted(set(table) - set(keys))
    if unknown:
        raise VehicleError(f"{where}: unknown key(s) {', '.join(unknown)} in {shown} (known: {', '.join(keys)})")
    values = {}
    for key, (unit, low, high, needed) in keys.items():
        if key not in table:
            if needed:
                raise VehicleError(f"{where}: {shown} is missing '{key}' ({unit})")
            if key in defaults:
                values[key] = defaults[key]
            continue
        value = table[key]
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise VehicleError(f"{where}: {shown} {key} must be a number in {unit}, got {value!r}")
        if not low <= value <= high:
            raise VehicleError(
                f"{where}: {shown} {key} = {value} {unit} is outside the plausible range {low:g}..{high:g} {unit}; "
                f"vehicle files are in SI units ({unit})"
            )
        values[key] = float(value)
    return values
