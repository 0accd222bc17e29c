"""Rerun review of rig runs, drive iterations and FRFs (DESIGN.md "Rerun notes"; rerun-sdk 0.41).

Everything is logged columnar: one ``send_columns`` per entity and run, never one call per sample.

Timelines:
- ``time`` (duration, s): record channels, the rig animation, target/response/error/drive of iterations;
- ``iteration`` (sequence): per-iteration metrics of a drive iteration and its summary table;
- ``frequency_mHz`` (sequence, integer mHz): FRF magnitude and coherence (x axis in mHz: 12500 = 12.5 Hz).

Entity paths (SI values; ``<name>`` is a channel name ``<corner>/<quantity>``):
- ``run/<corner>/<quantity>``: every channel of a record;
- ``rig/<body>`` (``rig/FL/post``, ``rig/car.body``, ``rig/car.FL/wheel``): body world poses; static geometry
  under ``rig/<body>/boxes`` and ``rig/<body>/cylinders``; ``rig/tendons/<tendon>``: suspension and tyre;
- ``iterate/target/<name>``, ``iterate/response/<name>``, ``iterate/error/<name>`` (target minus response) and
  ``iterate/drive/<corner>`` on ``time``, the last three with one series (instance) per iteration;
  ``iterate/rms_error_pct/<name>``, ``iterate/tddi/<name>``, ``iterate/damage_ratio/<name>``,
  ``iterate/worst_rms_error_pct``, ``iterate/total_error_pct``, ``iterate/gain`` and the markdown table
  ``iterate/summary`` on ``iteration``;
- ``frf/magnitude_db/<output>/<input>`` (dB re 1 SI unit per SI unit) and ``frf/coherence/<output>``.
"""

from __future__ import annotations

import contextlib
import os
import sys
import warnings
from collections.abc import Iterator, Sequence
from pathlib import Path

import mujoco
import numpy as np
import rerun as rr
import rerun.blueprint as rrb

from rig.io.atomic import atomic_path
from rig.io.channels import CORNERS, channel, split_channel
from rig.io.record import Record
from rig.sim.replay import ReplayResult

APPLICATION_ID = "virtual_four_poster"
VIEWER_WAIT = 15.0  # s: at most this long for a spawned viewer to take a recording
Color = tuple[int, int, int]  # RGB, 0-255

#: Line colours (RGB) per quantity, so a quantity looks the same in every panel.
QUANTITY_COLORS: dict[str, Color] = {
    "drive": (230, 160, 40), "actuator_disp": (60, 140, 230), "road": (120, 120, 120),
    "actuator_force": (150, 100, 200), "sprung_acc": (220, 60, 60), "unsprung_acc": (60, 170, 90),
    "susp_travel": (40, 170, 200), "susp_velocity": (200, 120, 170), "tyre_force": (110, 80, 40),
}
TARGET_COLOR = (255, 255, 255)


# ---- recordings and the default layout ------------------------------------------------------------------
def open_recording(path: str | os.PathLike | None, spawn: bool = False, application_id: str = APPLICATION_ID,
                   blueprint: rrb.Blueprint | None = None) -> rr.RecordingStream:
    """A recording that saves to ``path`` (.rrd) and/or streams to a spawned viewer, with ``blueprint``
    (default: ``default_blueprint()``) as its default layout. Call ``close_recording`` when done."""
    if path is None and not spawn:
        raise ValueError("a recording needs a file path, a spawned viewer or both")
    blueprint = blueprint or default_blueprint()
    stream = rr.RecordingStream(application_id)
    if spawn:  # the viewer ships with rerun-sdk, beside this Python even when its environment is not activated
        beside = Path(sys.executable).with_name("rerun")
        rr.spawn(connect=path is None, executable_path=str(beside) if beside.is_file() else None,
                 default_blueprint=blueprint, recording=stream)
    if path is not None:
        sinks = (rr.GrpcSink(), rr.FileSink(str(path))) if spawn else (rr.FileSink(str(path)),)
        stream.set_sinks(*sinks, default_blueprint=blueprint)
    return stream


def close_recording(stream: rr.RecordingStream, wait: float | None = None) -> None:
    """Flush everything logged and close the sinks (a saved file is complete only after this). ``wait`` (s)
    bounds the wait for a spawned viewer: one that cannot be reached (no display, say) gets a warning."""
    try:
        stream.flush(timeout_sec=1e38 if wait is None else wait)  # 1e38: rerun's "no timeout"
    except RuntimeError as err:
        warnings.warn(f"the Rerun viewer did not get the recording: {err}", stacklevel=2)
    finally:
        stream.disconnect()


@contextlib.contextmanager
def recording(path: str | os.PathLike | None, spawn: bool = False,
              blueprint: rrb.Blueprint | None = None) -> Iterator[rr.RecordingStream]:
    """``open_recording`` as a context: the .rrd file appears complete at ``path`` or not at all."""
    with contextlib.ExitStack() as stack:
        stream = open_recording(None if path is None else stack.enter_context(atomic_path(path)), spawn,
                                blueprint=blueprint)
        try:
            yield stream
        finally:
            close_recording(stream, VIEWER_WAIT if spawn else None)


def _series_view(name: str, *paths: str) -> rrb.TimeSeriesView:
    return rrb.TimeSeriesView(name=name, origin="/", contents=[f"+ {p}" for p in paths])


def default_blueprint(corners: Sequence[str] = CORNERS, iteration_channels: Sequence[str] = ()) -> rrb.Blueprint:
    """The layout a test engineer starts from.

    Left: the rig in 3D (``rig``) and, for a drive iteration (``iteration_channels`` given), tabs with the
    convergence (RMS error per channel, worst and total error, gain; TDDI), the summary table of the
    iteration under the cursor, and the FRF magnitude per output corner and multiple coherence. Right: one
    tab per corner with accelerations, post motion (drive, achieved, road), suspension travel and forces
    (tyre, post) of ``run``; for an iteration also target vs response and error per channel (every
    iteration, darker = later) and the drive of every iteration. The time panel starts on ``time``.
    """
    corner_tabs = []
    for c in corners:
        views = [
            _series_view(f"{c} accelerations (m/s²)", f"run/{c}/sprung_acc", f"run/{c}/unsprung_acc"),
            _series_view(f"{c} post: drive, achieved, road (m)", f"run/{c}/drive", f"run/{c}/actuator_disp",
                         f"run/{c}/road"),
            _series_view(f"{c} suspension travel (m, compression +)", f"run/{c}/susp_travel"),
            _series_view(f"{c} forces: tyre, post (N)", f"run/{c}/tyre_force", f"run/{c}/actuator_force"),
        ]
        for name in (n for n in iteration_channels if split_channel(n)[0] == c):
            views.append(_series_view(f"{name}: target vs response", f"iterate/target/{name}",
                                      f"iterate/response/{name}"))
            views.append(_series_view(f"{name}: error (target − response)", f"iterate/error/{name}"))
        if iteration_channels:
            views.append(_series_view(f"{c} drive per iteration (m)", f"iterate/drive/{c}"))
        corner_tabs.append(rrb.Grid(*views, name=c, grid_columns=2))
    rig = rrb.Spatial3DView(origin="rig", name="Rig (3D)",
                            eye_controls=rrb.EyeControls3D(position=(3.5, -5.0, 2.0), look_target=(-0.3, 0.0, 0.4),
                                                           eye_up=(0.0, 0.0, 1.0)))
    left: list[rrb.Container | rrb.View] = [rig]
    if iteration_channels:
        left.append(rrb.Tabs(
            rrb.Vertical(_series_view("RMS error per channel (%)", "iterate/rms_error_pct/**",
                                      "iterate/worst_rms_error_pct", "iterate/total_error_pct"),
                         _series_view("gain", "iterate/gain"), name="Convergence (iteration)"),
            _series_view("TDDI per channel (iteration)", "iterate/tddi/**"),
            rrb.TextDocumentView(origin="iterate/summary", name="Iteration summary"),
            rrb.Vertical(*[_series_view(f"FRF to {c} |H1| (dB; frequency_mHz)", f"frf/magnitude_db/{c}/**")
                           for c in corners], name="FRF"),
            _series_view("Multiple coherence (frequency_mHz)", "frf/coherence/**"),
        ))
    return rrb.Blueprint(rrb.Horizontal(rrb.Vertical(*left), rrb.Tabs(*corner_tabs), column_shares=(2, 3)),
                         rrb.TimePanel(timeline="time"), collapse_panels=False)


# ---- records and the rig ----------------------------------------------------------------------------------
def _log_series(stream: rr.RecordingStream, path: str, index: rr.TimeColumn, values: np.ndarray | Sequence[float],
                names: str | list[str], colors: Color | list[Color] | None) -> None:
    """Scalar series: their style (static) and all samples in one columnar send. ``values`` is one series
    (samples) or several (samples x series, with one name and colour each)."""
    stream.log(path, rr.SeriesLines(names=names, colors=colors), static=True)
    stream.send_columns(path, indexes=[index], columns=rr.Scalars.columns(scalars=np.asarray(values, float)))


def log_record(stream: rr.RecordingStream, record: Record, prefix: str = "run") -> None:
    """Every channel of ``record`` (SI) as the series ``<prefix>/<corner>/<quantity>`` on ``time`` (s)."""
    time = rr.TimeColumn("time", duration=record.time)
    for name, values in record.channels.items():
        unit = record.units.get(name, "")
        _log_series(stream, f"{prefix}/{name}", time, values, f"{name} [{unit}]" if unit else name,
                    QUANTITY_COLORS.get(split_channel(name)[1]))


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


def _xyzw(wxyz: np.ndarray) -> np.ndarray:
    """MuJoCo quaternions (..., w x y z) in Rerun's order (..., x y z w)."""
    return np.roll(wxyz, -1, axis=-1)


def _rgba8(rgba: np.ndarray) -> np.ndarray:
    return np.round(np.clip(rgba, 0.0, 1.0) * 255).astype(np.uint8)


def _log_geometry(stream: rr.RecordingStream, model: mujoco.MjModel, prefix: str) -> None:
    """Static geoms in body frames: planes and boxes as ``<body>/boxes``, cylinders as ``<body>/cylinders``
    (other geom types and invisible geoms, alpha 0, are not drawn)."""
    solid = rr.components.FillMode.Solid
    for body in range(model.nbody):
        path = f"{prefix}/{model.body(body).name}"
        visible = (model.geom_bodyid == body) & (model.geom_rgba[:, 3] > 0)
        planes = visible & (model.geom_type == mujoco.mjtGeom.mjGEOM_PLANE)
        boxes = np.flatnonzero(planes | (visible & (model.geom_type == mujoco.mjtGeom.mjGEOM_BOX)))
        cylinders = np.flatnonzero(visible & (model.geom_type == mujoco.mjtGeom.mjGEOM_CYLINDER))
        if boxes.size:
            half = model.geom_size[boxes] * np.where(planes[boxes, None], (1.0, 1.0, 0.0), 1.0)  # a plane is flat
            stream.log(f"{path}/boxes", rr.Boxes3D(
                half_sizes=half, centers=model.geom_pos[boxes], quaternions=_xyzw(model.geom_quat[boxes]),
                colors=_rgba8(model.geom_rgba[boxes]), fill_mode=solid,
                labels=[model.geom(int(g)).name for g in boxes], show_labels=False), static=True)
        if cylinders.size:
            size = model.geom_size[cylinders]
            stream.log(f"{path}/cylinders", rr.Cylinders3D(
                lengths=2 * size[:, 1], radii=size[:, 0], centers=model.geom_pos[cylinders],
                quaternions=_xyzw(model.geom_quat[cylinders]), colors=_rgba8(model.geom_rgba[cylinders]),
                fill_mode=solid, labels=[model.geom(int(g)).name for g in cylinders], show_labels=False), static=True)


def log_rig_animation(stream: rr.RecordingStream, model: mujoco.MjModel, qpos: np.ndarray, time: np.ndarray,
                      prefix: str = "rig") -> None:
    """The rig in 3D: static geometry once, every moving body's world pose (``<prefix>/<body>``, m) and
    the visible site-to-site tendons (``<prefix>/tendons/<tendon>``) at the sample ``time`` (s) of
    ``qpos`` (samples x nq, from ``ReplayResult.qpos``). Bodies that do not move get one static pose."""
    xpos, xquat, sites = body_poses(model, np.asarray(qpos, float))
    index = rr.TimeColumn("time", duration=np.asarray(time, float))
    _log_geometry(stream, model, prefix)
    for body in range(1, model.nbody):
        path = f"{prefix}/{model.body(body).name}"
        translation, quaternion = xpos[:, body], _xyzw(xquat[:, body])
        if np.ptp(translation, axis=0).max() == 0 and np.ptp(quaternion, axis=0).max() == 0:
            stream.log(path, rr.Transform3D(translation=translation[0], quaternion=quaternion[0]), static=True)
        else:
            stream.send_columns(path, indexes=[index],
                                columns=rr.Transform3D.columns(translation=translation, quaternion=quaternion))
    for tendon in range(model.ntendon):
        adr, num = model.tendon_adr[tendon], model.tendon_num[tendon]
        if model.tendon_rgba[tendon, 3] == 0 or np.any(model.wrap_type[adr:adr + num] != mujoco.mjtWrap.mjWRAP_SITE):
            continue
        path = f"{prefix}/tendons/{model.tendon(tendon).name}"
        stream.log(path, rr.LineStrips3D.from_fields(radii=[model.tendon_width[tendon]],
                                                     colors=[_rgba8(model.tendon_rgba[tendon])]), static=True)
        stream.send_columns(path, indexes=[index],
                            columns=rr.LineStrips3D.columns(strips=sites[:, model.wrap_objid[adr:adr + num]]))


def log_replay(stream: rr.RecordingStream, result: ReplayResult, prefix: str = "run") -> None:
    """A replay or track run: its record (``log_record``) and, when it carries joint positions, the rig."""
    log_record(stream, result.record, prefix)
    if result.qpos is not None and result.model is not None:
        log_rig_animation(stream, result.model, result.qpos, result.record.time)


# ---- drive iteration and FRF -------------------------------------------------------------------------------
def _ramp(start: Color, end: Color, share: float) -> Color:
    """A colour ``share`` (0..1) of the way from ``start`` to ``end``."""
    return tuple(int(round(a + (b - a) * share)) for a, b in zip(start, end))


ITERATION_COLORS = {"response": ((170, 200, 255), (20, 70, 200)), "error": ((255, 190, 170), (190, 30, 20)),
                    "drive": ((190, 235, 190), (20, 130, 40))}
CORNER_COLORS: dict[str, Color] = {"FL": (220, 60, 60), "FR": (60, 170, 90), "RL": (60, 120, 230), "RR": (230, 160, 40)}
CHANNEL_METRICS = ("rms_error_pct", "tddi", "damage_ratio")
RUN_METRICS = ("worst_rms_error_pct", "total_error_pct", "gain")


def _summary(entry: dict) -> str:
    """One iteration of history.json as a markdown table."""
    lines = [f"### Iteration {entry['iteration']}: gain {entry['gain']:.3g}, worst channel "
             f"{entry['worst_rms_error_pct']:.2f} % RMS error", "",
             "| channel | RMS error (%) | TDDI | damage ratio |", "|---|---|---|---|"]
    lines += [f"| {name} | {m['rms_error_pct']:.2f} | {m.get('tddi', float('nan')):.4f} | "
              f"{m.get('damage_ratio', float('nan')):.3f} |" for name, m in entry["channels"].items()]
    hits = entry.get("limit_hits") or ["none"]
    return "\n".join(lines + ["", "Limit hits: " + "; ".join(hits)])


def log_iteration(stream: rr.RecordingStream, history: Sequence[dict], target: np.ndarray,
                  responses: Sequence[np.ndarray], rate: float, channels: Sequence[str],
                  drives: Sequence[np.ndarray] = (), corners: Sequence[str] = CORNERS, start_time: float = 0.0,
                  prefix: str = "iterate") -> None:
    """A drive iteration: time series on ``time`` and metrics on the ``iteration`` sequence timeline.

    ``history``: the per-iteration dicts of history.json (``iteration``, ``gain``, ``worst_rms_error_pct``,
    ``channels`` -> name -> ``rms_error_pct``, ``tddi``, ``damage_ratio``); ``target``: samples x channels
    (SI, sampled at ``rate`` Hz from ``start_time`` s); ``responses`` (samples x channels, SI) and ``drives``
    (samples x corners, m) belong to the last ``len(responses)`` / ``len(drives)`` entries of ``history``
    (all of them unless the run was resumed). Logs ``<prefix>/target/<name>``; ``response/<name>`` and
    ``error/<name>`` (target - response) and ``drive/<corner>`` with one series per iteration (named
    ``iteration k``, darker = later); the per-channel metrics ``<metric>/<name>``, the run's worst and
    total error and gain, and a markdown ``summary`` of every iteration.
    """
    time = rr.TimeColumn("time", duration=start_time + np.arange(target.shape[0]) / rate)
    last = max(len(history) - 1, 1)

    def styles(count: int, kind: str) -> tuple[list[str], list[Color]]:
        entries = history[len(history) - count:]
        return ([f"iteration {e['iteration']}" for e in entries],
                [_ramp(*ITERATION_COLORS[kind], e["iteration"] / last) for e in entries])

    for j, name in enumerate(channels):
        _log_series(stream, f"{prefix}/target/{name}", time, target[:, j], "target", TARGET_COLOR)
        if responses:
            response = np.stack([r[:, j] for r in responses], axis=1)  # samples x iterations
            _log_series(stream, f"{prefix}/response/{name}", time, response, *styles(len(responses), "response"))
            _log_series(stream, f"{prefix}/error/{name}", time, target[:, j:j + 1] - response,
                        *styles(len(responses), "error"))
    for i, corner in enumerate(corners if drives else ()):
        _log_series(stream, f"{prefix}/drive/{corner}", time, np.stack([d[:, i] for d in drives], axis=1),
                    *styles(len(drives), "drive"))
    iteration = rr.TimeColumn("iteration", sequence=[entry["iteration"] for entry in history])
    for key in (key for key in RUN_METRICS if key in history[0]):
        _log_series(stream, f"{prefix}/{key}", iteration, [entry[key] for entry in history], key, None)
    for name in history[0]["channels"]:
        for key in CHANNEL_METRICS:
            values = [entry["channels"][name].get(key, np.nan) for entry in history]
            _log_series(stream, f"{prefix}/{key}/{name}", iteration, values, name,
                        QUANTITY_COLORS.get(split_channel(name)[1]))
    stream.send_columns(f"{prefix}/summary", indexes=[iteration], columns=rr.TextDocument.columns(
        text=[_summary(entry) for entry in history], media_type=["text/markdown"] * len(history)))


def log_frf(stream: rr.RecordingStream, frequency: np.ndarray, h1: np.ndarray, coherence: np.ndarray,
            inputs: Sequence[str], outputs: Sequence[str], band: tuple[float, float] | None = None,
            prefix: str = "frf") -> None:
    """FRF magnitude and multiple coherence against frequency, on the sequence timeline ``frequency_mHz``
    (each line's frequency rounded to an integer number of mHz).

    ``frequency``: lines in Hz; ``h1``: lines x outputs x inputs (output SI unit per input SI unit), logged
    as 20 log10 |H1| dB at ``<prefix>/magnitude_db/<output>/<input>``; ``coherence``: lines x outputs
    (0..1) at ``<prefix>/coherence/<output>``. ``band`` (Hz) keeps only the lines inside it.
    """
    keep = np.ones(frequency.size, bool) if band is None else (frequency >= band[0]) & (frequency <= band[1])
    millihertz = np.round(frequency[keep] * 1000).astype(np.int64)
    if np.unique(millihertz).size != millihertz.size:
        raise ValueError("FRF lines closer than 1 mHz cannot be told apart on the frequency_mHz timeline")
    index = rr.TimeColumn("frequency_mHz", sequence=millihertz)
    magnitude = 20 * np.log10(np.maximum(np.abs(h1[keep]), np.finfo(float).tiny))
    for o, output in enumerate(outputs):
        for i, source in enumerate(inputs):
            _log_series(stream, f"{prefix}/magnitude_db/{output}/{source}", index, magnitude[:, o, i],
                        f"{output} / {source} [dB]", CORNER_COLORS.get(split_channel(source)[0]))
        _log_series(stream, f"{prefix}/coherence/{output}", index, coherence[keep, o], output,
                    QUANTITY_COLORS.get(split_channel(output)[1]))


class IterationLog:
    """Every drive a drive iteration plays (samples x corners, m) and its band-passed response (samples x
    channels, SI): pass it as ``callback`` to ``DriveIteration.run`` (it reads ``step.drive`` and
    ``step.response``), then to ``log_iteration``."""

    def __init__(self) -> None:
        self.drives: list[np.ndarray] = []
        self.responses: list[np.ndarray] = []

    def __call__(self, step) -> None:
        self.drives.append(np.array(step.drive, float))
        self.responses.append(step.response)


def log_drive_iteration(stream: rr.RecordingStream, result, plays: IterationLog, target: np.ndarray,
                        start_time: float, channels: Sequence[str], band: tuple[float, float]) -> None:
    """A finished drive iteration (``controllers.rpc.IterationResult``: its ``history``, ``frf`` and the
    best drive's ``replay``): the iterations played now (``plays``) against the edited ``target`` (samples x
    channels, from ``start_time`` s) and the metrics of all (``log_iteration``), the FRF estimate it ended
    with (``log_frf``, lines in ``band``), and the best drive on the rig (``log_replay``)."""
    rate, corners = result.replay.record.rate, result.replay.record.corners_with("drive")
    log_iteration(stream, [h.to_json() for h in result.history], target, plays.responses, rate, channels,
                  plays.drives, corners, start_time)
    log_frf(stream, result.frf.frequency, result.frf.h1, result.frf.coherence, [channel(c, "drive") for c in corners],
            channels, band)
    log_replay(stream, result.replay)
