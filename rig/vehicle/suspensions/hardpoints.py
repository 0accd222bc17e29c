"""Hardpoints of a linkage corner: the ``[front.kinematics]`` / ``[rear.kinematics]`` table (docs/contracts.md).

Points are the LEFT corner's, in metres, vehicle axes (x forward, y left, z up), origin on the ground under the
axle's centre with x = 0 at the design wheel centres; the right corner is the mirror image (y -> -y). The table
is checked here for what can be checked without solving the loop (numbers, ranges, links of zero length); the
suspension type checks that its loop closes and moves at design (rig/vehicle/suspensions/geometry.py).

Keys beyond the contract (all optional):
- ``steered``: the tie rod's inner end sits on the steering rack (default: true at the front, false at the rear);
- ``rack_rate`` (N/m, default 5e6): stiffness of the steering at the rack, with the wheel on the ground held;
- ``bushing_rate`` = [kx, ky, kz] (N/m, vehicle axes) and ``bushing_damping`` = [cx, cy, cz] (N s/m): each arm's
  inner mount is compliant in translation by these rates (the two pivots' bushings together); without them it is
  rigid (per joint, with rotational rates too: ``[<axle>.bushings.<joint>]``, rig/vehicle/suspensions/bushings.py).
  As the source paper ("Validation of a Suspension Model and its Elastic Behaviour Demonstrated at the
  Formula Student Race Car of the University Duisburg-Essen") recalls, the elasticity of the parts can be
  lumped into the bearings;
- ``pushrod_outer``, ``pushrod_inner``, ``rocker_pivot``, ``rocker_axis`` (double wishbone): the spring and damper
  act through a pushrod from the lower arm and a rocker on the body (rig/vehicle/suspensions/rocker.py);
- ``lasers``: true adds the paper's laser distance sensors (three on a plate on the lower arm, four on a plate on
  the wheel carrier) to the model (rig/vehicle/suspensions/lasers.py).
"""

from __future__ import annotations

import math
import dataclasses
from dataclasses import dataclass, field

import numpy as np

from rig.errors import RigError

SUSPENSION_TYPES = ("double_wishbone", "macpherson")
COMMON_POINTS = ("lower_front", "lower_rear", "lower_outer", "tie_rod_inner", "tie_rod_outer", "wheel_centre")
TYPE_POINTS = {"double_wishbone": ("upper_front", "upper_rear", "upper_outer"),
               "macpherson": ("strut_top", "strut_lower")}
SPRING_POINTS = ("spring_lower", "spring_upper")
ROCKER_POINTS = ("pushrod_outer", "pushrod_inner", "rocker_pivot", "rocker_axis")  # double wishbone: rocker.py
MIN_LINK = 0.005  # m: a link shorter than this is taken for two names of one point
MAX_COORDINATE = 3.0  # m: hardpoints further from the axle's origin are a unit mistake
_ANGLES = {"static_camber": (-10.0, 10.0), "static_toe": (-5.0, 5.0)}  # deg
_RATES = {"rack_rate": (1e4, 1e9)}
_VECTORS = {"bushing_rate": (1e4, 1e10), "bushing_damping": (0.0, 1e6)}
DEFAULT_RACK_RATE = 5e6  # N/m: steering stiffness at the rack (column, rack and mounts in series), ASSUMPTION


class KinematicsError(RigError):
    """A kinematics table that cannot describe a linkage: names the point or key at fault."""


@dataclass(frozen=True)
class Kinematics:
    """A corner's linkage: its type and the left corner's hardpoints (m, vehicle axes, axle origin)."""

    type: str
    points: dict[str, tuple[float, float, float]]
    static_camber: float = 0.0   # deg, negative: top of the wheel inboard
    static_toe: float = 0.0      # deg, positive: toe-in
    steered: bool = False
    rack_rate: float = DEFAULT_RACK_RATE
    bushing_rate: tuple[float, float, float] | None = None
    bushing_damping: tuple[float, float, float] = (0.0, 0.0, 0.0)
    lasers: bool = False
    bushings: dict = field(default_factory=dict)  # joint -> Bushing ([<axle>.bushings.<joint>], bushings.py)

    def point(self, name: str, side: int = 1) -> np.ndarray:
        """A hardpoint of the left (``side`` +1) or right (-1) corner, m, axle frame."""
        x, y, z = self.points[name]
        return np.array([x, side * y, z])

    @property
    def has_spring_line(self) -> bool:
        return all(p in self.points for p in SPRING_POINTS)

    def to_table(self) -> dict:
        """The TOML table (inverse of ``parse_kinematics``)."""
        table: dict = {"type": self.type, **{k: list(v) for k, v in self.points.items()},
                       "static_camber": self.static_camber, "static_toe": self.static_toe, "steered": self.steered,
                       "rack_rate": self.rack_rate}
        if self.bushing_rate is not None:
            table["bushing_rate"] = list(self.bushing_rate)
            table["bushing_damping"] = list(self.bushing_damping)
        if self.lasers:
            table["lasers"] = True
        return table

    def moved(self, offsets: dict[str, np.ndarray]) -> Kinematics:
        """These kinematics with hardpoints moved by ``offsets`` (name -> m, left corner)."""
        points = dict(self.points)
        for name, offset in offsets.items():
            points[name] = tuple(float(v) for v in np.asarray(points[name]) + np.asarray(offset))
        return dataclasses.replace(self, points=points)


def parse_kinematics(table: object, where: str, axle: str) -> Kinematics:
    """A ``[<axle>.kinematics]`` table, checked: points of the type, numbers, ranges, no zero-length link."""
    section = f"[{axle}.kinematics]"
    if not isinstance(table, dict):
        raise KinematicsError(f"{where}: {section} must be a table")
    kind = table.get("type")
    if kind not in SUSPENSION_TYPES:
        raise KinematicsError(f"{where}: {section} type must be one of {', '.join(SUSPENSION_TYPES)}, got {kind!r}")
    required = COMMON_POINTS + TYPE_POINTS[kind]
    flags = ("steered", "lasers")
    rocker = ROCKER_POINTS if kind == "double_wishbone" else ()
    known = {"type", *required, *SPRING_POINTS, *rocker, *_ANGLES, *_RATES, *_VECTORS, *flags}
    unknown = sorted(set(table) - known)
    if unknown:
        raise KinematicsError(f"{where}: {section} unknown key(s) {', '.join(unknown)} (a {kind} has "
                              f"{', '.join(required + SPRING_POINTS)})")
    missing = [p for p in required if p not in table]
    if missing:
        raise KinematicsError(f"{where}: {section} is missing hardpoint(s) {', '.join(missing)} of a {kind}")
    springs = [p for p in SPRING_POINTS if p in table]
    if len(springs) == 1:
        raise KinematicsError(f"{where}: {section} {springs[0]} needs its other end "
                              f"({next(p for p in SPRING_POINTS if p not in table)})")
    rockers = [p for p in rocker if p in table]
    if rockers and (len(rockers) < len(ROCKER_POINTS) or len(springs) < 2):
        missing = [p for p in (*ROCKER_POINTS, *SPRING_POINTS) if p not in table]
        raise KinematicsError(f"{where}: {section} a pushrod and rocker needs {', '.join(missing)} too (the spring "
                              f"runs from the rocker, spring_lower, to the body, spring_upper)")
    points = {name: _point(table[name], f"{where}: {section} {name}")
              for name in required + tuple(springs) + tuple(rockers)}
    options = {key: _number(table[key], f"{where}: {section} {key}", *_ANGLES.get(key) or _RATES[key])
               for key in (*_ANGLES, *_RATES) if key in table}
    vectors = {key: tuple(_number(v, f"{where}: {section} {key}", *_VECTORS[key])
                          for v in _triple(table[key], f"{where}: {section} {key}"))
               for key in _VECTORS if key in table}
    if "bushing_damping" in vectors and "bushing_rate" not in vectors:
        raise KinematicsError(f"{where}: {section} bushing_damping needs bushing_rate (the bushings' stiffness)")
    for key in flags:
        if key in table and not isinstance(table[key], bool):
            raise KinematicsError(f"{where}: {section} {key} must be true or false, got {table[key]!r}")
    kinematics = Kinematics(type=kind, points=points, steered=bool(table.get("steered", axle == "front")),
                            lasers=bool(table.get("lasers", False)), **options, **vectors)
    check_links(kinematics, f"{where}: {section}")
    return kinematics


def links(kinematics: Kinematics) -> list[tuple[str, str]]:
    """Pairs of hardpoints joined by a rigid part (arms, upright or strut axis, tie rod, spring line)."""
    pairs = [("lower_front", "lower_rear"), ("lower_front", "lower_outer"), ("lower_rear", "lower_outer"),
             ("tie_rod_inner", "tie_rod_outer")]
    if kinematics.type == "double_wishbone":
        pairs += [("upper_front", "upper_rear"), ("upper_front", "upper_outer"), ("upper_rear", "upper_outer"),
                  ("lower_outer", "upper_outer")]
    else:
        pairs += [("strut_top", "strut_lower"), ("lower_outer", "strut_top")]
    if kinematics.has_spring_line:
        pairs.append(SPRING_POINTS)
    if all(p in kinematics.points for p in ROCKER_POINTS):
        pairs += [("pushrod_outer", "pushrod_inner"), ("rocker_pivot", "rocker_axis"),
                  ("rocker_pivot", "pushrod_inner"), ("rocker_pivot", "spring_lower")]
    return pairs


def check_links(kinematics: Kinematics, where: str) -> None:
    """Refuse a link of zero length (two names for one point) and an arm whose outer joint is on its axis."""
    for a, b in links(kinematics):
        length = float(np.linalg.norm(kinematics.point(a) - kinematics.point(b)))
        if length < MIN_LINK:
            raise KinematicsError(f"{where}: the link {a} - {b} has zero length ({length * 1e3:.2f} mm): "
                                  f"{b} must be a point of its own")
    arms = [("lower_front", "lower_rear", "lower_outer")]
    if kinematics.type == "double_wishbone":
        arms.append(("upper_front", "upper_rear", "upper_outer"))
    for front, rear, outer in arms:
        axis = kinematics.point(rear) - kinematics.point(front)
        arm = np.linalg.norm(np.cross(axis / np.linalg.norm(axis), kinematics.point(outer) - kinematics.point(front)))
        if arm < MIN_LINK:
            raise KinematicsError(f"{where}: {outer} lies on the axis {front} - {rear} ({arm * 1e3:.2f} mm off it): "
                                  f"the arm cannot carry the wheel")


def _triple(value: object, where: str) -> list:
    if not isinstance(value, (list, tuple)) or len(value) != 3:
        raise KinematicsError(f"{where} must be [x, y, z] (three numbers), got {value!r}")
    return list(value)


def _point(value: object, where: str) -> tuple[float, float, float]:
    coordinates = tuple(_number(v, where, -MAX_COORDINATE, MAX_COORDINATE) for v in _triple(value, where))
    return coordinates  # type: ignore[return-value]


def _number(value: object, where: str, low: float, high: float) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise KinematicsError(f"{where} must be a number, got {value!r}")
    if not low <= value <= high:
        raise KinematicsError(f"{where} = {value} is outside the plausible range {low:g}..{high:g} "
                              f"(hardpoints in m, angles in deg, rates in N/m)")
    return float(value)
