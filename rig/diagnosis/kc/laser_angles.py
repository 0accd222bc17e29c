"""The lower wishbone's angle from three laser distances, the wheel carrier's steering angle from four more, and the
lasers' calibration, after the source paper ("Validation of a Suspension Model and its Elastic Behaviour Demonstrated
at the Formula Student Race Car of the University Duisburg-Essen").

- Eq. 5: each laser's spot on the plate is its position plus its distance along its beam.
- Eq. 6: the plate's normal is (P3 - P1) x (P2 - P1), normalised.
- Eqs. 7-8: the wishbone's normal at angle alpha is (A3 - A1) x (T_A(alpha) (A2 - A1)), normalised, with A1, A3 the
  inner pivots (lower_front, lower_rear) and A2 the ball joint (lower_outer), T_A the turn about A1 -> A3.
- Eqs. 9-10: the plate lies parallel to the wishbone, so alpha solves n_plate = n_A(alpha), an overdetermined
  nonlinear system (three components, one unknown) solved in the least-squares sense by Levenberg-Marquardt
  (SciPy ``least_squares``, method 'lm'), per sample.
- Eqs. 11-16 (a double wishbone): the carrier lasers' spots (eq. 11) give the carrier plate's normal (eq. 12; a
  least-squares plane through all four spots, the paper's fourth laser being there for redundancy). The lower ball
  joint A2 follows from alpha (eq. 8), the upper one A5 from the upper wishbone's angle beta that keeps |A5 - A2|
  at its design length (eq. 13, Newton). The carrier's pose is then a turn about the kingpin A2 -> A5 by the
  steering angle delta after the smallest rotation that takes the design kingpin to the present one (eq. 14), and
  delta solves n_plate = n_B(delta) (eqs. 15-16) by Levenberg-Marquardt per sample, as alpha does. The carrier's
  rotation gives its camber and toe (conventions: rig/vehicle/suspensions/geometry.py).
- Eqs. 22-29: a laser's pose is known only roughly; it is calibrated by Nelder-Mead (SciPy ``minimize``) on a sweep
  where its plate's place is known: its offset along the beam and the beam's two tilts, so that the distances it
  would read (its beam against the plate at each known place) match those it read. The wishbone's lasers on a sweep
  of known wishbone angles (eqs. 22-27), the wheel carrier's on a sweep of known carrier poses (eqs. 28-29; the
  paper calibrates both at the wishbone's design angle, a sweep makes the tilts identifiable). A laser's offset
  across its beam moves its spot within the plate's plane and leaves the normal alone, so it is not calibrated.
Lasers and plates come from rig/vehicle/suspensions/lasers.py (axle frame, design).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares, minimize

from rig.vehicle.suspensions.geometry import Poses, design_spin_axis, rotate_about, rotation_matrices
from rig.vehicle.suspensions.hardpoints import Kinematics, KinematicsError
from rig.vehicle.suspensions.lasers import Laser, Plate

SIMPLEX = np.array([1e-3, 1e-2, 1e-2])  # m, rad, rad: the calibration's unit steps (its first simplex)


def spots(distances: np.ndarray, lasers: list[Laser]) -> np.ndarray:
    """Eq. 5: the lasers' spots (samples, lasers, 3) from their distances (samples, lasers), m."""
    positions = np.array([laser.position for laser in lasers])
    directions = np.array([laser.direction for laser in lasers])
    return positions + np.asarray(distances)[..., None] * directions


def plate_normal(points: np.ndarray) -> np.ndarray:
    """Eq. 6: unit normal (P3 - P1) x (P2 - P1) of the plane through the first three spots (samples, 3)."""
    normal = np.cross(points[:, 2] - points[:, 0], points[:, 1] - points[:, 0])
    return normal / np.linalg.norm(normal, axis=1, keepdims=True)


def wishbone_normal(kinematics: Kinematics, side: int, alpha: np.ndarray) -> np.ndarray:
    """Eqs. 7-8: unit normal of the lower wishbone turned by ``alpha`` (rad) about lower_front -> lower_rear."""
    first, third, second = (kinematics.point(n, side) for n in ("lower_front", "lower_rear", "lower_outer"))
    axis = (third - first) / np.linalg.norm(third - first)
    turned = rotation_matrices(np.outer(np.atleast_1d(alpha), axis)) @ (second - first)
    normal = np.cross(third - first, turned)
    return normal / np.linalg.norm(normal, axis=1, keepdims=True)


def wishbone_angle(distances: np.ndarray, lasers: list[Laser], kinematics: Kinematics, side: int) -> np.ndarray:
    """Eqs. 9-10: the lower wishbone's angle (rad, about lower_front -> lower_rear) at each sample of the three
    wishbone lasers' distances (samples, 3), by Levenberg-Marquardt from the previous sample's angle."""
    measured = plate_normal(spots(distances, lasers))
    reference = wishbone_normal(kinematics, side, 0.0)[0]
    measured *= np.sign(measured @ reference)[:, None]  # the plate's normal, turned to the wishbone's side
    angles, guess = np.empty(len(measured)), 0.0
    for k, normal in enumerate(measured):
        fit = least_squares(lambda a, n=normal: wishbone_normal(kinematics, side, a[0])[0] - n, [guess], method="lm",
                            xtol=1e-15, ftol=1e-15, gtol=1e-15)
        angles[k] = guess = fit.x[0]
    return angles


@dataclass(frozen=True)
class CarrierPose:
    """The wheel carrier's pose per sample from the lasers: arm angles and steering angle (rad), its rotation from
    design (samples, 3, 3), and the camber and toe that follow (rad; docs/kinematics.md)."""

    alpha: np.ndarray      # lower wishbone, about lower_front -> lower_rear
    beta: np.ndarray       # upper wishbone, about upper_front -> upper_rear
    delta: np.ndarray      # steering: the carrier's turn about the kingpin lower_outer -> upper_outer
    rotation: np.ndarray
    camber: np.ndarray
    toe: np.ndarray


def plane_normal(points: np.ndarray) -> np.ndarray:
    """Eq. 12: unit normal of the least-squares plane through the spots (samples, k >= 3, 3)."""
    centred = points - points.mean(axis=1, keepdims=True)
    return np.linalg.svd(centred)[2][:, -1]


def _axis_rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    return rotation_matrices(np.array([angle * axis / np.linalg.norm(axis)]))[0]


def _aligning(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The smallest rotation taking direction ``a`` to direction ``b``."""
    a, b = a / np.linalg.norm(a), b / np.linalg.norm(b)
    axis = np.cross(a, b)
    if not np.linalg.norm(axis) > 0:
        return np.eye(3)
    return _axis_rotation(axis, float(np.arctan2(np.linalg.norm(axis), a @ b)))


def _upper_angle(kinematics: Kinematics, side: int, lower_ball: np.ndarray, guess: float) -> float:
    """Eq. 13: the upper wishbone's angle (rad) that keeps the kingpin's length, by Newton from ``guess``."""
    front, rear, outer = (kinematics.point(n, side) for n in ("upper_front", "upper_rear", "upper_outer"))
    length = np.linalg.norm(outer - kinematics.point("lower_outer", side))

    def residual(beta: float) -> float:
        return float(np.linalg.norm(rotate_about(outer, front, rear, beta)[0] - lower_ball) - length)

    beta = guess
    for _ in range(50):
        value = residual(beta)
        if abs(value) < 1e-14:
            return beta
        beta -= value / ((residual(beta + 1e-7) - residual(beta - 1e-7)) / 2e-7)
    raise KinematicsError(f"the upper wishbone cannot reach the lower ball joint at {lower_ball} (lasers off?)")


def carrier_pose(distances: np.ndarray, lasers: list[Laser], plate: Plate, kinematics: Kinematics, side: int
                 ) -> CarrierPose:
    """Eqs. 5-16: the carrier's pose at each sample of a double-wishbone corner's seven laser distances (samples,
    7: three on the wishbone, four on the carrier ``plate``), each sample solved from the previous one."""
    if kinematics.type != "double_wishbone":
        raise KinematicsError(f"the carrier's pose from lasers needs a double_wishbone (the paper's), got "
                              f"{kinematics.type}")
    distances = np.asarray(distances, float)
    alpha = wishbone_angle(distances[:, :3], lasers[:3], kinematics, side)
    measured = plane_normal(spots(distances[:, 3:], lasers[3:]))
    measured *= np.sign(measured @ plate.normal)[:, None]
    front, rear = kinematics.point("lower_front", side), kinematics.point("lower_rear", side)
    lower = rotate_about(kinematics.point("lower_outer", side), front, rear, alpha)
    kingpin0 = kinematics.point("upper_outer", side) - kinematics.point("lower_outer", side)
    upper = [kinematics.point(n, side) for n in ("upper_front", "upper_rear", "upper_outer")]
    n = len(alpha)
    beta, delta, rotation = np.empty(n), np.empty(n), np.empty((n, 3, 3))
    guess_beta, guess_delta = 0.0, 0.0
    for k in range(n):
        beta[k] = guess_beta = _upper_angle(kinematics, side, lower[k], guess_beta)
        kingpin = rotate_about(upper[2], upper[0], upper[1], beta[k])[0] - lower[k]
        aligned = _aligning(kingpin0, kingpin)

        def normal_misfit(d: np.ndarray, kingpin=kingpin, aligned=aligned, target=measured[k]) -> np.ndarray:
            return _axis_rotation(kingpin, d[0]) @ aligned @ plate.normal - target

        fit = least_squares(normal_misfit, [guess_delta], method="lm", xtol=1e-15, ftol=1e-15, gtol=1e-15)
        delta[k] = guess_delta = fit.x[0]
        rotation[k] = _axis_rotation(kingpin, delta[k]) @ aligned
    outboard = side * rotation @ design_spin_axis(kinematics, side)
    return CarrierPose(alpha=alpha, beta=beta, delta=delta, rotation=rotation,
                       camber=-np.arcsin(np.clip(outboard[:, 2], -1.0, 1.0)),
                       toe=np.arctan2(outboard[:, 0], side * outboard[:, 1]))


def predicted_distances(laser: Laser, plate: Plate, kinematics: Kinematics, side: int, alpha: np.ndarray
                        ) -> np.ndarray:
    """Distance along ``laser``'s beam to ``plate`` (carried by the lower wishbone) at angles ``alpha`` (rad)."""
    centres, normals = wishbone_plate(plate, kinematics, side, alpha)
    return distances_to(laser, centres, normals)


def wishbone_plate(plate: Plate, kinematics: Kinematics, side: int, alpha: np.ndarray
                   ) -> tuple[np.ndarray, np.ndarray]:
    """The lower wishbone's plate (centres, normals; samples x 3) turned by ``alpha`` (rad) with the wishbone."""
    front, rear = kinematics.point("lower_front", side), kinematics.point("lower_rear", side)
    axis = (rear - front) / np.linalg.norm(rear - front)
    turn = rotation_matrices(np.outer(np.atleast_1d(alpha), axis))
    return front + turn @ (plate.centre - front), turn @ plate.normal


def carrier_plate(plate: Plate, poses: Poses) -> tuple[np.ndarray, np.ndarray]:
    """The wheel carrier's plate (centres, normals; samples x 3) at the carrier's ``poses`` (geometry.Poses)."""
    return poses.moved(plate.centre), poses.rotation @ plate.normal


def distances_to(laser: Laser, centres: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """Distance along ``laser``'s beam to the plane through ``centres`` with ``normals`` (samples x 3), m."""
    return np.einsum("ni,ni->n", centres - laser.position, normals) / (normals @ laser.direction)


def _adjusted(laser: Laser, parameters: np.ndarray) -> Laser:
    """``laser`` moved along its beam by parameters[0] (m) and its beam tilted by parameters[1:] (rad) about two
    axes across it."""
    across = np.cross(laser.direction, [1.0, 0.0, 0.0] if abs(laser.direction[0]) < 0.9 else [0.0, 1.0, 0.0])
    across /= np.linalg.norm(across)
    other = np.cross(laser.direction, across)
    tilt = rotation_matrices(np.array([parameters[1] * across + parameters[2] * other]))[0]
    return Laser(laser.name, laser.position + parameters[0] * laser.direction, tilt @ laser.direction, laser.target)


def calibrate_on_plate(distances: np.ndarray, lasers: list[Laser], centres: np.ndarray, normals: np.ndarray
                       ) -> list[Laser]:
    """Eqs. 22-29: each laser's offset along its beam and its beam's tilts, by Nelder-Mead, from its distances
    (samples, lasers) to a plate whose place is known at each sample (``centres``, ``normals``: samples x 3)."""
    calibrated = []
    for k, laser in enumerate(lasers):
        def misfit(parameters: np.ndarray, k: int = k, laser: Laser = laser) -> float:
            predicted = distances_to(_adjusted(laser, parameters), centres, normals)
            return float(np.sum((predicted - distances[:, k]) ** 2))

        fit = minimize(lambda p, misfit=misfit: misfit(p * SIMPLEX), np.zeros(3), method="Nelder-Mead",
                       options={"xatol": 1e-9, "fatol": 1e-18, "maxiter": 4000, "maxfev": 8000})
        calibrated.append(_adjusted(laser, fit.x * SIMPLEX))
    return calibrated


def calibrate_lasers(distances: np.ndarray, alpha: np.ndarray, lasers: list[Laser], plate: Plate,
                     kinematics: Kinematics, side: int) -> list[Laser]:
    """Eqs. 22-27: the wishbone lasers calibrated on a sweep of known wishbone angles ``alpha`` (rad)."""
    return calibrate_on_plate(distances, lasers, *wishbone_plate(plate, kinematics, side, alpha))


def calibrate_carrier_lasers(distances: np.ndarray, poses: Poses, lasers: list[Laser], plate: Plate) -> list[Laser]:
    """Eqs. 28-29: the wheel carrier's lasers calibrated on a sweep of known carrier ``poses`` (a travel or steer
    test whose travel and rack the rig sets, solved by the linkage's loop closure)."""
    return calibrate_on_plate(distances, lasers, *carrier_plate(plate, poses))
