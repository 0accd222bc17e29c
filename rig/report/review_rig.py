"""The rig in 3D for a Rerun review: posts, pans, wheels and body from a simulation's joint positions.

Entity paths (m): ``rig/<body>`` (``rig/FL/post``, ``rig/car.body``, ``rig/car.FL/wheel``) world poses on
``time``; static geometry ``rig/<body>/boxes`` and ``rig/<body>/cylinders`` (wheels in their corner's colour,
labelled with the corner); ``rig/tendons/<tendon>`` (suspension and tyre lines); ``rig/springs/<corner>`` (a
coil between body and wheel, stretched with the suspension); ``rig/car.body/front`` (an arrow at the front).
``magnification`` scales every joint's motion about the first sample (the settled car): at true scale a few
millimetres of travel on a 4 m car do not show; a magnified scene says so in its title and a label.

Posts without a joint (ideal posts: a track run's road, a measured post motion replayed exactly) do not move in
the simulation, which feeds their height to the tyre instead; the scene moves them by that height, read from the
run's record (``post_heights``), so that each wheel stands on its pan.
"""

from __future__ import annotations

from collections.abc import Sequence

import mujoco
import numpy as np
import rerun as rr

from rig.io.channels import channel, is_corner
from rig.io.record import Record
from rig.report.review import Review
from rig.report.style import corner_color

SPRING_TURNS, SPRING_RADIUS, SPRING_WIDTH = 6, 0.055, 0.008  # a drawn coil: turns, radius (m), wire radius (m)
SPRING_INBOARD = 0.2  # m: the coil is drawn this far inboard of the wheel centre


def magnified(model: mujoco.MjModel, qpos: np.ndarray, factor: float) -> np.ndarray:
    """Joint positions with every joint's motion from the first sample scaled by ``factor`` (hinges and slides
    linearly, free and ball joints along their rotation's axis)."""
    if factor == 1.0:
        return qpos
    out = np.empty_like(qpos)
    velocity = np.zeros(model.nv)
    for i, row in enumerate(qpos):
        mujoco.mj_differentiatePos(model, velocity, 1.0, qpos[0], row)
        out[i] = qpos[0]
        mujoco.mj_integratePos(model, out[i], velocity, factor)
    return out


def body_poses(model: mujoco.MjModel, qpos: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """World poses for joint positions ``qpos`` (samples x nq): body positions (samples x bodies x 3, m),
    body orientations (samples x bodies x 4, MuJoCo's wxyz) and site positions (samples x sites x 3, m)."""
    data = mujoco.MjData(model)
    n = qpos.shape[0]
    xpos, xquat, sites = np.empty((n, model.nbody, 3)), np.empty((n, model.nbody, 4)), np.empty((n, model.nsite, 3))
    for i in range(n):
        data.qpos[:] = qpos[i]
        mujoco.mj_kinematics(model, data)
        xpos[i], xquat[i], sites[i] = data.xpos, data.xquat, data.site_xpos
    return xpos, xquat, sites


def post_heights(model: mujoco.MjModel, record: Record) -> dict[str, np.ndarray]:
    """Per corner whose post has no joint (ideal posts), the height its pan stands at (m): the record's measured post
    displacement, else its road."""
    heights = {}
    for corner in record.corners_with("actuator_disp") or record.corners_with("road"):
        body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, f"{corner}/post")
        if body >= 0 and model.body_jntnum[body] == 0:
            name = next(channel(corner, q) for q in ("actuator_disp", "road") if channel(corner, q) in record)
            heights[corner] = np.asarray(record[name], float)
    return heights


def _xyzw(wxyz: np.ndarray) -> np.ndarray:
    """MuJoCo quaternions (..., w x y z) in Rerun's order (..., x y z w)."""
    return np.roll(wxyz, -1, axis=-1)


def _rgba8(rgba: np.ndarray) -> np.ndarray:
    return np.round(np.clip(rgba, 0.0, 1.0) * 255).astype(np.uint8)


def _corner_of(name: str) -> str | None:
    """The corner a body or tendon belongs to (``car.FL/wheel`` -> ``FL``), None for the others."""
    head = name.removeprefix("car.").split("/")[0]
    return head if is_corner(head) else None


def _log_geometry(review: Review, model: mujoco.MjModel, prefix: str) -> None:
    """Static geoms in body frames: planes and boxes as ``<body>/boxes``, cylinders as ``<body>/cylinders``
    (wheels in their corner's colour, labelled); other geom types and invisible geoms are not drawn."""
    solid = rr.components.FillMode.Solid
    for body in range(model.nbody):
        name = model.body(body).name
        path = f"{prefix}/{name}"
        visible = (model.geom_bodyid == body) & (model.geom_rgba[:, 3] > 0)
        planes = visible & (model.geom_type == mujoco.mjtGeom.mjGEOM_PLANE)
        boxes = np.flatnonzero(planes | (visible & (model.geom_type == mujoco.mjtGeom.mjGEOM_BOX)))
        cylinders = np.flatnonzero(visible & (model.geom_type == mujoco.mjtGeom.mjGEOM_CYLINDER))
        if boxes.size:
            half = model.geom_size[boxes] * np.where(planes[boxes, None], (1.0, 1.0, 0.0), 1.0)  # a plane is flat
            review.static(f"{path}/boxes", rr.Boxes3D(
                half_sizes=half, centers=model.geom_pos[boxes], quaternions=_xyzw(model.geom_quat[boxes]),
                colors=_rgba8(model.geom_rgba[boxes]), fill_mode=solid,
                labels=[model.geom(int(g)).name for g in boxes], show_labels=False))
        if cylinders.size:
            size = model.geom_size[cylinders]
            corner = _corner_of(name) if name.endswith("/wheel") else None
            colors = [corner_color(corner)] * cylinders.size if corner else _rgba8(model.geom_rgba[cylinders])
            review.static(f"{path}/cylinders", rr.Cylinders3D(
                lengths=2 * size[:, 1], radii=size[:, 0], centers=model.geom_pos[cylinders],
                quaternions=_xyzw(model.geom_quat[cylinders]), colors=colors, fill_mode=solid,
                labels=[corner] * cylinders.size if corner else [model.geom(int(g)).name for g in cylinders],
                show_labels=corner is not None))


def _log_front(review: Review, model: mujoco.MjModel, prefix: str) -> None:
    """An arrow on the car body's front end, pointing forward (x), labelled ``front``."""
    body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "car.body")
    boxes = np.flatnonzero((model.geom_bodyid == body) & (model.geom_type == mujoco.mjtGeom.mjGEOM_BOX))
    if body < 0 or not boxes.size:
        return
    centre, half = model.geom_pos[boxes[0]], model.geom_size[boxes[0]]
    review.static(f"{prefix}/car.body/front", rr.Arrows3D(
        origins=[centre + np.array([half[0], 0.0, half[2]])], vectors=[(0.5, 0.0, 0.0)], radii=0.02,
        colors=[(240, 240, 240)], labels=["front"], show_labels=True))


def _coil() -> np.ndarray:
    """A unit coil along z (0 to 1 m), SPRING_TURNS turns of radius SPRING_RADIUS (m)."""
    angle = np.linspace(0.0, 2 * np.pi * SPRING_TURNS, 24 * SPRING_TURNS + 1)
    return np.column_stack([SPRING_RADIUS * np.cos(angle), SPRING_RADIUS * np.sin(angle), angle / angle[-1]])


def _along(vectors: np.ndarray) -> np.ndarray:
    """Quaternions (xyzw) turning z onto each of ``vectors`` (samples x 3; the half-way quaternion)."""
    unit = vectors / np.linalg.norm(vectors, axis=1, keepdims=True)
    q = np.column_stack([-unit[:, 1], unit[:, 0], np.zeros(len(unit)), 1.0 + unit[:, 2]])
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def _log_lines(review: Review, model: mujoco.MjModel, sites: np.ndarray, indexes: list, rows: list,
               prefix: str) -> None:
    """Visible site-to-site tendons as lines, and each suspension tendon also as a coil spring."""
    for tendon in range(model.ntendon):
        adr, num = model.tendon_adr[tendon], model.tendon_num[tendon]
        if model.tendon_rgba[tendon, 3] == 0 or np.any(model.wrap_type[adr:adr + num] != mujoco.mjtWrap.mjWRAP_SITE):
            continue
        name = model.tendon(tendon).name
        ends = sites[:, model.wrap_objid[adr:adr + num]]
        path = f"{prefix}/tendons/{name}"
        review.static(path, rr.LineStrips3D.from_fields(radii=[model.tendon_width[tendon] / 2],
                                                        colors=[_rgba8(model.tendon_rgba[tendon])]))
        for index, at in zip(indexes, rows):
            review.send(path, index, rr.LineStrips3D.columns(strips=ends[at]))
        corner = _corner_of(name)
        if name.endswith("/suspension") and corner and num == 2:
            spring = f"{prefix}/springs/{corner}"
            review.static(spring, rr.LineStrips3D([_coil()], radii=SPRING_WIDTH, colors=[corner_color(corner)]))
            inboard = np.array([0.0, -np.sign(ends[0, 1, 1]) * SPRING_INBOARD, 0.0])  # beside the wheel, not in it
            low, high = ends[:, 1] + inboard, ends[:, 0] + inboard  # hub, body
            length = np.linalg.norm(high - low, axis=1)
            for index, at in zip(indexes, rows):
                review.send(spring, index, rr.Transform3D.columns(
                    translation=low[at], quaternion=_along(high - low)[at],
                    scale=np.column_stack([np.ones_like(length), np.ones_like(length), length])[at]))


def log_rig(review: Review, model: mujoco.MjModel, qpos: np.ndarray, time: np.ndarray, prefix: str = "rig",
            still_on: Sequence[str] = (), magnification: float = 1.0,
            heights: dict[str, np.ndarray] | None = None) -> None:
    """The rig in 3D at the sample ``time`` (s) of ``qpos`` (samples x nq, e.g. ``ReplayResult.qpos``), its
    motion scaled by ``magnification``; ``heights`` (m per corner, ``post_heights``) lift posts without a joint.
    Bodies that do not move get one static pose; on each sequence timeline of ``still_on`` the moving parts stand
    in their last pose (at 0) instead of falling apart."""
    xpos, xquat, sites = body_poses(model, magnified(model, np.asarray(qpos, float), magnification))
    for corner, height in (heights or {}).items():
        lift = magnification * (height - height[0]) + height[0]
        body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, f"{corner}/post")
        xpos[:, body, 2] += lift
        sites[:, model.site_bodyid == body, 2] += lift[:, None]
    indexes = [[rr.TimeColumn("time", duration=np.asarray(time, float))]]
    indexes += [[rr.TimeColumn(timeline, sequence=[0])] for timeline in still_on]
    rows = [slice(None)] + [slice(-1, None)] * len(still_on)
    _log_geometry(review, model, prefix)
    _log_front(review, model, prefix)
    for body in range(1, model.nbody):
        path = f"{prefix}/{model.body(body).name}"
        translation, quaternion = xpos[:, body], _xyzw(xquat[:, body])
        if np.ptp(translation, axis=0).max() == 0 and np.ptp(quaternion, axis=0).max() == 0:
            review.static(path, rr.Transform3D(translation=translation[0], quaternion=quaternion[0]))
            continue
        for index, at in zip(indexes, rows):
            review.send(path, index, rr.Transform3D.columns(translation=translation[at], quaternion=quaternion[at]))
    _log_lines(review, model, sites, indexes, rows, prefix)
    if magnification != 1.0:
        review.scene = f"Rig (3D): motion magnified ×{magnification:g}"
        review.static(f"{prefix}/magnification", rr.Points3D(
            [xpos[0, 0] + (0.0, 0.0, 1.3)], radii=0.001, labels=[f"motion ×{magnification:g}"], show_labels=True))
