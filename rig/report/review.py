"""Rerun review of a command's run (docs/review.md; rerun-sdk 0.41): the recording, its overview and the default
layout built from what the recording logs.

A ``Review`` is a recording being written. Whatever logs into it (``log_record`` here, the rig in 3D in
``review_rig``, a drive iteration in ``review_iteration``, a diagnosis in ``review_diagnosis``) goes through
its ``series`` / ``static`` / ``send`` / ``image`` methods, which note each entity path, and adds the views
that show it to a tab. When the recording closes, the overview (a markdown text: what was run and the result)
is written and the default layout is sent: the overview (and the rig in 3D, when logged) on the left, the tabs
on the right, each view only when its query selects a logged entity. Everything is logged columnar (one
``send_columns`` per entity and run) and every series keeps its peaks (min/max aggregation when a pixel holds
several samples).

Timelines: ``time`` (duration, s; the recording opens on it) and, for a drive iteration, ``iteration``
(sequence). Plots against anything but time (FRFs, order spectra, force laws, convergence) are images: the
time-series view draws only linear axes against a timeline.

Entity paths: ``overview``; ``run/<corner>/<quantity>`` (a run's record, in the units of
``rig.report.style.DISPLAY_UNITS``: mm, m/s², m/s, kN); ``target/<corner>/<quantity>`` (a reference
record, grey); the rig under ``rig/`` (``review_rig``); ``iterate/...`` and ``diagnosis/...`` (their modules).
"""

from __future__ import annotations

import contextlib
import io
import os
import sys
import warnings
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import rerun as rr
import rerun.blueprint as rrb

from rig.io.atomic import atomic_path
from rig.io.channels import CORNERS, channel, split_channel
from rig.io.record import Record
from rig.report.style import REFERENCE_COLOR, Color, channel_color, display_unit, tint

APPLICATION_ID = "virtual_four_poster"
VIEWER_WAIT = 15.0  # s: at most this long for a spawned viewer to take a recording
#: Line widths (points): the quantity a panel is about, a command beside it (the drive), a reference on top.
LINE_WIDTH, COMMAND_WIDTH, REFERENCE_WIDTH = 2.0, 1.0, 1.0
_EVERYTHING = rrb.TimeRangeBoundary.infinite()


# ---- views, kept only when they show something ------------------------------------------------------------
def _selects(query: str, logged: set[str]) -> bool:
    """Whether a view's ``query`` (an entity path, ``path/**`` for it and everything below) selects a logged
    entity."""
    if query.endswith("/**"):
        base = query.removesuffix("/**")
        return any(e == base or e.startswith(base + "/") for e in logged)
    return query in logged


@dataclass(frozen=True)
class Plot:
    """A time-series view of ``paths``; ``notes`` (path, words) add words to the title when that path is
    logged (so that a title never promises a line that is not there)."""

    name: str
    paths: tuple[str, ...]
    notes: tuple[tuple[str, str], ...] = ()
    legend: bool = True

    def view(self, logged: set[str]) -> rrb.View | None:
        paths = [p for p in self.paths if _selects(p, logged)]
        if not paths:
            return None
        name = "; ".join([self.name, *(words for path, words in self.notes if _selects(path, logged))])
        return rrb.TimeSeriesView(
            name=name, origin="/", contents=[f"+ {p}" for p in paths],
            time_ranges=[rrb.VisibleTimeRange(t, start=_EVERYTHING, end=_EVERYTHING) for t in ("time", "iteration")],
            axis_x=rrb.TimeAxis(link="Independent", view_range=rr.TimeRange(start=_EVERYTHING, end=_EVERYTHING)),
            plot_legend=rrb.PlotLegend("LeftTop" if self.legend else None, visible=self.legend))


@dataclass(frozen=True)
class Picture:
    """An image (a plot drawn as a PNG) or a markdown text at ``path``."""

    name: str
    path: str
    text: bool = False

    def view(self, logged: set[str]) -> rrb.View | None:
        if self.path not in logged:
            return None
        kind = rrb.TextDocumentView if self.text else rrb.Spatial2DView
        return kind(origin=self.path, contents=[f"+ {self.path}"], name=self.name)


@dataclass
class Tab:
    """Views in rows of ``columns`` (a last, shorter row is drawn wider: no empty cell)."""

    name: str
    views: list[Plot | Picture] = field(default_factory=list)
    columns: int = 2
    shares: tuple[float, ...] | None = None  # row heights, when given

    def container(self, logged: set[str]) -> rrb.Container | rrb.View | None:
        views = [v for v in (spec.view(logged) for spec in self.views) if v is not None]
        if not views:
            return None
        rows = [views[i:i + self.columns] for i in range(0, len(views), self.columns)]
        cells = [row[0] if len(row) == 1 else rrb.Horizontal(*row) for row in rows]
        shares = self.shares if self.shares is not None and len(self.shares) == len(cells) else None
        return rrb.Vertical(*cells, name=self.name, row_shares=shares)


# ---- the recording ------------------------------------------------------------------------------------------
class Review:
    """A recording being written: the stream, the entities logged, the tabs that show them and the overview
    (``title``; ``ran``: what was run; ``results``: what came out, markdown lines)."""

    def __init__(self, stream: rr.RecordingStream, title: str = "run"):
        self.stream, self.title = stream, title
        self.logged: set[str] = set()
        self.tabs: dict[str, Tab] = {}
        self.headline = ""
        self.ran: list[str] = []
        self.results: list[str] = []
        self.scene = "Rig (3D)"

    # logging: every entity goes through these
    def static(self, path: str, archetype) -> None:
        self.stream.log(path, archetype, static=True)
        self.logged.add(path)

    def send(self, path: str, indexes: list[rr.TimeColumn], columns) -> None:
        self.stream.send_columns(path, indexes=indexes, columns=columns)
        self.logged.add(path)

    def series(self, path: str, index: rr.TimeColumn, values: np.ndarray | Sequence[float], names: str | list[str],
               colors: Color | Sequence[Color | tuple[int, int, int, int]], widths: float | list[float]) -> None:
        """Scalar series: their style (static; min/max aggregation keeps the peaks) and all samples in one send.
        ``values``: one series (samples) or several (samples x series, one name, colour, width each)."""
        self.static(path, rr.SeriesLines(names=names, colors=colors, widths=widths, aggregation_policy="MinMax"))
        self.send(path, [index], rr.Scalars.columns(scalars=np.asarray(values, float)))

    def image(self, path: str, figure) -> None:
        """A matplotlib figure as a PNG image (static: shown on every timeline), laid out as the report's files are;
        the figure is closed."""
        import matplotlib.pyplot as plt

        from rig.report.plots import lay_out

        lay_out(figure)
        buffer = io.BytesIO()
        figure.savefig(buffer, format="png", dpi=100)
        plt.close(figure)
        self.static(path, rr.EncodedImage(contents=buffer.getvalue(), media_type="image/png"))

    def text(self, path: str, markdown: str) -> None:
        self.static(path, rr.TextDocument(markdown, media_type="text/markdown"))

    # layout
    def tab(self, name: str, views: Sequence[Plot | Picture], columns: int = 2,
            shares: tuple[float, ...] | None = None) -> None:
        """Add ``views`` to the tab ``name`` (tabs open in the order they were first named)."""
        tab = self.tabs.setdefault(name, Tab(name, columns=columns, shares=shares))
        tab.views.extend(views)

    def overview(self) -> str:
        """The overview's markdown: title, headline (the result in one line), what was run, the result."""
        lines = [f"# {self.title}", ""]
        if self.headline:
            lines += [f"**{self.headline}**", ""]
        if self.results:
            lines += ["## Result", "", *self.results, ""]
        if self.ran:
            lines += ["## What was run", "", *self.ran, ""]
        return "\n".join(lines)

    def blueprint(self) -> rrb.Blueprint:
        """The default layout: the overview (and the rig in 3D, when logged) on the left; on the right the tabs,
        each with the views whose queries select logged entities."""
        left: list[rrb.View] = [rrb.TextDocumentView(origin="overview", contents=["+ overview"], name="Overview")]
        if _selects("rig/**", self.logged):
            left.append(rrb.Spatial3DView(origin="rig", name=self.scene, eye_controls=rrb.EyeControls3D(
                position=(2.8, -3.8, 1.6), look_target=(-0.3, 0.0, 0.35), eye_up=(0.0, 0.0, 1.0))))
        tabs = [c for c in (tab.container(self.logged) for tab in self.tabs.values()) if c is not None]
        layout = rrb.Vertical(*left, row_shares=(3, 2)) if len(left) > 1 else left[0]  # the result first
        if tabs:
            layout = rrb.Horizontal(layout, rrb.Tabs(*tabs), column_shares=(2, 3))
        return rrb.Blueprint(layout, rrb.BlueprintPanel(state="collapsed"), rrb.SelectionPanel(state="collapsed"),
                             rrb.TimePanel(timeline="time", state="collapsed"))

    def close(self) -> None:
        """Write the overview and send the default layout (made active: a recording opens in its own)."""
        self.text("overview", self.overview())
        self.stream.send_blueprint(self.blueprint(), make_active=True, make_default=True)


def open_review(path: str | os.PathLike | None, spawn: bool = False, title: str = "run",
                application_id: str = APPLICATION_ID) -> Review:
    """A review that saves to ``path`` (.rrd) and/or streams to a spawned viewer; ``close_review`` ends it."""
    if path is None and not spawn:
        raise ValueError("a recording needs a file path, a spawned viewer or both")
    stream = rr.RecordingStream(application_id)
    if spawn:  # the viewer ships with rerun-sdk, beside this Python even when its environment is not activated
        beside = Path(sys.executable).with_name("rerun")
        rr.spawn(connect=path is None, executable_path=str(beside) if beside.is_file() else None, recording=stream)
    if path is not None:
        stream.set_sinks(*((rr.GrpcSink(),) if spawn else ()), rr.FileSink(str(path)))
    return Review(stream, title)


def close_review(review: Review, wait: float | None = None) -> None:
    """Write the overview and layout, flush everything and close the sinks (a saved file is complete only
    after this). ``wait`` (s) bounds the wait for a spawned viewer: one that cannot be reached gets a warning."""
    stream = review.stream
    try:
        review.close()
        stream.flush(timeout_sec=1e38 if wait is None else wait)  # 1e38: rerun's "no timeout"
    except RuntimeError as err:
        warnings.warn(f"the Rerun viewer did not get the recording: {err}", stacklevel=2)
    finally:
        stream.disconnect()


@contextlib.contextmanager
def recording(path: str | os.PathLike | None, spawn: bool = False, title: str = "run") -> Iterator[Review]:
    """``open_review`` as a context: the .rrd file appears complete at ``path`` or not at all."""
    with contextlib.ExitStack() as stack:
        review = open_review(None if path is None else stack.enter_context(atomic_path(path)), spawn, title)
        try:
            yield review
        finally:
            close_review(review, VIEWER_WAIT if spawn else None)


# ---- records ---------------------------------------------------------------------------------------------------
#: Panels of a corner tab: (title, quantities in the panel; the first one sets the unit).
CORNER_PANELS = (
    ("body acceleration", ("sprung_acc",)),
    ("wheel acceleration", ("unsprung_acc",)),
    ("post or road", ("actuator_disp", "drive", "road")),
    ("travel, compr. +", ("susp_travel",)),
    ("susp. velocity, compr. +", ("susp_velocity",)),
    ("tyre force", ("tyre_force",)),
    ("post force", ("actuator_force",)),
    ("controller force", ("control_force",)),
)
#: Words a panel's title gets for a line that is logged (its entity's quantity, or the prefix of a record beside
#: the run's).
LINE_NOTES = {"drive": "drive light, thin", "road": "road grey", "target": "target grey, thin, on top",
              "before": "the baseline model's drive light, thin", "without_controller": "passive grey, thin, on top"}
#: Records a corner tab puts beside the run's, by prefix. The viewer draws a panel's entities in the order of
#: their paths: ``before`` under the run, the references (``target``, ``without_controller``) over it.
BESIDE = ("before", "target", "without_controller")


def series_style(name: str, reference: bool = False, faint: bool = False) -> tuple[Color, float]:
    """Colour and width of channel ``name``: its corner's colour; a command (the drive), or any channel of a
    ``faint`` record (a run to compare with), in a light tint of it, thin; a reference (the road, or any channel
    of a ``reference`` record) grey and thin."""
    quantity = split_channel(name)[1]
    if reference or quantity == "road":
        return REFERENCE_COLOR, REFERENCE_WIDTH
    if quantity == "drive" or faint:
        return tint(channel_color(name)), COMMAND_WIDTH
    return channel_color(name), LINE_WIDTH


def display(name: str, values: np.ndarray) -> tuple[np.ndarray, str]:
    """A channel's values in the unit it is read in, and that unit."""
    unit, scale = display_unit(split_channel(name)[1])
    return np.asarray(values, float) * scale, unit


def log_record(review: Review, record: Record, prefix: str = "run", reference: bool = False,
               label: str = "", faint: bool = False) -> None:
    """Every channel of ``record`` as the series ``<prefix>/<corner>/<quantity>`` on ``time`` (s), in the unit
    it is read in (``display``), named ``<label> <name> [unit]``, styled by ``series_style``."""
    time = rr.TimeColumn("time", duration=record.time)
    for name, values in record.channels.items():
        shown, unit = display(name, values)
        review.series(f"{prefix}/{name}", time, shown, f"{label} {name} [{unit}]".strip(),
                      *series_style(name, reference, faint))


def corner_tabs(review: Review, corners: Sequence[str] = CORNERS, prefix: str = "run",
                references: Sequence[str] = BESIDE) -> None:
    """One tab per corner: a panel per quantity of ``CORNER_PANELS`` with ``<prefix>/<corner>/<quantity>``
    and the lines of the records beside it (``<reference>/<corner>/<quantity>``, where logged)."""
    for corner in corners:
        views = []
        for title, quantities in CORNER_PANELS:
            unit = display_unit(quantities[0])[0]
            paths = [f"{p}/{channel(corner, q)}" for q in quantities for p in (prefix, *references)]
            notes = [(f"{prefix}/{channel(corner, q)}", LINE_NOTES[q]) for q in quantities if q in LINE_NOTES]
            notes += [(f"{r}/{channel(corner, q)}", LINE_NOTES.get(r, f"{r} grey"))
                      for r in references for q in quantities]
            views.append(Plot(f"{corner} {title} ({unit})", tuple(paths), tuple(dict.fromkeys(notes))))
        review.tab(corner, views, columns=3)


def what_ran(command: str, options: dict[str, object]) -> list[str]:
    """Markdown lines: the command and its options (those given or defaulted, not the empty ones)."""
    shown = {k: v for k, v in options.items() if v not in (None, False, [], ())}
    return [f"`rig {command}`", "", "| option | value |", "|---|---|",
            *(f"| --{k.replace('_', '-')} | {' '.join(map(str, v)) if isinstance(v, list) else v} |"
              for k, v in shown.items())]


def peaks_line(record: Record, quantities: Sequence[str] = ("sprung_acc", "unsprung_acc", "susp_travel")) -> list[str]:
    """Markdown table: the peak (largest magnitude, signed) and RMS of ``quantities`` per corner, in display
    units: what the plots must show."""
    lines = ["| channel | peak | RMS |", "|---|---|---|"]
    for name in (channel(c, q) for c in record.corners_with(quantities[0]) for q in quantities):
        if name in record:
            values, unit = display(name, record[name])
            peak = values[np.argmax(np.abs(values))]
            lines.append(f"| {name} | {peak:+.4g} {unit} | {np.sqrt(np.mean(values**2)):.4g} {unit} |")
    return lines
