"""An independent model of a double-wishbone axle's compliance for the tests: linear statics of rigid bodies on
bushings, written from the contract (docs/kinematics.md) without the project's code.

Each corner's lower arm, upper arm and upright are rigid bodies displaced by small translations and rotations
(six coordinates each, about the axle frame's origin), the steering rack a slide across the body. Every joint is a
bushing between two parts at its hardpoint: per direction of its frame (axial along the joint's axis, two radial
across it) a spring of its rate or, without a table or a rate, a rigid constraint (a Lagrange multiplier); its
conical and torsional rates are springs on the parts' relative rotation. The tie rod is a two-force link: its two
ends' axial rates in series along the rod (rigid if neither has one). The coil acts along its line at the spring
rate over the motion ratio squared (the motion ratio from the reference kinematics, tests/kinematics_reference.py).
The K&C rig holds each wheel centre's height and lets it move freely in x and y. The loads' static preloads are
left out, so compliance is K^-1 per unit load at the design contact patch, K reduced to the motions the rigid
joints allow (their constraints' null space).
"""

from __future__ import annotations

import numpy as np
from scipy.linalg import null_space

from kinematics_reference import ReferenceCorner

PIVOTS = {"lower_front": "lower", "lower_rear": "lower", "upper_front": "upper", "upper_rear": "upper"}


def _unit(v):
    return np.asarray(v, float) / np.linalg.norm(v)


def _frame(axis):
    """Axial and two radial unit vectors of a joint with ``axis``."""
    axis = _unit(axis)
    helper = np.array([1.0, 0.0, 0.0]) if abs(axis[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    first = _unit(np.cross(axis, helper))
    return axis, first, np.cross(axis, first)


def _skew(p):
    return np.array([[0, -p[2], p[1]], [p[2], 0, -p[0]], [-p[1], p[0], 0]])


class LinearAxle:
    """An axle of two mirrored double-wishbone corners, from its kinematics and bushing tables as in a vehicle file."""

    def __init__(self, kinematics: dict, bushings: dict, spring_rate: float, loaded_radius: float,
                 rack_rate: float | None, parasitic_rate: float = 0.0):
        self.table, self.bushings = kinematics, bushings
        self.rack = rack_rate is not None
        self.size = 36 + (1 if self.rack else 0)
        self.stiffness = np.zeros((self.size, self.size))
        self.rows: list[np.ndarray] = []
        self.radius = loaded_radius
        for k, side in enumerate((1, -1)):
            self._corner(k, side, spring_rate, parasitic_rate)
        if self.rack:
            self.stiffness[36, 36] += rack_rate

    # coordinates
    def point(self, name, side):
        x, y, z = self.table[name]
        return np.array([x, side * y, z], float)

    def body(self, corner: int, part: str) -> int:
        return 18 * corner + 6 * ("lower", "upper", "upright").index(part)

    def motion(self, corner: int, part: str | None, p: np.ndarray) -> np.ndarray:
        """(3, size): displacement of the point ``p`` of a part (None: the ground) per coordinate."""
        out = np.zeros((3, self.size))
        if part is not None:
            start = self.body(corner, part)
            out[:, start:start + 3] = np.eye(3)
            out[:, start + 3:start + 6] = -_skew(p)
        return out

    def turn(self, corner: int, part: str | None) -> np.ndarray:
        out = np.zeros((3, self.size))
        if part is not None:
            start = self.body(corner, part) + 3
            out[:, start:start + 3] = np.eye(3)
        return out

    # elements
    def _spring(self, row: np.ndarray, rate: float) -> None:
        if np.isfinite(rate):
            self.stiffness += rate * np.outer(row, row)
        else:
            self.rows.append(row)

    def _joint(self, corner, side, name, parts, axis):
        """A bushing between ``parts`` (a, b; None: ground) at hardpoint ``name``."""
        table = self.bushings.get(name, {})
        p = self.point(name, side)
        relative = self.motion(corner, parts[1], p) - self.motion(corner, parts[0], p)
        axial, first, second = _frame(axis)
        self._spring(axial @ relative, table.get("axial", np.inf))
        for direction in (first, second):
            self._spring(direction @ relative, table.get("radial", np.inf))
        rotation = self.turn(corner, parts[1]) - self.turn(corner, parts[0])
        for direction, key in ((axial, "torsional"), (first, "conical"), (second, "conical")):
            if table.get(key, 0.0) > 0:
                self._spring(direction @ rotation, table[key])

    def _corner(self, corner, side, spring_rate, parasitic_rate):
        point = lambda name: self.point(name, side)  # noqa: E731
        for name, arm in PIVOTS.items():
            self._joint(corner, side, name, (None, arm), point(f"{arm}_rear") - point(f"{arm}_front"))
        kingpin = point("upper_outer") - point("lower_outer")
        self._joint(corner, side, "lower_outer", ("lower", "upright"), kingpin)
        self._joint(corner, side, "upper_outer", ("upper", "upright"), kingpin)
        inner, outer = point("tie_rod_inner"), point("tie_rod_outer")
        rod = _unit(outer - inner)
        elongation = rod @ self.motion(corner, "upright", outer)
        if self.rack:
            elongation = elongation - rod[1] * np.eye(self.size)[36]
        compliance = sum(1.0 / self.bushings.get(end, {}).get("axial", np.inf) for end in ("tie_rod_inner",
                                                                                              "tie_rod_outer"))
        self._spring(elongation, 1.0 / compliance if compliance > 0 else np.inf)
        upper, lower = point("spring_upper"), point("spring_lower")
        line = _unit(lower - upper)
        ratio, arm_rate = self._motion_ratio(side)
        self._spring(line @ self.motion(corner, "lower", lower), spring_rate / ratio**2)
        axis = _unit(point("lower_rear") - point("lower_front"))
        if parasitic_rate > 0:
            self._spring(axis @ self.turn(corner, "lower"), parasitic_rate / arm_rate**2)
        self.rows.append(np.array([0.0, 0.0, 1.0]) @ self.motion(corner, "upright", point("wheel_centre")))

    def _motion_ratio(self, side, step=1e-4):
        """Spring compression and lower-arm rotation (rad) per m of travel at design, from the reference kinematics."""
        corner = ReferenceCorner(self.table, side)
        lengths, angles = [], []
        front, rear = self.point("lower_front", side), self.point("lower_rear", side)
        for travel in (-step, step):
            corner.solve(travel)
            angles.append(corner.x[0])
            moved = front + _rotation(rear - front, corner.x[0]) @ (self.point("spring_lower", side) - front)
            lengths.append(np.linalg.norm(moved - self.point("spring_upper", side)))
        return -(lengths[1] - lengths[0]) / (2 * step), (angles[1] - angles[0]) / (2 * step)

    # loads
    def patch(self, side: int) -> np.ndarray:
        """The design contact patch: below the wheel centre in the wheel plane at the loaded radius."""
        normal = self.normal(side)
        down = np.array([0.0, 0.0, -1.0]) + normal[2] * normal
        return self.point("wheel_centre", side) + self.radius * _unit(down)

    def normal(self, side: int) -> np.ndarray:
        camber, toe = np.radians(self.table.get("static_camber", 0.0)), np.radians(self.table.get("static_toe", 0.0))
        return np.array([np.sin(toe) * np.cos(camber), side * np.cos(toe) * np.cos(camber), -np.sin(camber)])

    def solve(self, force=(0.0, 0.0, 0.0), moment_z: float = 0.0) -> np.ndarray:
        """Coordinates under ``force`` (N, at each contact patch) and ``moment_z`` (N m about z at each)."""
        load = np.zeros(self.size)
        for corner, side in enumerate((1, -1)):
            load += self.motion(corner, "upright", self.patch(side)).T @ np.asarray(force, float)
            load += self.turn(corner, "upright").T @ np.array([0.0, 0.0, moment_z])
        free = null_space(np.array(self.rows))  # the motions the rigid joints allow
        return free @ np.linalg.solve(free.T @ self.stiffness @ free, free.T @ load)

    def alignment_change(self, coordinates: np.ndarray, corner: int) -> dict[str, float]:
        """Toe and camber change (rad) and the wheel centre's lateral (outboard +) and longitudinal motion (m)."""
        side = (1, -1)[corner]
        normal = self.normal(side)
        turned = normal + np.cross(self.turn(corner, "upright") @ coordinates, normal)
        camber = lambda n: -np.arcsin(n[2])  # noqa: E731
        toe = lambda n: np.arctan2(n[0], side * n[1])  # noqa: E731
        centre = self.motion(corner, "upright", self.point("wheel_centre", side)) @ coordinates
        return {"toe": toe(turned) - toe(normal), "camber": camber(turned) - camber(normal),
                "track_change": side * centre[1], "wheelbase_change": centre[0]}


def _rotation(axis, angle):
    k = _unit(axis)
    cross = _skew(k)
    return np.eye(3) + np.sin(angle) * cross + (1 - np.cos(angle)) * cross @ cross
