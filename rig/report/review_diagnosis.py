"""Rerun review of a diagnosis (``rig diagnose``): the named cause and the evidence for it.

Rig test. Overview: the verdict, the named causes with their parameters (units, 95 % intervals), the held-out
TDDI of the baseline, recalibrated and extended models against the noise floor, the ranked causes, where an
unexplained residual lives. Tabs: one per corner with each compared channel's held-out data (on the time of the
record it was held out from) as the baseline, recalibrated and extended models simulate it (one colour per model,
``MODEL_COLORS``) and as measured (grey, drawn last: on top of the models); below each, the residual of the
recalibrated and extended models over the band noise alone would leave (+-2 RMS, grey); *Force laws* (an image:
the restoring force measured from the data against travel and rate, and the tyre's, beside the model's). Track
test: the unbalance per wheel in the overview, the order spectra, unbalance and transmissibility images, and the
measured record per corner.

Draw order: the viewer draws the series of one entity in their order and entities in the order of their paths, so
the models and the measurement of a channel are one entity, the measurement its last series (and the residuals one
entity, the extended model's last).

Entity paths: ``diagnosis/compared/<corner>/<quantity>`` (series: the models in ``MODELS`` order, then measured),
``diagnosis/residual/<corner>/<quantity>`` (series: noise +2 RMS, noise -2 RMS, measured - recalibrated, measured
- extended) on ``time`` (display units, held-out data as compared, in the diagnosis band); images
``diagnosis/force_laws``, ``diagnosis/order_spectra``, ``diagnosis/unbalance``, ``diagnosis/transmissibility``; a
track test's record under ``run/``.

``DiagnosisShown`` is what the review reads of a diagnosis result, in one place (``shown``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import rerun as rr

from rig.io.channels import split_channel
from rig.io.record import Record
from rig.report.review import REFERENCE_WIDTH, Picture, Plot, Review, display
from rig.report.review_runs import corners_of, log_run
from rig.report.style import MODEL_COLORS, REFERENCE_COLOR, display_unit, value_text

MODELS = ("baseline", "recalibrated", "extended")  # drawn in this order, under the measurement
MODEL_WIDTHS = {"baseline": 1.0, "recalibrated": 1.5, "extended": 1.5}
MEASURED_WIDTH = 1.5
NOISE_SIGMAS = 2.0


@dataclass(frozen=True)
class Ranked:
    """A ranked cause: its gain, held-out TDDI and parameters with their units and 95 % intervals."""

    cause: str
    gain: float
    tddi_holdout: float
    params: dict[str, float]
    units: dict[str, str]
    intervals: dict[str, tuple[float, float]]

    def parameters(self) -> str:
        """The parameters in words, each to the precision its interval supports, with its unit."""
        return ", ".join(f"{k} = {value_text(v, self.units.get(k, '-'), self.intervals.get(k))}"
                         for k, v in self.params.items())


@dataclass(frozen=True)
class DiagnosisShown:
    """What the review shows of a rig diagnosis."""

    verdict: tuple[str, ...]          # cause names; ("none",) or ("unexplained",)
    compared: dict[str, Record]       # held-out data as compared: measured and each model's simulation
    tddi: dict[str, float]            # baseline, recalibrated, extended, noise_floor
    ranking: list[Ranked]             # best first
    unexplained: str                  # where an unexplained residual lives, in words ("" otherwise)
    force_laws: object                # rig.diagnosis.rig_test.force_laws.ForceLaws
    data_sheet: object                # the vehicle as given
    start_s: float                    # where the held-out part starts in the record it was held out from (s)


def shown(result) -> DiagnosisShown:
    """The parts of a ``rig.diagnosis.rig_test.diagnosis_results.Diagnosis`` the review shows."""
    verdict = tuple(str(result.verdict).split("+"))
    where = ""
    if result.unexplained is not None:
        where = (f"{result.unexplained.floor_multiple:.1f} times the noise floor left, the residual "
                 f"{result.unexplained.where.text()}")
    return DiagnosisShown(
        verdict, dict(result.compared),
        {"baseline": result.baseline_tddi, "recalibrated": result.recalibrated_tddi,
         "extended": result.extended_tddi, "noise_floor": result.noise_floor},
        [Ranked(c.effect, c.gain, c.tddi_holdout, dict(c.params), dict(c.units), dict(c.intervals))
         for c in result.causes],
        where, result.force_laws, result.data_sheet, float(result.split.holdout.start))


def _force_law_image(review: Review, diagnosis: DiagnosisShown) -> None:
    """The force-law figure of the report, as an image."""
    from rig.report.force_law_report import plot_force_laws

    figure = plot_force_laws(diagnosis.force_laws, diagnosis.data_sheet) if diagnosis.force_laws is not None else None
    if figure is not None:
        review.image("diagnosis/force_laws", figure)


def _overview(review: Review, diagnosis: DiagnosisShown) -> None:
    """The verdict, then its evidence first (the named causes, the held-out TDDI in one row), then the ranking."""
    tddi = diagnosis.tddi
    gain = (tddi["recalibrated"] - tddi["extended"]) / tddi["recalibrated"] if tddi["recalibrated"] > 0 else 0.0
    verdict = " + ".join(diagnosis.verdict)
    review.headline = (f"verdict: {verdict}; held-out TDDI {tddi['recalibrated']:.3g} (recalibrated) -> "
                       f"{tddi['extended']:.3g} (extended), gain {100 * gain:.1f} %; noise floor "
                       f"{tddi['noise_floor']:.3g}")
    review.results += [f"- named **{r.cause}**: {r.parameters()} (gain {r.gain:.3f})"
                       for r in diagnosis.ranking if r.cause in diagnosis.verdict]
    if diagnosis.unexplained:
        review.results += [f"- unexplained: {diagnosis.unexplained}"]
    review.results += ["", "| held-out TDDI | " + " | ".join(k.replace("_", " ") for k in tddi) + " |",
                       "|---" * (len(tddi) + 1) + "|", "| | " + " | ".join(f"{v:.4g}" for v in tddi.values()) + " |",
                       "", "| cause (ranked) | gain | held-out TDDI | parameters (95 % intervals) |",
                       "|---|---|---|---|",
                       *(f"| {'**' + r.cause + '**' if r.cause in diagnosis.verdict else r.cause} | "
                         f"{r.gain if abs(r.gain) >= 5e-4 else 0.0:.3f} | "
                         f"{r.tddi_holdout:.4g} | {r.parameters()} |" for r in diagnosis.ranking[:8])]


def _log_channel(review: Review, diagnosis: DiagnosisShown, name: str, time: rr.TimeColumn) -> None:
    """One compared channel: the models and, last (on top), the measurement; the residuals over the noise band."""
    values, unit = display(name, diagnosis.compared["measured"][name])
    models = [m for m in MODELS if m in diagnosis.compared]
    simulated = {m: display(name, diagnosis.compared[m][name])[0] for m in models}
    review.series(f"diagnosis/compared/{name}", time, np.column_stack([*simulated.values(), values]),
                  [f"{m} [{unit}]" for m in models] + [f"measured [{unit}]"],
                  [MODEL_COLORS[m] for m in models] + [REFERENCE_COLOR],
                  [MODEL_WIDTHS[m] for m in models] + [MEASURED_WIDTH])
    fitted = [m for m in models if m != "baseline"]
    noise = np.full(values.size, NOISE_SIGMAS * np.sqrt(2 * diagnosis.tddi["noise_floor"] * np.mean(values**2)))
    review.series(f"diagnosis/residual/{name}", time,
                  np.column_stack([noise, -noise, *(values - simulated[m] for m in fitted)]),
                  [f"noise +{NOISE_SIGMAS:g} RMS", f"noise -{NOISE_SIGMAS:g} RMS",
                   *(f"measured - {m} [{unit}]" for m in fitted)],
                  [REFERENCE_COLOR] * 2 + [MODEL_COLORS[m] for m in fitted],
                  [REFERENCE_WIDTH] * 2 + [MODEL_WIDTHS[m] for m in fitted])


def log_diagnosis(review: Review, result) -> None:
    """A rig diagnosis (see the module docstring): the overview, the compared held-out data per corner with the
    residuals and the noise band, and the force laws."""
    diagnosis = shown(result)
    _overview(review, diagnosis)
    measured = diagnosis.compared["measured"]
    time = rr.TimeColumn("time", duration=diagnosis.start_s + measured.time)
    for name in measured.names:
        _log_channel(review, diagnosis, name, time)
    for corner in corners_of(measured):
        views = []
        for name in (n for n in measured.names if split_channel(n)[0] == corner):
            unit = display_unit(split_channel(name)[1])[0]
            views += [Plot(f"{name} ({unit}), held out: measured grey, on top of the models",
                           (f"diagnosis/compared/{name}",)),
                      Plot(f"{name} residual ({unit}): measured minus the recalibrated and the extended model; "
                           "noise band grey", (f"diagnosis/residual/{name}",))]
        review.tab(f"{corner} models vs measured", views)
    _force_law_image(review, diagnosis)
    review.tab("Force laws", [Picture("Force laws measured from the data against the model's",
                                      "diagnosis/force_laws")], columns=1)


def log_track_diagnosis(review: Review, result, record: Record) -> None:
    """A track diagnosis (``rig.diagnosis.track.track_diagnosis.TrackDiagnosis``) of the measured ``record``: the
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
