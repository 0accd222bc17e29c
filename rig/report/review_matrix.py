"""Rerun review of a test matrix (``rig track`` over roads x speeds with repeats): per case a tab with, for each
compared channel, the repeats' band (their lowest and highest value at each sample, grey) and the model's run in the
channel's colour, the panel's title saying the verdict; the verdict chart; the overview's table of verdicts."""

from __future__ import annotations

import numpy as np
import rerun as rr

from rig.diagnosis.track.test_matrix import MatrixResult
from rig.report.matrix_report import plot_verdicts
from rig.report.review import LINE_WIDTH, REFERENCE_WIDTH, Picture, Plot, Review, display
from rig.report.style import REFERENCE_COLOR, channel_color

PANELS_PER_CASE = 12  # the channels of a case shown, furthest beyond their scatter first


def present_matrix(review: Review, result: MatrixResult) -> None:
    """The matrix's cases (a tab each), the verdict chart and the overview's result."""
    review.image("matrix/verdicts", plot_verdicts(result))
    review.tab("Verdicts", [Picture("model TDDI against the repeats' scatter, per channel", "matrix/verdicts")],
               columns=1)
    for number, case in enumerate(result.cases, 1):
        time = rr.TimeColumn("time", duration=np.arange(case.model.shape[0]) / case.rate)
        order = sorted(case.names, key=lambda n: -case.channels[n].model / max(case.channels[n].scatter, 1e-300))
        views = []
        for name in order[:PANELS_PER_CASE]:
            k = case.names.index(name)
            path = f"matrix/case_{number}/{name}"
            band, unit = display(name, np.column_stack([case.low[:, k], case.high[:, k]]))
            review.series(f"{path}/band", time, band, ["repeats' lowest", "repeats' highest"],
                          [REFERENCE_COLOR, REFERENCE_COLOR], [REFERENCE_WIDTH, REFERENCE_WIDTH])
            review.series(f"{path}/model", time, display(name, case.model[:, k])[0], "model", channel_color(name),
                          LINE_WIDTH)
            score = case.channels[name]
            verdict = "inside" if score.inside else "OUTSIDE"
            views.append(Plot(f"{name} [{unit}]: model {verdict} ({score.model:.3g} vs scatter {score.scatter:.3g})",
                              (f"{path}/band", f"{path}/model")))
        review.tab(f"case {number}", views, columns=3)
    outside = sum(len(c.outside) for c in result.cases)
    review.headline = (f"{result.vehicle} over {len(result.cases)} case(s) against the scatter of their repeats "
                       f"({result.repeats_of}): {outside} channel(s) outside")
    review.results += ["| case | road and speed | repeats | channels outside the scatter |", "|---|---|---|---|",
                       *(f"| {i} | {c.label} | {c.repeats.shape[0]} | {', '.join(c.outside) or 'none'} |"
                         for i, c in enumerate(result.cases, 1))]
