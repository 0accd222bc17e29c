"""Assemble the MuJoCo model of a vehicle on the four-poster from the MJCF templates and a vehicle file.

The rig template (assets/mjcf/four_poster.xml) and the car template (assets/mjcf/ride_car.xml) hold
structure only; every number comes from the vehicle file or its ``[rig]`` section through
``mujoco.MjSpec``. The tyres join the two: per corner a spatial tendon from the wheel pan (or, with
ideal posts, from a fixed point under the wheel) to the hub, loaded by a ``general`` actuator

    F = kt * (L0 + u - L) - ct * dL/dt,  clamped to F >= 0  (the tyre pushes only and can lift off),

where L is the tendon length, L0 its unloaded length and u the actuator input: zero on the rig, the
road (or measured post) height plus (ct/kt) times its rate with ideal posts. All forces stay inside
``mj_step`` so whole runs go through ``mujoco.rollout``.

Between body and wheel of every corner stands a force actuator, ``<corner>/active_force`` on a tendon from the body
site to the hub: its input is the force (N) an actuator applies to the body, equal and opposite on the wheel,
positive pushing the body up (a record's ``<corner>/active_force``: a lab bench's actuator, an active suspension),
read late and interpolated like the posts' drives; zero without one. Its gain and dynamics are the causes'
(``force_constant_error``, ``force_actuator_lag``). Sensors ``<corner>/body_height`` and ``<corner>/hub_height``
(frame positions of the body site and the hub) give the displacements from static, ``sprung_disp`` and
``unsprung_disp``. A ``clock`` sensor reads the simulation's time, so that a rollout that keeps only sensor data still
shows a run that MuJoCo stopped (rig/sim/simulate.py).

A wheel that turns (a cause's body on a hinge about the axle, such as an unbalance) has a position servo
``<corner>/wheel_spin`` on that hinge: its input is the wheel's angle (rad) plus (kv/kp) times its rate, read
late and interpolated like the tyres' road input, so the hinge follows the angle without lag.

Posts (``posts="servo"``): slide joint with the rig's stroke as its range, moving mass, and a
``general`` actuator: drive -> ``delay`` -> first-order ``filter`` lag -> position loop
``F = kp (act - x) - kv dx/dt + F_static``, limited to the rig's force rating. ``posts="ideal"``
removes the post joints: the posts then move exactly as the input says (measured actuator
displacement, or a road).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import mujoco
import numpy as np

from rig.elements.tendons import FORCE_CAP, PHYSICS_STEP
from rig.io.channels import CORNERS
from rig.io.units import STANDARD_GRAVITY
from rig.vehicle.assets import mjcf_path
from rig.vehicle.extensions import in_build_order
from rig.vehicle.parts import Vehicle
from rig.vehicle.suspensions import suspension_of
from rig.vehicle.tables import VehicleError
from rig.vehicle.truck_mjcf import add_corner, add_post, build_frame, build_mounted_bodies

POST_MODES = ("servo", "ideal")
MAX_TIMESTEP = PHYSICS_STEP  # s: RK4 at <= 1 ms resolves the post loop (150 Hz) and wheel hop (~12 Hz) accurately
#: Every input actuator reads its control from a history buffer this many steps late. MuJoCo reads delayed
#: controls at each RK4 stage time, interpolating (cubic needs three steps), so inputs run continuously through a step
#: instead of being held; the simulator feeds controls this much early (rig/sim/simulate.py).
INPUT_DELAY_STEPS = 3
#: the baseline's force actuator between body and wheel at each corner, in the car's MjSpec
ACTIVE_FORCE = "{corner}/active_force"
LONGEST_FORCE_DELAY = 0.05  # s: the longest delay of an active force's input the model keeps history for
#: a turning wheel's position servo on its hinge (a cause's wheel that turns: ``wheel_unbalance``)
SPIN_ACTUATOR = "{corner}/wheel_spin"
CLOCK_SENSOR = "clock"  # the simulation's time (s), a sensor
GROUND_SITE_DEPTH = 100.0  # m: the road tyre tendon's lower end below the surface (any road stays above it)


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
    tyre_ctrl: np.ndarray           # ctrl address of each tyre's input (one per corner, two at dual tyres)
    active_ctrl: np.ndarray = field(default_factory=lambda: np.zeros(0, int))  # each corner's active_force input
    sensor_adr: dict[str, int] = field(default_factory=dict)  # sensor name -> first sensordata index
    post_qpos: np.ndarray = field(default_factory=lambda: np.zeros(0, int))
    post_dof: np.ndarray = field(default_factory=lambda: np.zeros(0, int))
    free_dofs: np.ndarray = field(default_factory=lambda: np.zeros(0, int))  # car DOFs (not posts)
    servo_ids: np.ndarray = field(default_factory=lambda: np.zeros(0, int))
    tyre_ids: np.ndarray = field(default_factory=lambda: np.zeros(0, int))
    tyre_corner: np.ndarray = field(default_factory=lambda: np.zeros(0, int))  # each tyre's corner (column index)
    tyre_sensors: np.ndarray = field(default_factory=lambda: np.zeros(0, int))  # each tyre's force sensor address
    spin_corners: tuple[str, ...] = ()  # corners whose wheel turns (a ``wheel_spin`` servo on a hinge)
    spin_ctrl: np.ndarray = field(default_factory=lambda: np.zeros(0, int))   # their servos' ctrl addresses
    spin_ids: np.ndarray = field(default_factory=lambda: np.zeros(0, int))    # their servos' actuator ids
    spin_qpos: np.ndarray = field(default_factory=lambda: np.zeros(0, int))   # their hinges' qpos addresses
    spin_dof: np.ndarray = field(default_factory=lambda: np.zeros(0, int))    # their hinges' dof addresses
    spin_lead: np.ndarray = field(default_factory=lambda: np.zeros(0))        # kv / kp of their servos, s
    linkage_dofs: np.ndarray = field(default_factory=lambda: np.zeros(0, int))  # DOFs inside linkage corners

    @property
    def timestep(self) -> float:
        return self.model.opt.timestep

    def tyre_forces(self, sensors: np.ndarray) -> np.ndarray:
        """Each corner's total tyre force (N; a dual pair summed) from sensor data (..., nsensordata)."""
        per_tyre = sensors[..., self.tyre_sensors]
        if len(self.tyre_sensors) == len(self.corners):  # one tyre per corner: the sensor values themselves
            return per_tyre
        summed = np.zeros((*per_tyre.shape[:-1], len(self.corners)))
        for column, corner in enumerate(self.tyre_corner):
            summed[..., corner] += per_tyre[..., column]
        return summed


def timestep_for(rate: float, longest: float = MAX_TIMESTEP) -> tuple[float, int]:
    """Physics step (s) and steps per sample so that record samples fall on steps and h <= ``longest``."""
    steps = max(1, math.ceil(1.0 / (rate * longest) - 1e-9))
    return 1.0 / (rate * steps), steps


def longest_step(vehicle: Vehicle, posts: str, asked: float) -> float:
    """The longest physics step (s) a model may take where ``asked`` allows: MAX_TIMESTEP with servo posts (their
    150 Hz loop) or an element sized to it or stiffer than a longer step resolves (a cause's ``fine_step``), else
    ``asked`` (rig/sim/step_size.py)."""
    fine = posts == "servo" or any(c.fine_step and c.present(vehicle) for c in in_build_order())
    return min(asked, MAX_TIMESTEP) if fine else asked


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
    _remove_corners(spec, car, [c for c in CORNERS if c not in corners or vehicle.layout_type.axle_list])
    if not vehicle.layout_type.footprint:
        for dof in ("pitch", "roll"):
            car.delete(car.joint(dof))
    if vehicle.layout_type.axle_list:
        for corner in corners:
            add_post(spec, corner)
    _set_car(car, vehicle)
    spec.copy_during_attach = True  # the car spec is a local: the rig must own copies of its elements
    spec.attach(car, frame=spec.frame("car_mount"), prefix="car.")
    _set_posts(spec, vehicle, posts, timestep)
    for corner in corners:
        _add_tyre(spec, vehicle, corner, posts, timestep)
        # a cause's lag and delay (force_actuator_lag), then the input's own delay; with a lag, the history holds the
        # longest delay the cause allows, so that variants with other delays share one state layout (a fit's batch)
        active = spec.actuator(f"car.{ACTIVE_FORCE.format(corner=corner)}")
        lagging = active.dyntype == mujoco.mjtDyn.mjDYN_FILTER
        _read_input_late(active, active.delay, timestep, LONGEST_FORCE_DELAY if lagging else 0.0)
        spin = spec.actuator(f"car.{SPIN_ACTUATOR.format(corner=corner)}")
        if spin is not None:
            _read_input_late(spin, 0.0, timestep)
    # the simulation's time among the sensors: a rollout that keeps only sensor data still shows a run that stopped
    # (MuJoCo's rollout repeats a warned run's last outputs: rig/sim/simulate.py)
    spec.add_sensor(name=CLOCK_SENSOR, type=mujoco.mjtSensor.mjSENS_CLOCK)
    return spec


def without_idle_constraint_solver(model: mujoco.MjModel) -> None:
    """Turn MuJoCo's constraint stage off (``mjDSBL_CONSTRAINT``) where the model holds nothing it could solve: contact
    disabled, no equality, no limited joint or tendon, no friction loss, no flex. Every step then skips making and
    projecting an empty constraint set (about 1 of 15 us a step of a car on ideal posts) and computes the same
    numbers; servo posts keep it (their stroke is a joint limit)."""
    idle = (model.opt.disableflags & mujoco.mjtDisableBit.mjDSBL_CONTACT and model.neq == 0 and model.nflex == 0
            and not model.jnt_limited.any() and not model.tendon_limited.any()
            and not model.dof_frictionloss.any() and not model.tendon_frictionloss.any())
    if idle:
        model.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONSTRAINT


def build_model(vehicle: Vehicle, rate: float, posts: str = "servo",
                extend: Callable[[mujoco.MjSpec], None] | None = None, longest: float = MAX_TIMESTEP) -> RigModel:
    """Compile the model for records sampled at ``rate`` Hz and collect its addresses; ``extend(spec)``, if
    given, adds elements (a controller's actuators) to the assembled spec before it is compiled. ``longest``: the
    longest physics step (s) asked, where the model allows it (``longest_step``)."""
    timestep, steps = timestep_for(rate, longest_step(vehicle, posts, longest))
    spec = build_spec(vehicle, posts, timestep)
    if extend is not None:
        extend(spec)
    try:
        model = spec.compile()
    except ValueError as err:  # a mass or inertia no body can have (a fit's trial: a payload lighter than nothing)
        raise VehicleError(f"{vehicle.source}: MuJoCo cannot build this vehicle: {err}") from None
    without_idle_constraint_solver(model)
    corners = vehicle.corners

    def actuator_ctrl(name: str) -> int:
        return int(model.actuator_ctrladr[model.actuator(name).id])

    sensor_adr = {model.sensor(i).name: int(model.sensor_adr[i]) for i in range(model.nsensor)}
    tyres = [(i, c, suffix) for i, c in enumerate(corners) for suffix, _ in tyre_suffixes(vehicle, c)]
    rig = RigModel(
        model=model, vehicle=vehicle, posts=posts, rate=float(rate), steps_per_sample=steps, corners=corners,
        servo_ctrl=np.array([actuator_ctrl(f"{c}/servo") for c in corners] if posts == "servo" else [], int),
        tyre_ctrl=np.array([actuator_ctrl(f"{c}/tyre{s}") for _, c, s in tyres], int),
        active_ctrl=np.array([actuator_ctrl(f"car.{ACTIVE_FORCE.format(corner=c)}") for c in corners], int),
        sensor_adr=sensor_adr,
        tyre_ids=np.array([model.actuator(f"{c}/tyre{s}").id for _, c, s in tyres], int),
        tyre_corner=np.array([i for i, _, _ in tyres], int),
        tyre_sensors=np.array([sensor_adr[f"{c}/tyre_force{s}"] for _, c, s in tyres], int),
    )
    if posts == "servo":
        joints = [model.joint(f"{c}/post") for c in corners]
        rig.post_qpos = np.array([int(j.qposadr[0]) for j in joints])
        rig.post_dof = np.array([int(j.dofadr[0]) for j in joints])
        rig.servo_ids = np.array([model.actuator(f"{c}/servo").id for c in corners], int)
    rig.free_dofs = np.setdiff1d(np.arange(model.nv), rig.post_dof)
    linkage = {f"car.{j}" for c in corners for j in suspension_of(vehicle, c).linkage_joints(vehicle, c)}
    rig.linkage_dofs = np.array(sorted(int(model.joint(j).dofadr[0]) for j in linkage), int)
    spins = [(c, model.actuator(f"car.{SPIN_ACTUATOR.format(corner=c)}")) for c in corners
             if mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_ACTUATOR, f"car.{SPIN_ACTUATOR.format(corner=c)}") >= 0]
    if spins:
        hinges = [model.joint(int(a.trnid[0])) for _, a in spins]
        rig.spin_corners = tuple(c for c, _ in spins)
        rig.spin_ctrl = np.array([actuator_ctrl(a.name) for _, a in spins], int)
        rig.spin_ids = np.array([a.id for _, a in spins], int)
        rig.spin_qpos = np.array([int(j.qposadr[0]) for j in hinges], int)
        rig.spin_dof = np.array([int(j.dofadr[0]) for j in hinges], int)
        rig.spin_lead = np.array([-a.biasprm[2] / a.gainprm[0] for _, a in spins])
    return rig


def _remove_corners(spec: mujoco.MjSpec, car: mujoco.MjSpec, corners: list[str]) -> None:
    """Delete the named corners of the templates (posts, wheels, tendons, sensors)."""
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


def _set_car(car: mujoco.MjSpec, v: Vehicle) -> None:
    """Fill the car template: body inertia at the CG (or a truck's frame segments), corner sites, and each corner as
    its suspension type builds it (rig/vehicle/suspensions/); a truck's cab and driveline on their mounts; then each
    extension the vehicle has (a cause: rig/vehicle/extensions.py) realises itself."""
    causes = [c for c in in_build_order() if c.present(v)]
    for cause in causes:
        if (problem := cause.implausible(v)) is not None:
            raise VehicleError(problem)
    body = car.body("body")
    body.pos = [0.0, 0.0, v.cg_height]
    mass, com, inertia = _sprung_inertia(v, causes)
    body.mass, body.ipos, body.inertia, body.explicitinertial = mass, com.tolist(), inertia.tolist(), True
    length = v.wheelbase if v.layout_type.footprint else 0.6
    width = max(v.track_front, v.track_rear) if v.layout_type.footprint else 0.6
    box = car.geom("body")
    box.size = [length / 2 + 0.4, width / 2, 0.15]
    box.pos = [(v.cg_to_front_axle - v.wheelbase / 2) if v.layout_type.footprint else 0.0, 0.0, 0.1]
    if v.layout_type.frame:
        build_frame(car, v, mass, com, inertia)
    for corner in v.corners:
        if v.layout_type.axle_list:
            add_corner(car, v, corner)
        else:
            x, y = v.corner_position(corner)
            car.site(f"{corner}/body").pos = [x, y, 0.0]
    for corner in v.corners:
        suspension_of(v, corner).build_corner(car, v, corner)
        _add_active_force(car, corner)
    if v.layout_type.frame:
        build_mounted_bodies(car, v)
    for cause in causes:
        cause.build(car, v)


def _add_active_force(car: mujoco.MjSpec, corner: str) -> None:
    """The corner's force actuator between body and wheel (input: N on the body, up positive; the tendon from the body
    site down to the hub lengthens when it pushes) and the height sensors of the body site and the hub. It acts on the
    suspension's own line where that runs from the body site to the hub (a vertical corner's: the same line, and one
    tendon fewer to compute at each evaluation, 9 % of a car's physics step), else on a line of its own."""
    line = car.tendon(f"{corner}/suspension")
    if line is None or [getattr(w.target, "name", None) for w in line.path] != [f"{corner}/body", f"{corner}/hub"]:
        line = car.add_tendon(name=f"{corner}/active")
        line.wrap_site(f"{corner}/body")
        line.wrap_site(f"{corner}/hub")
        line.rgba = [0.2, 0.5, 0.9, 0.0]
    actuator = car.add_actuator(name=ACTIVE_FORCE.format(corner=corner), target=line.name)
    actuator.trntype = mujoco.mjtTrn.mjTRN_TENDON
    actuator.gainprm[0] = 1.0
    actuator.ctrllimited = mujoco.mjtLimited.mjLIMITED_FALSE
    for site, name in (("body", "body_height"), ("hub", "hub_height")):
        car.add_sensor(name=f"{corner}/{name}", type=mujoco.mjtSensor.mjSENS_FRAMEPOS,
                       objtype=mujoco.mjtObj.mjOBJ_SITE, objname=f"{corner}/{site}")


def _sprung_inertia(v: Vehicle, causes: list) -> tuple[float, np.ndarray, np.ndarray]:
    """Sprung mass, CG offset and principal inertia about the CG, as the corners' links (rig/vehicle/suspensions/)
    and the vehicle's causes change them (a payload, top-mount masses)."""
    mass, com = v.sprung_mass, np.zeros(3)
    inertia = np.array([v.roll_inertia or 1.0, v.pitch_inertia or 1.0, v.yaw_inertia or 1.0])
    for corner in v.corners:
        mass, com, inertia = suspension_of(v, corner).adjust_sprung(v, corner, mass, com, inertia)
    for cause in causes:
        mass, com, inertia = cause.adjust_sprung(v, mass, com, inertia)
    return mass, com, inertia


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


def _read_input_late(actuator: mujoco.MjsActuator, delay: float, timestep: float, longest: float = 0.0) -> None:
    """Read the control from history, ``delay`` s plus the input delay late, cubic (Catmull-Rom) between steps; the
    history holds at least ``longest`` s of delay."""
    actuator.delay = delay + INPUT_DELAY_STEPS * timestep
    actuator.nsample = math.ceil((max(delay, longest) + INPUT_DELAY_STEPS * timestep) / timestep - 1e-9) + 2
    actuator.interp = 2  # cubic (0 zoh, 1 linear, 2 cubic)


def tyre_suffixes(vehicle: Vehicle, corner: str) -> tuple[tuple[str, float], ...]:
    """The tyres at a wheel station: (name suffix, lateral offset from the station in m, y left): one, or a dual
    pair (the outer tyre keeps the plain names, the inner one ``_inner``)."""
    axle = vehicle.axle(corner)
    if axle.tyres != "dual":
        return (("", 0.0),)
    outward = axle.dual_spacing / 2 * (1 if corner.endswith("L") else -1)
    return ("", outward), ("_inner", -outward)


def _add_tyre(spec: mujoco.MjSpec, v: Vehicle, corner: str, posts: str, timestep: float) -> None:
    """The station's tyre(s): per tyre a tendon from the pan (or a ground site) to a hub site and a one-sided
    spring-damper actuator on it, with its force sensor (``<corner>/tyre_force``, ``<corner>/tyre_force_inner``)."""
    tyres = tyre_suffixes(v, corner)
    if len(tyres) > 1:  # hub and pan sites of the pair, beside the station's own
        hub = spec.site(f"car.{corner}/hub")
        for suffix, dy in tyres:
            hub.parent.add_site(name=f"car.{corner}/hub{suffix or '_outer'}", pos=list(np.add(hub.pos, [0, dy, 0])))
            if posts == "servo":
                spec.body(f"{corner}/post").add_site(name=f"{corner}/pan{suffix or '_outer'}", pos=[0.0, dy, 0.0])
    for suffix, dy in tyres:
        tag = suffix or ("_outer" if len(tyres) > 1 else "")
        _add_one_tyre(spec, v, corner, suffix, tag, dy, posts, timestep)


def _add_one_tyre(spec: mujoco.MjSpec, v: Vehicle, corner: str, suffix: str, tag: str, dy: float, posts: str,
                  timestep: float) -> None:
    axle = v.axle(corner)
    below = 0.0  # m from the tendon's lower site down to the road surface under the tyre
    if posts == "servo":
        lower = f"{corner}/pan{tag}"
    else:
        # on the road, the lower site sits far below the surface: a tendon's length is a distance, so a site
        # at the surface would let the road fall past the hub (a road dropping by a wheel radius) and turn
        # the tyre force round
        below = GROUND_SITE_DEPTH
        x, y = v.corner_position(corner)
        lower = f"{corner}/ground{suffix}"
        spec.worldbody.add_site(name=lower, pos=[x, y + dy, -below])
    tendon = spec.add_tendon(name=f"{corner}/tyre_spring{suffix}")
    tendon.wrap_site(lower)
    tendon.wrap_site(f"car.{corner}/hub{tag}")
    tendon.width = 0.03
    tendon.rgba = [0.1, 0.1, 0.1, 1.0 if posts == "servo" else 0.0]  # on the road: no 100 m line to draw
    unloaded_length = v.wheel_radius + below  # the template draws the tyre just touching the pan, unloaded
    tyre = spec.add_actuator(name=f"{corner}/tyre{suffix}", target=f"{corner}/tyre_spring{suffix}")
    tyre.trntype = mujoco.mjtTrn.mjTRN_TENDON
    tyre.gainprm[0] = axle.tyre_rate
    tyre.biastype = mujoco.mjtBias.mjBIAS_AFFINE
    tyre.biasprm[:3] = [axle.tyre_rate * unloaded_length, -axle.tyre_rate, -axle.tyre_damping]
    tyre.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
    tyre.forcerange = [0.0, FORCE_CAP]
    tyre.ctrllimited = mujoco.mjtLimited.mjLIMITED_FALSE
    _read_input_late(tyre, 0.0, timestep)
    spec.add_sensor(name=f"{corner}/tyre_force{suffix}", type=mujoco.mjtSensor.mjSENS_ACTUATORFRC,
                    objtype=mujoco.mjtObj.mjOBJ_ACTUATOR, objname=f"{corner}/tyre{suffix}")
