"""The MJCF of a truck (layout ``truck``): what the car's templates hold per corner, made for any number of axles,
the frame (rigid, or segments: rig/elements/frame.py) and the bodies on mounts (cab, driveline:
rig/elements/mounted_body.py).

The rig and car templates (assets/mjcf/) hold four corners; a truck's corners are made here with the same elements
and names: per corner a post (slide ``<corner>/post``, rod and pan geoms, site ``<corner>/pan``, actuator
``<corner>/servo``, sensors ``<corner>/actuator_disp`` and ``<corner>/actuator_force``) and, on the car, the vertical
corner of the template (site ``<corner>/body`` on the frame above the wheel, body and slide ``<corner>/wheel``, site
``<corner>/hub``, tendon ``<corner>/suspension``, sensors ``<corner>/sprung_acc``, ``<corner>/unsprung_acc``,
``<corner>/suspension_length`` and ``<corner>/suspension_rate``), which a beam-axle type then replaces.
"""

from __future__ import annotations

import mujoco
import numpy as np

from rig.elements.air_spring import add_air_spring
from rig.elements.frame import (
    ROOT_BODY,
    add_segments,
    parse_frame,
    root_index,
    segment_at,
    segment_name,
    segment_origin,
    segments_of,
)
from rig.elements.mounted_body import MOUNTED_BODIES, MOUNTS, SEAT_SITE, MountedBody
from rig.vehicle.extensions import extensions

WHEEL_COLOR = [0.08, 0.08, 0.08, 1.0]
SPRING_COLOR = [0.85, 0.75, 0.20, 1.0]
BODY_COLOR = {"cab": [0.85, 0.85, 0.90, 0.6], "driveline": [0.35, 0.35, 0.40, 0.8]}
_SITE = mujoco.mjtObj.mjOBJ_SITE


def frame_of(vehicle):
    """The vehicle's frame as built: its ``[frame]``, as its causes change it (a cause may give a ``[frame]`` table;
    None: rigid)."""
    frame = vehicle.frame
    for cause in extensions().values():
        if cause.present(vehicle):
            frame = cause.adjust_frame(vehicle, frame)
            if isinstance(frame, dict):
                frame = parse_frame(frame, f"{vehicle.source}: [{cause.name}]", vehicle.sprung_mass,
                                    vehicle.roll_inertia)
    return frame


def frame_body(car: mujoco.MjSpec, vehicle, x: float) -> tuple[mujoco.MjsBody, float]:
    """The frame body at ``x`` m from the sprung CG (forward) and the x of its origin there."""
    frame = frame_of(vehicle)
    if frame is None:
        return car.body(ROOT_BODY), 0.0
    segments = segments_of(frame, vehicle.cg_to_front_axle, 1.0, 1.0)
    index = segment_at(segments, x)
    root = root_index(segments)
    return car.body(segment_name(index, root)), segment_origin(segments, index, root)


def frame_point_terms(vehicle, x: float, y: float) -> dict[str, float]:
    """Joint -> coefficient whose weighted sum is the rise (m) of the frame's point (x, y) m from the sprung CG, for
    small angles: the sprung body's heave, pitch and roll, and a flexible frame's bending and torsion hinges between
    the CG's segment and the point's."""
    terms = {"heave": 1.0, "pitch": -x, "roll": y}
    frame = frame_of(vehicle)
    if frame is None:
        return terms
    segments = segments_of(frame, vehicle.cg_to_front_axle, 1.0, 1.0)
    root, index = root_index(segments), segment_at(segments, x)
    chain = range(root - 1, index - 1, -1) if index < root else range(root + 1, index + 1)
    for k in chain:  # each hinge turns the segments beyond it about its own axis at its joint
        joint = segment_origin(segments, k, root)
        terms[f"{segment_name(k, root)}_bend"] = -(x - joint)
        terms[f"{segment_name(k, root)}_twist"] = y
    return terms


def add_frame_site(car: mujoco.MjSpec, vehicle, name: str, x: float, y: float, z: float = 0.0) -> None:
    """A site on the frame at (x, y, z) m from the sprung CG's design position."""
    body, origin = frame_body(car, vehicle, x)
    body.add_site(name=name, pos=[x - origin, y, z])


def build_frame(car: mujoco.MjSpec, vehicle, mass: float, com: np.ndarray, inertia: np.ndarray) -> None:
    """The flexible frame's segments in place of the rigid body's mass (``mass``, ``com`` and principal ``inertia``
    as the corners and causes leave them); nothing for a rigid frame."""
    frame = frame_of(vehicle)
    if frame is None:
        return
    car.delete(car.geom(ROOT_BODY))
    segments = segments_of(frame, vehicle.cg_to_front_axle, mass, float(inertia[0]), float(inertia[1]),
                           cg=float(com[0]))
    add_segments(car, car.body(ROOT_BODY), segments, frame, (float(com[1]), float(com[2])))


def add_post(spec: mujoco.MjSpec, corner: str) -> None:
    """A post of the template (assets/mjcf/four_poster.xml) for ``corner``; rig/vehicle/mjcf.py sets its numbers."""
    post = spec.worldbody.add_body(name=f"{corner}/post")
    post.add_joint(name=f"{corner}/post", type=mujoco.mjtJoint.mjJNT_SLIDE, axis=[0, 0, 1],
                   limited=mujoco.mjtLimited.mjLIMITED_TRUE)
    for name, material in (("rod", "steel"), ("pan", "pan")):
        post.add_geom(name=f"{corner}/{name}", type=mujoco.mjtGeom.mjGEOM_CYLINDER, material=material,
                      contype=0, conaffinity=0)
    post.add_site(name=f"{corner}/pan")
    servo = spec.add_actuator(name=f"{corner}/servo", target=f"{corner}/post")
    servo.trntype = mujoco.mjtTrn.mjTRN_JOINT
    spec.add_sensor(name=f"{corner}/actuator_disp", type=mujoco.mjtSensor.mjSENS_JOINTPOS,
                    objtype=mujoco.mjtObj.mjOBJ_JOINT, objname=f"{corner}/post")
    spec.add_sensor(name=f"{corner}/actuator_force", type=mujoco.mjtSensor.mjSENS_ACTUATORFRC,
                    objtype=mujoco.mjtObj.mjOBJ_ACTUATOR, objname=f"{corner}/servo")


def add_corner(car: mujoco.MjSpec, vehicle, corner: str) -> None:
    """The template's vertical corner (assets/mjcf/ride_car.xml) for ``corner``, its body site on the frame above the
    wheel centre; the suspension type fills in the numbers (or replaces it)."""
    x, y = vehicle.corner_position(corner)
    add_frame_site(car, vehicle, f"{corner}/body", x, y)
    wheel = car.worldbody.add_body(name=f"{corner}/wheel")
    wheel.add_joint(name=f"{corner}/wheel", type=mujoco.mjtJoint.mjJNT_SLIDE, axis=[0, 0, 1])
    wheel.add_geom(name=f"{corner}/wheel", type=mujoco.mjtGeom.mjGEOM_CYLINDER, rgba=WHEEL_COLOR,
                   euler=[np.pi / 2, 0, 0], contype=0, conaffinity=0)
    wheel.add_site(name=f"{corner}/hub")
    tendon = car.add_tendon(name=f"{corner}/suspension")
    tendon.wrap_site(f"{corner}/body")
    tendon.wrap_site(f"{corner}/hub")
    tendon.width, tendon.rgba = 0.02, SPRING_COLOR
    for quantity, site in (("sprung_acc", "body"), ("unsprung_acc", "hub")):
        car.add_sensor(name=f"{corner}/{quantity}", type=mujoco.mjtSensor.mjSENS_FRAMELINACC, objtype=_SITE,
                       objname=f"{corner}/{site}")
    for quantity, kind in (("suspension_length", mujoco.mjtSensor.mjSENS_TENDONPOS),
                           ("suspension_rate", mujoco.mjtSensor.mjSENS_TENDONVEL)):
        car.add_sensor(name=f"{corner}/{quantity}", type=kind, objtype=mujoco.mjtObj.mjOBJ_TENDON,
                       objname=f"{corner}/suspension")


def build_mounted_bodies(car: mujoco.MjSpec, vehicle) -> None:
    """The cab and the driveline on their mounts, where the vehicle has them."""
    for name in MOUNTED_BODIES:
        body = getattr(vehicle, name)
        if body is not None:
            add_mounted_body(car, vehicle, name, body)


def add_mounted_body(car: mujoco.MjSpec, vehicle, name: str, spec: MountedBody) -> None:
    """Body ``name`` with heave, pitch and roll of its own at its CG, on four vertical spring-damper mounts."""
    x = vehicle.cg_to_front_axle - spec.position
    body = car.worldbody.add_body(name=name, pos=[x, 0.0, vehicle.cg_height + spec.height])
    body.mass, body.ipos = spec.mass, [0.0, 0.0, 0.0]
    body.inertia = [spec.roll_inertia, spec.pitch_inertia, max(spec.roll_inertia, spec.pitch_inertia)]
    body.explicitinertial = True
    for joint, kind, axis in (("heave", mujoco.mjtJoint.mjJNT_SLIDE, [0, 0, 1]),
                              ("pitch", mujoco.mjtJoint.mjJNT_HINGE, [0, 1, 0]),
                              ("roll", mujoco.mjtJoint.mjJNT_HINGE, [1, 0, 0])):
        body.add_joint(name=f"{name}/{joint}", type=kind, axis=axis)
    body.add_geom(name=f"{name}/box", type=mujoco.mjtGeom.mjGEOM_BOX, rgba=BODY_COLOR[name], contype=0,
                  conaffinity=0, mass=0.0, size=[spec.mount_base / 2 + 0.1, spec.mount_track / 2 + 0.1, 0.3])
    # each mount is a fixed tendon: its stretch is the frame point's rise less the body point's (small angles,
    # joint coordinates), a spring and damper in joint space that neither buckles nor leans with the frame's pitch
    for mount, (dx, dy) in zip(MOUNTS, spec.mount_points()):
        tendon = car.add_tendon(name=f"{name}/{mount}_mount")
        terms = frame_point_terms(vehicle, x + dx, dy)
        for joint, coefficient in (("heave", 1.0), ("pitch", -dx), ("roll", dy)):
            terms[f"{name}/{joint}"] = -coefficient
        for joint, coefficient in terms.items():
            if coefficient != 0.0:
                tendon.wrap_joint(joint, coefficient)
        tendon.stiffness, tendon.damping = [spec.stiffness, 0.0, 0.0], [spec.damping, 0.0, 0.0]
        tendon.springlength = [0.0, 0.0]  # drawn unloaded: the static solve lets the body settle
        if spec.air_spring is not None:  # drawn at design height, the gas carrying the body there
            add_air_spring(car, f"{name}/{mount}_air_spring", tendon, spec.air_spring, 0.0, lengthens=True)
    if name == "cab" and spec.seat is not None:
        body.add_site(name=SEAT_SITE, pos=list(spec.seat))
        car.add_sensor(name="cab/seat_acc", type=mujoco.mjtSensor.mjSENS_FRAMELINACC, objtype=_SITE,
                       objname=SEAT_SITE)
