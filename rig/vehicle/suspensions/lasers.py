"""Laser distance sensors on a linkage corner, as the source paper ("Validation of a Suspension Model and its
Elastic Behaviour Demonstrated at the Formula Student Race Car of the University Duisburg-Essen") mounts them: three
aimed at a plate on the lower wishbone, four at a plate on the wheel carrier, from a rack fixed to the body.

A kinematics table with ``lasers = true`` gets, per corner, MuJoCo ``rangefinder`` sensors ``<corner>/laser_1`` to
``_7`` (m along each beam to the first surface; the sites' z axes are the beams) and the two plates as thin boxes:
- the wishbone plate parallel to the plane of the lower wishbone's hardpoints (lower_front, lower_rear,
  lower_outer), PLATE_GAP above it, centred half way from the pivot axis to the ball joint; its lasers
  LASER_STANDOFF above, beams down along the plane's normal, at the corners of a triangle of BEAM_SPREAD radius;
- the carrier plate on a bracket of the upright at mid height between its ball joints (MacPherson: the lower ball
  joint and strut_lower), facing inboard, PLATE_GAP inboard of the kingpin and clear of the wheel; its four lasers
  LASER_STANDOFF further inboard, beams outboard, at the corners of a square of half side BEAM_SPREAD.
Distances at design lie in the paper's sensors' range (30-150 mm).
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from rig.vehicle.suspensions.hardpoints import Kinematics

PLATE_GAP = 0.02        # m: plate below the wishbone's plane / inboard of the upright
LASER_STANDOFF = 0.09   # m: laser to plate at design
BEAM_SPREAD = 0.03      # m: beams' spread over the plate
PLATE_HALF = {"lower_arm": 0.06, "upright": 0.1}  # m: half side of the plates (the carrier's for +-60 mm travel)
PLATE_COLOR = [0.45, 0.45, 0.45, 1.0]
WISHBONE_LASERS = 3
CARRIER_LASERS = 4


@dataclass(frozen=True)
class Laser:
    """A laser at design: its name, position and unit beam direction (axle frame, m), and its plate's carrier."""

    name: str
    position: np.ndarray
    direction: np.ndarray
    target: str  # 'lower_arm' or 'upright'


@dataclass(frozen=True)
class Plate:
    """A plate at design: carrier body, centre and unit normal pointing at its lasers (axle frame, m)."""

    carrier: str
    centre: np.ndarray
    normal: np.ndarray


def wishbone_normal(kinematics: Kinematics, side: int) -> np.ndarray:
    """Unit normal (lower_rear - lower_front) x (lower_outer - lower_front) of the lower wishbone (the paper's eq. 7
    at design); it points down for a wishbone reaching outboard."""
    front, rear, outer = (kinematics.point(n, side) for n in ("lower_front", "lower_rear", "lower_outer"))
    normal = np.cross(rear - front, outer - front)
    return normal / np.linalg.norm(normal)


def laser_layout(kinematics: Kinematics, side: int, upright_top: str, wheel_half_width: float
                 ) -> tuple[list[Laser], list[Plate]]:
    """Lasers and plates of one corner at design; ``upright_top`` names the upright's upper hardpoint, and the
    wheel's inner face (``wheel_half_width`` inboard of its centre) bounds the carrier plate."""
    point = kinematics.point
    front, rear, outer = (point(n, side) for n in ("lower_front", "lower_rear", "lower_outer"))
    middle = (front + rear) / 2
    up = wishbone_normal(kinematics, side)
    if up[2] < 0:
        up = -up
    centre = middle + 0.5 * (outer - middle) + PLATE_GAP * up
    across = (outer - middle) - ((outer - middle) @ up) * up
    across /= np.linalg.norm(across)
    along = np.cross(up, across)
    plates = [Plate("lower_arm", centre, up)]
    lasers = []
    for k in range(WISHBONE_LASERS):
        angle = 2 * np.pi * k / WISHBONE_LASERS
        offset = BEAM_SPREAD * (np.cos(angle) * across + np.sin(angle) * along)
        lasers.append(Laser(f"laser_{k + 1}", centre + offset + LASER_STANDOFF * up, -up, "lower_arm"))
    inboard = np.array([0.0, -float(side), 0.0])
    carrier = (outer + point(upright_top, side)) / 2 + PLATE_GAP * inboard
    face = side * point("wheel_centre", side)[1] - wheel_half_width - PLATE_GAP  # outboard distance
    carrier[1] = side * min(side * carrier[1], face)
    plates.append(Plate("upright", carrier, inboard))
    for k, (dx, dz) in enumerate(((1, 1), (-1, 1), (-1, -1), (1, -1))):
        offset = BEAM_SPREAD * np.array([dx, 0.0, dz])
        lasers.append(Laser(f"laser_{WISHBONE_LASERS + k + 1}", carrier + offset + LASER_STANDOFF * inboard,
                            -inboard, "upright"))
    return lasers, plates


def _quat_z_along(direction: np.ndarray) -> list[float]:
    """Quaternion (w, x, y, z) of a frame whose z axis is ``direction``."""
    quat = np.empty(4)
    mujoco.mju_quatZ2Vec(quat, np.asarray(direction, float))
    return list(quat)


def add_lasers(car: mujoco.MjSpec, corner: str, lasers: list[Laser], plates: list[Plate],
               carriers: dict[str, tuple[mujoco.MjsBody, np.ndarray]], axle_to_body) -> None:
    """Plates on their carriers (``carriers``: name -> (body, its origin, axle frame)) and the lasers on the body,
    as rangefinders ``<corner>/laser_<i>``."""
    for plate in plates:
        body, origin = carriers[plate.carrier]
        plate_geom = body.add_geom(name=f"{corner}/{plate.carrier}_plate", type=mujoco.mjtGeom.mjGEOM_BOX,
                                   size=[PLATE_HALF[plate.carrier], PLATE_HALF[plate.carrier], 0.002],
                                   pos=list(plate.centre - origin),
                                   quat=_quat_z_along(plate.normal), rgba=PLATE_COLOR, contype=0, conaffinity=0)
        plate_geom.mass = 0.0
    for laser in lasers:
        site = f"{corner}/{laser.name}"
        car.body("body").add_site(name=site, pos=list(axle_to_body(laser.position)),
                                  quat=_quat_z_along(laser.direction), size=[0.005, 0.0, 0.0])
        sensor = car.add_sensor(name=site, type=mujoco.mjtSensor.mjSENS_RANGEFINDER, objtype=mujoco.mjtObj.mjOBJ_SITE,
                                objname=site)
        sensor.intprm[0] = 1 << int(mujoco.mjtRayDataField.mjRAYDATA_DIST)  # the distance only
