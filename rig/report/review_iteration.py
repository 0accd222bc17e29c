"""Rerun review of a drive iteration (``rig iterate``): did it reach the target error, and how.

Overview: the stop reason, the best iteration's worst-channel error against the target error (met or missed)
and every channel's error. Tabs: *Convergence* (an image: RMS error per channel and iteration on a log axis with
the target error as a dashed line and the worst channel ringed, and the gain; a table of every iteration),
one *<corner> target vs achieved* tab per corner (each iterated channel: the achieved response of every
iteration, wide, faint = early, under the target, thin and grey; their difference; the drive of every
iteration), *FRF* (images, one per corner: |H1| in dB re 1 output unit per m of drive, phase and multiple
coherence against frequency in Hz on a log axis over the analysis band), and the best drive replayed, per
corner. The metrics are also logged against the ``iteration`` timeline (RMS error per channel with the target
error and the worst channel as dots, log10 TDDI, damage ratio, the summary of each iteration), for a view a
user adds; the default layout leaves them out, as it opens on ``time``.

Entity paths: ``iterate/target/<name>``, ``iterate/response/<name>``, ``iterate/error/<name>`` (target minus
response), ``iterate/drive/<corner>`` on ``time`` (display units, one series per iteration);
``iterate/rms_error_pct/<name>``, ``iterate/log10_tddi/<name>``, ``iterate/damage_ratio/<name>``,
``iterate/worst_rms_error_pct``, ``iterate/target_error_pct``, ``iterate/gain`` and ``iterate/summary`` on
``iteration``; static images ``iterate/convergence/plot``, ``iterate/frf/<corner>`` and the text
``iterate/convergence/table``; the best drive's replay under ``run/`` and ``rig/``, the target record's post
motion under ``target/``.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import rerun as rr

from rig.io.channels import CORNERS, channel, split_channel
from rig.io.record import Record
from rig.report.plots import plot_convergence, plot_frf
from rig.report.review import REFERENCE_WIDTH, Picture, Plot, Review, display, log_record
from rig.report.review_runs import log_run
from rig.report.style import REFERENCE_COLOR, Color, channel_color, corner_color, display_unit

RESPONSE_WIDTH = 3.0  # the achieved response: wide, under the thin target
TDDI_FLOOR = 1e-12    # log10 TDDI of identical signals: far below any noise floor
QUANTITY_WIDTHS = {"sprung_acc": 2.5, "unsprung_acc": 1.0}  # metric lines: sprung thick, unsprung thin


def _faded(color: Color, share: float) -> tuple[int, int, int, int]:
    """``color`` with an opacity from a quarter (``share`` 0: the first iteration) to full (1: the last)."""
    return (*color, round(255 * (0.25 + 0.75 * share)))


def _metric(entry, name: str, key: str) -> float:
    """A channel's metric in an iteration's record (``IterationRecord``), NaN where it was not computed."""
    return float(getattr(entry.channels[name], key))


def _summary(entry) -> str:
    """One iteration as a markdown table (three significant figures: TDDI near the noise floor is 1e-4)."""
    lines = [f"### Iteration {entry.iteration}: gain {entry.gain:.3g}, worst channel {entry.worst_rms_error_pct:.3g} "
             "% RMS error", "", "| channel | RMS error (%) | TDDI | damage ratio |", "|---|---|---|---|"]
    lines += [f"| {name} | {_metric(entry, name, 'rms_error_pct'):.3g} | {_metric(entry, name, 'tddi'):.3g} | "
              f"{_metric(entry, name, 'damage_ratio'):.3g} |" for name in entry.channels]
    return "\n".join([*lines, "", "Limit hits: " + ("; ".join(entry.limit_hits) or "none")])


def _convergence_table(history: Sequence) -> str:
    """Every iteration in one markdown table: gain, worst-channel and total error, worst and mean TDDI."""
    lines = ["| iteration | gain | worst RMS error (%) | total error (%) | worst TDDI | mean TDDI |",
             "|---|---|---|---|---|---|"]
    for entry in history:
        tddi = [_metric(entry, name, "tddi") for name in entry.channels]
        lines.append(f"| {entry.iteration} | {entry.gain:.3g} | {entry.worst_rms_error_pct:.3g} | "
                     f"{entry.total_error_pct:.3g} | {np.nanmax(tddi):.3g} | {np.nanmean(tddi):.3g} |")
    return "\n".join(lines)


def log_time_series(review: Review, history: Sequence, target: np.ndarray, responses: Sequence[np.ndarray],
                    rate: float, channels: Sequence[str], drives: Sequence[np.ndarray] = (),
                    corners: Sequence[str] = CORNERS, start_time: float = 0.0) -> None:
    """Target, every played iteration's response and error (target - response) per channel, and every drive
    per corner, on ``time`` (``start_time`` s + sample / ``rate``), in display units, with a tab per corner.
    ``responses`` and ``drives`` (SI) belong to the last ``len(responses)`` / ``len(drives)`` entries of
    ``history`` (all of them unless the run was resumed)."""
    time = rr.TimeColumn("time", duration=start_time + np.arange(target.shape[0]) / rate)
    last = max(history[-1].iteration, 1)

    def styles(count: int, color: Color, width: float) -> tuple[list[str], list, list[float]]:
        entries = history[len(history) - count:]
        return ([f"iteration {e.iteration}" for e in entries], [_faded(color, e.iteration / last) for e in entries],
                [width] * count)

    for j, name in enumerate(channels):
        shown, unit = display(name, target[:, j])
        review.series(f"iterate/target/{name}", time, shown, "target", REFERENCE_COLOR, REFERENCE_WIDTH)
        if responses:
            response = display(name, np.stack([r[:, j] for r in responses], axis=1))[0]  # samples x iterations
            review.series(f"iterate/response/{name}", time, response,
                          *styles(len(responses), channel_color(name), RESPONSE_WIDTH))
            review.series(f"iterate/error/{name}", time, shown[:, None] - response,
                          *styles(len(responses), channel_color(name), 1.5))
    for i, corner in enumerate(corners if drives else ()):
        review.series(f"iterate/drive/{corner}", time, display(channel(corner, "drive"),
                                                                 np.stack([d[:, i] for d in drives], axis=1))[0],
                      *styles(len(drives), corner_color(corner), 1.5))
    for corner in corners:
        views = []
        for name in (n for n in channels if split_channel(n)[0] == corner):
            unit = display_unit(split_channel(name)[1])[0]
            views += [Plot(f"{name} ({unit}): achieved per iteration, wide (faint = early); target grey, thin, on top",
                           (f"iterate/response/{name}", f"iterate/target/{name}"), legend=False),
                      Plot(f"{name} error, target − achieved ({unit}), per iteration", (f"iterate/error/{name}",),
                           legend=False)]
        views.append(Plot(f"{corner} drive per iteration (mm; faint = early)", (f"iterate/drive/{corner}",),
                          legend=False))
        review.tab(f"{corner} target vs achieved", views)


def log_metrics(review: Review, history: Sequence, target_error_pct: float) -> None:
    """Per-iteration metrics on the ``iteration`` timeline (see the module docstring). The default layout
    leaves them out: a view shows the timeline the time panel is on, and the recording opens on ``time``,
    where they would be empty; the *Convergence* image shows them on every timeline."""
    numbers = [entry.iteration for entry in history]
    iteration = rr.TimeColumn("iteration", sequence=numbers)
    names = list(history[0].channels)
    for name in names:
        color, width = channel_color(name), QUANTITY_WIDTHS.get(split_channel(name)[1], 1.5)
        review.series(f"iterate/rms_error_pct/{name}", iteration, [_metric(e, name, "rms_error_pct") for e in history],
                      name, color, width)
        tddi = np.array([_metric(e, name, "tddi") for e in history])
        review.series(f"iterate/log10_tddi/{name}", iteration, np.log10(np.maximum(tddi, TDDI_FLOOR)), name, color,
                      width)
        review.series(f"iterate/damage_ratio/{name}", iteration, [_metric(e, name, "damage_ratio") for e in history],
                      name, color, width)
    review.series("iterate/target_error_pct", iteration, np.full(len(numbers), target_error_pct),
                  f"target error {target_error_pct:g} %", REFERENCE_COLOR, 1.5)
    review.series("iterate/gain", iteration, [e.gain for e in history], "gain", REFERENCE_COLOR, 1.5)
    review.static("iterate/worst_rms_error_pct", rr.SeriesPoints(names="worst channel", colors=REFERENCE_COLOR,
                                                                 markers="circle", marker_sizes=6.0))
    review.send("iterate/worst_rms_error_pct", [iteration],
                rr.Scalars.columns(scalars=[e.worst_rms_error_pct for e in history]))
    review.send("iterate/summary", [iteration], rr.TextDocument.columns(
        text=[_summary(e) for e in history], media_type=["text/markdown"] * len(history)))


def _verdict(result, target_error_pct: float) -> str:
    best = result.best
    met = "met" if best.worst_rms_error_pct <= target_error_pct else "missed"
    return (f"{result.stop_reason}: best iteration {best.iteration}, worst channel {best.worst_rms_error_pct:.3g} % "
            f"RMS error against a target of {target_error_pct:g} % ({met})")


def log_drive_iteration(review: Review, result, plays, target: np.ndarray, start_time: float,
                        channels: Sequence[str], settings, reference: Record | None = None,
                        magnification: float = 1.0) -> None:
    """A finished drive iteration (``controllers.rpc.IterationResult``) with its ``settings``
    (``IterationSettings``): the overview, the iterations played now (``plays``, an ``IterationLog``) against
    the edited ``target`` (samples x channels, SI, from ``start_time`` s), the metrics of every iteration, the
    FRF it ended with, and the best drive on the rig; ``reference``, the target record as read, gives the post
    motion the target was recorded with (``target/<corner>/actuator_disp``, else ``road``, grey)."""
    history, replay = result.history, result.replay
    corners = replay.record.corners_with("drive")
    review.headline = _verdict(result, settings.target_error_pct)
    best = result.best
    review.results += ["| channel (best iteration) | RMS error (%) | TDDI | damage ratio |", "|---|---|---|---|",
                       *(f"| {n} | {_metric(best, n, 'rms_error_pct'):.3g} | {_metric(best, n, 'tddi'):.3g} | "
                         f"{_metric(best, n, 'damage_ratio'):.3g} |" for n in best.channels),
                       "", "Limit hits: " + ("; ".join(best.limit_hits) or "none")]
    review.image("iterate/convergence/plot", plot_convergence(history, settings.target_error_pct,
                                                              review.headline, "drive iteration"))
    review.text("iterate/convergence/table", _convergence_table(history))
    review.tab("Convergence", [Picture("RMS error per channel and iteration, target error dashed, worst ringed",
                                       "iterate/convergence/plot"),
                               Picture("Every iteration", "iterate/convergence/table", text=True)],
               columns=1, shares=(3, 2))
    log_time_series(review, history, target, plays.responses, replay.record.rate, channels, plays.drives, corners,
                    start_time)
    frf, band = result.frf, settings.band
    inputs = [channel(c, "drive") for c in corners]
    for corner in dict.fromkeys(split_channel(n)[0] for n in channels):
        mine = [j for j, n in enumerate(channels) if split_channel(n)[0] == corner]
        figure = plot_frf(frf.frequency, frf.h1[:, mine], frf.coherence[:, mine], inputs, [channels[j] for j in mine],
                          band, f"{corner}: the FRF the iteration ended with")
        review.image(f"iterate/frf/{corner}", figure)
    review.tab("FRF", [Picture(f"{c}: |H1| (dB re 1 unit/m), phase, coherence; Hz, log",
                               f"iterate/frf/{c}") for c in dict.fromkeys(split_channel(n)[0] for n in channels)])
    log_metrics(review, history, settings.target_error_pct)
    if reference is not None:
        posts = [next((channel(c, q) for q in ("actuator_disp", "road") if channel(c, q) in reference), None)
                 for c in corners]
        log_record(review, reference.select([n for n in posts if n is not None]), "target", reference=True,
                   label="target")
    log_run(review, replay.record, replay.model, replay.qpos, magnification, still_on=("iteration",))


class IterationLog:
    """Every drive a drive iteration plays (samples x corners, m) and its band-passed response (samples x
    channels, SI): pass it as ``callback`` to ``DriveIteration.run`` (it reads ``step.drive`` and
    ``step.response``), then to ``log_drive_iteration``."""

    def __init__(self) -> None:
        self.drives: list[np.ndarray] = []
        self.responses: list[np.ndarray] = []

    def __call__(self, step) -> None:
        self.drives.append(np.array(step.drive, float))
        self.responses.append(step.response)
