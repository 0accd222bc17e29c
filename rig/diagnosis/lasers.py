"""The lower wishbone's angle from three laser distances, and the lasers' calibration, after the source paper
("Validation of a Suspension Model and its Elastic Behaviour Demonstrated at the Formula Student Race Car of the
University Duisburg-Essen").

- Eq. 5: each laser's spot on the plate is its position plus its distance along its beam.
- Eq. 6: the plate's normal is (P3 - P1) x (P2 - P1), normalised.
- Eqs. 7-8: the wishbone's normal at angle alpha is (A3 - A1) x (T_A(alpha) (A2 - A1)), normalised, with A1, A3 the
  inner pivots (lower_front, lower_rear) and A2 the ball joint (lower_outer), T_A the turn about A1 -> A3.
- Eqs. 9-10: the plate lies parallel to the wishbone, so alpha solves n_plate = n_A(alpha), an overdetermined
  nonlinear system (three components, one unknown) solved in the least-squares sense by Levenberg-Marquardt
  (SciPy ``least_squares``, method 'lm'), per sample.
- Eqs. 22-27: a laser's pose is known only roughly; it is calibrated by Nelder-Mead (SciPy ``minimize``) on a sweep
  of known wishbone angles: its offset along the beam and the beam's two tilts, so that the distances it would read
  (its beam against the plate at each known angle) match those it read. A laser's offset across its beam moves its
  spot within the plate's plane and leaves the normal alone, so it is not calibrated.
Lasers and plates come from rig/vehicle/suspensions/lasers.py (axle frame, design).
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import least_squares, minimize

from rig.vehicle.suspensions.geometry import rotation_matrices
from rig.vehicle.suspensions.hardpoints import Kinematics
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


def predicted_distances(laser: Laser, plate: Plate, kinematics: Kinematics, side: int, alpha: np.ndarray
                        ) -> np.ndarray:
    """Distance along ``laser``'s beam to ``plate`` (carried by the lower wishbone) at angles ``alpha`` (rad)."""
    front, rear = kinematics.point("lower_front", side), kinematics.point("lower_rear", side)
    axis = (rear - front) / np.linalg.norm(rear - front)
    turn = rotation_matrices(np.outer(np.atleast_1d(alpha), axis))
    centres = front + turn @ (plate.centre - front)
    normals = turn @ plate.normal
    return np.einsum("ni,ni->n", centres - laser.position, normals) / (normals @ laser.direction)


def _adjusted(laser: Laser, parameters: np.ndarray) -> Laser:
    """``laser`` moved along its beam by parameters[0] (m) and its beam tilted by parameters[1:] (rad) about two
    axes across it."""
    across = np.cross(laser.direction, [1.0, 0.0, 0.0] if abs(laser.direction[0]) < 0.9 else [0.0, 1.0, 0.0])
    across /= np.linalg.norm(across)
    other = np.cross(laser.direction, across)
    tilt = rotation_matrices(np.array([parameters[1] * across + parameters[2] * other]))[0]
    return Laser(laser.name, laser.position + parameters[0] * laser.direction, tilt @ laser.direction, laser.target)


def calibrate_lasers(distances: np.ndarray, alpha: np.ndarray, lasers: list[Laser], plate: Plate,
                     kinematics: Kinematics, side: int) -> list[Laser]:
    """Eqs. 22-27: each wishbone laser's offset along its beam and its beam's tilts, by Nelder-Mead, from its
    distances (samples, lasers) at known wishbone angles ``alpha`` (rad)."""
    calibrated = []
    for k, laser in enumerate(lasers):
        def misfit(parameters: np.ndarray, k: int = k, laser: Laser = laser) -> float:
            predicted = predicted_distances(_adjusted(laser, parameters), plate, kinematics, side, alpha)
            return float(np.sum((predicted - distances[:, k]) ** 2))

        fit = minimize(lambda p, misfit=misfit: misfit(p * SIMPLEX), np.zeros(3), method="Nelder-Mead",
                       options={"xatol": 1e-9, "fatol": 1e-18, "maxiter": 4000, "maxfev": 8000})
        calibrated.append(_adjusted(laser, fit.x * SIMPLEX))
    return calibrated
