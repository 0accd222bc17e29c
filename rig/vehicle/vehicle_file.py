"""Vehicle files (TOML, docs/contracts.md contract): the baseline vertical ride model's parameters, in SI.

``load_vehicle`` takes a built-in name (``proton_x``) or a path. Keys are checked against plausible
ranges that hold every real vehicle and rig, and each corner's frequencies, damping ratios and ratios of masses
and rates are checked (rig/vehicle/plausibility.py), so that a file written in the wrong units (N/mm instead of
N/m, g instead of kg) is refused with a message that names the check and its numbers, instead of simulating
nonsense, while a lab quarter car and a laden truck both load.
"""

from __future__ import annotations

import dataclasses
import os
import tomllib
from pathlib import Path

from rig.io.channels import axle_names
from rig.io.text import read_text
from rig.vehicle.assets import builtin_vehicles, vehicle_path
from rig.vehicle.extensions import extensions
from rig.vehicle.layouts import DEFAULT, Layout, layout_named
from rig.vehicle.parts import Axle, Vehicle
from rig.vehicle.plausibility import corner_findings
from rig.vehicle.rig_config import RigConfig
from rig.vehicle.suspensions import suspensions
from rig.vehicle.suspensions.bushings import parse_bushings
from rig.vehicle.suspensions.hardpoints import Kinematics, KinematicsError, parse_kinematics
from rig.vehicle.tables import AXLE_KEYS, GEOMETRY_KEYS, SPRUNG_KEYS, VehicleError, read_section
from rig.vehicle.truck_file import check_truck, truck_fields, truck_key_unit, truck_tables


def key_unit(key: str) -> str:
    """The unit of a vehicle-file key (a dotted path such as ``front.damping`` or a truck's ``axles.1.damping``),
    '' for a key not in the schema."""
    sections = {"geometry": GEOMETRY_KEYS, "sprung": SPRUNG_KEYS, "front": AXLE_KEYS, "rear": AXLE_KEYS}
    section, _, name = key.partition(".")
    if section not in sections:
        return truck_key_unit(key)
    return sections[section].get(name, ("",))[0]


def resolve_vehicle_path(name_or_path: str | os.PathLike) -> Path:
    """A built-in vehicle's file, or the given path; refuses names that are neither."""
    path = vehicle_path(name_or_path)
    if path is not None:
        return path
    if Path(name_or_path).suffix == ".toml" or Path(name_or_path).exists():
        raise VehicleError(f"vehicle file {name_or_path} does not exist")
    raise VehicleError(f"unknown vehicle '{name_or_path}': not a file, and not one of {', '.join(builtin_vehicles())}")


def load_vehicle(name_or_path: str | os.PathLike) -> Vehicle:
    """Load and check a vehicle file (built-in name or path)."""
    path = resolve_vehicle_path(name_or_path)
    try:
        data = tomllib.loads(read_text(path, "vehicle file", VehicleError))
    except tomllib.TOMLDecodeError as err:
        raise VehicleError(f"{path}: not valid TOML ({err})") from None
    return vehicle_from_dict(data, str(path))


def vehicle_from_dict(data: dict, where: str = "vehicle") -> Vehicle:
    """Build a Vehicle from the parsed TOML tables (see docs/contracts.md for the keys)."""
    layout = data.get("layout", DEFAULT)
    try:
        layout_type = layout_named(layout)
    except ValueError as err:
        raise VehicleError(f"{where}: {err}") from None
    name = data.get("name")
    if not isinstance(name, str) or not name:
        raise VehicleError(f"{where}: missing 'name'")
    if layout_type.axle_list:
        values, known = truck_fields(data, where)
        axles = axle_names(1 + len(values["middle"]) + 1)
    else:
        values, known = _car_fields(data, layout_type, where)
        axles = axle_names(2) if layout_type.footprint else ("front",)
    try:
        rig = RigConfig.from_table(data.get("rig", {}), where)
    except ValueError as err:
        raise VehicleError(str(err)) from None
    sections = {name: extension for name, extension in extensions().items() if extension.has_section()}
    try:
        values_of = {name: section.parse(data[name], where, axles)
                     for name, section in sections.items() if name in data}
    except ValueError as err:
        raise VehicleError(str(err)) from None
    known = {"name", "layout", "rig", *known, *sections}
    unknown = sorted(set(data) - known)
    if unknown:
        raise VehicleError(f"{where}: unknown section(s) {', '.join(unknown)} (known: {', '.join(sorted(known))})")
    vehicle = Vehicle(name=name, layout=layout, rig=rig, source=where, extensions=values_of, **values)
    implausible = corner_findings(vehicle)
    if implausible:
        raise VehicleError(f"{where}: {implausible[0]}")
    try:
        for extension in values_of:
            sections[extension].check(vehicle)
    except ValueError as err:
        raise VehicleError(str(err)) from None
    if layout_type.axle_list:
        check_truck(vehicle)
    return vehicle


def _car_fields(data: dict, layout: Layout, where: str) -> tuple[dict, tuple[str, ...]]:
    """A car's (or quarter car's) Vehicle fields from its tables, and the sections they come from."""
    full = layout.footprint
    sprung_keys = SPRUNG_KEYS if full else {"mass": SPRUNG_KEYS["mass"]}
    geometry_keys = GEOMETRY_KEYS if full else {k: GEOMETRY_KEYS[k] for k in ("cg_height", "wheel_radius")}
    geometry = read_section(data, "geometry", geometry_keys, where, required=full)
    sprung = read_section(data, "sprung", sprung_keys, where)
    front = _axle(data, "front", where, geometry.get("track_front") if full else None)
    rear = _axle(data, "rear", where, geometry.get("track_rear")) if full else None
    if full and not 0 < geometry["cg_to_front_axle"] < geometry["wheelbase"]:
        raise VehicleError(f"{where}: [geometry] cg_to_front_axle must lie between 0 and the wheelbase")
    sprung = {("sprung_mass" if k == "mass" else k): v for k, v in sprung.items()}
    if full and "yaw_inertia" not in sprung:
        sprung["yaw_inertia"] = 0.9 * (sprung["pitch_inertia"] + sprung["roll_inertia"])  # no yaw DOF: any valid value
    return {"front": front, "rear": rear, **geometry, **sprung}, ("geometry", "sprung", "front", "rear")


def _axle(data: dict, axle: str, where: str, track: float | None) -> Axle:
    """An axle's table and its optional linkage (``[<axle>.kinematics]``), whose wheel centre must stand on the
    track and whose loop must close at design."""
    table = data.get(axle)
    if not isinstance(table, dict) or "kinematics" not in table:
        if isinstance(table, dict) and "bushings" in table:
            raise VehicleError(f"{where}: [{axle}.bushings] needs the linkage's [{axle}.kinematics]")
        return Axle(**read_section(data, axle, AXLE_KEYS, where))
    rest = {k: v for k, v in table.items() if k not in ("kinematics", "bushings")}
    values = read_section({axle: rest}, axle, AXLE_KEYS, where)
    try:
        if track is None:
            raise KinematicsError(f"{where}: [{axle}.kinematics] needs a full car (a quarter car has no track)")
        kinematics = parse_kinematics(table["kinematics"], where, axle)
        if "bushings" in table:
            kinematics = dataclasses.replace(kinematics, bushings=parse_bushings(table["bushings"], where, axle,
                                                                                 kinematics))
        _check_station(kinematics, track, f"{where}: [{axle}.kinematics]")
        suspensions()[kinematics.type].check(kinematics, f"{where}: [{axle}.kinematics]")
    except KinematicsError as err:
        raise VehicleError(str(err)) from None
    return Axle(**values, kinematics=kinematics)


def _check_station(kinematics: Kinematics, track: float, where: str) -> None:
    """The hardpoints' origin is under the axle's centre, x = 0 at the design wheel centres: the wheel centre must
    be at x = 0 and y = track / 2 (within a millimetre)."""
    x, y, _ = kinematics.points["wheel_centre"]
    if abs(x) > 1e-3:
        raise KinematicsError(f"{where} wheel_centre x = {x} m: the axle's origin is under the design wheel centres, "
                              f"so x must be 0")
    if abs(y - track / 2) > 1e-3:
        raise KinematicsError(f"{where} wheel_centre y = {y} m is not half the track ({track / 2} m)")


def vehicle_to_toml(vehicle: Vehicle, comment: str = "") -> str:
    """The vehicle as a vehicle file (the keys load_vehicle reads), e.g. an extended model to diff and reuse."""
    lines = [f"# {line}" for line in comment.splitlines()] + [f'name = "{vehicle.name}"']
    if vehicle.layout != DEFAULT:
        lines.append(f'layout = "{vehicle.layout}"')
    tables = truck_tables(vehicle) if vehicle.layout_type.axle_list else _car_tables(vehicle)
    tables["rig"] = {f: getattr(vehicle.rig, f) for f in vehicle.rig.__dataclass_fields__}
    tables.update({name: extensions()[name].to_table(value) for name, value in vehicle.extensions.items()})
    for name, table in tables.items():
        for element in table if isinstance(table, list) else [table]:
            plain = {k: v for k, v in element.items() if not isinstance(v, dict)}
            nested = {k: v for k, v in element.items() if isinstance(v, dict)}
            if plain or isinstance(table, list):
                header = f"[[{name}]]" if isinstance(table, list) else f"[{name}]"
                lines += ["", header] + [f"{_key(k)} = {_value(v)}" for k, v in plain.items()]
            lines += _sub_tables(name, nested)
    return "\n".join(lines) + "\n"


def _sub_tables(name: str, nested: dict) -> list[str]:
    """TOML lines of the tables ``[name.sub]`` (and deeper: ``[front.bushings.lower_front]``)."""
    lines = []
    for sub, values in nested.items():
        plain = {k: v for k, v in values.items() if not isinstance(v, dict)}
        if plain or not values:
            lines += ["", f"[{name}.{sub}]"] + [f"{_key(k)} = {_value(v)}" for k, v in plain.items()]
        lines += _sub_tables(f"{name}.{sub}", {k: v for k, v in values.items() if isinstance(v, dict)})
    return lines


def _car_tables(vehicle: Vehicle) -> dict:
    geometry = {k: getattr(vehicle, k) for k in GEOMETRY_KEYS} if vehicle.layout_type.footprint else \
        {k: getattr(vehicle, k) for k in ("cg_height", "wheel_radius")}
    sprung = {"mass": vehicle.sprung_mass}
    if vehicle.layout_type.footprint:
        sprung.update(pitch_inertia=vehicle.pitch_inertia, roll_inertia=vehicle.roll_inertia,
                      yaw_inertia=vehicle.yaw_inertia)
    tables = {"geometry": geometry, "sprung": sprung, "front": _axle_table(vehicle.front)}
    if vehicle.rear is not None:
        tables["rear"] = _axle_table(vehicle.rear)
    return tables


def _axle_table(axle: Axle) -> dict:
    table = {k: getattr(axle, k) for k in AXLE_KEYS}
    if axle.kinematics is not None:
        table["kinematics"] = axle.kinematics.to_table()
        if axle.kinematics.bushings:
            table["bushings"] = {joint: b.to_table() for joint, b in axle.kinematics.bushings.items()}
    return table


def _key(key: str) -> str:
    return key if key.replace("_", "").isalnum() else f'"{key}"'


def _value(value: object) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_value(v) for v in value) + "]"
    return repr(float(value)) if isinstance(value, (int, float)) else f'"{value}"'
