"""A pushrod and rocker between a double wishbone's lower arm and its spring, as the Formula Student car of the source
paper ("Validation of a Suspension Model and its Elastic Behaviour Demonstrated at the Formula Student Race Car of
the University Duisburg-Essen") carries its rear spring and damper.

    pushrod_outer = [0.0, 0.44, 0.125]   # on the lower wishbone
    pushrod_inner = [0.0, 0.28, 0.38]    # on the rocker
    rocker_pivot = [0.0, 0.22, 0.33]     # the rocker's axis on the body: a point on it
    rocker_axis = [0.05, 0.22, 0.33]     # and another
    spring_lower = [0.0, 0.19, 0.40]     # with a rocker: on the rocker
    spring_upper = [0.0, 0.03, 0.38]     # on the body

The rocker turns about its axis; the pushrod (ball-jointed at both ends) keeps its length, so the rocker's angle
follows from the lower arm's: |pushrod_outer(arm) - pushrod_inner(rocker)| = the pushrod's length, solved by Newton's
method per pose from design. The spring and damper act between the body and the rocker, and their motion ratio
(spring compression per wheel travel) follows from the whole linkage: wheel, arm, pushrod, rocker.

In the MJCF the rocker is a body hinged on the car body about its axis (behind its pivot's bushing), the pushrod a
spatial tendon from the arm to the rocker held at its length by a tendon ``equality`` (as the tie rod), and the
spring line ends on the rocker. The rocker weighs ROCKER_SHARE of the corner's unsprung mass (a share of the mass at
the wheel, as the arms', ASSUMPTION), spread over its three points.
"""

from __future__ import annotations

import mujoco
import numpy as np

from rig.vehicle.suspensions import bushings
from rig.vehicle.suspensions.geometry import rotate_about
from rig.vehicle.suspensions.hardpoints import Kinematics, KinematicsError
from rig.vehicle.suspensions.links import add_link_geom, add_part_body, add_rod

ROCKER_POINTS = ("pushrod_outer", "pushrod_inner", "rocker_pivot", "rocker_axis")
ROCKER_SHARE = 0.03  # of the unsprung mass, ASSUMPTION
_TOLERANCE = 1e-13   # m
_STEP = 1e-7         # rad


def has_rocker(kinematics: Kinematics) -> bool:
    return all(p in kinematics.points for p in ROCKER_POINTS)


def rocker_angle(kinematics: Kinematics, side: int, pushrod_outer: np.ndarray) -> np.ndarray:
    """The rocker's angle (rad, right-handed about rocker_pivot -> rocker_axis) that keeps the pushrod's length with
    its outer end at ``pushrod_outer`` (n, 3; axle frame), by Newton's method from design for each sample."""
    point = kinematics.point
    pivot, axis, inner = point("rocker_pivot", side), point("rocker_axis", side), point("pushrod_inner", side)
    length = float(np.linalg.norm(point("pushrod_outer") - point("pushrod_inner")))
    outer = np.atleast_2d(pushrod_outer)
    angle = np.zeros(len(outer))

    def misfit(values: np.ndarray) -> np.ndarray:
        return np.linalg.norm(rotate_about(inner, pivot, axis, values) - outer, axis=1) - length

    for _ in range(50):
        value = misfit(angle)
        if np.max(np.abs(value)) < _TOLERANCE:
            return angle
        slope = (misfit(angle + _STEP) - value) / _STEP
        if np.any(np.abs(slope) < 1e-9):
            break
        angle = angle - np.clip(value / slope, -0.1, 0.1)
    raise KinematicsError("the rocker cannot follow the pushrod (pushrod_inner: the pushrod's line runs through the "
                          "rocker's axis, or the travel is beyond the rocker's reach)")


def spring_lower(kinematics: Kinematics, side: int, pushrod_outer: np.ndarray) -> np.ndarray:
    """The spring's end on the rocker (n, 3) with the pushrod's outer end at ``pushrod_outer``."""
    point = kinematics.point
    angle = rocker_angle(kinematics, side, pushrod_outer)
    return rotate_about(point("spring_lower", side), point("rocker_pivot", side), point("rocker_axis", side), angle)


def add_rocker(car: mujoco.MjSpec, frame, arm: mujoco.MjsBody, arm_origin: np.ndarray, part) -> mujoco.MjsBody:
    """The rocker body on its hinge (behind its pivot's bushing), its sites ``<corner>/pushrod_inner``, and the
    pushrod: a tendon from ``<corner>/pushrod_outer`` on the lower arm (its origin ``arm_origin``) held at its
    length. ``frame``: the corner's CornerFrame; ``part``: the rocker's mass properties."""
    kinematics, side = frame.kinematics, frame.side
    pivot = kinematics.point("rocker_pivot", side)
    axis = kinematics.point("rocker_axis", side) - pivot
    axis /= np.linalg.norm(axis)
    rocker = add_part_body(car.body("body"), frame.name("rocker"), frame.body_point("rocker_pivot"), part, pivot)
    bushing = kinematics.bushings.get("rocker_pivot")
    bushings.add_slides(rocker, frame.name("rocker_pivot"), bushings.ball_slides(kinematics, "rocker_pivot", side))
    if bushing is not None and bushing.conical > 0:
        bushings.add_conical(rocker, frame.name("rocker"), axis, (bushing.conical, bushing.conical_damping))
    rate, damping = (bushing.torsional, bushing.torsional_damping) if bushing is not None else (0.0, 0.0)
    rocker.add_joint(name=frame.name("rocker"), type=mujoco.mjtJoint.mjJNT_HINGE, axis=list(axis),
                     stiffness=[rate, 0.0, 0.0], damping=[damping, 0.0, 0.0])
    for name, body, origin in (("pushrod_inner", rocker, pivot), ("pushrod_outer", arm, arm_origin)):
        bushings.bushed_site(body, frame.name(name), kinematics.point(name, side) - origin,
                             bushings.ball_slides(kinematics, name, side), frame.name(name))
    for end in ("pushrod_inner", "spring_lower"):
        add_link_geom(rocker, np.zeros(3), kinematics.point(end, side) - pivot)
    add_rod(car, frame.name("pushrod"), frame.name("pushrod_outer"), frame.name("pushrod_inner"))
    return rocker
