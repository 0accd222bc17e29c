"""Layout ``truck`` of the vehicle file (docs/contracts.md, docs/trucks.md): axles in an ``[[axles]]`` array.

```toml
layout = "truck"
[geometry]      # wheelbase (first to last axle), cg_to_front_axle, cg_height, wheel_radius
[sprung]        # mass, pitch_inertia, roll_inertia (of the frame and load: the cab and driveline have their own)
[[axles]]       # front to rear; one wheel station (corner, post) at each end
position = 0.0          # m behind the front axle: 0 for the first, the wheelbase for the last
track = 2.05            # m between the stations
tyres = "single"        # or "dual": two tyres per station, dual_spacing (m) between their centres
suspension = "beam_leaf"  # vertical | beam_leaf | beam_air (rig/vehicle/suspensions/)
unsprung_mass = 400.0   # kg per station (a beam axle weighs twice this)
spring_rate = 3.0e5     # N/m, each spring (a beam axle's at spring_track; not for beam_air)
damping = 1.5e4         # N s/m, each damper (a beam axle's at damper_track, default spring_track)
tyre_rate = 9.0e5       # N/m per tyre
spring_track = 0.9      # m between a beam axle's springs
[axles.leaf_spring]     # beam_leaf: Fancher's inter-leaf friction (rig/elements/leaf_spring.py)
[axles.air_spring]      # beam_air: the gas law (rig/elements/air_spring.py)
[frame] [cab] [driveline]   # optional (rig/elements/frame.py, rig/elements/mounted_body.py)
```
Corners are named by the axles: ``FL FR``, then ``ML MR`` for one middle axle (``M1L M1R``, ``M2L M2R``, ... for more),
then ``RL RR``. An axle outside the wheelbase, dual tyres without their spacing and an air spring without volume are
refused with a message naming the key.
"""

from __future__ import annotations

import dataclasses
from dataclasses import fields

from rig.io.channels import axle_names
from rig.elements.frame import Frame, parse_frame, segments_of
from rig.elements.mounted_body import MOUNTED_BODIES, parse_mounted_body
from rig.vehicle.suspensions import suspensions
from rig.vehicle.parts import Axle, Vehicle
from rig.vehicle.tables import AXLE_KEYS as CAR_AXLE_KEYS
from rig.vehicle.tables import SPRUNG_KEYS, VehicleError, read_section

TYRES = ("single", "dual")

GEOMETRY_KEYS = {
    "wheelbase": ("m", 1.0, 20.0, True),
    "cg_to_front_axle": ("m", 0.0, 20.0, True),
    "cg_height": ("m", 0.1, 3.0, False),
    "wheel_radius": ("m", 0.1, 1.5, False),
}
AXLE_KEYS = {
    "position": ("m", 0.0, 20.0, True),
    "track": ("m", 0.5, 3.5, True),
    **CAR_AXLE_KEYS,  # masses and rates: as a car's (rig/vehicle/plausibility.py judges them)
    "spring_rate": (*CAR_AXLE_KEYS["spring_rate"][:3], False),  # an air-sprung axle has none
    "dual_spacing": ("m", 0.2, 0.8, False),
    "spring_track": ("m", 0.2, 3.5, False),
    "damper_track": ("m", 0.2, 3.5, False),
    "roll_inertia": ("kg m^2", 1.0, 1e4, False),
}
_TEXT_KEYS = ("tyres", "suspension")
_DEFAULTS = {"parasitic_rate": 0.0, "tyre_damping": 0.0, "cg_height": 1.0, "wheel_radius": 0.5}


def truck_key_unit(key: str) -> str:
    """The unit of a truck's vehicle-file key (``axles.1.damping``, ``frame.length``), '' if unknown."""
    parts = key.split(".")
    if parts[0] == "axles" and len(parts) == 3:
        return AXLE_KEYS.get(parts[2], ("",))[0]
    if parts[0] in ("geometry", "sprung") and len(parts) == 2:
        return {**GEOMETRY_KEYS, **SPRUNG_KEYS}.get(parts[1], ("",))[0]
    return ""


def truck_fields(data: dict, where: str) -> tuple[dict, tuple[str, ...]]:
    """A truck's Vehicle fields from its tables, and the sections they come from."""
    geometry = read_section(data, "geometry", GEOMETRY_KEYS, where, defaults=_DEFAULTS)
    sprung = read_section(data, "sprung", SPRUNG_KEYS, where)
    wheelbase = geometry["wheelbase"]
    if not 0 < geometry["cg_to_front_axle"] < wheelbase:
        raise VehicleError(f"{where}: [geometry] cg_to_front_axle must lie between 0 and the wheelbase")
    tables = data.get("axles")
    if not isinstance(tables, list) or len(tables) < 2 or not all(isinstance(t, dict) for t in tables):
        raise VehicleError(f"{where}: layout 'truck' needs an [[axles]] array of at least two tables, front to rear")
    names = axle_names(len(tables))
    axles = [_truck_axle(table, i, name, wheelbase, where) for i, (table, name) in enumerate(zip(tables, names))]
    _check_positions(axles, names, wheelbase, where)
    sprung = {("sprung_mass" if k == "mass" else k): v for k, v in sprung.items()}
    sprung.setdefault("yaw_inertia", 0.9 * (sprung["pitch_inertia"] + sprung["roll_inertia"]))
    values = {"front": axles[0], "rear": axles[-1], "middle": tuple(axles[1:-1]), **geometry, **sprung,
              "track_front": axles[0].track, "track_rear": axles[-1].track}
    try:
        if "frame" in data:
            values["frame"] = parse_frame(data["frame"], where, sprung["sprung_mass"], sprung["roll_inertia"])
            _check_frame(values, where)
        for body in MOUNTED_BODIES:
            if body in data:
                values[body] = parse_mounted_body(data[body], body, where)
    except ValueError as err:
        raise VehicleError(str(err)) from None
    return values, ("geometry", "sprung", "axles", "frame", *MOUNTED_BODIES)


def _truck_axle(table: dict, index: int, name: str, wheelbase: float, where: str) -> Axle:
    label = f"[[axles]] {index + 1} ({name})"
    suspension = table.get("suspension", "vertical")
    types = {n: s for n, s in suspensions().items() if s.truck_axle}
    if suspension not in types:
        raise VehicleError(f"{where}: {label} suspension must be one of {', '.join(types)}, got {suspension!r}")
    tyres = table.get("tyres", "single")
    if tyres not in TYRES:
        raise VehicleError(f"{where}: {label} tyres must be one of {', '.join(TYRES)}, got {tyres!r}")
    law_section = types[suspension].law
    numbers = {k: v for k, v in table.items() if k not in _TEXT_KEYS and not isinstance(v, dict)}
    nested = sorted(k for k, v in table.items() if isinstance(v, dict))
    allowed = [law_section[0]] if law_section else []
    if set(nested) - set(allowed):
        raise VehicleError(f"{where}: {label} has sub-table(s) {', '.join(nested)}; a {suspension} axle takes "
                           f"{' or '.join(allowed) or 'none'}")
    values = read_section({"axle": numbers}, "axle", AXLE_KEYS, where, label=label, defaults=_DEFAULTS)
    kind = types[suspension]
    if tyres == "dual" and "dual_spacing" not in values:
        raise VehicleError(f"{where}: {label} tyres = \"dual\" needs dual_spacing (m between the two tyres' centres)")
    if tyres == "single" and "dual_spacing" in values:
        raise VehicleError(f"{where}: {label} dual_spacing is for tyres = \"dual\"")
    law = None
    if law_section:
        key, law_kind, needed = law_section
        if key in table:
            law = _law(law_kind, table[key], f"{label} {key}", where)
        elif needed:
            raise VehicleError(f"{where}: {label} a {suspension} axle needs its [axles.{key}] table")
    rate = kind.law_rate(law)
    if rate is None and "spring_rate" not in values:
        raise VehicleError(f"{where}: {label} is missing 'spring_rate' (N/m)")
    try:
        values = kind.complete_axle(values, label)
    except ValueError as err:
        raise VehicleError(f"{where}: {err}") from None
    values["spring_rate"] = values.get("spring_rate", 0.0) if rate is None else rate
    return Axle(**values, tyres=tyres, suspension=suspension, law=law)


def _law(kind: type, table: dict, label: str, where: str) -> object:
    names = [f.name for f in fields(kind)]
    keys = {f.name: (f.metadata["unit"], f.metadata["low"], f.metadata["high"],
                     f.default is dataclasses.MISSING) for f in fields(kind)}
    values = read_section({"law": table}, "law", keys, where, label=f"{label}", defaults={})
    return kind(**{k: values[k] for k in names if k in values})


def _check_positions(axles: list[Axle], names: tuple[str, ...], wheelbase: float, where: str) -> None:
    for i, (axle, name) in enumerate(zip(axles, names)):
        label = f"[[axles]] {i + 1} ({name})"
        if not -1e-9 <= axle.position <= wheelbase + 1e-9:
            raise VehicleError(f"{where}: {label} position = {axle.position:g} m lies outside the wheelbase "
                               f"(0..{wheelbase:g} m, [geometry] wheelbase)")
        if i and axle.position <= axles[i - 1].position:
            raise VehicleError(f"{where}: {label} position = {axle.position:g} m is not behind the axle before it "
                               f"({axles[i - 1].position:g} m): list the axles front to rear")
        if axle.tyres == "dual" and axle.dual_spacing >= axle.track:
            raise VehicleError(f"{where}: {label} dual_spacing = {axle.dual_spacing:g} m is not below the track")
    if abs(axles[0].position) > 1e-3 or abs(axles[-1].position - wheelbase) > 1e-3:
        raise VehicleError(f"{where}: [[axles]] positions run from 0 (the front axle) to the wheelbase "
                           f"({wheelbase:g} m, the last axle); got {axles[0].position:g} and {axles[-1].position:g} m")


def check_truck(vehicle: Vehicle) -> None:
    """A frame a cause gives (``[frame_flexibility]``) reaches the last axle and can carry the sprung mass spread
    along it (VehicleError); ``[frame]`` itself is checked as it is read."""
    from rig.vehicle.truck_mjcf import frame_of

    try:
        frame = frame_of(vehicle)
        if frame is None or frame is vehicle.frame:
            return
        _check_frame({"frame": frame, **{k: getattr(vehicle, k) for k in (
            "wheelbase", "cg_to_front_axle", "sprung_mass", "roll_inertia", "pitch_inertia")}},
            f"{vehicle.source}: the frame of [frame_flexibility]")
    except ValueError as err:
        raise VehicleError(str(err)) from None


def _check_frame(values: dict, where: str) -> None:
    frame: Frame = values["frame"]
    rear_end = frame.length - frame.front_overhang
    if rear_end < values["wheelbase"]:
        raise ValueError(f"{where}: [frame] length = {frame.length:g} m does not reach the last axle "
                         f"(front_overhang {frame.front_overhang:g} m + wheelbase {values['wheelbase']:g} m)")
    try:
        segments_of(frame, values["cg_to_front_axle"], values["sprung_mass"], values["roll_inertia"],
                    values["pitch_inertia"])
    except ValueError as err:
        raise ValueError(f"{where}: [frame] {err}") from None


def truck_tables(vehicle: Vehicle) -> dict:
    """A truck's tables as vehicle_to_toml writes them (``axles`` a list of tables)."""
    geometry = {k: getattr(vehicle, k) for k in GEOMETRY_KEYS}
    sprung = {"mass": vehicle.sprung_mass, "pitch_inertia": vehicle.pitch_inertia,
              "roll_inertia": vehicle.roll_inertia, "yaw_inertia": vehicle.yaw_inertia}
    tables = {"geometry": geometry, "sprung": sprung, "axles": [_axle_table(a) for a in vehicle.axles]}
    if vehicle.frame is not None:
        tables["frame"] = vehicle.frame.to_table()
    for body in MOUNTED_BODIES:
        if getattr(vehicle, body) is not None:
            tables[body] = getattr(vehicle, body).to_table()
    return tables


def _axle_table(axle: Axle) -> dict:
    table = {"position": axle.position, "track": axle.track, "tyres": axle.tyres, "suspension": axle.suspension}
    kind = suspensions()[axle.suspension]
    skip = {"spring_rate"} if kind.law_rate(axle.law) is not None else set()
    if axle.tyres == "single":
        skip.add("dual_spacing")
    skip |= {k for s in suspensions().values() for k in s.own_keys} - set(kind.own_keys)
    table.update({k: getattr(axle, k) for k in AXLE_KEYS if k not in table and k not in skip})
    if axle.law is not None:
        table[suspensions()[axle.suspension].law[0]] = dataclasses.asdict(axle.law)
    return table
