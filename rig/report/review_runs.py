"""Rerun review of runs: a replay, a track run, a controlled run, the demo's replay. Each logs the run's record
(``run/...``, one tab per corner), the rig in 3D when the run carries joint positions, and the overview's
result: what came out (limits hit, tyres in the air, peaks, ride metrics)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from rig.io.channels import sort_corners, split_channel
from rig.io.record import Record
from rig.report.review import Review, corner_tabs, log_record, peaks_line
from rig.report.review_rig import log_rig, post_heights
from rig.sim.replay import ReplayResult


def log_run(review: Review, record: Record, model=None, qpos: np.ndarray | None = None, magnification: float = 1.0,
            still_on: Sequence[str] = ()) -> None:
    """A run's record under ``run/`` with a tab per corner, and the rig in 3D when ``model`` and ``qpos`` are
    given (``log_rig``; ideal posts stand at the record's post or road height)."""
    log_record(review, record)
    corner_tabs(review, corners_of(record))
    if model is not None and qpos is not None:
        log_rig(review, model, qpos, record.time, still_on=still_on, magnification=magnification,
                heights=post_heights(model, record))


def corners_of(record: Record) -> list[str]:
    """The corners ``record`` has channels of, in the contract's order (any layout's; not ``cab/``, ``damper/``)."""
    return sort_corners(split_channel(n)[0] for n in record.names)


def _airborne(result: ReplayResult) -> str:
    airborne = {c: t for c, t in result.airborne_time().items() if t > 0}
    return ("tyres in the air: " + ", ".join(f"{c} {t:.3f} s" for c, t in airborne.items())) if airborne \
        else "every tyre stayed on the ground"


def present_replay(review: Review, result: ReplayResult, magnification: float = 1.0) -> None:
    """A replay (``rig replay``, ``rig demo --quick``): the run and its result (limits, airborne, peaks)."""
    record = result.record
    log_run(review, record, result.model, result.qpos, magnification)
    hits = [hit.describe() for hit in result.limit_hits]
    review.headline = (f"replayed {record.duration:.1f} s at {record.rate:g} Hz on {record.metadata.get('posts', '')} "
                       f"posts: " + ("limits hit" if hits else "within the post limits") + f"; {_airborne(result)}")
    review.results += [*(f"- clipped: {h}" for h in hits), "", *peaks_line(record)]


def present_track(review: Review, result: ReplayResult, road: str, speed: float, comfort: dict[str, float],
                  magnification: float = 1.0) -> None:
    """A track run (``rig track``): the run and its result (road, speed, ISO 2631 comfort, airborne, peaks)."""
    record = result.record
    log_run(review, record, result.model, result.qpos, magnification)
    worst = max(comfort, key=comfort.get)
    review.headline = (f"{record.duration:.1f} s at {speed:g} m/s over {road}: ISO 2631-1 a_w up to "
                       f"{comfort[worst]:.3f} m/s² ({worst.split('/')[0]}); {_airborne(result)}")
    review.results += ["| corner | a_w, body (Wk-weighted RMS) |", "|---|---|",
                       *(f"| {n.split('/')[0]} | {v:.3f} m/s² |" for n, v in comfort.items()), "",
                       *peaks_line(record)]


#: A controlled run's metrics as the overview states them: (key, words, unit, factor from SI, format).
CONTROL_METRICS = (("a_w", "a_w, ISO 2631-1 Wk-weighted RMS body acceleration", "m/s²", 1.0, ".3f"),
                   ("tyre_load_rms", "dynamic tyre load RMS / static (worst corner)", "", 1.0, ".3f"),
                   ("travel_rms", "suspension travel RMS (worst corner)", "mm", 1e3, ".2f"),
                   ("power_w", "mean actuator power", "W", 1.0, ".0f"))


def present_control(review: Review, run, spec: str, magnification: float = 1.0,
                    front: dict[str, float | None] | None = None, passive=None) -> None:
    """A controlled run (``rig control``; ``run``: ``rig.envs.policy_run.PolicyRun``): the controller, its ride
    metrics and, with ``front`` (controller -> gain below the passive front), where it stands; ``passive`` (a
    ``PolicyRun`` of the same car and road without the controller) is drawn in grey over the run, and its metrics
    stand beside the controller's."""
    record, metrics = run.record, run.metrics
    if passive is not None:  # its road is the run's: drawn once
        log_record(review, passive.record.select([n for n in passive.record.names if not n.endswith("/road")]),
                   "without_controller", reference=True, label="passive")
    log_run(review, record, run.model, run.qpos, magnification)
    review.headline = (f"{spec}: a_w {metrics['a_w']:.3f} m/s², tyre load RMS {metrics['tyre_load_rms']:.3f} of "
                       f"static, travel RMS {metrics['travel_rms'] * 1e3:.1f} mm, power {metrics['power_w']:.0f} W")
    header = ["| controller metric | " + spec + (" | passive (without the controller) | change |" if passive else " |"),
              "|---|---|" + ("---|---|" if passive else "")]
    review.results += [*header, *(_metric_row(row, metrics, passive) for row in CONTROL_METRICS)]
    if front:
        none = "no passive setting holds the road as well"
        review.results += ["", "| against the passive front | a_w below the front at equal road holding |", "|---|---|",
                           *(f"| {n} | {none if g is None else f'{100 * g:+.1f} %'} |" for n, g in front.items())]
    review.results += ["", *peaks_line(record, ("sprung_acc", "unsprung_acc", "susp_travel", "control_force"))]


def _metric_row(row: tuple, metrics: dict[str, float], passive) -> str:
    key, words, unit, scale, form = row
    value = f"{metrics[key] * scale:{form}} {unit}".strip()
    if passive is None:
        return f"| {words} | {value} |"
    reference = passive.metrics[key]
    change = f"{100 * (metrics[key] / reference - 1):+.1f} %" if reference else ""
    return f"| {words} | {value} | {f'{reference * scale:{form}} {unit}'.strip()} | {change} |"
