"""A truck's cab, or its driveline (engine and gearbox), as a rigid body on four mounts on the frame.

``[cab]`` and ``[driveline]`` (layout ``truck``) give the body's mass, pitch and roll inertia about its CG, its CG
(``position`` m behind the front axle, ``height`` m above the sprung CG), and four vertical mounts, a front pair and
a rear pair ``mount_base`` apart and ``mount_track`` wide, each a spring ``stiffness`` (N/m) and damper ``damping``
(N s/m) to the frame below. The body moves in heave, pitch and roll (its own slide and hinges at its CG); each mount
is a fixed tendon whose length is the frame point's rise less the body point's, in joint coordinates for small
angles, with the mount's stiffness and damping: inside ``mj_step``, and upright whatever the frame's pitch.
The cab carries the seat point (``seat`` = [x, y, z] m from the cab's CG, x forward, y left): ``cab/seat_acc`` is its
vertical acceleration, which ``rig.signal.comfort.weighted_rms`` weights by ISO 2631-1 Wk. The sprung mass of the
vehicle file is then the rest of the sprung mass: frame, load and everything else.

A body may stand on air springs instead (``[cab.air_spring]``: area, volume, pressure, polytropic_index, area_slope of
each of the four, rig/elements/air_spring.py), as Forsén's cab does: the mounts' springs then follow the polytropic
law about the design height, the drawn position (``stiffness`` is not given: it is the law's rate there), realised as
a cubic fitted over +-40 mm; their dampers are ``damping``.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field, fields

import numpy as np

from rig.elements.air_spring import MountAirSpring
from rig.elements.parameters import param, parse_values

MOUNTED_BODIES = ("cab", "driveline")
MOUNTS = ("front_left", "front_right", "rear_left", "rear_right")
SEAT_SITE = "cab/seat"


@dataclass(frozen=True)
class MountedBody:
    """A rigid body on four vertical spring-damper mounts (SI)."""

    mass: float = field(metadata=param("kg", 10.0, 5000.0, "mass"))
    pitch_inertia: float = field(metadata=param("kg m^2", 1.0, 1e5, "about its CG"))
    roll_inertia: float = field(metadata=param("kg m^2", 1.0, 1e5, "about its CG"))
    position: float = field(metadata=param("m", -5.0, 20.0, "its CG behind the front axle"))
    height: float = field(metadata=param("m", -2.0, 4.0, "its CG above the sprung CG"))
    mount_base: float = field(metadata=param("m", 0.1, 5.0, "between the front and rear mounts"))
    mount_track: float = field(metadata=param("m", 0.1, 3.0, "between the left and right mounts"))
    stiffness: float = field(metadata=param("N/m", 1e3, 1e8, "vertical rate of each mount"))
    damping: float = field(metadata=param("N s/m", 0.0, 1e6, "vertical damping of each mount"))
    seat: tuple[float, float, float] | None = None  # m from the CG (the cab's seat point)
    air_spring: MountAirSpring | None = None  # each mount's spring is this air spring (``stiffness``: its rate)

    def mount_points(self) -> np.ndarray:
        """(4, 2) mount positions (x forward, y left) relative to the body's CG, in MOUNTS order."""
        x, y = self.mount_base / 2, self.mount_track / 2
        return np.array([[x, y], [x, -y], [-x, y], [-x, -y]])

    def to_table(self) -> dict:
        skip = {"seat", "air_spring"} | ({"stiffness"} if self.air_spring is not None else set())
        table = {f.name: getattr(self, f.name) for f in fields(self) if f.name not in skip}
        if self.seat is not None:
            table["seat"] = list(self.seat)
        if self.air_spring is not None:
            table["air_spring"] = dataclasses.asdict(self.air_spring)
        return table


def parse_mounted_body(table: object, section: str, where: str) -> MountedBody:
    """``[cab]`` or ``[driveline]``; ValueError names the key that is wrong."""
    if not isinstance(table, dict):
        raise ValueError(f"{where}: [{section}] must be a table")
    air = "air_spring" in table
    if air and "stiffness" in table:
        raise ValueError(f"{where}: [{section}] give stiffness or [{section}.air_spring], not both (the air springs' "
                         f"rate is their law's)")
    numbers = [f for f in fields(MountedBody) if f.name not in ("seat", "air_spring") and not (
        air and f.name == "stiffness")]
    known = [f.name for f in numbers] + (["seat"] if section == "cab" else []) + ["air_spring"]
    unknown = sorted(set(table) - set(known))
    missing = [f.name for f in numbers if f.name not in table]
    if unknown or missing:
        raise ValueError(f"{where}: [{section}] " + "; ".join(
            ([f"unknown key(s) {', '.join(unknown)}"] if unknown else [])
            + ([f"missing {', '.join(missing)}"] if missing else [])) + f" (keys: {', '.join(known)})")
    values = {}
    for f in numbers:
        value, meta = table[f.name], f.metadata
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not meta["low"] <= value <= meta["high"]:
            raise ValueError(f"{where}: [{section}] {f.name} = {value!r} is outside the plausible range "
                             f"{meta['low']:g}..{meta['high']:g} {meta['unit']}")
        values[f.name] = float(value)
    seat = table.get("seat")
    if seat is not None:
        if (not isinstance(seat, list) or len(seat) != 3
                or not all(isinstance(v, (int, float)) and not isinstance(v, bool) and abs(v) <= 3.0 for v in seat)):
            raise ValueError(f"{where}: [{section}] seat must be [x, y, z] in m from the cab's CG (each within 3 m), "
                             f"got {seat!r}")
        values["seat"] = tuple(float(v) for v in seat)
    if air:
        values["air_spring"] = parse_values(MountAirSpring, table["air_spring"], f"{where}: [{section}.air_spring]")
        values["stiffness"] = values["air_spring"].rate
    return MountedBody(**values)
