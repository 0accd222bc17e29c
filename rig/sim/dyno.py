"""A vehicle file's damper on a dynamometer, in MuJoCo: the damper alone between a fixed frame and a post that
moves as a displacement signal says, and the force it puts on the post.

The damper is built as the car builds it (rig/vehicle/mjcf.py): a tendon from the body's corner site to the hub with the
axle's ``damping``, and every cause of the damper line (``DAMPER_CAUSES``, the causes that say ``damper_line``: its
asymmetry, its quadratic term, the damping ramps of a measured law, its gas preload, a top mount in series, the strut's
friction) realising itself on it, as in the car; springs, stops and the tyre are left out. The body is the fixed frame
(no joints); the hub's body is the post, on a vertical slide, moved kinematically: before each physics step its position
(at the step's start) and velocity (at its midpoint) are set from the signal (a post of unlimited stiffness), and RK4
integrates what the damper carries (a top mount's body). The force on the post is the sum of the damper's generalised
forces on the post's joint: passive (tendon damping), actuators (clamped branches, measured-law ramps, the preload) and
constraints (friction), read by ``mj_forward`` at each sample; a run-in at the first sample's speed first brings a top
mount to its steady state. Vehicle files hold the damper at the wheel: a dyno displacement x and force F are x / MR and
F MR at the wheel, MR the motion ratio (damper travel over wheel travel), so wheel damping is c MR^2. """

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import mujoco
import numpy as np

from rig.causes import CAUSES, damper_line_causes, in_build_order
from rig.elements.tendons import damper_tendon
from rig.io.record import Record
from rig.signal.differentiate import rate_of
from rig.vehicle.mjcf import timestep_for
from rig.vehicle.vehicle_file import Vehicle, VehicleError

DAMPER_CAUSES = damper_line_causes()
POST_MASS = 1e6     # kg: the damper's forces do not move the post within a step (a kinematic post)
FRAME_HEIGHT = 0.4  # m: the frame's site above the post's (the damper's length does not enter its law)
CORNER = "FL"
SETTLE_LIMIT = 20.0  # s: the longest run-in at the first speed
SETTLE_CHUNK = 100   # steps between checks of the run-in


@dataclass(frozen=True)
class DynoSimulation:
    """A simulated dyno test at the damper (SI): time (s), displacement (m, extension positive), its velocity (m/s),
    force (N, positive resisting extension); ``motion_ratio`` (damper over wheel travel) converted to the wheel."""

    time: np.ndarray
    displacement: np.ndarray
    velocity: np.ndarray
    force: np.ndarray
    motion_ratio: float

    def record(self, metadata: dict | None = None) -> Record:
        """The simulation as a dyno record (``damper/displacement``, ``damper/force``)."""
        rate = 1.0 / (self.time[1] - self.time[0])
        return Record(rate, {"damper/displacement": self.displacement, "damper/force": self.force},
                      {"damper/displacement": "m", "damper/force": "N"}, dict(metadata or {"test": "dyno"}),
                      start_time=float(self.time[0]))


def damper_alone(vehicle: Vehicle, axle: str) -> Vehicle:
    """A quarter vehicle that holds only ``axle``'s damper line (its damping and the ``DAMPER_CAUSES`` on it, each
    as much of it as acts on the damper alone: ``Cause.on_damper_alone``, a measured law's damping ramps)."""
    if axle not in ("front", "rear") or getattr(vehicle, axle, None) is None:
        raise VehicleError(f"{vehicle.source or vehicle.name}: no axle '{axle}' (it has: "
                           f"{'front, rear' if vehicle.rear is not None else 'front'})")
    extensions = {}
    for name in DAMPER_CAUSES:
        value = vehicle.extensions.get(name, {}).get(axle)
        if value is not None and (value := CAUSES[name].on_damper_alone(value)) is not None:
            extensions[name] = {"front": value}
    return dataclasses.replace(vehicle, layout="quarter", front=getattr(vehicle, axle), rear=None,
                               extensions=extensions)


def build_dyno(vehicle: Vehicle, axle: str, timestep: float) -> mujoco.MjModel:
    """The dyno model of ``axle``'s damper: frame, post on a slide joint ``post``, damper line between them."""
    damper = damper_alone(vehicle, axle)
    spec = mujoco.MjSpec()
    spec.modelname = f"{vehicle.name}_{axle}_damper_on_dyno"
    spec.option.timestep = timestep
    spec.option.gravity = [0.0, 0.0, 0.0]
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_RK4
    frame = spec.worldbody.add_body(name="body", pos=[0.0, 0.0, FRAME_HEIGHT])
    frame.add_site(name=f"{CORNER}/body")
    post = spec.worldbody.add_body(name=f"{CORNER}/wheel")
    post.add_joint(name="post", type=mujoco.mjtJoint.mjJNT_SLIDE, axis=[0, 0, 1])
    post.mass, post.inertia, post.explicitinertial = POST_MASS, [1.0, 1.0, 1.0], True
    post.add_site(name=f"{CORNER}/hub")
    strut = spec.add_tendon(name=f"{CORNER}/suspension")  # the strut: friction only, no spring on a dyno
    strut.wrap_site(f"{CORNER}/body")
    strut.wrap_site(f"{CORNER}/hub")
    damper_tendon(spec, CORNER, f"{CORNER}/body", [damper.front.damping, 0.0, 0.0])
    for cause in in_build_order():
        if cause.name in DAMPER_CAUSES and cause.present(damper):
            cause.build(spec, damper)
    return spec.compile()


def simulate_dyno(vehicle: Vehicle, axle: str, displacement: np.ndarray, rate: float,
                  velocity: np.ndarray | None = None, motion_ratio: float = 1.0) -> DynoSimulation:
    """Move ``axle``'s damper as ``displacement`` (m, at the damper, extension positive, sampled at ``rate`` Hz)
    says and return the force on the post, at the damper. ``velocity`` (m/s) defaults to the displacement's rate
    as the dyno fit takes it (rig/signal/differentiate.py); between samples both are interpolated linearly."""
    if not motion_ratio > 0:
        raise VehicleError(f"motion ratio must be positive, got {motion_ratio}")
    displacement = np.asarray(displacement, dtype=float)
    velocity = rate_of(displacement, rate).values if velocity is None else np.asarray(velocity, dtype=float)
    wheel_x, wheel_v = displacement / motion_ratio, velocity / motion_ratio
    timestep, steps = timestep_for(rate)
    model = build_dyno(vehicle, axle, timestep)
    steps *= _substeps(model, timestep, float(np.max(np.abs(wheel_v))))
    model.opt.timestep = 1.0 / (rate * steps)
    data = mujoco.MjData(model)
    joint = model.joint("post")
    qpos, dof = int(joint.qposadr[0]), int(joint.dofadr[0])
    _settle(model, data, qpos, dof, wheel_x[0], wheel_v[0])
    force = np.empty(displacement.size)
    start, middle = np.arange(steps) / steps, (np.arange(steps) + 0.5) / steps
    for n in range(displacement.size):
        following = min(n + 1, displacement.size - 1)
        xs = wheel_x[n] + start * (wheel_x[following] - wheel_x[n])
        vs = wheel_v[n] + middle * (wheel_v[following] - wheel_v[n])  # each step moves at its midpoint's speed
        data.qpos[qpos], data.qvel[dof] = -wheel_x[n], -wheel_v[n]  # extension: the post moves down, off the frame
        mujoco.mj_forward(model, data)
        force[n] = data.qfrc_passive[dof] + data.qfrc_actuator[dof] + data.qfrc_constraint[dof]
        for j in range(steps):
            data.qpos[qpos], data.qvel[dof] = -xs[j], -vs[j]
            mujoco.mj_step(model, data)
    time = np.arange(displacement.size) / rate
    return DynoSimulation(time, displacement, velocity, force / motion_ratio, motion_ratio)


def _settle(model: mujoco.MjModel, data: mujoco.MjData, qpos: int, dof: int, position: float, speed: float) -> None:
    """Run the post at the signal's first speed until what the damper carries (a top mount) is steady, so that a
    test starts as a dyno's does, mid-motion, rather than with the mount at rest; at most ``SETTLE_LIMIT`` s."""
    if model.nv == 1:
        return
    for _ in range(int(SETTLE_LIMIT / (SETTLE_CHUNK * model.opt.timestep))):
        for _ in range(SETTLE_CHUNK):
            data.qpos[qpos], data.qvel[dof] = -position, -speed
            mujoco.mj_step(model, data)
        others = np.abs(np.delete(data.qvel, dof))
        if np.all(others <= 1e-9 * max(abs(speed), 1e-3)):
            break


def _substeps(model: mujoco.MjModel, timestep: float, speed: float) -> int:
    """Steps per physics step that keep RK4 well inside its stability limit for the damper's moving bodies (a
    top mount: its spring, and the damper's largest tangent damping at up to twice ``speed``, on its mass)."""
    moving = [b for b in range(1, model.nbody) if model.body_dofnum[b] and model.body(b).name != f"{CORNER}/wheel"]
    if not moving:
        return 1
    data = mujoco.MjData(model)
    post = int(model.joint("post").dofadr[0])
    slopes = []
    for v in np.linspace(-2 * speed - 1e-3, 2 * speed + 1e-3, 41):
        data.qvel[:] = 0.0
        data.qvel[post] = v
        mujoco.mj_forward(model, data)
        slopes.append(data.qfrc_passive[post] + data.qfrc_actuator[post])
    damping = np.max(np.abs(np.diff(slopes) / np.diff(np.linspace(-2 * speed - 1e-3, 2 * speed + 1e-3, 41))))
    rate = max(damping / model.body_mass[b] + np.sqrt(model.jnt_stiffness[model.body_jntadr[b]] / model.body_mass[b])
               for b in moving)
    return max(1, int(np.ceil(timestep * rate / 1.0)))
