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
from dataclasses import dataclass, field
from pathlib import Path

from rig.errors import RigError
from rig.causes import CAUSES
from rig.causes._base import AXLES
from rig.io.channels import CORNERS, axle_corners, axle_names, corner_axle
from rig.io.text import read_text
from rig.vehicle.assets import builtin_vehicles, vehicle_path
from rig.vehicle.plausibility import corner_findings
from rig.vehicle.rig_config import RigConfig
from rig.vehicle.suspensions import suspensions
from rig.vehicle.suspensions.bushings import parse_bushings
from rig.vehicle.suspensions.hardpoints import Kinematics, KinematicsError, parse_kinematics


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


def key_unit(key: str) -> str:
    """The unit of a vehicle-file key (a dotted path such as ``front.damping`` or a truck's ``axles.1.damping``),
    '' for a key not in the schema."""
    from rig.vehicle.truck_file import truck_key_unit

    sections = {"geometry": GEOMETRY_KEYS, "sprung": SPRUNG_KEYS, "front": AXLE_KEYS, "rear": AXLE_KEYS}
    section, _, name = key.partition(".")
    if section not in sections:
        return truck_key_unit(key)
    return sections[section].get(name, ("",))[0]


_DEFAULTS = {"parasitic_rate": 0.0, "tyre_damping": 0.0, "cg_height": 0.55, "wheel_radius": 0.30}
_LAYOUTS = ("full", "quarter", "truck")


@dataclass(frozen=True)
class Axle:
    """Per-corner parameters of one axle (both corners alike), at the wheel."""

    unsprung_mass: float
    spring_rate: float
    parasitic_rate: float
    damping: float
    tyre_rate: float
    tyre_damping: float
    kinematics: Kinematics | None = None  # a linkage's hardpoints; None: the vertical slider
    # layout 'truck' (rig/vehicle/truck_file.py): where the axle is and what it is
    position: float = 0.0       # m behind the front axle
    track: float = 0.0          # m between the wheel stations' centres
    tyres: str = "single"       # 'single' or 'dual' (two tyres at each station, dual_spacing apart)
    dual_spacing: float = 0.0   # m between the centres of a station's dual tyres
    suspension: str = ""        # suspension type (rig/vehicle/suspensions/); '' on a car: its kinematics, or vertical
    spring_track: float = 0.0   # m between a beam axle's springs
    damper_track: float = 0.0   # m between a beam axle's dampers
    roll_inertia: float = 0.0   # kg m^2, a beam axle's about its centre
    law: object | None = None   # the springs' own law: LeafFriction (beam_leaf), AirSpring (beam_air)

    @property
    def suspension_rate(self) -> float:
        """Spring plus parasitic (bushing) rate in N/m: k_s + k_p of Nurhadiyanto's eq. 3.1."""
        return self.spring_rate + self.parasitic_rate


@dataclass(frozen=True)
class Vehicle:
    """A vehicle file, parsed and checked. Lengths in m, masses in kg, rates in N/m, damping in N s/m."""

    name: str
    layout: str
    sprung_mass: float
    front: Axle
    rear: Axle | None
    middle: tuple[Axle, ...] = ()  # a truck's axles between its front and rear axle, front to rear
    wheelbase: float = 0.0
    cg_to_front_axle: float = 0.0
    track_front: float = 0.0
    track_rear: float = 0.0
    cg_height: float = 0.55
    wheel_radius: float = 0.30
    pitch_inertia: float = 0.0
    roll_inertia: float = 0.0
    yaw_inertia: float = 0.0
    rig: RigConfig = field(default_factory=RigConfig)
    extensions: dict = field(default_factory=dict)  # cause -> parameters (rig/causes/)
    source: str = ""
    frame: object | None = None      # a truck's flexible frame (rig/vehicle/frame.py); None: rigid
    cab: object | None = None        # a truck's cab on its mounts (rig/vehicle/mounted_body.py)
    driveline: object | None = None  # a truck's engine and gearbox on their mounts

    @property
    def axles(self) -> tuple[Axle, ...]:
        """The axles front to rear."""
        return (self.front,) if self.rear is None else (self.front, *self.middle, self.rear)

    @property
    def axle_names(self) -> tuple[str, ...]:
        """Their names: ``front``, [``middle`` | ``middle1``, ...], ``rear`` (docs/contracts.md)."""
        return axle_names(len(self.axles))

    @property
    def corners(self) -> tuple[str, ...]:
        if self.layout == "full":
            return CORNERS
        if self.layout == "quarter":
            return ("FL",)
        return tuple(c for axle in self.axle_names for c in axle_corners(axle))

    def axle(self, corner: str) -> Axle:
        return self.axle_named(corner_axle(corner))

    def axle_named(self, name: str) -> Axle:
        """The axle called ``name`` (``front``, ``middle``, ``rear``...); ValueError names the vehicle's axles."""
        names = self.axle_names
        if name not in names:
            raise ValueError(f"{self.name} has no {name!r} axle (its axles: {', '.join(names)})")
        return self.axles[names.index(name)]

    def with_axle(self, name: str, axle: Axle) -> Vehicle:
        """This vehicle with axle ``name`` replaced."""
        self.axle_named(name)  # refuses a name the vehicle does not have
        index = self.axle_names.index(name)
        if index == 0:
            return dataclasses.replace(self, front=axle)
        if index == len(self.axle_names) - 1:
            return dataclasses.replace(self, rear=axle)
        middle = list(self.middle)
        middle[index - 1] = axle
        return dataclasses.replace(self, middle=tuple(middle))

    def corner_position(self, corner: str) -> tuple[float, float]:
        """(x, y) of the corner relative to the sprung CG in m: x forward, y left."""
        if self.layout == "quarter":
            return 0.0, 0.0
        side = 1 if corner.endswith("L") else -1
        if self.layout == "truck":
            axle = self.axle(corner)
            return self.cg_to_front_axle - axle.position, side * axle.track / 2
        front = corner[0] == "F"
        x = self.cg_to_front_axle if front else self.cg_to_front_axle - self.wheelbase
        track = self.track_front if front else self.track_rear
        return x, side * track / 2


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
    layout = data.get("layout", "full")
    if layout not in _LAYOUTS:
        raise VehicleError(f"{where}: layout must be one of {', '.join(_LAYOUTS)}, got {layout!r}")
    name = data.get("name")
    if not isinstance(name, str) or not name:
        raise VehicleError(f"{where}: missing 'name'")
    if layout == "truck":
        from rig.vehicle.truck_file import truck_fields

        values, known = truck_fields(data, where)
        axles = axle_names(1 + len(values["middle"]) + 1)
    else:
        values, known = _car_fields(data, layout, where)
        axles = AXLES if layout == "full" else ("front",)
    try:
        rig = RigConfig.from_table(data.get("rig", {}), where)
    except ValueError as err:
        raise VehicleError(str(err)) from None
    sections = {name: cause for name, cause in CAUSES.items() if cause.has_section()}
    try:
        extensions = {name: cause.parse(data[name], where, axles) for name, cause in sections.items() if name in data}
    except ValueError as err:
        raise VehicleError(str(err)) from None
    known = {"name", "layout", "rig", *known, *sections}
    unknown = sorted(set(data) - known)
    if unknown:
        raise VehicleError(f"{where}: unknown section(s) {', '.join(unknown)} (known: {', '.join(sorted(known))})")
    vehicle = Vehicle(name=name, layout=layout, rig=rig, source=where, extensions=extensions, **values)
    implausible = corner_findings(vehicle)
    if implausible:
        raise VehicleError(f"{where}: {implausible[0]}")
    try:
        for cause in extensions:
            CAUSES[cause].check(vehicle)
    except ValueError as err:
        raise VehicleError(str(err)) from None
    if layout == "truck":
        from rig.vehicle.truck_file import check_truck

        check_truck(vehicle)
    return vehicle


def _car_fields(data: dict, layout: str, where: str) -> tuple[dict, tuple[str, ...]]:
    """A car's (or quarter car's) Vehicle fields from its tables, and the sections they come from."""
    full = layout == "full"
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


def vehicle_to_toml(vehicle: Vehicle, comment: str = "") -> str:
    """The vehicle as a vehicle file (the keys load_vehicle reads), e.g. an extended model to diff and reuse."""
    lines = [f"# {line}" for line in comment.splitlines()] + [f'name = "{vehicle.name}"']
    if vehicle.layout != "full":
        lines.append(f'layout = "{vehicle.layout}"')
    if vehicle.layout == "truck":
        from rig.vehicle.truck_file import truck_tables

        tables = truck_tables(vehicle)
    else:
        tables = _car_tables(vehicle)
    tables["rig"] = {f: getattr(vehicle.rig, f) for f in vehicle.rig.__dataclass_fields__}
    tables.update({name: CAUSES[name].to_table(value) for name, value in vehicle.extensions.items()})
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
    geometry = {k: getattr(vehicle, k) for k in GEOMETRY_KEYS} if vehicle.layout == "full" else \
        {k: getattr(vehicle, k) for k in ("cg_height", "wheel_radius")}
    sprung = {"mass": vehicle.sprung_mass}
    if vehicle.layout == "full":
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
