"""Linkage corners in MJCF from hardpoints: what double wishbones and MacPherson struts share.

A corner is a joint tree closed by one ``connect`` per loop: each arm hangs from the body on a hinge about its
inner pivots (behind three compliant slides when the table gives bushing rates); the upright hangs from one arm
(or the strut) on three hinges about a ball joint; the other ball joint is a site-to-site ``connect``; the tie
rod is a spatial tendon held at its design length by a tendon ``equality`` from the steering rack (a slide joint
across the body, stiff by the table's ``rack_rate``) or the body. Ball joints are hinge triples, not MuJoCo
balls, so that positions and velocities have equal sizes (the static solver and linearisation index both alike).
Equalities are soft in MuJoCo: their impedance is at its maximum and their reference stiffness as high as RK4 at
1 ms integrates stably (``CONSTRAINT_SOLREF``), which keeps a ball joint under load closed to ~1e-7 m.

Rates at the wheel at design (docs/contracts.md): the spring and the damper are tendons on the spring line (spring_upper
on the body to spring_lower on the lower arm, double wishbone, or on the knuckle, MacPherson; without spring
points, from the body site above the wheel to the hub), whose length is divided by the design motion ratio (a
pulley of that divisor), so that their stiffness and damping are the wheel's at design and the motion ratio
changes with travel as the geometry says. The spring's stiffness also makes up for its preload times the spring
line's curvature, so that the wheel rate at design is ``spring_rate`` exactly; the preload makes static ride
height the design position. The parasitic rate is the lower arm's pivot stiffness.

Masses: ``unsprung_mass`` stays the mass at the wheel (the vertical model's): the arms (ARM_SHARE each), the
upright (UPRIGHT_SHARE) and a MacPherson strut rod (STRUT_SHARE) take fixed shares, and the wheel the rest, so
that the kinetic energy of the corner moving by its travel at design is that of ``unsprung_mass`` moving with the
wheel centre. What the parts weigh beyond that, and the steering rack, are taken off the sprung body where they
are, so that the car's mass, CG and inertia stay the vehicle file's.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import mujoco
import numpy as np

from rig.io.channels import corner_axle
from rig.io.units import STANDARD_GRAVITY
from rig.vehicle.suspensions import bushings, geometry, kinematics_of, rocker
from rig.vehicle.suspensions._base import Suspension
from rig.vehicle.suspensions.bushings import BUSHING_PERIOD
from rig.vehicle.suspensions.hardpoints import Kinematics, KinematicsError
from rig.vehicle.suspensions.lasers import add_lasers, laser_layout
from rig.vehicle.suspensions.links import (
    LINK_RADIUS,
    Part,
    add_link_geom,
    add_part_body,
    add_rod,
    equality_stiff,
)

ARM_SHARE = 0.04       # of the unsprung mass, per arm, ASSUMPTION
UPRIGHT_SHARE = 0.15   # of the unsprung mass: upright / knuckle, ASSUMPTION
STRUT_SHARE = 0.02     # of the unsprung mass: a MacPherson strut's rod, ASSUMPTION
UPRIGHT_GYRATION = 0.08  # m: radius of gyration of the upright, ASSUMPTION
RACK_MASS = 2.0        # kg: rack and steering reflected to it, ASSUMPTION
RACK_DAMPING = 2000.0  # N s/m at the rack, ASSUMPTION
DESIGN_STEP = 1e-3     # m of travel for the design derivatives
WHEEL_HALF_WIDTH = 0.1  # m, drawn (the vertical template's)
HINGE_AXES = "xyz"     # a ball joint: hinges about x, y and z (names end in _x, _y, _z)


@dataclass(frozen=True)
class Arm:
    """An arm hinged on the body: its body suffix and hardpoints (inner front, inner rear, outer ball)."""

    name: str
    front: str
    rear: str
    outer: str


@dataclass(frozen=True)
class Design:
    """A corner at design: its parts, the spring line's motion ratio and curvature, the lower arm's rate."""

    parts: dict[str, Part]
    motion_ratio: float        # spring compression per wheel travel
    spring_length: float       # m, spring line
    spring_curvature: float    # d2(spring length)/d travel^2, 1/m
    lower_arm_rate: float      # rad of lower-arm rotation per m of travel


def corner_side(corner: str) -> int:
    return 1 if corner.endswith("L") else -1


def point_inertia(mass: float, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """CG and inertia about it of ``mass`` spread evenly over ``points`` (k, 3), plus that of tubes of LINK_RADIUS
    (so that a flat arm's moments keep clear of the triangle inequality)."""
    cg = points.mean(axis=0)
    r = points - cg
    inertia = mass / len(points) * sum(float(p @ p) * np.eye(3) - np.outer(p, p) for p in r)
    return cg, inertia + mass * LINK_RADIUS**2 * np.eye(3)


class Linkage(Suspension):
    """A corner built from hardpoints; subclasses give the loop's residuals and their own bodies."""

    rows: ClassVar[tuple[str, ...]]          # hardpoint whose loop each residual closes
    kingpin: ClassVar[tuple[str, str]]       # hardpoints on the steering axis: bottom, top (sites of that name)
    spring_carrier: ClassVar[str]            # 'lower_arm' or 'upright': what spring_lower moves with
    upright_origin: ClassVar[str]            # hardpoint at the upright body's origin
    upright_top: ClassVar[str]               # the upright's upper hardpoint (the carrier plate sits midway)

    # ---- geometry ------------------------------------------------------------------------------------------
    default_spring_line: ClassVar[tuple[str, str] | None] = None  # spring line without spring points

    def residuals(self, kinematics: Kinematics, side: int, coordinates: np.ndarray, rack: np.ndarray) -> np.ndarray:
        """The loop's five closure residuals (n, 5), m, at upright poses ``coordinates`` (geometry.Poses)."""
        raise NotImplementedError

    def arm_residuals(self, kinematics: Kinematics, side: int, coordinates: np.ndarray, arm: Arm) -> list[np.ndarray]:
        """An arm's outer ball stays at its distances from both inner pivots (it turns about their axis)."""
        outer = geometry.moved_points(kinematics, side, coordinates, arm.outer)
        return [geometry.distance_residual(outer, kinematics.point(pivot, side),
                                           float(np.linalg.norm(kinematics.point(arm.outer) - kinematics.point(pivot))))
                for pivot in (arm.front, arm.rear)]

    def tie_rod_residual(self, kinematics: Kinematics, side: int, coordinates: np.ndarray, rack: np.ndarray
                         ) -> np.ndarray:
        """The tie rod keeps its length from the rack (moved by ``rack`` to the left) or the body."""
        outer = geometry.moved_points(kinematics, side, coordinates, "tie_rod_outer")
        length = float(np.linalg.norm(kinematics.point("tie_rod_outer") - kinematics.point("tie_rod_inner")))
        return geometry.distance_residual(outer, self.tie_rod_inner(kinematics, side, rack), length)

    def arms(self, kinematics: Kinematics) -> tuple[Arm, ...]:
        raise NotImplementedError

    def solve(self, kinematics: Kinematics, travel, rack=0.0, side: int = 1) -> geometry.Poses:
        """Upright poses at ``travel`` (m, bump +) and ``rack`` (m, to the left), along the design's branch."""
        return geometry.solve_path(kinematics, self.residuals, self.rows, travel, rack, side)

    @staticmethod
    def tie_rod_inner(kinematics: Kinematics, side: int, rack: np.ndarray) -> np.ndarray:
        """The tie rod's inner end (n, 3): on the rack, moved by ``rack`` m to the left, or fixed on the body."""
        inner = kinematics.point("tie_rod_inner", side)
        return inner + np.outer(rack if kinematics.steered else 0.0 * rack, [0.0, 1.0, 0.0])

    def check(self, kinematics: Kinematics, where: str) -> None:
        """Refuse a linkage whose loop does not close and move at design (a locked or singular linkage)."""
        try:
            self.solve(kinematics, np.array([-0.005, 0.005]))
        except KinematicsError as err:
            raise KinematicsError(f"{where}: the loop does not close around design: {err}") from None

    def design(self, kinematics: Kinematics, side: int, unsprung_mass: float, wheel_radius: float) -> Design:
        """Parts, motion ratio and rates of the corner at design, from the loop's solution at +-DESIGN_STEP."""
        h = DESIGN_STEP
        poses = self.solve(kinematics, np.array([-h, 0.0, h]), 0.0, side)
        rotation = poses.rotation
        spin = _axial((rotation[2] - rotation[0]) / (2 * h))
        centre = kinematics.point("wheel_centre", side)
        centre_velocity = (poses.coordinates[2, 3:] - poses.coordinates[0, 3:]) / (2 * h)
        parts, arm_rates = {}, {}
        for arm in self.arms(kinematics):
            front, rear = kinematics.point(arm.front, side), kinematics.point(arm.rear, side)
            angle = geometry.arm_angle(front, rear, kinematics.point(arm.outer, side), poses.moved(arm.outer))
            arm_rates[arm.name] = (angle[2] - angle[0]) / (2 * h)
            omega = arm_rates[arm.name] * (rear - front) / np.linalg.norm(rear - front)
            cg, inertia = point_inertia(ARM_SHARE * unsprung_mass,
                                        np.array([front, rear, kinematics.point(arm.outer, side)]))
            parts[arm.name] = Part(ARM_SHARE * unsprung_mass, cg, inertia, np.cross(omega, cg - front), omega)
        upright = UPRIGHT_SHARE * unsprung_mass
        parts["upright"] = Part(upright, centre, upright * UPRIGHT_GYRATION**2 * np.eye(3), centre_velocity, spin)
        parts.update(self.extra_parts(kinematics, side, unsprung_mass, spin))
        if rocker.has_rocker(kinematics):
            parts["rocker"] = _rocker_part(kinematics, side, unsprung_mass, poses)
        parts["wheel"] = _wheel_part(unsprung_mass, parts, kinematics, side, wheel_radius, centre_velocity, spin)
        upper, lower = self.spring_ends(kinematics, side, poses)
        length = np.linalg.norm(lower - upper, axis=-1)
        return Design(parts=parts, motion_ratio=-(length[2] - length[0]) / (2 * h), spring_length=float(length[1]),
                      spring_curvature=(length[2] - 2 * length[1] + length[0]) / h**2,
                      lower_arm_rate=arm_rates["lower_arm"])

    def extra_parts(self, kinematics: Kinematics, side: int, unsprung_mass: float, spin: np.ndarray
                    ) -> dict[str, Part]:
        """Moving parts of the type beyond the arms, the upright and the wheel (a strut's rod)."""
        return {}

    def spring_ends(self, kinematics: Kinematics, side: int, poses: geometry.Poses | None
                    ) -> tuple[np.ndarray, np.ndarray]:
        """The spring line's ends at each pose, or at design for None (axle frame, m): on the body, and on its
        carrier (for a spring at the wheel: the body site above the design wheel centre, and the wheel centre)."""
        names = ("spring_upper", "spring_lower") if kinematics.has_spring_line else self.default_spring_line
        if names is None:
            centre = kinematics.point("wheel_centre", side)
            return body_site(kinematics, side), centre if poses is None else poses.moved("wheel_centre")
        upper, lower = kinematics.point(names[0], side), kinematics.point(names[1], side)
        if poses is None:
            return upper, lower
        if self.spring_carrier == "upright" or not kinematics.has_spring_line:
            return upper, poses.moved(lower)
        arm = next(a for a in self.arms(kinematics) if a.name == "lower_arm")
        front, rear = kinematics.point(arm.front, side), kinematics.point(arm.rear, side)
        angle = geometry.arm_angle(front, rear, kinematics.point(arm.outer, side), poses.moved(arm.outer))
        if rocker.has_rocker(kinematics):  # the arm pushes the rod, the rod turns the rocker, the rocker the spring
            pushrod = geometry.rotate_about(kinematics.point("pushrod_outer", side), front, rear, angle)
            return upper, rocker.spring_lower(kinematics, side, pushrod)
        return upper, geometry.rotate_about(lower, front, rear, angle)

    # ---- MJCF ------------------------------------------------------------------------------------------------
    def build_corner(self, car, vehicle, corner):
        axle = vehicle.axle(corner)
        frame = CornerFrame(corner, kinematics_of(vehicle, corner), vehicle.corner_position(corner)[0],
                            vehicle.cg_height)
        design = self.design(frame.kinematics, frame.side, axle.unsprung_mass, vehicle.wheel_radius)
        _remove_template_corner(car, corner)
        car.site(frame.name("body")).pos = list(frame.axle_to_body(body_site(frame.kinematics, frame.side)))
        arms = {arm.name: _add_arm(car, frame, arm, design.parts[arm.name])
                for arm in self.arms(frame.kinematics)}
        pivot = car.joint(frame.name("lower_arm"))
        pivot.stiffness = [pivot.stiffness[0] + axle.parasitic_rate / design.lower_arm_rate**2, 0.0, 0.0]
        pivot.userdata = [1.0 / design.lower_arm_rate]  # m of travel per rad at design (an anti-roll bar reads it)
        upright = self.add_upright(car, frame, arms, design)
        origin = frame.kinematics.point(self.upright_origin, frame.side)
        _add_wheel(upright, frame, origin, design.parts["wheel"], vehicle.wheel_radius)
        upright.add_site(name=frame.name("hub"), pos=list(frame.kinematics.point("wheel_centre", frame.side) - origin))
        bushings.bushed_site(upright, frame.name("tie_rod_outer"),
                             frame.kinematics.point("tie_rod_outer", frame.side) - origin,
                             bushings.ball_slides(frame.kinematics, "tie_rod_outer", frame.side),
                             frame.name("tie_rod_outer"))
        _add_tie_rod(car, frame)
        if rocker.has_rocker(frame.kinematics):
            arm_origin = frame.kinematics.point("lower_front", frame.side)
            carrier = rocker.add_rocker(car, frame, arms["lower_arm"], arm_origin, design.parts["rocker"])
            carrier_origin = frame.kinematics.point("rocker_pivot", frame.side)
        elif self.spring_carrier == "lower_arm" and frame.kinematics.has_spring_line:
            carrier, carrier_origin = arms["lower_arm"], frame.kinematics.point("lower_front", frame.side)
        else:
            carrier, carrier_origin = upright, origin
        _add_spring_and_damper(car, frame, self.spring_ends(frame.kinematics, frame.side, None), carrier,
                               carrier_origin, design, axle, _static_spring_force(vehicle, corner, design))
        _add_travel_sensors(car, frame)
        if frame.kinematics.lasers:
            lasers, plates = laser_layout(frame.kinematics, frame.side, self.upright_top, WHEEL_HALF_WIDTH)
            carriers = {"lower_arm": (arms["lower_arm"], frame.kinematics.point("lower_front", frame.side)),
                        "upright": (upright, origin)}
            add_lasers(car, corner, lasers, plates, carriers, frame.axle_to_body)

    def add_upright(self, car: mujoco.MjSpec, frame: CornerFrame, arms: dict, design: Design) -> mujoco.MjsBody:
        """The upright (knuckle) body with its joints, the sites ``<corner>/hub``, ``<corner>/tie_rod_outer``,
        the kingpin sites, and the loop-closing ``connect``; type specific."""
        raise NotImplementedError

    def upright_joints(self, corner: str) -> tuple[str, ...]:
        """Names of the joints that carry the upright (type specific)."""
        raise NotImplementedError

    def linkage_joints(self, vehicle, corner):
        kinematics = kinematics_of(vehicle, corner)
        joints = list(self.upright_joints(corner))
        for arm in self.arms(kinematics):
            joints.append(f"{corner}/{arm.name}")
            if kinematics.bushing_rate is not None:
                joints += [f"{corner}/{arm.name}_bushing_{label}" for label in HINGE_AXES]
        joints += bushings.joint_names(kinematics, corner, corner_side(corner),
                                       tuple((a.name, a.front, a.rear) for a in self.arms(kinematics)))
        if kinematics.steered:
            joints.append(f"{corner_axle(corner)}/rack")
        if rocker.has_rocker(kinematics):
            joints.append(f"{corner}/rocker")
        return tuple(joints)

    def adjust_sprung(self, vehicle, corner, mass, com, inertia):
        axle = vehicle.axle(corner)
        frame = CornerFrame(corner, kinematics_of(vehicle, corner), vehicle.corner_position(corner)[0],
                            vehicle.cg_height)
        design = self.design(frame.kinematics, frame.side, axle.unsprung_mass, vehicle.wheel_radius)
        excess = sum(p.mass for p in design.parts.values()) - axle.unsprung_mass
        mass, com, inertia = _remove_point_mass(mass, com, inertia, excess, frame.body_point("wheel_centre"))
        if frame.kinematics.steered:  # half the rack, which moves with the body
            rack = frame.body_point("tie_rod_inner") * np.array([1.0, 0.0, 1.0])
            mass, com, inertia = _remove_point_mass(mass, com, inertia, RACK_MASS / 2, rack)
        return mass, com, inertia


BODY_SITE_HEIGHT = 0.3  # m: the ``<corner>/body`` site this far above the design wheel centre


def body_site(kinematics: Kinematics, side: int) -> np.ndarray:
    """The ``<corner>/body`` site (axle frame, m): BODY_SITE_HEIGHT above the design wheel centre, so that tendons
    from it to the hub (a spring at the wheel, the causes' bump stops and springs) stay well clear of zero length
    over any travel (a vertical corner's site is at the CG's height, which on a low car is barely above the hub)."""
    return kinematics.point("wheel_centre", side) + np.array([0.0, 0.0, BODY_SITE_HEIGHT])


@dataclass(frozen=True)
class CornerFrame:
    """A corner's hardpoints in the car body's frame (origin at the sprung CG at design, vehicle axes)."""

    corner: str
    kinematics: Kinematics
    station_x: float   # m, the axle's x relative to the CG
    cg_height: float   # m

    @property
    def side(self) -> int:
        return corner_side(self.corner)

    def body_point(self, name: str) -> np.ndarray:
        return self.axle_to_body(self.kinematics.point(name, self.side))

    def axle_to_body(self, point: np.ndarray) -> np.ndarray:
        """A point of the axle frame in the car body's frame, m."""
        return point + np.array([self.station_x, 0.0, -self.cg_height])

    def name(self, part: str) -> str:
        return f"{self.corner}/{part}"


def _axial(skew: np.ndarray) -> np.ndarray:
    return np.array([skew[2, 1] - skew[1, 2], skew[0, 2] - skew[2, 0], skew[1, 0] - skew[0, 1]]) / 2


def spin_frame(axis: np.ndarray) -> np.ndarray:
    """Rotation whose y axis is the spin ``axis`` (pointing left) and whose x axis is horizontal, forward."""
    y = axis / np.linalg.norm(axis)
    x = np.cross(y, [0.0, 0.0, 1.0])
    x /= np.linalg.norm(x)
    return np.column_stack([x, y, np.cross(x, y)])


def _rocker_part(kinematics: Kinematics, side: int, unsprung_mass: float, poses: geometry.Poses) -> Part:
    """The rocker at design (ROCKER_SHARE of the unsprung mass over its pivot and two ends), turning with the lower
    arm through the pushrod: its turn per m of travel from the rocker's angle at the poses (-h, 0, +h)."""
    point = kinematics.point
    front, rear = point("lower_front", side), point("lower_rear", side)
    angle = geometry.arm_angle(front, rear, point("lower_outer", side), poses.moved("lower_outer"))
    pushrod = geometry.rotate_about(point("pushrod_outer", side), front, rear, angle)
    turn = rocker.rocker_angle(kinematics, side, pushrod)
    pivot, axis = point("rocker_pivot", side), point("rocker_axis", side) - point("rocker_pivot", side)
    omega = (turn[2] - turn[0]) / (2 * DESIGN_STEP) * axis / np.linalg.norm(axis)
    mass = rocker.ROCKER_SHARE * unsprung_mass
    cg, inertia = point_inertia(mass, np.array([pivot, point("pushrod_inner", side), point("spring_lower", side)]))
    return Part(mass, cg, inertia, np.cross(omega, cg - pivot), omega)


def _wheel_part(unsprung_mass: float, parts: dict[str, Part], kinematics: Kinematics, side: int, radius: float,
                velocity: np.ndarray, spin: np.ndarray) -> Part:
    """The wheel: mass at the centre, moments 0.5 m r^2 about its axle and 0.3 m r^2 about its diameters (a tyre on a
    rim, ASSUMPTION), its mass what ``unsprung_mass`` leaves."""
    turn = spin_frame(geometry.design_spin_axis(kinematics, side))
    unit = turn @ np.diag([0.3, 0.5, 0.3]) @ turn.T * radius**2
    rest = unsprung_mass - sum(p.kinetic_mass for p in parts.values())
    mass = rest / (velocity @ velocity + spin @ unit @ spin)
    if mass <= 0:
        raise KinematicsError(f"unsprung_mass {unsprung_mass} kg is less than the links' share of it")
    return Part(mass, kinematics.point("wheel_centre", side), mass * unit, velocity, spin)


def _remove_point_mass(mass: float, com: np.ndarray, inertia: np.ndarray, removed: float, point: np.ndarray
                       ) -> tuple[float, np.ndarray, np.ndarray]:
    """A body (mass, CG, principal moments about x, y, z) less a point mass at ``point``; products of inertia
    that appear are left out (left and right corners cancel them but for x-z)."""
    def about_origin(m, c, moments):
        return np.diag(moments) + m * (float(c @ c) * np.eye(3) - np.outer(c, c))

    total = about_origin(mass, com, inertia) - about_origin(removed, point, np.zeros(3))
    new_mass = mass - removed
    new_com = (mass * com - removed * point) / new_mass
    about_cg = total - new_mass * (float(new_com @ new_com) * np.eye(3) - np.outer(new_com, new_com))
    return new_mass, new_com, np.diag(about_cg).copy()


def _static_spring_force(vehicle, corner: str, design: Design) -> float:
    """Force (N, at the wheel) the spring carries at design when the car stands at its static ride height."""
    from rig.vehicle.ride_model import static_loads

    tyre = static_loads(vehicle).tyre_force[vehicle.corners.index(corner)]
    return float(tyre - STANDARD_GRAVITY * sum(p.mass * p.velocity[2] for p in design.parts.values()))


def _remove_template_corner(car: mujoco.MjSpec, corner: str) -> None:
    """Delete the template's vertical corner (wheel body, spring tendon, their sensors); keep the body site."""
    for quantity in ("unsprung_acc", "suspension_length", "suspension_rate"):
        car.delete(car.sensor(f"{corner}/{quantity}"))
    car.delete(car.tendon(f"{corner}/suspension"))
    car.delete(car.body(f"{corner}/wheel"))


def _add_arm(car: mujoco.MjSpec, frame: CornerFrame, arm: Arm, part: Part) -> mujoco.MjsBody:
    """An arm on its inner pivots' hinge, behind its pivots' bushings (rig/vehicle/suspensions/bushings.py; or the
    three slides of ``bushing_rate``), drawn as two links."""
    kinematics, side = frame.kinematics, frame.side
    origin = kinematics.point(arm.front, side)
    body = add_part_body(car.body("body"), frame.name(arm.name), frame.body_point(arm.front), part, origin)
    if kinematics.bushing_rate is not None:
        for axis, rate, damping, label in zip(np.eye(3), kinematics.bushing_rate, kinematics.bushing_damping,
                                              HINGE_AXES):
            body.add_joint(name=frame.name(f"{arm.name}_bushing_{label}"), type=mujoco.mjtJoint.mjJNT_SLIDE,
                           axis=list(axis), stiffness=[rate, 0.0, 0.0], damping=[damping, 0.0, 0.0],
                           armature=rate * BUSHING_PERIOD**2)
    axis = kinematics.point(arm.rear, side) - origin
    axis = axis / np.linalg.norm(axis)
    compliance = bushings.arm_compliance(kinematics, arm.front, arm.rear, side)
    for slide in compliance.front:
        bushings.add_slides(body, frame.name(arm.name if slide.label == "axial" else arm.front), [slide])
    if compliance.conical is not None:
        bushings.add_conical(body, frame.name(arm.name), axis, compliance.conical)
    rate, damping = compliance.torsional
    body.add_joint(name=frame.name(arm.name), type=mujoco.mjtJoint.mjJNT_HINGE, axis=list(axis),
                   stiffness=[rate, 0.0, 0.0], damping=[damping, 0.0, 0.0])
    if compliance.closed_by_connect:  # the rear pivot: the arm's site held to the body's (or its sleeve's)
        rear = kinematics.point(arm.rear, side)
        body.add_site(name=frame.name(f"{arm.rear}_arm"), pos=list(rear - origin))
        bushings.bushed_site(car.body("body"), frame.name(arm.rear), frame.axle_to_body(rear), compliance.rear,
                             frame.name(arm.rear))
        connect(car, frame.name(arm.rear), frame.name(f"{arm.rear}_arm"))
    outer = kinematics.point(arm.outer, side) - origin
    add_link_geom(body, np.zeros(3), outer)
    add_link_geom(body, axis, outer)
    return body


def _add_wheel(upright: mujoco.MjsBody, frame: CornerFrame, origin: np.ndarray, part: Part, radius: float) -> None:
    """The wheel body ``<corner>/wheel`` at the wheel centre, its y axis the spin axis, drawn as a cylinder."""
    turn = spin_frame(geometry.design_spin_axis(frame.kinematics, frame.side))
    quat = np.empty(4)
    mujoco.mju_mat2Quat(quat, turn.flatten())
    centre = frame.kinematics.point("wheel_centre", frame.side)
    wheel = upright.add_body(name=frame.name("wheel"), pos=list(centre - origin), quat=list(quat))
    wheel.mass, wheel.ipos, wheel.explicitinertial = part.mass, [0.0, 0.0, 0.0], True
    wheel.inertia = list(np.diag(turn.T @ part.inertia @ turn))
    wheel.add_geom(name=frame.name("wheel"), type=mujoco.mjtGeom.mjGEOM_CYLINDER, size=[radius, WHEEL_HALF_WIDTH, 0.0],
                   quat=[np.sqrt(0.5), np.sqrt(0.5), 0.0, 0.0], rgba=[0.08, 0.08, 0.08, 1.0], contype=0, conaffinity=0,
                   mass=0.0)


def connect(car: mujoco.MjSpec, site1: str, site2: str) -> None:
    """A ball joint closing a loop: ``site1`` and ``site2`` (on two bodies, coincident at design) held together."""
    equality = car.add_equality(name=f"{site1}-{site2}", type=mujoco.mjtEq.mjEQ_CONNECT,
                                objtype=mujoco.mjtObj.mjOBJ_SITE, name1=site1, name2=site2)
    equality_stiff(equality)


def _rack(car: mujoco.MjSpec, frame: CornerFrame) -> mujoco.MjsBody:
    """The axle's steering rack (created with its first corner): a body on a slide joint along y across the
    body, stiff by ``rack_rate``, through the tie rods' inner ends."""
    axle = corner_axle(frame.corner)
    rack = car.body(f"{axle}/rack")
    if rack is not None:
        return rack
    inner = frame.body_point("tie_rod_inner") * [1.0, 0.0, 1.0]
    rack = car.body("body").add_body(name=f"{axle}/rack", pos=list(inner))
    rack.mass, rack.ipos, rack.inertia, rack.explicitinertial = RACK_MASS, [0, 0, 0], [1e-3] * 3, True
    rack.add_joint(name=f"{axle}/rack", type=mujoco.mjtJoint.mjJNT_SLIDE, axis=[0.0, 1.0, 0.0],
                   stiffness=[frame.kinematics.rack_rate, 0.0, 0.0], damping=[RACK_DAMPING, 0.0, 0.0])
    half = abs(frame.kinematics.point("tie_rod_inner")[1])
    add_link_geom(rack, np.array([0.0, -half, 0.0]), np.array([0.0, half, 0.0]), 1.5 * LINK_RADIUS)
    return rack


def _add_tie_rod(car: mujoco.MjSpec, frame: CornerFrame) -> None:
    """The tie rod: a spatial tendon from the rack (or the body) to the upright, held at its design length."""
    site = frame.name("tie_rod_inner")
    slides = bushings.ball_slides(frame.kinematics, "tie_rod_inner", frame.side)
    if frame.kinematics.steered:
        bushings.bushed_site(_rack(car, frame), site, np.array([0.0, frame.body_point("tie_rod_inner")[1], 0.0]),
                             slides, site)
    else:
        bushings.bushed_site(car.body("body"), site, frame.body_point("tie_rod_inner"), slides, site)
    add_rod(car, frame.name("tie_rod"), site, frame.name("tie_rod_outer"))


def _add_spring_and_damper(car: mujoco.MjSpec, frame: CornerFrame, ends: tuple[np.ndarray, np.ndarray],
                           carrier: mujoco.MjsBody, carrier_origin: np.ndarray, design: Design, axle, preload: float
                           ) -> None:
    """Spring ``<corner>/suspension`` and damper ``<corner>/damper`` on the spring line, their lengths divided by
    the design motion ratio (rates at the wheel at design), the spring preloaded to carry the static load."""
    upper, lower = ends
    car.body("body").add_site(name=frame.name("spring_upper"), pos=list(frame.axle_to_body(upper)))
    carrier.add_site(name=frame.name("spring_lower"), pos=list(lower - carrier_origin))
    ratio = design.motion_ratio
    if not ratio > 0.05:
        raise KinematicsError(f"{frame.corner}: the spring line spring_upper - spring_lower hardly moves with the "
                              f"wheel (motion ratio {ratio:.3f}): put spring_lower on the arm or the knuckle")
    curvature = design.spring_curvature / ratio  # of the divided length
    stiffness = axle.spring_rate + preload * curvature
    for name, rgba in (("suspension", [0.85, 0.75, 0.2, 0.0]), ("damper", [0.3, 0.3, 0.3, 0.0]),
                       ("spring_line", [0.85, 0.75, 0.2, 1.0])):
        tendon = car.add_tendon(name=frame.name(name))
        if name != "spring_line":  # the drawn line is the real one; the divided ones carry the forces
            tendon.wrap_pulley(ratio)
        tendon.wrap_site(frame.name("spring_upper"))
        tendon.wrap_site(frame.name("spring_lower"))
        tendon.rgba, tendon.width = rgba, 0.02
    spring = car.tendon(frame.name("suspension"))
    spring.stiffness = [stiffness, 0.0, 0.0]
    spring.springlength = [design.spring_length / ratio + preload / stiffness] * 2
    car.tendon(frame.name("damper")).damping = [axle.damping, 0.0, 0.0]


def _add_travel_sensors(car: mujoco.MjSpec, frame: CornerFrame) -> None:
    """``<corner>/unsprung_acc`` (hub, world frame) and ``<corner>/suspension_length`` / ``_rate``: the hub's
    distance and its rate below the body site along the body's -z (a site turned so that its x axis points down)."""
    reference = frame.name("travel")
    car.body("body").add_site(name=reference, pos=list(frame.axle_to_body(body_site(frame.kinematics, frame.side))),
                              quat=[np.sqrt(0.5), 0.0, np.sqrt(0.5), 0.0])
    site = mujoco.mjtObj.mjOBJ_SITE
    car.add_sensor(name=frame.name("unsprung_acc"), type=mujoco.mjtSensor.mjSENS_FRAMELINACC, objtype=site,
                   objname=frame.name("hub"))
    for quantity, kind in (("suspension_length", mujoco.mjtSensor.mjSENS_FRAMEPOS),
                           ("suspension_rate", mujoco.mjtSensor.mjSENS_FRAMELINVEL)):
        car.add_sensor(name=frame.name(quantity), type=kind, objtype=site, objname=frame.name("hub"),
                       reftype=site, refname=reference)
