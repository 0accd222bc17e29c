"""Which causes a diagnosis names: forward selection on held-out data, with the evidence formed again on what
each named cause leaves.

1. Every cause the force laws do not rule out (``ruled_out``: a cause that would show only shapes of a corner's
   law, none of which the laws, formed at every corner, show anywhere), nor the post servo's whose most possible gain
   is under half GAIN_THRESHOLD (``out_of_reach``: the posts already follow the drives as the model's do), is
   screened on the recalibrated model; the best car causes are refitted jointly with the linear parameters, sensor
   causes with them too
   (rig/diagnosis/rig_test/candidates.py).
2. The best cause by held-out gain less PARAMETER_PENALTY per parameter is named when that clears
   GAIN_THRESHOLD; a cause of the car yields to a measurement explanation that gains alike within the held-out
   scatter, and both are reported (rig/diagnosis/core/parsimony.py). A sensor cause whose fault is confined to one
   quantity at every corner (not how a DAQ fails, rig/diagnosis/rig_test/sensors.py) yields to a car cause that clears
   the
   threshold too and whose signature on those channels (the measured response against the model's, per frequency: a
   delay's phase is a line, a compliance's follows its stiffness) matches at least as well, within PHASE_MATCH.
3. While the model leaves more than SECOND_CAUSE_FLOOR times the noise floor and fewer than MAX_CAUSES are named,
   the evidence is formed again on what remains: the model's residual on the fit data (the hints), and the causes
   that explain other evidence than the named ones (rivals, which explain the same force-law shapes, are not
   companions) screened again on top of the model, the force laws' unexplained shapes first. The best is fitted
   jointly with the named causes and the linear parameters (with the first cause's close rival in its place too,
   when there is one), and named when what it adds clears its penalty and the threshold, and so does its own share
   of the joint fit (the joint fit without it, every other value as fitted): on truck_6x4 with a stiffer frame, a
   payload of 11.8 kg fitted beside the frame took 1.03e-3 to 1.75e-4, the frame and the linear factors fitted
   further; such a refit is kept for the causes already named, the cause not named. Within the detection
   limit only a force-law shape still unexplained is followed (the car causes that explain it): friction's
   stick-slip lifts the noise floor measured on a record 13-fold (5.4e-4 against 4.1e-5 of noise), and the anti-roll
   bar the force laws measured beside it (their left-right coupling) was then not sought.
4. A named car cause that explains less than MIN_EXPLAINED of what it was fitted to, or whose model leaves more
   than POLISH_FLOOR times the noise floor, is refitted in its richer form (``Cause.refined_parameters``) and kept
   when that pays for its extra parameters; the model is then fitted further while it still leaves that much, or
   while a named cause's fit stopped short of converging (the Gauss-Newton step from its solution leaves its 95 %
   interval: the driveline mounts' damping stopped at 7114 N s/m for 3369, within the detection limit). A
   model so changed is searched again for a force-law shape still unexplained (step 3): strut friction's plain form
   left 0.0125 beside an anti-roll bar, its richer form 0.00127, where the bar's coupling is what remains; searched
   again for any cause, a Duffing spring and a payload, refined to 5.3 times the floor, drew in a set of per-corner
   accelerometer gains as a third cause. What a cause that explains under MIN_EXPLAINED still leaves is reported as a
   shortfall.
A first cause whose fit starts where the data put it (``Cause.measured_start``: the frame) is refitted from the data
sheet's linear values, as its first fit started, and polished (step 4) while that gains, at most MAX_POLISHES times,
before a further cause is sought: on truck_6x4 with a stiffer frame, the frame's joint fit left enough that a
secondary mass and a payload were named beside it; polished once first, the secondary mass no longer was, but what
the polish left (1.58e-3) a payload's joint fit took to 1.75e-4, its own share 0.003 (the frame and the linear
factors fitted further); polished on (2.30e-2, 1.18e-3, 3.49e-4, 1.75e-4), nothing is sought beside it.
Every cause that crosses the naming threshold without being named is told why.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from rig.causes import BODY_SHAPES, CAUSES, Shape
from rig.diagnosis.rig_test.candidates import Model, Run
from rig.diagnosis.rig_test.evidence import locate_residual, phase_curves, signature_misfit, transfer
from rig.diagnosis.core.fitting import Intervals
from rig.diagnosis.rig_test.force_laws import described
from rig.diagnosis.core.parsimony import alike_statement, by_measurement, compare
from rig.diagnosis.rig_test.diagnosis_results import Candidate, Shortfall, Step
from rig.diagnosis.rig_test.sensors import confined_quantity
from rig.io.channels import split_channel
from rig.signal.metrics import tddi
from rig.vehicle.vehicle_file import Vehicle

GAIN_THRESHOLD = 0.2      # relative held-out TDDI reduction needed to name a cause
PARAMETER_PENALTY = 0.01  # subtracted from the gain per fitted cause parameter
JOINT_FITS = 2            # screened car causes refitted jointly with the linear parameters
SECOND_CAUSE_FLOOR = 5.0  # a further cause only above this multiple of the noise floor: the detection limit
MAX_CAUSES = 3            # named at most (a triple where the data carry it)
RESCREEN = 4              # car causes screened again on what a named cause leaves, at most
RIVAL_MARGIN = 0.15       # a rival of the first cause within this gain of it is tried in its place beside the second
MIN_EXPLAINED = 0.5       # a named cause's held-out gain below this is refined, then reported as a shortfall
PHASE_MATCH = 1.5         # a car cause matches a suspicious sensor cause's signature within this factor
POLISH_FLOOR = 5.0        # named causes that leave more than this multiple of the floor are fitted further...
POLISH_EVALUATIONS = 6    # ...by this many more evaluations of the joint fit
MAX_POLISHES = 3          # a first cause started where the data put it: polished at most this often before the search
#: what a corner's force law shows (the other shapes are departures from the data sheet)
CORNER_SHAPES = frozenset(Shape) - BODY_SHAPES - {Shape.SUSPENSION_RATE, Shape.DAMPING, Shape.TYRE_RATE,
                                                  Shape.TYRE_DAMPING}


def penalised(candidate: Candidate) -> float:
    return candidate.gain - PARAMETER_PENALTY * candidate.n_params


@dataclass
class Selection:
    """The causes named (in the order named, each with its gain on what the model left before it), the final
    model, every candidate ranked, the evidence after each named cause and the shortfalls."""

    model: Model
    ranked: list[Candidate]                     # first-round candidates, best first
    steps: list[Step] = field(default_factory=list)
    shortfalls: list[Shortfall] = field(default_factory=list)
    bases: dict[str, float] = field(default_factory=dict)  # named cause -> the held-out TDDI before it was named
    rescreened: dict[str, Candidate] = field(default_factory=dict)  # the latest fit of a cause on what remained
    excluded: dict[str, str] = field(default_factory=dict)  # causes that may not be named, and why
    refined_tried: set[str] = field(default_factory=set)   # named causes whose richer form was fitted
    joined: dict[str, Model] = field(default_factory=dict)  # a cause's joint fit from the measured body, on a model


def first_round(run: Run, names: tuple[str, ...]) -> list[Candidate]:
    """Every cause screened on the recalibrated model, the best car causes and the sensor causes refitted with the
    linear parameters; ranked by penalised gain."""
    quantities = {split_channel(n)[1] for n in run.train.record.names}
    names = tuple(n for n in names if n not in run.recalibrated.names)  # the input faults corrected first

    def screen(name: str) -> Candidate | None:
        with run.clock.part(f"fitting {name}"):
            return run.screen(CAUSES[name], run.recalibrated)

    candidates = [c for c in run.each(screen, screened(names, run.vehicle.layout, quantities)) if c is not None]
    cars = sorted((c for c in candidates if c.cause.subsystem == "car"), key=lambda c: c.tddi_holdout)
    measured = [c for c in cars if body_measured(run, c)]
    refitted = measured + [c for c in cars[:JOINT_FITS] if not body_measured(run, c)] + \
        [c for c in candidates if c.cause.subsystem == "sensor"]

    def refit(candidate: Candidate) -> Model:
        if not body_measured(run, candidate):
            return run.joint(run.recalibrated, candidate)
        with run.clock.part(f"fitting {candidate.effect} from the measured body"):
            return run.from_evidence(candidate, run.recalibrated)

    for candidate, joint in zip(refitted, run.each(refit, refitted)):
        run.adopt(candidate, joint)
    for candidate in candidates:
        candidate.gain = run.gain(candidate.tddi_holdout, run.recalibrated)
        _judge_as_sensor(run, candidate)
    return sorted(candidates, key=penalised, reverse=True)


def body_measured(run: Run, candidate: Candidate) -> bool:
    """Whether the force laws measured a departure of the sprung body that ``candidate``'s cause explains, or the
    cause starts where the data put it (``Cause.measured_start``)."""
    return candidate.cause.measured_start or bool(set(candidate.cause.evidence) & BODY_SHAPES & run.shown())


def ruled_out(run: Run, names: tuple[str, ...]) -> dict[str, tuple[Shape, ...]]:
    """The causes among ``names`` the force laws rule out, each with the shapes it would show: a cause whose evidence
    is only shapes of a corner's law, none of which the laws show at any corner, where they were formed at every
    corner and describe its suspension (a beam axle's do not: ``Suspension.corner_law``). Where a law could not be
    formed (a channel missing or saturated, a short record), nothing is ruled out."""
    laws = run.force_laws
    if not all(c in laws.corners and described(run.vehicle, c) for c in run.test.corners):
        return {}
    shown = laws.shown(run.vehicle)
    return {n: CAUSES[n].evidence for n in names
            if CAUSES[n].evidence and set(CAUSES[n].evidence) <= CORNER_SHAPES and not set(CAUSES[n].evidence) & shown}


def ruled_out_note(ruled: dict[str, tuple[Shape, ...]]) -> str:
    """The report's sentence on the causes the first round did not screen."""
    return ("not screened, the force laws measured at every corner showing none of the shapes they would: " +
            "; ".join(f"{name} ({', '.join(shapes)})" for name, shapes in ruled.items()))


def out_of_reach(run: Run, names: tuple[str, ...], floors: np.ndarray) -> dict[str, float]:
    """The causes of the rig among ``names`` that could not be named, each with its reach: such a cause changes only the
    achieved post displacements (drive -> post), so the most it can gain is what the recalibrated model leaves on
    those channels above their noise floors (``floors``, per held-out channel), over all the model leaves; under
    half GAIN_THRESHOLD it is not screened. Without drives nothing is out of reach."""
    if run.test.drive is None or run.reference_tddi <= 0:
        return {}
    left = np.array([tddi(run.measured[:, i], run.reference[:, i]) for i in range(run.n_car, run.measured.shape[1])])
    reach = float(np.sum(np.maximum(left - floors[run.n_car:], 0.0)) / (run.measured.shape[1] * run.reference_tddi))
    if reach >= GAIN_THRESHOLD / 2:
        return {}
    return {n: reach for n in names if CAUSES[n].subsystem == "rig"}


def out_of_reach_note(beyond: dict[str, float]) -> str:
    """The report's sentence on the rig causes the first round did not screen."""
    reach = next(iter(beyond.values()))
    return (f"not screened, the achieved post displacements already matching the drives within their noise: "
            f"{', '.join(beyond)} (the most a cause of the rig could gain: {reach:.3f})")


def screened(names: tuple[str, ...], layout: str, quantities: set[str]) -> tuple[str, ...]:
    """The causes among ``names`` that the first round fits on a vehicle of ``layout`` whose record carries
    ``quantities``: no generic element, and none that layout cannot show (a bench's bearings on a car, a truck's
    leaves on a car, a strut's friction on a truck's beam axle)."""
    return tuple(n for n in names if not CAUSES[n].generic and CAUSES[n].shows_in(layout, quantities))


def _judge_as_sensor(run: Run, candidate: Candidate) -> None:
    """A sensor cause's plausibility: a fault confined to one quantity at every corner is not a DAQ's."""
    if candidate.cause.subsystem != "sensor":
        return
    quantity = confined_quantity(list(candidate.params), run.test.corners)
    if quantity is not None:
        kind = candidate.effect.split("_")[1]
        candidate.plausibility = (f"a {kind} confined to {quantity} at every corner, nothing else: not how a DAQ "
                                  f"groups its channels")


def select(run: Run, candidates: list[Candidate], floor: float) -> Selection:
    """Name causes (module docstring) among ``candidates`` (``first_round``) against a noise floor TDDI."""
    selection = Selection(run.recalibrated, list(candidates))
    first = choose(run, run.recalibrated, candidates)
    if first is None:
        _why_not(selection, floor)
        return selection
    if first.cause.subsystem == "car":  # polished with the budget a pair gets: a second is judged on what it adds
        sheet = np.ones(len(run.linear)) if first.cause.measured_start else None  # as its first fit started
        with run.clock.part(f"refining {first.effect}"):
            run.adopt(first, run.joint(run.recalibrated, first, linear_start=sheet))
        first.gain = run.gain(first.tddi_holdout, run.recalibrated)
    selection.bases[first.effect] = run.reference_tddi
    selection.bases.update({c.effect: run.score(run.baseline) for c in run.recalibrated.named})
    selection.excluded.update({c.effect: c.why_not for c in candidates if c.why_not is not None})
    model = run.as_model(first, run.recalibrated, formed=False)
    if first.cause.measured_start:  # fitted on to convergence before a further cause is sought on what it leaves
        model = _converged(run, selection, model, floor)
    model = _search(run, selection, model, floor)
    selection.model = model
    _refine(run, selection, floor)
    selection.model = _polished(run, selection, selection.model, floor)
    if selection.model is not model:  # a richer form or a longer fit changed what is left: its shapes sought again
        selection.model = _search(run, selection, selection.model, floor, shapes_only=True)
    _note_shortfalls(run, selection, floor)
    _why_not(selection, floor)
    return selection


def _search(run: Run, selection: Selection, model: Model, floor: float, shapes_only: bool = False) -> Model:
    """``model`` with further causes named while the evidence asks for one (module docstring, step 3); with
    ``shapes_only``, or within the detection limit, only a force-law shape still unexplained asks."""
    while len(model.found) < MAX_CAUSES:
        beyond = model.score > SECOND_CAUSE_FLOOR * floor and not shapes_only
        shapes = None if beyond else shapes_left(run, model, selection)
        if shapes is not None and not shapes:
            break
        model = run.model(model.vehicle, model.named, model.simulated, model.linear_values)  # evidence formed again
        selection.steps.append(Step(model.names, model.score, locate_residual(
            run.test, run.measured, model.simulated, np.full(run.measured.shape[1], floor), SECOND_CAUSE_FLOOR)))
        following = _next_cause(run, model, selection, shapes)
        if following is None:
            break
        added = following.names != model.names  # else no cause added: the named ones as a joint fit left them
        model = following
        if not added:
            break
    return model


def choose(run: Run, on: Model, ranked: list[Candidate]) -> Candidate | None:
    """The best candidate that clears the threshold, a suspicious sensor cause yielding to a car cause whose
    signature matches (module docstring); a cause whose values cannot be told from no effect is not named."""
    for candidate in (c for c in ranked if c.why_not is None):
        candidate.why_not = candidate.cause.indistinct(candidate.params)
    eligible = [c for c in ranked if penalised(c) >= GAIN_THRESHOLD and c.why_not is None]
    if not eligible:
        return None
    top = eligible[0]
    if top.cause.subsystem != "sensor":
        return _by_parsimony(run, top, eligible)
    _judge_as_sensor(run, top)
    if top.plausibility is None:
        return top
    for car in (c for c in eligible if c.cause.subsystem == "car"):
        own, theirs = signature_misfits(run, on, top, car)
        if theirs <= PHASE_MATCH * own:
            top.why_not = (f"{top.plausibility}; {car.effect} explains the same channels with a matching signature "
                           f"(misfit {theirs:.3f} against the sensor's {own:.3f})")
            return car
    return top


def _by_parsimony(run: Run, top: Candidate, eligible: list[Candidate]) -> Candidate:
    """``top``, or the measurement explanation that gains alike within the held-out scatter, with the statement that
    the records cannot separate them (rig/diagnosis/core/parsimony.py)."""
    if by_measurement(top.cause):
        return top
    for other in (c for c in eligible if by_measurement(c.cause) and c.plausibility is None):
        comparison = compare(run.measured, top.simulated, other.simulated)
        if comparison.alike or comparison.log_ratio > 0:  # the car cause is not better beyond the scatter
            tests = " or ".join(filter(None, (other.cause.separated_by, top.cause.separated_by)))
            other.alike[top.effect] = top.why_not = alike_statement(other.effect, top.effect, (other.gain, top.gain),
                                                                    comparison, tests)
            return other
    return top


def signature_misfits(run: Run, on: Model, sensor: Candidate, car: Candidate) -> tuple[float, float]:
    """On the sensor cause's channels, how far the measured response against the model ``on`` lies from what the
    sensor cause predicts (a delay's phase line, a gain) and from what the car cause's simulation predicts; each
    the mean over the channels of the coherence-weighted RMS difference of the complex responses."""
    names = [n for n in sensor.params if n in run.test.car_channels]
    index = [run.test.names.index(n) for n in names]
    rate, band = run.test.record.rate, run.test.band
    curves = phase_curves(run.measured[:, index], on.simulated[:, index], names, rate, band)
    frequency, predicted_car, _ = transfer(on.simulated[:, index], car.simulated[:, index], rate, band)
    own, theirs = [], []
    for k, name in enumerate(names):
        own.append(signature_misfit(curves[name], sensor.cause.response(sensor.params[name], frequency)))
        theirs.append(signature_misfit(curves[name], predicted_car[:, k]))
    return float(np.mean(own)), float(np.mean(theirs))


def _polished(run: Run, selection: Selection, model: Model, floor: float) -> Model:
    """Named car causes that leave more than POLISH_FLOOR times the noise floor, or whose fit stopped short of
    converging (``_unconverged``), fitted further with the linear parameters (a few evaluations of a joint fit are
    not always enough to converge); the better model, its gain credited to the cause named last."""
    cars = [c for c in model.named if c.cause.subsystem == "car"]
    if not cars or (model.score <= POLISH_FLOOR * floor and not _unconverged(cars)):
        return model
    with run.clock.part("polishing the joint fit"):
        polished = run.joint(model, None, evaluations=POLISH_EVALUATIONS)
    if polished.score >= model.score:
        return model
    last = polished.named[-1]
    base = selection.bases[last.effect]
    last.gain = (base - polished.score) / base
    last.tddi_holdout, last.vehicle, last.simulated = polished.score, polished.vehicle, polished.simulated
    return polished


def _converged(run: Run, selection: Selection, model: Model, floor: float) -> Model:
    """``model`` polished again while a polish improves it and it still asks for one (``_polished``), at most
    MAX_POLISHES times: on truck_6x4 with a stiffer frame, one polish left 1.58e-3 (9.7 times the floor), and the
    payload sought on that took it to 1.75e-4 as the frame and the linear factors fitted further, its own share 0.003:
    a second cause's search (its joint fit and four causes screened again, 35 s on two cores) paid for the first
    cause's fit."""
    for _ in range(MAX_POLISHES):
        polished = _polished(run, selection, model, floor)
        if polished is model:
            break
        model = polished
    return model


def _unconverged(cars: list[Candidate]) -> list[str]:
    """The named car causes' parameters whose fit stopped short of converging (``Intervals.unconverged``): on truck_6x4
    the driveline mounts' joint fit left 4.9 times the floor, within POLISH_FLOOR, with their damping 7114 N s/m for
    3369 (its interval 7036-7191 N s/m, the Gauss-Newton step from there far outside it)."""
    return [f"{c.effect}.{n}" for c in cars if isinstance(c.intervals, Intervals) for n in c.intervals.unconverged()]


def shapes_left(run: Run, model: Model, selection: Selection) -> set[Shape]:
    """The force laws' shapes and departures that no cause named in ``model`` explains and a car cause still in the
    running would; the sprung mass's only where ``model``'s own linear fit still stops at its tolerance (on truck_6x4
    with a stiffer frame the recalibration's sprung mass stopped at 1.0495, bent to stand in for the frame; the frame's
    joint fit left it at 1.0006, and a payload sought on it gained nothing)."""
    explained = {s for c in model.named for s in c.cause.evidence}
    explicable = {s for c in selection.ranked if c.effect not in model.names and c.effect not in selection.excluded
                  and c.cause.subsystem == "car" for s in c.cause.evidence}
    return (run.shown(model.linear_values) - explained) & explicable


def _next_cause(run: Run, model: Model, selection: Selection, shapes: set[Shape] | None = None) -> Model | None:
    """The model with one more cause named, or None when no cause adds enough on what ``model`` leaves (or
    ``model``'s causes as the best cause's joint fit left them, where that leaves less); with ``shapes`` (below the
    detection limit), only a car cause that explains one of them is sought."""
    pool = sorted(_rescreen(run, model, selection, shapes), key=penalised, reverse=True)
    selection.rescreened.update({c.effect: c for c in pool})
    best = choose(run, model, [c for c in pool if c.effect not in selection.excluded])
    for yielded in (c for c in pool if c.why_not is not None):
        selection.excluded[yielded.effect] = yielded.why_not
    if best is None:
        return None
    joined = selection.joined.pop(best.effect, None)
    fits = [(lambda: joined) if joined is not None else (lambda: _with(run, model, best))]
    rival = _close_rival(selection, model)
    if rival is not None and best.cause.subsystem != "rig":
        fits.append(lambda: run.joint(model, best, replace={model.found[0].effect: rival}))
    new = min(run.each(lambda fit: fit(), fits), key=lambda m: m.score)
    added = run.gain(new.score, model)
    share, vehicle, simulated = _share(run, new)
    if min(added, share) - PARAMETER_PENALTY * best.n_params < GAIN_THRESHOLD:
        best.why_not = (f"fitted jointly with {' + '.join(model.names)} it adds {added:.3f} of what they leave, "
                        + (f"under the threshold with its {best.n_params} parameter(s)" if share >= added else
                           f"of which {share:.3f} is its own (the joint fit without it), under the threshold with "
                           f"its {best.n_params} parameter(s): the rest is the named causes fitted further"))
        kept = new.names[:-1] == model.names and run.score(simulated) < model.score
        return _credited(run, selection, new, vehicle, simulated) if kept else None
    named = new.named[-1]
    named.gain, named.tddi_holdout, named.simulated, named.vehicle = added, new.score, new.simulated, new.vehicle
    named.added_to = tuple(c.effect for c in new.named[:-1])
    selection.bases[named.effect] = model.score
    if new.found[0].effect != model.found[0].effect:  # the rival took the first cause's place
        replaced = model.found[0].effect
        selection.bases[new.found[0].effect] = selection.bases.pop(replaced)
        selection.excluded[replaced] = (f"named first, it gave way to its rival {new.found[0].effect}: beside "
                                        f"{named.effect}, the rival leaves less")
    return new


def _share(run: Run, new: Model) -> tuple[float, Vehicle, np.ndarray]:
    """The cause named last in ``new`` (a joint fit), its own share: the held-out TDDI reduction over ``new`` without
    it, every other value as the joint fit left them; with that vehicle and its held-out simulation."""
    added = new.named[-1]
    vehicle = without(run, new.vehicle, added.effect)
    simulated = run.simulate(vehicle, {added.cause.subsystem}, new)
    score = run.score(simulated)
    return (score - new.score) / score if score > 0 else 0.0, vehicle, simulated


def _credited(run: Run, selection: Selection, new: Model, vehicle: Vehicle, simulated: np.ndarray) -> Model:
    """The causes ``new`` names before its last, as its joint fit left them (``vehicle``, its held-out
    ``simulated``), the evidence formed on them, their improvement credited to the cause named last of them."""
    model = run.model(vehicle, new.named[:-1], simulated, new.linear_values)
    last = model.named[-1]
    base = selection.bases[last.effect]
    last.gain = (base - model.score) / base
    last.tddi_holdout, last.vehicle, last.simulated = model.score, model.vehicle, model.simulated
    return model


def _rescreen(run: Run, model: Model, selection: Selection, shapes: set[Shape] | None) -> list[Candidate]:
    """The causes that explain other evidence than the named ones, fitted again on top of ``model``: car causes
    (the force laws' unexplained shapes first, then by their first-round gain, at most RESCREEN) from their
    first-round values, sensor causes from the model's residual, rig causes added as fitted (their path is the
    posts'); with ``shapes``, only the car causes that explain one of them. A car cause whose evidence the force
    laws measured (a body departure, or a shape at every corner but one at most) is fitted jointly with the named
    causes and the linear parameters from the data sheet's values instead: on top of a model whose recalibration
    bent its damping 22-28 % up and its springs 11-20 % down to stand in for 138 N of strut friction, the friction's
    own fit beside an asymmetric damper gained 0.004, as the factors it should undo stayed where they were."""
    explained = {s for c in model.named for s in c.cause.evidence}
    shown = run.shown() - explained
    others = [c for c in selection.ranked if c.effect not in model.names and c.effect not in selection.excluded
              and not set(c.cause.evidence) & explained]
    if shapes is not None:
        others = [c for c in others if c.cause.subsystem == "car" and set(c.cause.evidence) & shapes]
    cars = sorted((c for c in others if c.cause.subsystem == "car"),
                  key=lambda c: (not set(c.cause.evidence) & shown, -penalised(c)))

    widely = run.force_laws.widely_shown(run.vehicle) - explained

    def screen(first: Candidate) -> Candidate | None:
        if not body_measured(run, first) and not set(first.cause.evidence) & widely:
            with run.clock.part(f"fitting {first.effect} on what {' + '.join(model.names)} leave(s)"):
                return run.screen(first.cause, model, start=first.params, evaluations=3)
        with run.clock.part(f"fitting {first.effect} from the measured evidence beside {' + '.join(model.names)}"):
            joined = run.from_evidence(first, model)
        selection.joined[first.effect] = joined
        return dataclasses.replace(joined.named[-1], vehicle=joined.vehicle, tddi_holdout=joined.score,
                                   simulated=joined.simulated, gain=run.gain(joined.score, model),
                                   added_to=model.names)

    pool = []
    firsts = cars[:RESCREEN] + [c for c in others if c.cause.subsystem == "sensor"]
    for first, candidate in zip(firsts, run.each(screen, firsts)):
        if candidate is not None:
            pool.append(candidate)
        else:
            selection.excluded.setdefault(first.effect, f"on what {' + '.join(model.names)} leave(s), nothing of "
                                                        f"it is left: no channel departs by {first.cause.name}'s "
                                                        f"smallest effect")
    for first in (c for c in others if c.cause.subsystem == "rig"):
        combined = _with(run, model, first)
        pool.append(Candidate(first.effect, first.params, combined.vehicle, combined.score, combined.simulated,
                              gain=run.gain(combined.score, model), n_params=first.n_params,
                              parameters=first.parameters, fit=first.fit, intervals=first.intervals,
                              units=first.units, added_to=model.names))
    return pool


def _with(run: Run, on: Model, candidate: Candidate) -> Model:
    """``on`` with ``candidate`` named: car and sensor causes fitted jointly, a rig cause added as fitted."""
    if candidate.cause.subsystem != "rig":
        return run.joint(on, candidate)
    vehicle = candidate.cause.copy(candidate.vehicle, on.vehicle)
    simulated = run.simulate(vehicle, {"rig"}, on)
    return Model(vehicle, [*on.named, candidate], simulated, run.score(simulated), on.linear_values,
                 on.train_simulated, on.hints)


def _close_rival(selection: Selection, model: Model) -> Candidate | None:
    """With one cause named, the first-round candidate that explains the same evidence within RIVAL_MARGIN of its
    gain (a payload beside a stiffening spring can tilt the choice between a bump stop and a progressive spring)."""
    if len(model.found) != 1 or model.found[0].cause.subsystem != "car":
        return None
    first = model.found[0]
    rivals = [c for c in selection.ranked if c.effect != first.effect and c.cause.subsystem == "car"
              and set(c.cause.evidence) & set(first.cause.evidence) and c.gain >= first.gain - RIVAL_MARGIN]
    return max(rivals, key=penalised, default=None)


def without(run: Run, vehicle, effect: str):
    """``vehicle`` without the cause ``effect`` (its section removed, or its keys as the data sheet has them)."""
    cause = CAUSES[effect]
    if cause.has_section():
        return dataclasses.replace(vehicle, extensions={k: v for k, v in vehicle.extensions.items() if k != effect})
    return cause.copy(run.vehicle, vehicle)


def _own_gain(run: Run, model: Model, candidate: Candidate) -> float:
    """A named cause's gain on what the other named causes leave: the final model against itself without it."""
    if len(model.named) == 1:
        return candidate.gain
    simulated = run.simulate(without(run, model.vehicle, candidate.effect), {candidate.cause.subsystem}, model)
    score = run.score(simulated)
    return (score - model.score) / score if score > 0 else 0.0


def _refine(run: Run, selection: Selection, floor: float) -> None:
    """Named car causes that explain less than MIN_EXPLAINED, or leave more than POLISH_FLOOR times the floor,
    refitted in their richer form, kept when the gain pays for the extra parameters."""
    for effect in [c.effect for c in selection.model.named]:
        model = selection.model
        named = next(c for c in model.named if c.effect == effect)
        wanted = model.score > POLISH_FLOOR * floor or _own_gain(run, model, named) < MIN_EXPLAINED
        parameters = named.cause.refined_parameters(run.vehicle, model.hints) if wanted and not named.refined else []
        if named.cause.subsystem != "car" or not parameters:
            continue
        selection.refined_tried.add(effect)
        refined = dataclasses.replace(named, parameters=parameters, refined=True, n_params=len(parameters),
                                      params={p.name: named.params.get(p.name, p.initial) for p in parameters},
                                      units={p.name: p.unit for p in parameters})
        with run.clock.part(f"refining the form of {effect}"):
            new = run.joint(model, None, replace={effect: refined})
        if (model.score - new.score) / model.score <= PARAMETER_PENALTY * (len(parameters) - named.n_params):
            continue
        kept = next(c for c in new.named if c.effect == effect)
        base = selection.bases[effect]
        kept.gain = (base - (base * (1 - named.gain) - (model.score - new.score))) / base
        kept.tddi_holdout, kept.vehicle, kept.simulated = new.score, new.vehicle, new.simulated
        selection.model = new


def _note_shortfalls(run: Run, selection: Selection, floor: float) -> None:
    """Named causes that explain less than MIN_EXPLAINED of what they were fitted to (on what the other named
    causes leave), with what the model leaves; each named cause keeps that share (``own_gain``)."""
    model = selection.model
    for named in model.named:
        own = named.own_gain = _own_gain(run, model, named)
        if own < MIN_EXPLAINED:
            left = (f"the model with {' + '.join(model.names)} leaves a held-out TDDI of {model.score:.3g}, "
                    f"{model.score / floor:.1f} times the noise floor")
            selection.shortfalls.append(Shortfall(named.effect, own, named.effect in selection.refined_tried, left))


def _why_not(selection: Selection, floor: float) -> None:
    """Each candidate whose gain crosses the naming threshold without being named is told why."""
    model = selection.model
    names = model.names
    for candidate in selection.ranked:
        if candidate.effect in names or candidate.gain < GAIN_THRESHOLD or candidate.why_not is not None:
            continue
        rivals = [c for c in model.named if set(c.cause.evidence) & set(candidate.cause.evidence)]
        again = selection.rescreened.get(candidate.effect)
        if candidate.effect in selection.excluded:
            candidate.why_not = selection.excluded[candidate.effect]
        elif penalised(candidate) < GAIN_THRESHOLD:
            cost = PARAMETER_PENALTY * candidate.n_params
            candidate.why_not = (f"its {candidate.n_params} parameters cost {cost:.2f} of its gain: "
                                 f"{penalised(candidate):.3f} is under the threshold")
        elif rivals:
            shared = sorted(set(rivals[0].cause.evidence) & set(candidate.cause.evidence))
            candidate.why_not = (f"a rival of {rivals[0].effect}: both explain {', '.join(shared)}, and "
                                 f"{rivals[0].effect} gains more")
        elif again is not None:
            candidate.why_not = again.why_not or (f"fitted again on what {' + '.join(again.added_to)} leave(s), it "
                                                  f"adds {again.gain:.3f}: under the threshold")
        elif not selection.steps:
            candidate.why_not = (f"what {' + '.join(names)} leave(s) is within {SECOND_CAUSE_FLOOR:g} times the noise "
                                 f"floor: nothing left for another cause")
        else:
            candidate.why_not = (f"not fitted again on what {' + '.join(names)} leave(s): {RESCREEN} causes with a "
                                 f"better claim were")
