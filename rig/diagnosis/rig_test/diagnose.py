"""Discrepancy diagnosis: name the physical causes of what the model gets wrong, extend it, measure the gain.

Steps (Forsén's practice of identifying parameters by simulation and judging a model against
experimental scatter):
1. integrity checks of the measured record (rig/diagnosis/core/integrity.py), a record sampled far above what the
   diagnosis uses resampled (rig/diagnosis/core/working_rate.py), and the parts to fit and to score
   chosen on content, rest dropped (rig/diagnosis/core/holdout.py); the analysis band the parts support
   (rig/constants.py ``analysis_band``), narrower than 0.5-50 Hz for short or low-rate records (said so), and a
   one-line refusal of a record too short for any band;
2. the input channels checked from the records (rig/diagnosis/rig_test/input_chain.py: each input's gain on the
responses),
   and linear recalibration: spring and tyre rates, damping, sprung and unsprung masses refitted (a real car
   differs from its data sheet by a few percent), so that such differences are not mistaken for a
   structural cause (without the unsprung masses, a hidden tyre damping also drew in a mass error), beside the
   input channels found reversed or grossly scaled, which are corrected first and named;
3. every cause of the registry (rig/causes/) is a candidate, fitted by the strategy of its subsystem
   (rig/diagnosis/rig_test/candidates.py) and scored on the held-out part by the mean TDDI; its gain is the relative
   reduction against the model it was added to, less a penalty per parameter;
4. causes are named one after another, the evidence formed again on what each leaves, pairs and triples fitted
   jointly, sensor faults judged as sensors (rig/diagnosis/rig_test/selection.py);
5. the verdict is honest about the noise: with causes named, a remainder beyond NONE_FACTOR times the noise
   floor measured on the record itself (rig/diagnosis/core/noise.py) is named ``unexplained`` beside them, with
   where it lives; with none named, ``none`` only within that factor, and ``unexplained`` beyond it, the model
   then still extended by a generic element (the corner law as measured, ``measured_law``) whose held-out gain is
   reported. A record too short to judge a model no cause explains (DetectionLimit) gets ``none`` with its
   detection limit, never ``unexplained``.
Law-independent evidence is computed for the report: the residual's (rig/diagnosis/rig_test/evidence.py) and the
force laws measured from the data, without a model form (rig/diagnosis/rig_test/force_laws.py). Confidence intervals
are formed
for the causes named and those whose gain crosses the naming threshold, on a thread of their own while the verdict's
generic extension is fitted (neither changes the other's fits), and for the generic extension where the extended
model carries it; a candidate that gains less, and a generic extension the named causes keep out, have none (its
Jacobian at the solution, a simulation per parameter, was a quarter of a truck's diagnosis for 14 of 18 candidates).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from rig.causes import CAUSES, causes_seen_on
from rig.constants import ANALYSIS_BAND, LOWEST_PERIODS, MIN_BAND_RATIO, TOP_SHARE_OF_RATE, analysis_band, narrowed_note
from rig.diagnosis.rig_test.candidates import Model, Run
from rig.diagnosis.rig_test.evidence import locate_residual, residual_evidence
from rig.diagnosis.core.experiment import Experiment
from rig.diagnosis.rig_test.force_laws import MIN_SECONDS, described, measure_force_laws
from rig.diagnosis.rig_test.frequency_fit import LINEAR_NOTE
from rig.diagnosis.rig_test.input_chain import input_chain
from rig.diagnosis.core.holdout import HOLDOUT_SHARE, Split, choose_split, part_of, split_holdout
from rig.diagnosis.core.integrity import integrity_findings, refuse_errors
from rig.diagnosis.core.model_residuals import model_residual_tests, parameters_of
from rig.diagnosis.core.noise import DETECTION_FACTOR, input_floor, measurement_floor, noise_band
from rig.diagnosis.rig_test.diagnosis_results import Candidate, DetectionLimit, Diagnosis, Unexplained, Verdict
from rig.diagnosis.rig_test.selection import (
    GAIN_THRESHOLD,
    PARAMETER_PENALTY,
    SECOND_CAUSE_FLOOR,
    Selection,
    first_round,
    out_of_reach,
    out_of_reach_note,
    ruled_out,
    ruled_out_note,
    select,
)
from rig.diagnosis.core.timing import StageClock
from rig.diagnosis.core.working_rate import at_working_rate
from rig.io.record import Record, RecordError
from rig.sim.cores import one_blas_thread
from rig.sim.step_size import fit_timestep
from rig.vehicle.vehicle_file import Vehicle

NONE_FACTOR = DETECTION_FACTOR  # 'none' only while the model is within this multiple of the noise floor
MIN_JUDGED_HOLDOUT = 2.5   # s: a held-out part this long (and force laws formed) judges a model no cause explains

__all__ = ["GAIN_THRESHOLD", "NONE_FACTOR", "PARAMETER_PENALTY", "SECOND_CAUSE_FLOOR", "Diagnosis", "diagnose",
           "split_holdout"]


def _carried(generic: Candidate | None, extended) -> bool:
    """Whether the extended model is the generic element's: where it gains and the learned law wins over the named
    causes (``learned_wins``)."""
    return generic is not None and generic.gain > 0 and learned_wins(generic, extended)


def _final_model(extended, generic: Candidate | None, verdict: Verdict, notes: list[str]):
    """The final model (vehicle, simulated channels, held-out TDDI), the causes it names and the verdict: the named
    causes' model, or ``generic``, the generic extension where the model carries it (``_carried``; the input channels
    corrected first stay named: the generic element is fitted on them); ``notes`` told when the named causes give
    way."""
    if generic is None:
        return extended.vehicle, extended.simulated, extended.score, list(extended.named), verdict
    named = list(extended.named)
    if extended.found:
        named = [c for c in named if c.checked_first]
        verdict = Verdict((*(c.effect for c in named), "unexplained"))
        notes.append(gave_way(generic, extended))
    return generic.vehicle, generic.simulated, generic.tddi_holdout, named, verdict


def _judged(ranked: list[Candidate], extended) -> list[Candidate]:
    """The candidates that keep intervals: those named or nearly named (gain over GAIN_THRESHOLD); a fit that explains
    too little to be named keeps none (its spread says nothing), and the Jacobian at its solution is not formed."""
    judged = [c for c in ranked if c.effect in extended.names or c.gain >= GAIN_THRESHOLD]
    for candidate in (c for c in ranked if all(c is not j for j in judged)):
        candidate.intervals = {}
    return judged


@one_blas_thread
def diagnose(vehicle: Vehicle, measured: Record, holdout: Record | None = None,
             causes: tuple[str, ...] | None = None, progress: Callable[[str], None] | None = None,
             frequency_domain: bool = True) -> Diagnosis:
    """Diagnose what the model of ``vehicle`` gets wrong on a measured rig test (see the module docstring).

    ``causes``: names from the registry to consider (default: all that a rig test shows); ``progress(step)`` is told
    each fit as it starts, and the diagnosis's ``stage_times`` hold the wall time of each step and fit
    (rig/diagnosis/core/timing.py); ``frequency_domain``: where the car stays linear on the fit data, the recalibration
    and the first round's fits of causes that keep it linear on its frequency response (rig_test/frequency_fit.py;
    False: by time stepping). A track test is diagnosed by ``rig.diagnosis.track.track_diagnosis.diagnose_track``. BLAS
    runs on one thread meanwhile (rig/sim/cores.py).
    """
    clock = StageClock(progress)
    with clock.step("integrity and split"):
        findings = integrity_findings(measured) + (integrity_findings(holdout) if holdout is not None else [])
        refuse_errors(findings)
        measured, holdout, resampling = at_working_rate(measured, holdout)
        split = choose_split(measured, holdout)
        band, notes = supported_band(measured.rate, split)
        notes = resampling + notes
        fit_record, _ = part_of(measured, split.fit)
        held_record, settle = part_of(holdout if holdout is not None else measured, split.holdout)
    with clock.step("force laws"), clock.part("force laws"):
        clipped = tuple(f.channel for f in findings if f.check == "clipping")
        force_laws = measure_force_laws(fit_record, vehicle, clipped, band)  # fit data only: the held-out part judges
    with clock.step("input chain"), clock.part("input chain"):
        step = fit_timestep(vehicle, measured.rate, band[1])
        train = Experiment.from_record(fit_record, vehicle, band, longest=step)
        inputs = input_chain(train, vehicle)
    with clock.step("baseline and linear recalibration"):
        run = Run(vehicle, train, Experiment.from_record(held_record, vehicle, band, settle, step), force_laws, clock,
                  inputs, frequency_domain)
        floors = measurement_floor(run.test) + input_floor(run.test, run.recalibrated.vehicle,
                                                           run.reference[:, :run.n_car])
        floor = float(np.mean(floors))
        notes += [LINEAR_NOTE] if run.car_linear else []
    with clock.step("first round"):
        names = causes if causes is not None else causes_seen_on("rig")
        ruled = ruled_out(run, names) if causes is None else {}  # a list asked for is screened whole
        beyond = out_of_reach(run, names, floors) if causes is None else {}
        notes += ([ruled_out_note(ruled)] if ruled else []) + ([out_of_reach_note(beyond)] if beyond else [])
        candidates = first_round(run, tuple(n for n in names if n not in ruled and n not in beyond))
    with clock.step("selection"):
        selection = select(run, candidates, floor)
    extended = selection.model
    ranked = extended.named + [c for c in selection.ranked if c.effect not in extended.names]
    with ThreadPoolExecutor(1) as beside:  # the named causes' intervals formed while the verdict's fits run
        judged = beside.submit(run.form_intervals, _judged(ranked, extended))
        with clock.step("verdict"):
            limit = detection_limit(floor, split)
            notes += limit_notes(limit, measured.rate, band)
            verdict, unexplained = judge(run, selection, floors, floor, limit)
        generic = unexplained.generic_extension if unexplained is not None else None
        carried = _carried(generic, extended)
        with clock.step("intervals"):
            run.form_intervals([generic] if carried else [])
            judged.result()
    if generic is not None and not carried:
        generic.intervals = {}  # no model carries it: its Jacobian at the solution is not simulated
    final = _final_model(extended, generic if carried else None, verdict, notes)
    extended_vehicle, extended_simulated, extended_score, named, verdict = final
    if generic is not None:
        unexplained.generic_carried = carried
    return Diagnosis(
        verdict=verdict, causes=ranked, baseline_tddi=run.score(run.baseline), recalibrated_tddi=run.reference_tddi,
        extended_tddi=extended_score, extended_vehicle=extended_vehicle, recalibrated_vehicle=run.recalibrated.vehicle,
        findings=findings, evidence=residual_evidence(run.test, run.reference[:, :run.n_car]), noise_floor=floor,
        compared=compared_records(run, extended_simulated), force_laws=force_laws, data_sheet=vehicle,
        recalibration=run.recalibration, band_hz=band, split=split, detection_limit=limit, unexplained=unexplained,
        named=named, shortfalls=selection.shortfalls, steps=selection.steps, notes=notes, stage_times=clock.times,
        inputs=inputs, residual_tests=model_residual_tests(
            run.test, run.measured, extended_simulated,
            parameters_of(run, named, generic if carried else None)))


def compared_records(run: Run, extended: np.ndarray) -> dict[str, Record]:
    """The held-out data as compared (analysis band): measured, and as the baseline, recalibrated and extended
    models simulate it."""
    return {label: Record(run.test.record.rate, {n: values[:, i] for i, n in enumerate(run.test.names)},
                          metadata={"model": label})
            for label, values in (("measured", run.measured), ("baseline", run.baseline),
                                  ("recalibrated", run.reference), ("extended", extended))}


def supported_band(rate: float, split: Split) -> tuple[tuple[float, float], list[str]]:
    """The analysis band both parts support (Hz) and a note when it is narrower than ANALYSIS_BAND; a RecordError
    naming the need when the record is too short for any band."""
    shortest = min(split.fit.seconds, split.holdout.seconds)
    band = analysis_band(rate, shortest)
    if band is None:
        needed = LOWEST_PERIODS * MIN_BAND_RATIO / min(ANALYSIS_BAND[1], TOP_SHARE_OF_RATE * rate)
        if split.explicit:
            which = "hold-out record" if split.holdout.seconds < split.fit.seconds else "measured record"
            raise RecordError(f"{which} is {shortest:.3g} s (without rest); diagnose needs at least {needed:.2g} s "
                              f"at this rate ({rate:g} Hz)")
        raise RecordError(f"record is {split.fit.end - split.fit.start + split.holdout.seconds:.3g} s (without "
                          f"rest); diagnose needs at least {needed / HOLDOUT_SHARE:.2g} s at this rate ({rate:g} Hz)")
    notes = split.lines()
    notes += [n for n in [narrowed_note(band, rate, shortest)] if n]
    return band, notes


def detection_limit(floor: float, split: Split) -> DetectionLimit:
    """The held-out TDDI beyond which the model is called wrong, and whether the record is long enough to judge a
    model no cause explains: a fitted part the force laws can be formed on (where such a residual lives in the
    suspension) and a held-out part that holds the body's slow modes. A record that is long enough but lacks a
    channel the evidence needs is judged all the same: the force laws say what is missing and what it would add."""
    reasons = []
    if split.fit.seconds < MIN_SECONDS:
        reasons.append(f"the fitted part lasts {split.fit.seconds:.1f} s, the force laws need {MIN_SECONDS:g} s")
    if split.holdout.seconds < MIN_JUDGED_HOLDOUT:
        reasons.append(f"the held-out part lasts {split.holdout.seconds:.1f} s, under {MIN_JUDGED_HOLDOUT:g} s")
    return DetectionLimit(NONE_FACTOR * floor, not reasons, "; ".join(reasons))


def limit_notes(limit: DetectionLimit, rate: float, band: tuple[float, float]) -> list[str]:
    notes = []
    if noise_band(rate, band[1])[1]:
        notes.append(f"the noise floor is an upper bound: at {rate:g} Hz no band above the car's response is left "
                     f"to measure the noise in")
    if not limit.judged:
        needed = max(MIN_SECONDS / (1 - HOLDOUT_SHARE), MIN_JUDGED_HOLDOUT / HOLDOUT_SHARE)
        notes.append(f"too short to judge a discrepancy no cause explains ({limit.reason}): only a named cause "
                     f"states one; a record of at least {needed:g} s is judged fully")
    return notes


def judge(run: Run, selection: Selection, floors: np.ndarray, floor: float, limit: DetectionLimit
          ) -> tuple[Verdict, Unexplained | None]:
    """The verdict and the remainder no named cause explains (module docstring, step 5)."""
    model = selection.model
    explained = {s for c in model.named for s in c.cause.evidence}
    shapes = {corner: [s for s in law.shapes if s not in explained]
              for corner, law in run.force_laws.corners.items() if described(run.vehicle, corner)}
    shapes = {corner: found for corner, found in shapes.items() if found}
    if model.score <= NONE_FACTOR * floor or not limit.judged:
        return Verdict(model.names), None
    where = locate_residual(run.test, run.measured, model.simulated, floors, NONE_FACTOR)
    unexplained = Unexplained(where, model.score, model.score / floor, shapes)
    unexplained.generic_extension = generic_extension(run)
    return Verdict((*model.names, "unexplained")), unexplained


def generic_extension(run: Run) -> Candidate | None:
    """The best generic element (a cause with ``generic`` set: the corner law as measured, the corner law learned
    by the neuro-model paper's networks) fitted to the recalibrated model, with its held-out gain; None when none
    can be formed. Each is screened on the recalibrated model beside the others, and the best refitted jointly with
    the linear parameters (the costlier fit, as the first round's). The learned laws are trained on the fit data, when
    first asked for, on the thread of the element fitted on them (``Cause.learned``) while the others' screenings
    run: the training holds the interpreter's lock, a screening's rollouts do not."""
    def screen(cause) -> tuple[Candidate | None, Model]:
        on = _with_learned_laws(run) if cause.learned else run.recalibrated
        with run.clock.part(f"generic extension {cause.name}"):
            return run.screen(cause, on), on

    screened = [(c, on) for c, on in run.each(screen, [c for c in CAUSES.values() if c.generic]) if c is not None]
    if not screened:
        return None
    best, on = min(screened, key=lambda pair: pair[0].tddi_holdout)
    run.adopt(best, run.joint(on, best))  # the linear parameters bent to the law
    best.gain = run.gain(best.tddi_holdout, run.recalibrated)
    return best


def _with_learned_laws(run: Run) -> Model:
    """The recalibrated model with the corner laws learned from the fit data as its hints (``neuro_laws``)."""
    return dataclasses.replace(run.recalibrated, hints={**run.recalibrated.hints, "neuro_laws": {
        axle: learned.law for axle, learned in run.learned_laws().items()}})


def learned_wins(generic: Candidate, model) -> bool:
    """Whether the generic element extends the model instead of the named causes: always where none is named, else
    where it leaves GAIN_THRESHOLD less of the held-out TDDI than they do (the named causes then stood in for a law
    outside the vocabulary)."""
    return not model.found or generic.tddi_holdout < (1.0 - GAIN_THRESHOLD) * model.score


def gave_way(generic: Candidate, model) -> str:
    """The note that the named causes gave way to a generic element, and why; each told so."""
    names = " + ".join(c.effect for c in model.found)
    for candidate in model.found:
        candidate.why_not = (f"the generic extension {generic.effect} leaves less of the held-out TDDI "
                             f"({generic.tddi_holdout:.3g} against {model.score:.3g} with {names})")
    return (f"{names} gave way to the generic extension {generic.effect}: it leaves "
            f"{generic.tddi_holdout:.3g} of the held-out TDDI against their {model.score:.3g}, more than "
            f"{GAIN_THRESHOLD:.0%} less; the corner laws lie outside the vocabulary")
