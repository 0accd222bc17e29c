"""Static ride height: the equilibrium the car settles to on the rig before any test.

Solved directly (Newton's method on MuJoCo's own accelerations with the posts held at zero), not by
simulating until the motion dies out, so the initial state is at rest to machine precision and no
settling transient leaks into the responses. The post servos get the static load as feed-forward, so
a zero drive holds the posts at zero.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from rig.errors import RigError
from rig.vehicle.extensions import extensions
from rig.vehicle.mjcf import RigModel, build_model, build_spec
from rig.vehicle.parts import Vehicle

STATE_SPEC = mujoco.mjtState.mjSTATE_FULLPHYSICS
_TOLERANCE = 1e-9  # m/s^2 (rad/s^2): largest acceleration left at equilibrium
_LINKAGE_STEP = 1e-11  # m (rad): with linkage corners, a Newton step this small ends the solve


class EquilibriumError(RigError, RuntimeError):
    """The model has no static equilibrium the solver could find (e.g. springs too soft to carry it)."""


@dataclass(frozen=True)
class StaticState:
    state: np.ndarray                # full physics state at static ride height (mjSTATE_FULLPHYSICS)
    suspension_length: np.ndarray    # m, per corner: reference for suspension travel
    tyre_force: np.ndarray           # N, per corner: static tyre loads
    qpos: np.ndarray                 # the equilibrium joint positions
    heights: np.ndarray | None = None  # m, per corner the body site's then the hub's height: reference of the
    #                                    displacements sprung_disp, unsprung_disp (2 x corners, flattened)


def settle(rig: RigModel, max_iterations: int = 50) -> StaticState:
    """Find static ride height and set the post servos' static feed-forward (mutates ``rig.model``)."""
    model = rig.model
    data = mujoco.MjData(model)
    free = rig.free_dofs
    # dry friction makes every position in its dead zone an equilibrium: solve without it, at the
    # frictionless equilibrium (where a car settled by vibration ends up on average)
    friction = model.tendon_frictionloss.copy(), model.dof_frictionloss.copy()  # a strut's, a bench's bearings
    model.tendon_frictionloss[:] = 0.0
    model.dof_frictionloss[:] = 0.0
    qpos = model.qpos0.copy()
    # start with the car pressed 5 cm into its tyres: at the template's unloaded pose the tyres carry
    # nothing, so their one-sided stiffness would vanish under a finite-difference step
    slides = free[model.jnt_type[model.dof_jntid[free]] == mujoco.mjtJoint.mjJNT_SLIDE]
    slides = slides[~np.isin(slides, rig.linkage_dofs)]  # a linkage moves down with the body
    qpos[model.jnt_qposadr[model.dof_jntid[slides]]] -= 0.05

    def accelerations(q: np.ndarray) -> np.ndarray:
        data.qpos[:] = q
        data.qvel[:] = 0.0
        mujoco.mj_forward(model, data)
        return data.qacc.copy()

    for _ in range(max_iterations):
        qacc = accelerations(qpos)
        if np.max(np.abs(qacc[free])) < _TOLERANCE:
            break
        jacobian = np.empty((free.size, free.size))
        step = 1e-7
        for column, dof in enumerate(free):
            shifted = qpos.copy()
            shifted[dof] += step
            jacobian[:, column] = (accelerations(shifted)[free] - qacc[free]) / step
        try:
            correction = np.linalg.solve(jacobian, qacc[free])
        except np.linalg.LinAlgError:  # the differences lost every digit: a stiffness far beyond a car's
            raise EquilibriumError(f"no static equilibrium for {rig.vehicle.name}: the stiffness matrix is singular "
                                   f"to working precision (a rate far beyond a car's?)") from None
        qpos[free] -= correction
        if rig.linkage_dofs.size and np.max(np.abs(correction)) < _LINKAGE_STEP:
            qacc = accelerations(qpos)  # stiff loop closures: the accelerations sit at the differences' floor
            break
    else:
        raise EquilibriumError(
            f"no static equilibrium for {rig.vehicle.name}: largest residual acceleration "
            f"{np.max(np.abs(qacc[free])):.3g} after {max_iterations} Newton steps"
        )
    if rig.posts == "servo":
        # feed-forward = the force that holds each post at zero against its load (post DOFs are decoupled)
        qacc = accelerations(qpos)
        mass = model.body_mass[model.dof_bodyid[rig.post_dof]]
        model.actuator_biasprm[rig.servo_ids, 0] -= mass * qacc[rig.post_dof]
        qacc = accelerations(qpos)
        if np.max(np.abs(qacc)) > 1e3 * _TOLERANCE:
            raise EquilibriumError(f"posts do not hold the static load: residual {np.max(np.abs(qacc)):.3g} m/s^2")
    model.tendon_frictionloss[:], model.dof_frictionloss[:] = friction
    _set_static_references(rig, data)
    state = np.empty(mujoco.mj_stateSize(model, STATE_SPEC))
    mujoco.mj_getState(model, data, state, STATE_SPEC)
    lengths = np.array([data.sensordata[rig.sensor_adr[f"car.{c}/suspension_length"]] for c in rig.corners])
    tyre = rig.tyre_forces(data.sensordata)
    heights = np.array([data.sensordata[rig.sensor_adr[f"car.{c}/{name}"] + 2] for name in ("body_height", "hub_height")
                        for c in rig.corners])
    return StaticState(state=state, suspension_length=lengths, tyre_force=tyre, qpos=qpos.copy(), heights=heights)


def _set_static_references(rig: RigModel, data: mujoco.MjData) -> None:
    """Elements defined from static ride height (travel is measured from static: docs/contracts.md), set by their
    causes: a bump stop's contact, a progressive spring's centre (rig/causes/)."""
    for extension in extensions().values():
        if extension.present(rig.vehicle):
            extension.at_static_ride_height(rig.model, data, rig.vehicle)


def settled_mjcf(vehicle: Vehicle, posts: str = "servo") -> tuple[str, int]:
    """The assembled model as MJCF text with a keyframe ``static_ride_height`` (and the servos' static
    feed-forward), ready for MuJoCo's viewer, and its number of degrees of freedom."""
    rig = build_model(vehicle, rate=1000.0, posts=posts)
    static = settle(rig)
    spec = build_spec(vehicle, posts, rig.timestep)
    for servo_id in rig.servo_ids:  # carry the static-load feed-forward found by settling
        name = rig.model.actuator(int(servo_id)).name
        spec.actuator(name).biasprm[0] = rig.model.actuator_biasprm[servo_id, 0]
    spec.add_key(name="static_ride_height", qpos=static.qpos.tolist())
    return spec.to_xml(), rig.model.nv
