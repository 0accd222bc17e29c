"""Loop closure of a linkage corner from its hardpoints, and the wheel's alignment (conventions: docs/kinematics.md).

The upright (knuckle) is a rigid body; its pose relative to design is a rotation R about the design wheel centre
c0 and a translation t: a point p of the upright moves to c0 + t + R (p - c0). Each suspension type gives five
loop-closure residuals (its links keep their lengths, a strut stays on its top mount); the wheel centre's
vertical travel relative to the body is the sixth equation. Newton's method on the six pose coordinates (rotation
vector and translation), all samples of a sweep at once, from design (or a given start) solves them to 1e-12 m.
This solver serves the builder (design motion ratio, rates, masses), the hardpoint fit and the checks of a table;
``rig kc`` measures the MuJoCo model itself (rig/sim/kc.py). A batched Newton on a 6 x 6 system is written here
because SciPy's root finders solve one system per call, ~100 x slower for the fit's thousands of sweeps.

Alignment conventions (docs/kinematics.md): travel bump positive; camber negative with the top inboard; toe positive
toe-in; caster positive with the kingpin's top rearward; kingpin inclination positive with its top inboard;
track change the wheel centre's lateral displacement, outboard positive; wheelbase change its longitudinal
displacement, forward positive. The contact patch is the point of the wheel plane below the centre at the design
loaded radius (the design wheel centre height); the scrub radius is the contact patch's lateral distance outboard
of the kingpin axis's intersection with the ground there, the trail the kingpin's ground point ahead of the patch.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from rig.vehicle.suspensions.hardpoints import Kinematics, KinematicsError

#: residuals(kinematics, side, coordinates, rack) -> (n, 5), m: the loop's closure at the samples' upright poses
#: (``coordinates`` (n, 6), see ``Poses``) and ``rack`` (n,) m, positive to the left.
LoopResiduals = Callable[[Kinematics, int, np.ndarray, np.ndarray], np.ndarray]
TOLERANCE = 1e-12  # m
_STEP = 1e-7       # finite-difference step of the Newton Jacobian (rad, m)


def rotation_matrices(vectors: np.ndarray) -> np.ndarray:
    """Rotation matrices (n, 3, 3) of rotation vectors (n, 3), rad (Rodrigues)."""
    angle = np.linalg.norm(vectors, axis=1)
    safe = np.where(angle > 1e-300, angle, 1.0)
    k = vectors / safe[:, None]
    cross = np.zeros((len(vectors), 3, 3))
    cross[:, 0, 1], cross[:, 0, 2], cross[:, 1, 2] = -k[:, 2], k[:, 1], -k[:, 0]
    cross -= np.transpose(cross, (0, 2, 1))
    sin, cos = np.sin(angle)[:, None, None], np.cos(angle)[:, None, None]
    return np.eye(3) + sin * cross + (1 - cos) * cross @ cross


@dataclass(frozen=True)
class Poses:
    """Upright poses of a sweep: ``coordinates`` (n, 6) = rotation vector (rad) and translation (m) from design."""

    kinematics: Kinematics
    side: int
    coordinates: np.ndarray

    @property
    def rotation(self) -> np.ndarray:
        return rotation_matrices(self.coordinates[:, :3])

    def moved(self, point: str | np.ndarray) -> np.ndarray:
        """A point of the upright (a hardpoint's name, or its design position, axle frame) at each pose (n, 3), m."""
        return moved_points(self.kinematics, self.side, self.coordinates, point)


def moved_points(kinematics: Kinematics, side: int, coordinates: np.ndarray, point: str | np.ndarray) -> np.ndarray:
    """A point of the upright (hardpoint name or design position, axle frame) at upright poses ``coordinates``."""
    centre = kinematics.point("wheel_centre", side)
    design = kinematics.point(point, side) if isinstance(point, str) else np.asarray(point, float)
    return centre + coordinates[:, 3:] + rotation_matrices(coordinates[:, :3]) @ (design - centre)


def solve(kinematics: Kinematics, residuals: LoopResiduals, rows: tuple[str, ...], travel: np.ndarray,
          rack: np.ndarray, side: int = 1, start: np.ndarray | None = None, iterations: int = 40) -> Poses:
    """Upright poses at wheel ``travel`` (m, bump positive) and ``rack`` (m, to the left); KinematicsError names
    the hardpoint whose loop cannot close (a travel or rack beyond the linkage's reach)."""
    travel, rack = np.broadcast_arrays(np.atleast_1d(np.asarray(travel, float)), np.atleast_1d(np.asarray(rack, float)))
    coordinates = np.zeros((travel.size, 6)) if start is None else np.array(start, float)

    def all_residuals(x: np.ndarray) -> np.ndarray:
        loop = residuals(kinematics, side, x, rack)
        return np.column_stack([loop, x[:, 5] - travel])

    def jacobian_at(x: np.ndarray, value: np.ndarray) -> np.ndarray:
        jacobian = np.empty((travel.size, 6, 6))
        for j in range(6):
            shifted = x.copy()
            shifted[:, j] += _STEP
            jacobian[:, :, j] = (all_residuals(shifted) - value) / _STEP
        return jacobian

    for _ in range(iterations):
        value = all_residuals(coordinates)
        if np.max(np.abs(value)) < TOLERANCE:
            return Poses(kinematics, side, coordinates)
        jacobian = jacobian_at(coordinates, value)
        if np.any(np.abs(np.linalg.det(jacobian)) < 1e-14) or not np.all(np.isfinite(value)):
            break
        step = np.linalg.solve(jacobian, -value[:, :, None])[:, :, 0]
        coordinates = coordinates + np.clip(step, -0.05, 0.05)  # at most 50 mm / 50 mrad per step
    value = all_residuals(coordinates)
    worst = int(np.nanargmax(np.max(np.abs(value), axis=1)))
    if np.all(np.isfinite(value[worst])):  # the loop that folds: the row of the Jacobian's smallest singular value
        left = np.linalg.svd(jacobian_at(coordinates, value)[worst])[0][:, -1]
        row = int(np.argmax(np.abs(left)))
    else:
        row = int(np.argmax(np.abs(np.nan_to_num(value[worst], nan=np.inf))))
    raise KinematicsError(
        f"the {kinematics.type} loop does not close at travel {travel[worst] * 1e3:.1f} mm, rack "
        f"{rack[worst] * 1e3:.1f} mm: {(*rows, 'wheel_centre')[row]} cannot reach its place "
        f"(beyond the linkage's reach, or the linkage locks there)")


def solve_path(kinematics: Kinematics, residuals: LoopResiduals, rows: tuple[str, ...], travel: np.ndarray,
               rack: np.ndarray, side: int = 1, step: float = 0.01) -> Poses:
    """Like ``solve``, walking out from design in steps of at most ``step`` m of travel and rack, so that every
    sample lies on the design's assembly branch."""
    travel, rack = np.broadcast_arrays(np.atleast_1d(np.asarray(travel, float)), np.atleast_1d(np.asarray(rack, float)))
    count = max(1, int(np.ceil(max(np.max(np.abs(travel)), np.max(np.abs(rack))) / step)))
    coordinates = None
    for fraction in np.arange(1, count + 1) / count:
        coordinates = solve(kinematics, residuals, rows, fraction * travel, fraction * rack, side,
                            coordinates).coordinates
    return Poses(kinematics, side, coordinates)


def distance_residual(a: np.ndarray, b: np.ndarray, length: float) -> np.ndarray:
    """|a - b| - length for points (n, 3) and (3,) or (n, 3), m."""
    return np.linalg.norm(a - b, axis=-1) - length


def design_spin_axis(kinematics: Kinematics, side: int) -> np.ndarray:
    """The wheel's spin axis at design, pointing left (+y) on both sides, from static camber and toe."""
    camber, toe = np.radians(kinematics.static_camber), np.radians(kinematics.static_toe)
    outboard = np.array([np.sin(toe) * np.cos(camber), side * np.cos(toe) * np.cos(camber), -np.sin(camber)])
    return side * outboard


def arm_angle(front: np.ndarray, rear: np.ndarray, outer0: np.ndarray, outer: np.ndarray) -> np.ndarray:
    """Rotation (rad, right-handed about front -> rear) of an arm whose outer joint moved from outer0 to outer."""
    axis = (rear - front) / np.linalg.norm(rear - front)
    radial0 = outer0 - front - np.dot(outer0 - front, axis) * axis
    radial = outer - front - ((outer - front) @ axis)[..., None] * axis
    return np.arctan2(np.cross(radial0, radial) @ axis, radial @ radial0)


def rotate_about(point: np.ndarray, front: np.ndarray, rear: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """``point`` (3,) turned by ``angle`` (n,) rad about the axis front -> rear: (n, 3)."""
    axis = (rear - front) / np.linalg.norm(rear - front)
    return front + rotation_matrices(np.outer(np.atleast_1d(angle), axis)) @ (point - front)


@dataclass(frozen=True)
class Alignment:
    """A wheel's alignment per sample (conventions: docs/kinematics.md): angles in rad, lengths in m."""

    travel: np.ndarray
    camber: np.ndarray
    toe: np.ndarray
    caster: np.ndarray
    kingpin: np.ndarray
    scrub_radius: np.ndarray
    trail: np.ndarray
    track_change: np.ndarray
    wheelbase_change: np.ndarray


def alignment(spin_axis: np.ndarray, centre: np.ndarray, kingpin_bottom: np.ndarray, kingpin_top: np.ndarray,
              side: int, design_centre: np.ndarray) -> Alignment:
    """Alignment from the spin axis (n, 3; pointing left), wheel centre, kingpin points (n, 3; axle frame, m) and
    the design wheel centre (its height is the loaded radius)."""
    outboard = side * spin_axis / np.linalg.norm(spin_axis, axis=-1, keepdims=True)
    camber = -np.arcsin(np.clip(outboard[..., 2], -1.0, 1.0))
    toe = np.arctan2(outboard[..., 0], side * outboard[..., 1])
    kingpin_axis = kingpin_top - kingpin_bottom
    caster = np.arctan2(-kingpin_axis[..., 0], kingpin_axis[..., 2])
    kingpin = np.arctan2(-side * kingpin_axis[..., 1], kingpin_axis[..., 2])
    down = np.array([0.0, 0.0, -1.0]) + outboard[..., 2:3] * outboard  # -z projected onto the wheel plane
    down /= np.linalg.norm(down, axis=-1, keepdims=True)
    patch = centre + design_centre[2] * down
    reach = (patch[..., 2] - kingpin_bottom[..., 2]) / kingpin_axis[..., 2]
    ground = kingpin_bottom + reach[..., None] * kingpin_axis
    return Alignment(
        travel=centre[..., 2] - design_centre[2], camber=camber, toe=toe, caster=caster, kingpin=kingpin,
        scrub_radius=side * (patch[..., 1] - ground[..., 1]), trail=ground[..., 0] - patch[..., 0],
        track_change=side * (centre[..., 1] - design_centre[1]), wheelbase_change=centre[..., 0] - design_centre[0])
