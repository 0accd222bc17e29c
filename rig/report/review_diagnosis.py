"""Rerun review of a diagnosis (``rig diagnose``): the named cause and the evidence for it.

Rig test. Overview: the verdict, the held-out TDDI of the baseline, recalibrated and extended models against
the noise floor (and the gain), the ranked causes, where an unexplained residual lives. Tabs: one per corner
with each compared channel's held-out data as measured (grey, thin) and as the baseline, recalibrated
and extended models simulate it (the corner's colour, faint to full), and the residual of the recalibrated and
extended models with the band noise alone would leave (+-2 RMS, grey); *Force laws* (an image: the restoring
force measured from the data against travel and rate, and the tyre's, beside the model's). Track test: the
unbalance per wheel in the overview, the order spectra, unbalance and transmissibility images, and the
measured record per corner.

Entity paths: ``diagnosis/<model>/<corner>/<quantity>`` (model: measured, baseline, recalibrated, extended),
``diagnosis/residual/<model>/<name>``, ``diagnosis/noise_band/<name>`` on ``time`` (display units, held-out
data as compared, 0.5-50 Hz); images ``diagnosis/force_laws``, ``diagnosis/order_spectra``,
``diagnosis/unbalance``, ``diagnosis/transmissibility``; a track test's record under ``run/``.

``DiagnosisShown`` is what the review reads of a diagnosis result, in one place (``shown``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import rerun as rr

from rig.io.channels import split_channel
from rig.io.record import Record
from rig.report.review import REFERENCE_WIDTH, LINE_WIDTH, Picture, Plot, Review, display
from rig.report.review_runs import corners_of, log_run
from rig.report.style import REFERENCE_COLOR, channel_color, display_unit

MODELS = ("baseline", "recalibrated", "extended")  # simulated, faint to full
OPACITY = {"baseline": 90, "recalibrated": 160, "extended": 255}
NOISE_SIGMAS = 2.0


@dataclass(frozen=True)
class Ranked:
    cause: str
    gain: float
    tddi_holdout: float
    params: dict[str, float]


@dataclass(frozen=True)
class DiagnosisShown:
    """What the review shows of a rig diagnosis."""

    verdict: tuple[str, ...]          # cause names; ("none",) or ("unexplained",)
    compared: dict[str, Record]       # held-out data as compared: measured and each model's simulation
    tddi: dict[str, float]            # baseline, recalibrated, extended, noise_floor
    ranking: list[Ranked]             # best first
    unexplained: str                  # where an unexplained residual lives, in words ("" otherwise)
    force_laws: object                # rig.diagnosis.force_laws.ForceLaws
    data_sheet: object                # the vehicle as given


def shown(result) -> DiagnosisShown:
    """The parts of a ``rig.diagnosis.results.Diagnosis`` the review shows."""
    verdict = tuple(str(result.verdict).split("+"))
    where = ""
    if result.unexplained is not None:
        remainder = result.unexplained.where
        band = f" in {remainder.band_hz[0]:.1f}-{remainder.band_hz[1]:.1f} Hz" if remainder.band_hz else ""
        where = (f"{result.unexplained.floor_multiple:.1f} times the noise floor left, on "
                 f"{', '.join(remainder.channels) or 'no single channel'}{band}")
    return DiagnosisShown(
        verdict, dict(result.compared),
        {"baseline": result.baseline_tddi, "recalibrated": result.recalibrated_tddi,
         "extended": result.extended_tddi, "noise_floor": result.noise_floor},
        [Ranked(c.effect, c.gain, c.tddi_holdout, dict(c.params)) for c in result.causes],
        where, result.force_laws, result.data_sheet)


def _force_law_image(review: Review, diagnosis: DiagnosisShown) -> None:
    """The force-law figure of the report, as an image."""
    from rig.report.force_law_report import plot_force_laws

    figure = plot_force_laws(diagnosis.force_laws, diagnosis.data_sheet) if diagnosis.force_laws is not None else None
    if figure is not None:
        review.image("diagnosis/force_laws", figure)


def _overview(review: Review, diagnosis: DiagnosisShown) -> None:
    tddi = diagnosis.tddi
    gain = (tddi["recalibrated"] - tddi["extended"]) / tddi["recalibrated"] if tddi["recalibrated"] > 0 else 0.0
    verdict = " + ".join(diagnosis.verdict)
    review.headline = (f"verdict: {verdict}; held-out TDDI {tddi['recalibrated']:.3g} (recalibrated) -> "
                       f"{tddi['extended']:.3g} (extended), gain {100 * gain:.1f} %; noise floor "
                       f"{tddi['noise_floor']:.3g}")
    review.results += ["| model | held-out TDDI |", "|---|---|",
                       *(f"| {k.replace('_', ' ')} | {v:.4g} |" for k, v in tddi.items())]
    if diagnosis.unexplained:
        review.results += ["", f"Unexplained: {diagnosis.unexplained}."]
    review.results += ["", "| cause (ranked) | gain | held-out TDDI | parameters |", "|---|---|---|---|",
                       *(f"| {'**' + r.cause + '**' if r.cause in diagnosis.verdict else r.cause} | {r.gain:.3f} | "
                         f"{r.tddi_holdout:.4g} | " + ", ".join(f"{k} = {v:.4g}" for k, v in r.params.items()) + " |"
                         for r in diagnosis.ranking[:8])]


def log_diagnosis(review: Review, result) -> None:
    """A rig diagnosis (see the module docstring): the overview, the compared held-out data per corner with the
    residuals and the noise band, and the force laws."""
    diagnosis = shown(result)
    _overview(review, diagnosis)
    measured = diagnosis.compared["measured"]
    time = rr.TimeColumn("time", duration=measured.time)
    models = [m for m in MODELS if m in diagnosis.compared]
    for name in measured.names:
        values, unit = display(name, measured[name])
        color = channel_color(name)
        review.series(f"diagnosis/measured/{name}", time, values, f"measured {name} [{unit}]", REFERENCE_COLOR,
                      REFERENCE_WIDTH)
        for model in models:
            simulated = display(name, diagnosis.compared[model][name])[0]
            review.series(f"diagnosis/{model}/{name}", time, simulated, f"{model} [{unit}]",
                          (*color, OPACITY[model]), LINE_WIDTH)
            if model != "baseline":
                review.series(f"diagnosis/residual/{model}/{name}", time, values - simulated,
                              f"measured - {model} [{unit}]", (*color, OPACITY[model]), LINE_WIDTH)
        noise = NOISE_SIGMAS * np.sqrt(2 * diagnosis.tddi["noise_floor"]) * np.sqrt(np.mean(values**2))
        review.series(f"diagnosis/noise_band/{name}", time, np.column_stack([np.full(values.size, noise), -np.full(
            values.size, noise)]), [f"noise +{NOISE_SIGMAS:g} RMS", f"noise -{NOISE_SIGMAS:g} RMS"],
                      [REFERENCE_COLOR] * 2, [REFERENCE_WIDTH] * 2)
    for corner in corners_of(measured):
        views = []
        for name in (n for n in measured.names if split_channel(n)[0] == corner):
            unit = display_unit(split_channel(name)[1])[0]
            views += [Plot(f"{name} ({unit}): measured grey, thin; baseline, recalibrated, extended faint to full",
                           tuple(f"diagnosis/{m}/{name}" for m in (*models, "measured")), legend=False),
                      Plot(f"{name} residual ({unit}): measured − recalibrated (faint), − extended; noise band grey",
                           (f"diagnosis/residual/recalibrated/{name}", f"diagnosis/residual/extended/{name}",
                            f"diagnosis/noise_band/{name}"), legend=False)]
        review.tab(f"{corner} models vs measured", views)
    _force_law_image(review, diagnosis)
    review.tab("Force laws", [Picture("Force laws measured from the data against the model's",
                                      "diagnosis/force_laws")], columns=1)


def log_track_diagnosis(review: Review, result, record: Record) -> None:
    """A track diagnosis (``rig.diagnosis.track_diagnosis.TrackDiagnosis``) of the measured ``record``: the
    unbalance per wheel in the overview, order spectra, unbalance and transmissibility images, the record."""
    from rig.report.track_report import plot_order_spectra, plot_transmissibility, plot_unbalance

    found = result.unbalance
    named = found.named
    verdict = result.verdict if isinstance(result.verdict, str) else "+".join(result.verdict)
    review.headline = f"verdict: {verdict}" + (
        f"; unbalance at {named.corner}: m e {named.unbalance_kgm * 1e3:.2f} ± {named.std_kgm * 1e3:.2f} g·m at "
        f"{named.angle_deg:.1f} ± {named.std_deg:.1f}° from the mark" if named else "; no wheel unbalanced")
    review.results += ["| wheel | m e [g·m] | angle [°] | T² | called beyond | detection limit [g·m] |",
                       "|---|---|---|---|---|---|",
                       *(f"| {w.corner} | {w.unbalance_kgm * 1e3:.2f} ± {w.std_kgm * 1e3:.2f} | {w.angle_deg:.1f} | "
                         f"{w.t2:.1f} | {w.threshold:.1f} | {w.detection_limit_kgm * 1e3:.2f} |"
                         for w in found.wheels.values())]
    if result.transmissibility is not None:
        review.results += ["", "Transmissibility wheel to body, measured against the model: " + ", ".join(
            f"{c} {100 * e:.1f} % apart" for c, e in result.transmissibility.error.items())]
    if result.road is not None:
        review.results += ["", f"Road part, diagnosed as a rig test: {shown(result.road).verdict}"]
    review.image("diagnosis/order_spectra", plot_order_spectra(result))
    review.image("diagnosis/unbalance", plot_unbalance(found))
    pictures = [Picture("Order spectra per wheel, and the order amplitude against speed", "diagnosis/order_spectra"),
                Picture("Identified unbalance per wheel (2σ discs, detection limits dotted)", "diagnosis/unbalance")]
    if result.transmissibility is not None:
        review.image("diagnosis/transmissibility", plot_transmissibility(result))
        pictures.append(Picture("Transmissibility wheel to body: measured and model", "diagnosis/transmissibility"))
    review.tab("Unbalance", pictures)
    log_run(review, record)
