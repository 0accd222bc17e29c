"""``macpherson``: a lower arm hinged on the body and a strut: its rod hangs from the top mount (strut_top) on
three hinges, the knuckle slides on it along the strut's axis (strut_top - strut_lower), the lower ball joint is a
``connect`` between the knuckle and the arm, the tie rod goes to the rack or the body
(rig/vehicle/suspensions/linkage.py). The steering axis runs from the lower ball joint to the top mount. Without
spring points the spring and damper lie on the strut's axis (strut_top to strut_lower on the knuckle)."""

from __future__ import annotations

import numpy as np

from rig.vehicle.suspensions import bushings, geometry
from rig.vehicle.suspensions.linkage import HINGE_AXES, STRUT_SHARE, Arm, Linkage, connect
from rig.vehicle.suspensions.links import Part, add_link_geom, add_part_body

STRUT_GYRATION = 0.05  # m: radius of gyration of the strut's rod about the top mount, ASSUMPTION


class _MacPherson(Linkage):
    name = "macpherson"
    rows = ("lower_outer", "lower_outer", "strut_top", "strut_top", "tie_rod_outer")
    kingpin = ("lower_ball", "strut_top")
    spring_carrier = "upright"
    upright_top = "strut_lower"
    upright_origin = "strut_lower"
    default_spring_line = ("strut_top", "strut_lower")

    def arms(self, kinematics):
        return (Arm("lower_arm", "lower_front", "lower_rear", "lower_outer"),)

    def residuals(self, kinematics, side, coordinates, rack):
        top, lower = kinematics.point("strut_top", side), kinematics.point("strut_lower", side)
        axis = (top - lower) / np.linalg.norm(top - lower)
        rotation = geometry.rotation_matrices(coordinates[:, :3])
        offset = top - geometry.moved_points(kinematics, side, coordinates, "strut_lower")
        off_axis = [np.einsum("ni,ni->n", offset, rotation @ e) for e in bushings.perpendiculars(axis)]
        return np.column_stack([*self.arm_residuals(kinematics, side, coordinates, self.arms(kinematics)[0]),
                                *off_axis, self.tie_rod_residual(kinematics, side, coordinates, rack)])

    def extra_parts(self, kinematics, side, unsprung_mass, spin):
        mass = STRUT_SHARE * unsprung_mass
        return {"strut": Part(mass, kinematics.point("strut_top", side), mass * STRUT_GYRATION**2 * np.eye(3),
                              np.zeros(3), spin)}

    def add_upright(self, car, frame, arms, design):
        import mujoco

        point = frame.kinematics.point
        top, origin = point("strut_top", frame.side), point("strut_lower", frame.side)
        strut = add_part_body(car.body("body"), frame.name("strut"), frame.body_point("strut_top"),
                              design.parts["strut"], top)
        bushings.add_slides(strut, frame.name("strut_top"), bushings.ball_slides(frame.kinematics, "strut_top",
                                                                                  frame.side))
        for axis, label in zip(np.eye(3), HINGE_AXES):
            strut.add_joint(name=frame.name(f"strut_{label}"), type=mujoco.mjtJoint.mjJNT_HINGE, axis=list(axis))
        strut.add_site(name=frame.name("strut_top"), pos=[0.0, 0.0, 0.0])
        add_link_geom(strut, np.zeros(3), 0.6 * (origin - top))
        knuckle = add_part_body(strut, frame.name("upright"), origin - top, design.parts["upright"], origin)
        knuckle.add_joint(name=frame.name("strut_slide"), type=mujoco.mjtJoint.mjJNT_SLIDE,
                          axis=list((origin - top) / np.linalg.norm(origin - top)))
        lower = point("lower_outer", frame.side) - origin
        knuckle.add_site(name=frame.name("lower_ball"), pos=list(lower))
        bushings.bushed_site(arms["lower_arm"], frame.name("lower_ball_arm"),
                             point("lower_outer", frame.side) - point("lower_front", frame.side),
                             bushings.ball_slides(frame.kinematics, "lower_outer", frame.side),
                             frame.name("lower_outer"))
        connect(car, frame.name("lower_ball"), frame.name("lower_ball_arm"))
        add_link_geom(knuckle, 0.3 * (top - origin), lower, 1.5 * 0.012)
        add_link_geom(knuckle, np.zeros(3), point("tie_rod_outer", frame.side) - origin)
        add_link_geom(knuckle, np.zeros(3), point("wheel_centre", frame.side) - origin)
        return knuckle

    def upright_joints(self, corner):
        return (*(f"{corner}/strut_{label}" for label in HINGE_AXES), f"{corner}/strut_slide")


SUSPENSION = _MacPherson()
