"""Rerun review of K&C work (docs/review.md): a K&C test (``rig kc --rerun``) and a diagnosis on K&C records
(``rig diagnose --rerun`` on ``# test: kc`` records).

A K&C test: the car on the K&C rig in 3D stepping through the sweep (the ``time`` line runs one POINT_PERIOD per
sweep point: a K&C test is a sequence of static equilibria, not a motion in time), each corner's curves on the same
line (``kc/<corner>/<quantity>`` in deg or mm) and the test's plot against its sweep as an image (``kc/plot``). A
diagnosis: per record the measured curves against the vehicle file's and the extended model's (an image each,
``kc_diagnosis/<k>_<test>``), and the verdict, moved coordinates, aliases and rates in the overview. They take the
finished results and never simulate.
"""

from __future__ import annotations

import mujoco
import numpy as np
import rerun as rr

from rig.diagnosis.kc.kinematic_diagnosis import KcDiagnosis
from rig.io.kc_record import KcResult
from rig.report.kc_plots import PANELS, plot_kc, plot_kc_comparison
from rig.report.review import LINE_WIDTH, Picture, Plot, Review
from rig.report.review_rig import log_rig
from rig.report.style import channel_color

POINT_PERIOD = 1.0  # s of the time line per sweep point
CURVES = ("camber", "toe", "track_change", "caster", "kingpin", "wheel_load", "motion_ratio",
          "compliance_steer", "compliance_camber")


def log_kc_test(review: Review, model: mujoco.MjModel, result: KcResult, magnification: float = 1.0) -> None:
    """A K&C test: the rig in 3D at each sweep point (``result.states`` of ``model``, the K&C rig's), the curves on
    the time line, the plot as an image, and the sweep in the overview."""
    time = np.arange(result.sweep.size) * POINT_PERIOD
    if result.states is not None:
        log_rig(review, model, result.states, time, magnification=magnification)
    index = rr.TimeColumn("time", duration=time)
    views = []
    for quantity in (q for q in CURVES if any(f"{c}/{q}" in result.curves for c in result.corners)):
        label, factor = PANELS[quantity]
        paths = []
        for corner in result.corners:
            name = f"{corner}/{quantity}"
            if name in result.curves:
                review.series(f"kc/{name}", index, result.curves[name] * factor, f"{name} {label}",
                              channel_color(name), LINE_WIDTH)
                paths.append(f"kc/{name}")
        views.append(Plot(label, tuple(paths)))
    review.tab("K&C curves", views, columns=3)
    review.image("kc/plot", plot_kc(result))
    review.tab("K&C plot", [Picture(f"{result.vehicle}: {result.test} test", "kc/plot")], columns=1)
    unit = {"travel": "mm", "rack": "mm", "roll": "deg", "force": "N", "moment": "N m"}[result.sweep_name]
    scale = {"mm": 1e3, "deg": 180 / np.pi}.get(unit, 1.0)
    review.headline = (f"{result.vehicle}: K&C {result.test} test, {result.sweep_name} "
                       f"{result.sweep[0] * scale:+.4g} to {result.sweep[-1] * scale:+.4g} {unit} in "
                       f"{result.sweep.size} points")
    review.results += [f"- time line: one sweep point per {POINT_PERIOD:g} s (static equilibria, not a motion)",
                       *_range_lines(result)]
    review.scene = "K&C rig (3D)" if magnification == 1.0 else review.scene


def _range_lines(result: KcResult) -> list[str]:
    lines = ["", "| curve | from | to |", "|---|---|---|"]
    for corner in result.corners:
        for quantity in ("camber", "toe"):
            name = f"{corner}/{quantity}"
            if name in result.curves:
                values = np.degrees(result.curves[name])
                lines.append(f"| {name} [deg] | {values.min():+.3f} | {values.max():+.3f} |")
    return lines


def log_kc_diagnosis(review: Review, diagnosis: KcDiagnosis) -> None:
    """A diagnosis on K&C records: measured against the model per record (images) and the findings (overview)."""
    pictures = []
    for k, (record, before, after) in enumerate(zip(diagnosis.records, diagnosis.before, diagnosis.after)):
        path = f"kc_diagnosis/{k + 1}_{record.test}"
        review.image(path, plot_kc_comparison(record, before, after))
        pictures.append(Picture(f"{record.test}: measured, vehicle file (dashed), extended", path))
    review.tab("K&C records against the model", pictures, columns=1)
    review.headline = f"verdict: {diagnosis.verdict}"
    review.results += _finding_lines(diagnosis)


def _finding_lines(diagnosis: KcDiagnosis) -> list[str]:
    lines = []
    hardpoints = diagnosis.hardpoints
    if hardpoints is not None:
        fit = hardpoints.fit
        scope = "per corner" if hardpoints.per_corner else "both corners of an axle alike"
        lines += [f"Hardpoints ({scope}), p {hardpoints.significance.p_value:.3g}:", ""]
        lines += [f"- {c.name} {(f - n) * 1e3:+.2f} mm +- {i * 1e3:.2f}" for c, n, f, i in
                  zip(fit.free, fit.nominal, fit.fitted, fit.interval) if c.name in hardpoints.moved]
        lines += [f"- {a.sentence()}" for a in hardpoints.aliases] + [""]
    bushings = diagnosis.bushings
    if bushings is not None:
        lines += [f"Bushings, p {bushings.significance.p_value:.3g}:", ""]
        lines += [f"- {r.name} {n:.4g} -> {v:.4g} {r.unit}" for r, n, v in
                  zip(bushings.fit.free, bushings.fit.nominal, bushings.fit.fitted) if r.name in bushings.moved]
        lines += [""]
    return lines
