"""Assemble the MuJoCo model of a vehicle on the four-poster from the MJCF templates and a vehicle file.

The rig template (assets/mjcf/four_poster.xml) and the car template (assets/mjcf/ride_car.xml) hold
structure only; every number comes from the vehicle file or its ``[rig]`` section through
``mujoco.MjSpec``. The tyres join the two: per corner a spatial tendon from the wheel pan (or, with
ideal posts, from a fixed point under the wheel) to the hub, loaded by a ``general`` actuator

    F = kt * (L0 + u - L) - ct * dL/dt,  clamped to F >= 0  (the tyre pushes only and can lift off),

where L is the tendon length, L0 its unloaded length and u the actuator input: zero on the rig, the
road (or measured post) height plus (ct/kt) times its rate with ideal posts. All forces stay inside
``mj_step`` so whole runs go through ``mujoco.rollout``.

Posts (``posts="servo"``): slide joint with the rig's stroke as its range, moving mass, and a
``general`` actuator: drive -> ``delay`` -> first-order ``filter`` lag -> position loop
``F = kp (act - x) - kv dx/dt + F_static``, limited to the rig's force rating. ``posts="ideal"``
removes the post joints: the posts then move exactly as the input says (measured actuator
displacement, or a road).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import mujoco
import numpy as np

from rig.assets import mjcf_path
from rig.channels import CORNERS
from rig.units import STANDARD_GRAVITY
from rig.vehicle import Vehicle

POST_MODES = ("servo", "ideal")
MAX_TIMESTEP = 1e-3  # s: RK4 at <= 1 ms resolves the post loop (150 Hz) and wheel hop (~12 Hz) accurately
#: Every input actuator reads its control from a history buffer this many steps late. MuJoCo reads delayed
#: controls at each RK4 stage time, interpolating (cubic needs three steps), so inputs run continuously through a step
#: instead of being held; the simulator feeds controls this much early (rig/simulate.py).
INPUT_DELAY_STEPS = 3
_TYRE_FORCE_CAP = 1e7  # N, upper clamp of the tyre force (lower clamp 0: lift-off)
_BODY_DOFS = ("heave", "pitch", "roll")


@dataclass
class RigModel:
    """A compiled model with the addresses the simulator needs. Built by ``build_model``."""

    model: mujoco.MjModel
    vehicle: Vehicle
    posts: str
    rate: float                     # Hz, record sample rate the model is set up for
    steps_per_sample: int           # physics steps per record sample
    corners: tuple[str, ...]
    servo_ctrl: np.ndarray          # ctrl address of each corner's post servo (servo posts)
    tyre_ctrl: np.ndarray           # ctrl address of each corner's tyre input
    sensor_adr: dict[str, int] = field(default_factory=dict)  # sensor name -> first sensordata index
    post_qpos: np.ndarray = field(default_factory=lambda: np.zeros(0, int))
    post_dof: np.ndarray = field(default_factory=lambda: np.zeros(0, int))
    free_dofs: np.ndarray = field(default_factory=lambda: np.zeros(0, int))  # car DOFs (not posts)
    servo_ids: np.ndarray = field(default_factory=lambda: np.zeros(0, int))
    tyre_ids: np.ndarray = field(default_factory=lambda: np.zeros(0, int))

    @property
    def timestep(self) -> float:
        return self.model.opt.timestep


def timestep_for(rate: float) -> tuple[float, int]:
    """Physics step (s) and steps per sample so that record samples fall on steps and h <= MAX_TIMESTEP."""
    steps = max(1, math.ceil(1.0 / (rate * MAX_TIMESTEP) - 1e-9))
    return 1.0 / (rate * steps), steps


def build_spec(vehicle: Vehicle, posts: str = "servo", timestep: float = MAX_TIMESTEP) -> mujoco.MjSpec:
    """The assembled MjSpec (rig + car + tyres) for ``vehicle``; compile it or save it as MJCF."""
    if posts not in POST_MODES:
        raise ValueError(f"posts must be one of {POST_MODES}, got {posts!r}")
    spec = mujoco.MjSpec.from_file(str(mjcf_path("four_poster.xml")))
    car = mujoco.MjSpec.from_file(str(mjcf_path("ride_car.xml")))
    spec.modelname = f"{vehicle.name}_on_four_poster"
    spec.option.timestep = timestep
    spec.option.gravity = [0.0, 0.0, -STANDARD_GRAVITY]
    corners = vehicle.corners
    _remove_corners(spec, car, [c for c in CORNERS if c not in corners])
    _set_car(car, vehicle)
    spec.copy_during_attach = True  # the car spec is a local: the rig must own copies of its elements
    spec.attach(car, frame=spec.frame("car_mount"), prefix="car.")
    _set_posts(spec, vehicle, posts, timestep)
    for corner in corners:
        _add_tyre(spec, vehicle, corner, posts, timestep)
    return spec


def build_model(vehicle: Vehicle, rate: float, posts: str = "servo") -> RigModel:
    """Compile the model for records sampled at ``rate`` Hz and collect its addresses."""
    timestep, steps = timestep_for(rate)
    model = build_spec(vehicle, posts, timestep).compile()
    corners = vehicle.corners

    def actuator_ctrl(name: str) -> int:
        return int(model.actuator_ctrladr[model.actuator(name).id])

    sensor_adr = {model.sensor(i).name: int(model.sensor_adr[i]) for i in range(model.nsensor)}
    rig = RigModel(
        model=model, vehicle=vehicle, posts=posts, rate=float(rate), steps_per_sample=steps, corners=corners,
        servo_ctrl=np.array([actuator_ctrl(f"{c}/servo") for c in corners] if posts == "servo" else [], int),
        tyre_ctrl=np.array([actuator_ctrl(f"{c}/tyre") for c in corners], int),
        sensor_adr=sensor_adr,
        tyre_ids=np.array([model.actuator(f"{c}/tyre").id for c in corners], int),
    )
    if posts == "servo":
        joints = [model.joint(f"{c}/post") for c in corners]
        rig.post_qpos = np.array([int(j.qposadr[0]) for j in joints])
        rig.post_dof = np.array([int(j.dofadr[0]) for j in joints])
        rig.servo_ids = np.array([model.actuator(f"{c}/servo").id for c in corners], int)
    rig.free_dofs = np.setdiff1d(np.arange(model.nv), rig.post_dof)
    return rig


def _remove_corners(spec: mujoco.MjSpec, car: mujoco.MjSpec, corners: list[str]) -> None:
    """Delete the named corners (posts, wheels, tendons, sensors); a quarter car also loses pitch and roll."""
    if not corners:
        return
    for s in (spec, car):
        for element in list(s.sensors) + list(s.actuators) + list(s.tendons):
            if element.name.split("/")[0] in corners:
                s.delete(element)
        for element in list(s.sites):
            if element.name.split("/")[0] in corners:
                s.delete(element)
        for body in list(s.bodies):
            if body.name.split("/")[0] in corners:
                s.delete(body)
    for dof in ("pitch", "roll"):
        car.delete(car.joint(dof))


TOP_MOUNT_MASS = 5.0  # kg taken from the sprung mass per compliant top mount: keeps its mode RK4-stable at 1 ms


def _set_car(car: mujoco.MjSpec, v: Vehicle) -> None:
    """Fill the car template: body inertia at the CG, corner sites, wheels, springs, dampers, extensions."""
    body = car.body("body")
    body.pos = [0.0, 0.0, v.cg_height]
    _set_sprung_inertia(body, v)
    length = v.wheelbase if v.layout == "full" else 0.6
    width = max(v.track_front, v.track_rear) if v.layout == "full" else 0.6
    box = car.geom("body")
    box.size = [length / 2 + 0.4, width / 2, 0.15]
    box.pos = [(v.cg_to_front_axle - v.wheelbase / 2) if v.layout == "full" else 0.0, 0.0, 0.1]
    for corner in v.corners:
        x, y = v.corner_position(corner)
        axle = v.axle(corner)
        car.site(f"{corner}/body").pos = [x, y, 0.0]
        wheel = car.body(f"{corner}/wheel")
        wheel.pos = [x, y, v.wheel_radius]
        wheel.mass = axle.unsprung_mass
        wheel.ipos = [0.0, 0.0, 0.0]
        wheel.inertia = [1.0, 1.0, 1.0]  # vertical slide only: rotary inertia never enters
        wheel.explicitinertial = True
        car.geom(f"{corner}/wheel").size = [v.wheel_radius, 0.1, 0]
        spring = car.tendon(f"{corner}/suspension")
        spring.stiffness = [axle.suspension_rate, 0.0, 0.0]  # rest length: the template's unloaded length
        friction = v.extension("strut_friction", corner)
        if friction is not None:
            spring.frictionloss = friction.force
            spring.solimp_friction = [0.9999, 0.9999, 0.001, 0.5, 2.0]  # default impedance lets it creep
        _add_damper(car, v, corner, x, y)
        _add_bump_stop(car, v, corner)
        _add_progressive_spring(car, v, corner)
    for axle in ("front", "rear") if v.layout == "full" else ():
        bar = v.extensions.get("anti_roll_bar", {}).get(axle)
        if bar is not None:
            left, right = ("FL", "FR") if axle == "front" else ("RL", "RR")
            track = v.track_front if axle == "front" else v.track_rear
            # length = left minus right compression, linearised: track * roll - z_left + z_right
            tendon = car.add_tendon(name=f"{axle}/anti_roll_bar")
            tendon.wrap_joint("roll", track)
            tendon.wrap_joint(f"{left}/wheel", -1.0)
            tendon.wrap_joint(f"{right}/wheel", 1.0)
            tendon.stiffness = [bar.rate, 0.0, 0.0]


def _set_sprung_inertia(body: mujoco.MjsBody, v: Vehicle) -> None:
    """Sprung mass and inertia about the CG, plus a [mass_error] payload (parallel-axis theorem), less the
    top-mount masses (they move with the body at low frequency)."""
    mass, position = v.sprung_mass, np.zeros(3)
    inertia = np.array([v.roll_inertia or 1.0, v.pitch_inertia or 1.0, v.yaw_inertia or 1.0])
    payload = v.extensions.get("mass_error")
    if payload is not None:
        total = mass + payload.mass
        offset = np.array([payload.x, payload.y, 0.0])
        position = payload.mass * offset / total
        # point payload about the new CG, original body about the new CG
        for point_mass, point in ((payload.mass, offset - position), (mass, -position)):
            inertia += point_mass * np.array([point[1] ** 2, point[0] ** 2, point[0] ** 2 + point[1] ** 2])
        mass = total
    mounts = sum(1 for c in v.corners if v.extension("top_mount_compliance", c) is not None)
    body.mass = mass - TOP_MOUNT_MASS * mounts
    body.ipos = position.tolist()
    body.inertia = inertia.tolist()
    body.explicitinertial = True


def _add_damper(car: mujoco.MjSpec, v: Vehicle, corner: str, x: float, y: float) -> None:
    """The damper: a tendon from the body (or a compliant top mount) to the hub, linear or asymmetric."""
    upper = f"{corner}/body"
    mount = v.extension("top_mount_compliance", corner)
    if mount is not None:
        top = car.body("body").add_body(name=f"{corner}/top_mount", pos=[x, y, 0.0])
        top.add_joint(name=f"{corner}/top_mount", type=mujoco.mjtJoint.mjJNT_SLIDE, axis=[0, 0, 1],
                      stiffness=mount.rate)
        top.mass, top.ipos, top.inertia, top.explicitinertial = TOP_MOUNT_MASS, [0, 0, 0], [1e-3] * 3, True
        top.add_site(name=f"{corner}/top_mount")
        upper = f"{corner}/top_mount"
    damper_tendon = car.add_tendon(name=f"{corner}/damper")
    damper_tendon.wrap_site(upper)
    damper_tendon.wrap_site(f"{corner}/hub")
    damper_tendon.rgba = [0.3, 0.3, 0.3, 0.0]
    asymmetry = v.extension("damper_asymmetry", corner)
    if asymmetry is None:
        damper_tendon.damping = [v.axle(corner).damping, 0.0, 0.0]
        return
    # one affine actuator per sign of the damper velocity, each clamped to its own force sign
    for name, coefficient, force_range in (("rebound", asymmetry.rebound, [-_TYRE_FORCE_CAP, 0.0]),
                                           ("compression", asymmetry.compression, [0.0, _TYRE_FORCE_CAP])):
        actuator = car.add_actuator(name=f"{corner}/damper_{name}", target=f"{corner}/damper")
        actuator.trntype = mujoco.mjtTrn.mjTRN_TENDON
        actuator.gainprm[0] = 0.0
        actuator.biastype = mujoco.mjtBias.mjBIAS_AFFINE
        actuator.biasprm[:3] = [0.0, 0.0, -coefficient]
        actuator.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
        actuator.forcerange = force_range


def _add_progressive_spring(car: mujoco.MjSpec, v: Vehicle, corner: str) -> None:
    """Seed 003's F = K0 x + Kn x^2 (+ cubic) about static ride height: the nonlinear terms on a tendon beside
    the linear spring, with MuJoCo's f = -(a y + b y^2 + c y^3), y = -compression, so b = -Kn and c = cubic.
    rig/statics.py centres it on the static length (inactive dead band until then)."""
    progressive = v.extension("progressive_spring", corner)
    if progressive is not None:
        _inactive_spring_beside_suspension(car, f"{corner}/progressive_spring", corner,
                                           [0.0, -progressive.quadratic, progressive.cubic])


def _add_bump_stop(car: mujoco.MjSpec, v: Vehicle, corner: str) -> None:
    """Dead-band spring beside the suspension; rig/statics.py sets its contact length from static ride
    height (until then the dead band [0, 1 km] keeps it inactive)."""
    bump = v.extension("bump_stop", corner)
    if bump is not None:
        _inactive_spring_beside_suspension(car, f"{corner}/bump_stop", corner, [bump.rate, 0.0, 0.0])


def _inactive_spring_beside_suspension(car: mujoco.MjSpec, name: str, corner: str, stiffness: list[float]) -> None:
    """A hidden spring tendon from body to hub with a [0, 1 km] dead band: inactive until rig/statics.py
    sets its reference from static ride height."""
    tendon = car.add_tendon(name=name)
    tendon.wrap_site(f"{corner}/body")
    tendon.wrap_site(f"{corner}/hub")
    tendon.stiffness = stiffness
    tendon.springlength = [0.0, 1e3]
    tendon.rgba = [0.2, 0.2, 0.2, 0.0]


def _set_posts(spec: mujoco.MjSpec, v: Vehicle, posts: str, timestep: float) -> None:
    rig = v.rig
    for corner in v.corners:
        x, y = v.corner_position(corner)
        post = spec.body(f"{corner}/post")
        post.pos = [x, y, 0.0]
        post.mass = rig.post_mass
        post.ipos = [0.0, 0.0, 0.0]
        post.inertia = [1.0, 1.0, 1.0]
        post.explicitinertial = True
        spec.geom(f"{corner}/pan").size = [rig.pan_diameter / 2, 0.02, 0]
        spec.geom(f"{corner}/pan").pos = [0, 0, -0.02]
        spec.geom(f"{corner}/rod").size = [0.04, 0.5, 0]
        spec.geom(f"{corner}/rod").pos = [0, 0, -0.54]
        if posts == "ideal":
            spec.delete(spec.sensor(f"{corner}/actuator_disp"))
            spec.delete(spec.sensor(f"{corner}/actuator_force"))
            spec.delete(spec.actuator(f"{corner}/servo"))
            spec.delete(spec.joint(f"{corner}/post"))
            continue
        spec.joint(f"{corner}/post").range = [-rig.stroke, rig.stroke]
        servo = spec.actuator(f"{corner}/servo")
        servo.gainprm[0] = rig.loop_stiffness
        servo.biasprm[:3] = [0.0, -rig.loop_stiffness, -rig.loop_damping_coefficient]
        servo.biastype = mujoco.mjtBias.mjBIAS_AFFINE
        servo.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
        servo.forcerange = [-rig.force_limit, rig.force_limit]
        if rig.lag_time_constant > 0:
            # 'filter', integrated by RK4 with the rest of the state: 'filterexact' under RK4 lost 5 % of
            # amplitude at 30 Hz (h = 1 ms, tau = 3.2 ms) in our checks
            servo.dyntype = mujoco.mjtDyn.mjDYN_FILTER
            servo.dynprm[0] = rig.lag_time_constant
        _read_input_late(servo, rig.servo_delay, timestep)


def _read_input_late(actuator: mujoco.MjsActuator, delay: float, timestep: float) -> None:
    """Read the control from history, ``delay`` s plus the input delay late, cubic (Catmull-Rom) between steps."""
    actuator.delay = delay + INPUT_DELAY_STEPS * timestep
    actuator.nsample = math.ceil(actuator.delay / timestep - 1e-9) + 2
    actuator.interp = 2  # cubic (0 zoh, 1 linear, 2 cubic)


def _add_tyre(spec: mujoco.MjSpec, v: Vehicle, corner: str, posts: str, timestep: float) -> None:
    axle = v.axle(corner)
    if posts == "servo":
        lower = f"{corner}/pan"
    else:
        x, y = v.corner_position(corner)
        lower = f"{corner}/ground"
        spec.worldbody.add_site(name=lower, pos=[x, y, 0.0])
    tendon = spec.add_tendon(name=f"{corner}/tyre_spring")
    tendon.wrap_site(lower)
    tendon.wrap_site(f"car.{corner}/hub")
    tendon.width = 0.03
    tendon.rgba = [0.1, 0.1, 0.1, 1.0]
    unloaded_length = v.wheel_radius  # the template draws the tyre just touching the pan, unloaded
    tyre = spec.add_actuator(name=f"{corner}/tyre", target=f"{corner}/tyre_spring")
    tyre.trntype = mujoco.mjtTrn.mjTRN_TENDON
    tyre.gainprm[0] = axle.tyre_rate
    tyre.biastype = mujoco.mjtBias.mjBIAS_AFFINE
    tyre.biasprm[:3] = [axle.tyre_rate * unloaded_length, -axle.tyre_rate, -axle.tyre_damping]
    tyre.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
    tyre.forcerange = [0.0, _TYRE_FORCE_CAP]
    tyre.ctrllimited = mujoco.mjtLimited.mjLIMITED_FALSE
    _read_input_late(tyre, 0.0, timestep)
    spec.add_sensor(name=f"{corner}/tyre_force", type=mujoco.mjtSensor.mjSENS_ACTUATORFRC,
                    objtype=mujoco.mjtObj.mjOBJ_ACTUATOR, objname=f"{corner}/tyre")
