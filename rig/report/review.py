"""Rerun review of rig runs, drive iterations and FRFs (docs/review.md; rerun-sdk 0.41).

Everything is logged columnar: one ``send_columns`` per entity and run, never one call per sample.

Timelines:
- ``time`` (duration, s): record channels, the rig animation, target/response/error/drive of iterations;
- ``iteration`` (sequence): per-iteration metrics of a drive iteration and its summary table;
- ``frequency_mHz`` (sequence, integer mHz): FRF magnitude and coherence (x axis in mHz: 12500 = 12.5 Hz).
A plot shows the timeline selected in the viewer's time panel, so what must be seen on opening is static:
the geometry, the convergence bars and table; the rig also stands in its last pose on the sequence timelines.

Entity paths (SI values; ``<name>`` is a channel name ``<corner>/<quantity>``):
- ``run/<corner>/<quantity>``: every channel of a record;
- ``rig/<body>`` (``rig/FL/post``, ``rig/car.body``, ``rig/car.FL/wheel``): body world poses; static geometry
  under ``rig/<body>/boxes`` and ``rig/<body>/cylinders``; ``rig/tendons/<tendon>``: suspension and tyre;
- ``iterate/target/<name>``, ``iterate/response/<name>``, ``iterate/error/<name>`` (target minus response) and
  ``iterate/drive/<corner>`` on ``time``, the last three with one series (instance) per iteration; the
  target record's own post motion ``target/<corner>/actuator_disp`` (or ``road``);
  ``iterate/rms_error_pct/<name>``, ``iterate/tddi/<name>``, ``iterate/log10_tddi/<name>``,
  ``iterate/damage_ratio/<name>``, ``iterate/worst_rms_error_pct``, ``iterate/total_error_pct``,
  ``iterate/gain`` and the markdown table ``iterate/summary`` on ``iteration``; static
  ``iterate/convergence/worst_rms_error_pct`` (bar chart) and ``iterate/convergence/table`` (markdown);
- ``frf/magnitude_db/<output>/<input>`` (dB re 1 SI unit per SI unit) and ``frf/coherence/<output>``.

Colours: one per corner (``CORNER_COLORS``) in every panel; targets, measurements and the road are grey
(``REFERENCE_COLOR``) and wider; several iterations of one series fade from faint (first) to full (last).
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

#: One colour per corner (RGB; Okabe-Ito, told apart with colour-blind vision): every simulated or achieved
#: line of a corner, in every panel. Panels hold one quantity each, or tell quantities apart by line width.
CORNER_COLORS: dict[str, Color] = {"FL": (213, 94, 0), "FR": (0, 114, 178), "RL": (0, 150, 110), "RR": (170, 80, 160)}
#: Reference lines (a target, a measurement, the road under the tyre): a neutral grey that reads on the light
#: and on the dark theme (WCAG contrast above 3 against white and against near-black), thinner than the
#: simulated lines and drawn over them, so that both show where they agree. (The viewer draws a panel's
#: series in the order of their entity paths: ``iterate/target`` after ``iterate/response``, ``run/<c>/road``
#: after ``run/<c>/actuator_disp``, ``target/`` after ``run/``.)
REFERENCE_COLOR: Color = (115, 115, 115)
REFERENCE_WIDTH = 1.25
#: Line width (points) per quantity where one panel holds two of them; others are drawn at LINE_WIDTH.
QUANTITY_WIDTHS = {"sprung_acc": 2.5, "unsprung_acc": 1.0, "drive": 1.0}
LINE_WIDTH = 2.0
#: Quantities that are the input of a run, drawn as references.
REFERENCE_QUANTITIES = ("road",)
#: Timelines of these recordings (see the module's docstring).
TIMELINES = ("time", "iteration", "frequency_mHz")


def line_style(name: str) -> tuple[Color, float]:
    """Colour and width of the line of channel ``name`` (``<corner>/<quantity>``)."""
    corner, quantity = split_channel(name)
    if quantity in REFERENCE_QUANTITIES or corner not in CORNER_COLORS:
        return REFERENCE_COLOR, REFERENCE_WIDTH
    return CORNER_COLORS[corner], QUANTITY_WIDTHS.get(quantity, LINE_WIDTH)


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


_EVERYTHING = rrb.TimeRangeBoundary.infinite()


def _series_view(name: str, *paths: str, legend: bool | str = "LeftTop") -> rrb.TimeSeriesView:
    """A plot of the series at ``paths`` against the timeline in the time panel, opened on the whole of every
    timeline (its own x axis, not zoomed about the cursor). ``legend``: the corner it sits in, or False for
    panels with many lines (their title gives the colour code; hovering names a line)."""
    return rrb.TimeSeriesView(
        name=name, origin="/", contents=[f"+ {p}" for p in paths],
        time_ranges=[rrb.VisibleTimeRange(t, start=_EVERYTHING, end=_EVERYTHING) for t in TIMELINES],
        axis_x=rrb.TimeAxis(link="Independent", view_range=rr.TimeRange(start=_EVERYTHING, end=_EVERYTHING)),
        plot_legend=rrb.PlotLegend(legend or None, visible=bool(legend)))


def _corner_views(c: str) -> list[rrb.View]:
    """A corner's run, one quantity per panel; references (road, target post motion) in grey beside it."""
    return [
        _series_view(f"{c} body acceleration (m/s²); target in grey", f"run/{c}/sprung_acc", f"target/{c}/sprung_acc"),
        _series_view(f"{c} wheel acceleration (m/s²); target in grey", f"run/{c}/unsprung_acc",
                     f"target/{c}/unsprung_acc"),
        _series_view(f"{c} post (m): drive (thin), achieved; road or target in grey", f"run/{c}/drive",
                     f"run/{c}/actuator_disp", f"run/{c}/road", f"target/{c}/actuator_disp", f"target/{c}/road"),
        _series_view(f"{c} suspension travel (m, compression +)", f"run/{c}/susp_travel"),
        _series_view(f"{c} suspension velocity (m/s, compression +)", f"run/{c}/susp_velocity"),
        _series_view(f"{c} tyre force (N)", f"run/{c}/tyre_force"),
        _series_view(f"{c} post or controller force (N)", f"run/{c}/actuator_force", f"run/{c}/control_force"),
    ]


def _iteration_views(c: str, channels: Sequence[str]) -> list[rrb.View]:
    """A corner's iterated channels: target (grey) against every iteration's response, and the errors, and
    the drive of every iteration (faint = early, full corner colour = last)."""
    views = []
    for name in (n for n in channels if split_channel(n)[0] == c):
        views.append(_series_view(f"{name}: target (grey) vs response per iteration", f"iterate/target/{name}",
                                  f"iterate/response/{name}", legend=False))
        views.append(_series_view(f"{name}: error (target − response) per iteration", f"iterate/error/{name}",
                                  legend=False))
    views.append(_series_view(f"{c} drive per iteration (m)", f"iterate/drive/{c}", legend=False))
    return views


def default_blueprint(corners: Sequence[str] = CORNERS, iteration_channels: Sequence[str] = ()) -> rrb.Blueprint:
    """The layout a test engineer starts from.

    Left: the rig in 3D (``rig``; on every timeline) and, for a drive iteration (``iteration_channels``
    given), tabs with the convergence at a glance (worst-channel RMS error per iteration as bars and a table
    of every iteration, shown on every timeline), the metrics per channel against ``iteration`` (RMS error
    with the worst and total, log10 TDDI, gain) and the summary of the iteration under the cursor. Right: one
    tab per corner with body and wheel acceleration, post motion (drive, achieved, road or target), suspension
    travel and velocity, tyre and post force of ``run``, one panel each; for an iteration also one tab per
    corner with target vs response and error per channel (every iteration) and the drive of every iteration,
    and a tab with the FRF magnitude per output channel and the multiple coherence (``frequency_mHz``).
    Every corner has its colour (``CORNER_COLORS``) in every panel; references are grey. The time panel
    starts on ``time``; every plot opens on the whole range of the timeline selected there.
    """
    right = [rrb.Grid(*_corner_views(c), name=c, grid_columns=2) for c in corners]
    rig = rrb.Spatial3DView(origin="rig", name="Rig (3D)",
                            eye_controls=rrb.EyeControls3D(position=(3.5, -5.0, 2.0), look_target=(-0.3, 0.0, 0.4),
                                                           eye_up=(0.0, 0.0, 1.0)))
    left: list[rrb.Container | rrb.View] = [rig]
    if iteration_channels:
        right += [rrb.Grid(*_iteration_views(c, iteration_channels), name=f"{c} iterations", grid_columns=2)
                  for c in corners]
        right.append(rrb.Vertical(
            rrb.Grid(*[_series_view(f"{name} |H1| (dB) from each drive", f"frf/magnitude_db/{name}/**",
                                    legend="LeftBottom") for name in iteration_channels],
                     grid_columns=min(4, len(iteration_channels))),
            _series_view("Multiple coherence: corner colours, sprung thick, unsprung thin; x: frequency_mHz",
                         "frf/coherence/**", legend=False),
            row_shares=(2, 1), name="FRF"))
        left.append(rrb.Tabs(
            rrb.Vertical(rrb.BarChartView(origin="iterate/convergence/worst_rms_error_pct",
                                          name="Worst channel's RMS error (%) per iteration",
                                          plot_legend=rrb.PlotLegend(visible=False)),
                         rrb.TextDocumentView(origin="iterate/convergence/table", name="Every iteration"),
                         name="Convergence"),
            rrb.Vertical(_series_view("RMS error (%): corner colours, sprung thick, unsprung thin; worst grey",
                                      "iterate/rms_error_pct/**", "iterate/worst_rms_error_pct", legend=False),
                         _series_view("log10 TDDI: corner colours, sprung thick, unsprung thin",
                                      "iterate/log10_tddi/**", legend=False),
                         name="Per channel (iteration)"),
            rrb.TextDocumentView(origin="iterate/summary", name="Iteration summary (iteration)"),
        ))
    return rrb.Blueprint(rrb.Horizontal(rrb.Vertical(*left), rrb.Tabs(*right), column_shares=(2, 3)),
                         rrb.BlueprintPanel(state="collapsed"), rrb.SelectionPanel(state="collapsed"),
                         rrb.TimePanel(timeline="time", state="collapsed"))


# ---- records and the rig ----------------------------------------------------------------------------------
def _log_series(stream: rr.RecordingStream, path: str, index: rr.TimeColumn, values: np.ndarray | Sequence[float],
                names: str | list[str], colors: Color | Sequence[Color | tuple[int, int, int, int]],
                widths: float | list[float]) -> None:
    """Scalar series: their style (static) and all samples in one columnar send. ``values`` is one series
    (samples) or several (samples x series, with one name, colour (RGB or RGBA) and width each)."""
    stream.log(path, rr.SeriesLines(names=names, colors=colors, widths=widths), static=True)
    stream.send_columns(path, indexes=[index], columns=rr.Scalars.columns(scalars=np.asarray(values, float)))


def log_record(stream: rr.RecordingStream, record: Record, prefix: str = "run", reference: bool = False) -> None:
    """Every channel of ``record`` (SI) as the series ``<prefix>/<corner>/<quantity>`` on ``time`` (s), in
    its corner's colour (the road: grey, a reference); all grey for a ``reference`` record (a target, a
    measurement), named ``<prefix> <name> [unit]``."""
    time = rr.TimeColumn("time", duration=record.time)
    for name, values in record.channels.items():
        unit = record.units.get(name, "")
        label = f"{name} [{unit}]" if unit else name
        if reference:
            _log_series(stream, f"{prefix}/{name}", time, values, f"{prefix} {label}", REFERENCE_COLOR, REFERENCE_WIDTH)
        else:
            _log_series(stream, f"{prefix}/{name}", time, values, label, *line_style(name))


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
                      prefix: str = "rig", still_on: Sequence[str] = ()) -> None:
    """The rig in 3D: static geometry once, every moving body's world pose (``<prefix>/<body>``, m) and
    the visible site-to-site tendons (``<prefix>/tendons/<tendon>``) at the sample ``time`` (s) of
    ``qpos`` (samples x nq, from ``ReplayResult.qpos``). Bodies that do not move get one static pose. On
    each sequence timeline of ``still_on`` (``iteration``, ``frequency_mHz``) the moving parts also get their
    last pose at 0, so that the rig stands there in that pose instead of falling apart."""
    xpos, xquat, sites = body_poses(model, np.asarray(qpos, float))
    indexes = [[rr.TimeColumn("time", duration=np.asarray(time, float))]]
    indexes += [[rr.TimeColumn(timeline, sequence=[0])] for timeline in still_on]
    samples = [slice(None)] + [slice(-1, None)] * len(still_on)
    _log_geometry(stream, model, prefix)
    for body in range(1, model.nbody):
        path = f"{prefix}/{model.body(body).name}"
        translation, quaternion = xpos[:, body], _xyzw(xquat[:, body])
        if np.ptp(translation, axis=0).max() == 0 and np.ptp(quaternion, axis=0).max() == 0:
            stream.log(path, rr.Transform3D(translation=translation[0], quaternion=quaternion[0]), static=True)
            continue
        for index, rows in zip(indexes, samples):
            stream.send_columns(path, indexes=index, columns=rr.Transform3D.columns(
                translation=translation[rows], quaternion=quaternion[rows]))
    for tendon in range(model.ntendon):
        adr, num = model.tendon_adr[tendon], model.tendon_num[tendon]
        if model.tendon_rgba[tendon, 3] == 0 or np.any(model.wrap_type[adr:adr + num] != mujoco.mjtWrap.mjWRAP_SITE):
            continue
        path = f"{prefix}/tendons/{model.tendon(tendon).name}"
        stream.log(path, rr.LineStrips3D.from_fields(radii=[model.tendon_width[tendon]],
                                                     colors=[_rgba8(model.tendon_rgba[tendon])]), static=True)
        for index, rows in zip(indexes, samples):
            stream.send_columns(path, indexes=index, columns=rr.LineStrips3D.columns(
                strips=sites[rows][:, model.wrap_objid[adr:adr + num]]))


def log_replay(stream: rr.RecordingStream, result: ReplayResult, prefix: str = "run",
               still_on: Sequence[str] = ()) -> None:
    """A replay or track run: its record (``log_record``) and, when it carries joint positions, the rig
    (``log_rig_animation``, standing still in its last pose on the sequence timelines ``still_on``)."""
    log_record(stream, result.record, prefix)
    if result.qpos is not None and result.model is not None:
        log_rig_animation(stream, result.model, result.qpos, result.record.time, still_on=still_on)


# ---- drive iteration and FRF -------------------------------------------------------------------------------
CHANNEL_METRICS = ("rms_error_pct", "tddi", "damage_ratio")
RUN_METRICS = ("worst_rms_error_pct", "total_error_pct", "gain")
TDDI_FLOOR = 1e-12  # log10 TDDI of identical signals: far below any noise floor


def _faded(color: Color, share: float) -> tuple[int, int, int, int]:
    """``color`` with an opacity from a quarter (``share`` 0: the first iteration) to full (1: the last)."""
    return (*color, round(255 * (0.25 + 0.75 * share)))


def _summary(entry: dict) -> str:
    """One iteration of history.json as a markdown table (three significant figures: TDDI near the noise
    floor is 1e-4 or less)."""
    title = (f"### Iteration {entry['iteration']}: gain {entry['gain']:.3g}, worst channel "
             f"{entry['worst_rms_error_pct']:.3g} % RMS error")
    lines = [title, "",
             "| channel | RMS error (%) | TDDI | damage ratio |", "|---|---|---|---|"]
    lines += [f"| {name} | {m['rms_error_pct']:.3g} | {m.get('tddi', float('nan')):.3g} | "
              f"{m.get('damage_ratio', float('nan')):.3g} |" for name, m in entry["channels"].items()]
    hits = entry.get("limit_hits") or ["none"]
    return "\n".join([*lines, "", "Limit hits: " + "; ".join(hits)])


def _convergence_table(history: Sequence[dict]) -> str:
    """Every iteration in one markdown table: gain, worst-channel and total error, worst and mean TDDI."""
    lines = ["| iteration | gain | worst RMS error (%) | total error (%) | worst TDDI | mean TDDI |",
             "|---|---|---|---|---|---|"]
    for entry in history:
        tddi = [m.get("tddi", np.nan) for m in entry["channels"].values()]
        lines.append(f"| {entry['iteration']} | {entry['gain']:.3g} | {entry['worst_rms_error_pct']:.3g} | "
                     f"{entry.get('total_error_pct', np.nan):.3g} | {np.nanmax(tddi):.3g} | {np.nanmean(tddi):.3g} |")
    return "\n".join(lines)


def log_iteration(stream: rr.RecordingStream, history: Sequence[dict], target: np.ndarray,
                  responses: Sequence[np.ndarray], rate: float, channels: Sequence[str],
                  drives: Sequence[np.ndarray] = (), corners: Sequence[str] = CORNERS, start_time: float = 0.0,
                  prefix: str = "iterate") -> None:
    """A drive iteration: time series on ``time``, metrics on the ``iteration`` sequence timeline and the
    convergence at a glance as static data (on every timeline).

    ``history``: the per-iteration dicts of history.json (``iteration``, ``gain``, ``worst_rms_error_pct``,
    ``channels`` -> name -> ``rms_error_pct``, ``tddi``, ``damage_ratio``); ``target``: samples x channels
    (SI, sampled at ``rate`` Hz from ``start_time`` s); ``responses`` (samples x channels, SI) and ``drives``
    (samples x corners, m) belong to the last ``len(responses)`` / ``len(drives)`` entries of ``history``
    (all of them unless the run was resumed). Logs ``<prefix>/target/<name>`` (grey); ``response/<name>`` and
    ``error/<name>`` (target - response) and ``drive/<corner>`` with one series per iteration (named
    ``iteration k``, in the corner's colour, faint = early); the per-channel metrics ``<metric>/<name>`` and
    ``log10_tddi/<name>``, the run's worst and total error and gain, a markdown ``summary`` of every
    iteration; static: ``convergence/worst_rms_error_pct`` (bars per iteration) and ``convergence/table``.
    """
    time = rr.TimeColumn("time", duration=start_time + np.arange(target.shape[0]) / rate)
    last = max(history[-1]["iteration"], 1)

    def styles(count: int, color: Color) -> tuple[list[str], list[tuple[int, int, int, int]], list[float]]:
        entries = history[len(history) - count:]
        return ([f"iteration {e['iteration']}" for e in entries], [_faded(color, e["iteration"] / last)
                                                                  for e in entries], [LINE_WIDTH] * count)

    for j, name in enumerate(channels):
        color = line_style(name)[0]
        _log_series(stream, f"{prefix}/target/{name}", time, target[:, j], "target", REFERENCE_COLOR, REFERENCE_WIDTH)
        if responses:
            response = np.stack([r[:, j] for r in responses], axis=1)  # samples x iterations
            _log_series(stream, f"{prefix}/response/{name}", time, response, *styles(len(responses), color))
            _log_series(stream, f"{prefix}/error/{name}", time, target[:, j:j + 1] - response,
                        *styles(len(responses), color))
    for i, corner in enumerate(corners if drives else ()):
        _log_series(stream, f"{prefix}/drive/{corner}", time, np.stack([d[:, i] for d in drives], axis=1),
                    *styles(len(drives), CORNER_COLORS.get(corner, REFERENCE_COLOR)))
    numbers = [entry["iteration"] for entry in history]
    iteration = rr.TimeColumn("iteration", sequence=numbers)
    for key in (key for key in RUN_METRICS if key in history[0]):
        _log_series(stream, f"{prefix}/{key}", iteration, [entry[key] for entry in history], key, REFERENCE_COLOR,
                    LINE_WIDTH)
    for name in history[0]["channels"]:
        for key in CHANNEL_METRICS:
            values = [entry["channels"][name].get(key, np.nan) for entry in history]
            _log_series(stream, f"{prefix}/{key}/{name}", iteration, values, name, *line_style(name))
        tddi = np.array([entry["channels"][name].get("tddi", np.nan) for entry in history])
        _log_series(stream, f"{prefix}/log10_tddi/{name}", iteration, np.log10(np.maximum(tddi, TDDI_FLOOR)), name,
                    *line_style(name))
    stream.send_columns(f"{prefix}/summary", indexes=[iteration], columns=rr.TextDocument.columns(
        text=[_summary(entry) for entry in history], media_type=["text/markdown"] * len(history)))
    stream.log(f"{prefix}/convergence/worst_rms_error_pct", rr.BarChart(  # a bar starts at its abscissa
        [entry["worst_rms_error_pct"] for entry in history], abscissa=np.subtract(numbers, 0.4),
        widths=[0.8] * len(numbers),
        color=REFERENCE_COLOR), static=True)
    stream.log(f"{prefix}/convergence/table", rr.TextDocument(_convergence_table(history),
                                                              media_type="text/markdown"), static=True)


def log_frf(stream: rr.RecordingStream, frequency: np.ndarray, h1: np.ndarray, coherence: np.ndarray,
            inputs: Sequence[str], outputs: Sequence[str], band: tuple[float, float] | None = None,
            prefix: str = "frf") -> None:
    """FRF magnitude and multiple coherence against frequency, on the sequence timeline ``frequency_mHz``
    (each line's frequency rounded to an integer number of mHz).

    ``frequency``: lines in Hz; ``h1``: lines x outputs x inputs (output SI unit per input SI unit), logged
    as 20 log10 |H1| dB at ``<prefix>/magnitude_db/<output>/<input>`` in the input's corner colour;
    ``coherence``: lines x outputs (0..1) at ``<prefix>/coherence/<output>`` in the output's corner colour.
    ``band`` (Hz) keeps only the lines inside it.
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
                        f"from {source}", CORNER_COLORS.get(split_channel(source)[0], REFERENCE_COLOR), LINE_WIDTH)
        _log_series(stream, f"{prefix}/coherence/{output}", index, coherence[keep, o], output, *line_style(output))


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
                        start_time: float, channels: Sequence[str], band: tuple[float, float],
                        reference: Record | None = None) -> None:
    """A finished drive iteration (``controllers.rpc.IterationResult``: its ``history``, ``frf`` and the
    best drive's ``replay``): the iterations played now (``plays``) against the edited ``target`` (samples x
    channels, from ``start_time`` s) and the metrics of all (``log_iteration``), the FRF estimate it ended
    with (``log_frf``, lines in ``band``), and the best drive on the rig (``log_replay``; the rig stands in its
    last pose on the ``iteration`` and ``frequency_mHz`` timelines). ``reference``, the target record as read,
    gives the post motion the target was recorded with, per corner its ``actuator_disp`` or else its
    ``road``, logged as ``target/<corner>/<quantity>`` (grey) beside the achieved post motion."""
    rate, corners = result.replay.record.rate, result.replay.record.corners_with("drive")
    log_iteration(stream, [h.to_json() for h in result.history], target, plays.responses, rate, channels,
                  plays.drives, corners, start_time)
    log_frf(stream, result.frf.frequency, result.frf.h1, result.frf.coherence, [channel(c, "drive") for c in corners],
            channels, band)
    log_replay(stream, result.replay, still_on=("iteration", "frequency_mHz"))
    if reference is not None:
        posts = [next((channel(c, q) for q in ("actuator_disp", "road") if channel(c, q) in reference), None)
                 for c in corners]
        log_record(stream, reference.select([name for name in posts if name is not None]), "target", reference=True)
