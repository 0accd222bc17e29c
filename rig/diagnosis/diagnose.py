"""Discrepancy diagnosis: name the physical cause of what the model gets wrong, extend it, measure the gain.

Steps (Forsén's practice of identifying parameters by simulation and judging a model against
experimental scatter):
1. integrity checks of the measured record (rig/diagnosis/integrity.py);
2. linear recalibration: spring and tyre rates, damping, sprung and unsprung masses refitted (a real car
   differs from its data sheet by a few percent), so that such differences are not mistaken for a
   structural cause (without the unsprung masses, a hidden tyre damping also drew in a mass error);
3. every cause of the registry (rig/causes/) is a candidate, fitted by the strategy of its subsystem:
   car causes by simulation-in-the-loop least squares of their parameters (rig/diagnosis/fitting.py),
   rig causes on the drive -> post displacement path, sensor causes per channel from the residual;
4. each fitted candidate is scored on held-out data (the holdout record, or the last third of the
   measured one) by the mean TDDI in the analysis band; its gain is the relative reduction against the
   recalibrated model, less a penalty per extra parameter;
5. a cause is named when its gain clearly exceeds what extra parameters buy on data without that cause
   (GAIN_THRESHOLD); a second cause is added when it brings a further clear gain;
6. otherwise the verdict is honest about the noise: ``none`` only when the recalibrated model is within
   NONE_FACTOR of the noise floor measured from the record itself (rig/diagnosis/noise.py), and
   ``unexplained`` when it is wrong beyond that and no cause explains it, with where the residual lives
   (channels, band, amplitude dependence), the shapes the measured force laws show, and the model still
   extended by a generic element (the corner law as measured, ``measured_law``) whose held-out gain is
   reported.
Law-independent evidence is computed for the report: the residual's (rig/diagnosis/evidence.py) and the
force laws measured from the data, without a model form (rig/diagnosis/force_laws.py).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from rig.causes import CAUSES, Cause, causes_seen_on
from rig.causes._base import with_extension
from rig.diagnosis.evidence import locate_residual, residual_evidence
from rig.diagnosis.experiment import Experiment
from rig.diagnosis.fitting import build, fit_car, fit_posts, linear_parameters
from rig.diagnosis.force_laws import ForceLaws, measure_force_laws, pointing_to
from rig.diagnosis.integrity import integrity_findings
from rig.diagnosis.noise import input_floor, measurement_floor
from rig.diagnosis.validation import mean_tddi
from rig.io.record import Record, RecordError
from rig.vehicle.vehicle_file import Vehicle

GAIN_THRESHOLD = 0.2      # relative held-out TDDI reduction needed to name a cause
PARAMETER_PENALTY = 0.01  # subtracted from the gain per fitted cause parameter
JOINT_FITS = 2            # screened car causes refitted jointly with the linear parameters
SECOND_CAUSE_FLOOR = 3.0  # look for a second cause only above this multiple of the noise-floor TDDI
SECOND_CAUSE_MIN_GAIN = 0.1  # and only among causes that gain this much on their own (less their penalty)
NONE_FACTOR = 5.0         # 'none' only while the recalibrated model is within this multiple of the noise floor
#: which part of a rig test a subsystem's causes change: the car channels or the achieved posts
AFFECTS = {"car": "car", "sensor": "car", "rig": "posts"}


@dataclass
class Candidate:
    """A fitted cause: its parameters, the extended vehicle and its held-out score."""

    effect: str
    params: dict[str, float]
    vehicle: Vehicle
    tddi_holdout: float
    simulated: np.ndarray = field(repr=False)  # held-out channels as compared (samples x Experiment.names)
    gain: float = 0.0
    n_params: int = 0
    linear_values: np.ndarray | None = field(default=None, repr=False)  # from a joint fit with the linear ones

    @property
    def cause(self) -> Cause:
        return CAUSES[self.effect]

    def summary(self) -> dict:
        return {"effect": self.effect, "subsystem": self.cause.subsystem, "params": self.params,
                "tddi_holdout": self.tddi_holdout, "gain": self.gain}


@dataclass
class Diagnosis:
    """What ``diagnose`` found; ``to_json`` is diagnosis.json. ``compared`` holds the held-out data as
    compared (analysis band): ``measured`` and as the ``baseline``, ``recalibrated`` and ``extended`` models
    simulate it."""

    verdict: str
    causes: list[Candidate]          # ranked best first
    baseline_tddi: float
    recalibrated_tddi: float
    extended_tddi: float
    extended_vehicle: Vehicle
    recalibrated_vehicle: Vehicle
    findings: list[dict]
    evidence: dict
    noise_floor: float               # TDDI that measurement noise alone would leave (rig/diagnosis/noise.py)
    compared: dict[str, Record]
    force_laws: ForceLaws            # measured from the data without a model form
    data_sheet: Vehicle              # the vehicle as given, before recalibration
    unexplained: dict | None = None  # verdict 'unexplained': where the residual lives

    @property
    def named(self) -> list[Candidate]:
        """The causes the verdict names (none for 'none' and 'unexplained')."""
        return [] if self.verdict in ("none", "unexplained") else self.causes[:self.verdict.count("+") + 1]

    def to_json(self) -> dict:
        """The contract of diagnosis.json (docs/contracts.md)."""
        document = {"verdict": self.verdict, "causes": [c.summary() for c in self.causes],
                    "baseline": {"tddi_holdout": self.baseline_tddi},
                    "recalibrated": {"tddi_holdout": self.recalibrated_tddi},
                    "extended": {"tddi_holdout": self.extended_tddi}, "noise_floor": {"tddi_holdout": self.noise_floor},
                    "integrity": self.findings, "evidence": self.evidence}
        if self.unexplained is not None:
            document["unexplained"] = self.unexplained
        return document


def split_holdout(record: Record, share: float = 1 / 3) -> tuple[Record, Record]:
    """The first part of a record to fit and its last ``share`` as held-out data."""
    cut = int(record.n_samples * (1 - share))

    def part(s: slice) -> Record:
        return Record(record.rate, {n: v[s] - (v[s][0] if n.endswith(("/drive", "/actuator_disp")) else 0.0)
                                    for n, v in record.channels.items()}, dict(record.units), dict(record.metadata))
    return part(slice(0, cut)), part(slice(cut, None))


class _Diagnosis:
    """One diagnosis run: the fit and held-out experiments, the recalibrated model and its simulation."""

    def __init__(self, vehicle: Vehicle, train: Experiment, test: Experiment, force_laws: ForceLaws,
                 progress: Callable[[str], None]):
        self.vehicle, self.train, self.test, self.progress = vehicle, train, test, progress
        self.measured = test.measured_all()
        self.n_car = len(test.car_channels)
        self.baseline = self.simulate(vehicle)
        progress("linear recalibration")
        self.linear = linear_parameters(vehicle)
        self.linear_values = fit_car(train, vehicle, self.linear, max_evaluations=5)
        self.recalibrated = build(vehicle, self.linear, self.linear_values)
        self.reference = self.simulate(self.recalibrated)
        self.reference_tddi = self.score(self.reference)
        self.train_simulated = train.simulate_car([self.recalibrated])[0]
        # where the recalibrated model misses on the fit data: initial guesses of shape-seeking causes
        self.hints = locate_residual(train, train.measured, self.train_simulated,
                                     measurement_floor(train)[:self.n_car], 0.0)
        self.hints["measured_laws"] = force_laws.measured_laws(vehicle)
        self.hints["body"] = force_laws.body
        self.hints["axle_coupling"] = force_laws.axle_coupling(vehicle)

    def simulate(self, vehicle: Vehicle, subsystems: set[str] | None = None) -> np.ndarray:
        """Held-out channels of ``vehicle``; with ``subsystems``, only the parts their causes change are
        simulated again, the rest taken from the recalibrated model."""
        parts = {AFFECTS[s] for s in subsystems} if subsystems is not None else {"car", "posts"}
        car = self.test.simulate_car([vehicle])[0] if "car" in parts else self.reference[:, :self.n_car]
        if self.test.drive is None:
            return car
        posts = self.test.simulate_posts([vehicle])[0] if "posts" in parts else self.reference[:, self.n_car:]
        return np.hstack([car, posts])

    def score(self, simulated: np.ndarray) -> float:
        return mean_tddi(self.measured, simulated)

    def candidate(self, cause: Cause, params: dict[str, float], vehicle: Vehicle, n_params: int) -> Candidate:
        simulated = self.simulate(vehicle, {cause.subsystem})
        return Candidate(cause.name, params, vehicle, self.score(simulated), simulated, n_params=n_params)

    def gain(self, score: float) -> float:
        return (self.reference_tddi - score) / self.reference_tddi if self.reference_tddi > 0 else 0.0

    # ---- screening, one strategy per subsystem ----------------------------------------------------
    def screen_car(self, cause: Cause) -> Candidate | None:
        """The cause's own parameters on the recalibrated car (the joint fit follows for the best)."""
        params = cause.fit_parameters(self.vehicle, self.hints)
        if not params:
            return None
        values = fit_car(self.train, self.recalibrated, params, max_evaluations=5)
        return self.candidate(cause, {p.name: float(v) for p, v in zip(params, values)},
                              build(self.recalibrated, params, values), len(params))

    def screen_rig(self, cause: Cause) -> Candidate | None:
        """The rig model's parameters on the drive -> post displacement path (needs measured drives)."""
        if self.train.drive is None:
            return None
        params = cause.fit_parameters(self.recalibrated)
        values = fit_posts(self.train, self.recalibrated, params)
        return self.candidate(cause, {p.name: float(v) for p, v in zip(params, values)},
                              build(self.recalibrated, params, values), len(params))

    def screen_sensor(self, cause: Cause) -> Candidate | None:
        """Per-channel values from the recalibrated model's residual on the fit data."""
        fix = cause.estimate(self.train.measured, self.train_simulated, self.train.car_channels, self.train.record.rate)
        if not fix:
            return None
        return self.candidate(cause, fix, with_extension(self.recalibrated, cause.name, fix), len(fix))

    def refit(self, candidate: Candidate) -> None:
        """Fit a car cause's parameters together with the linear ones from where they are; keep it if better."""
        params = candidate.cause.fit_parameters(self.vehicle, self.hints)
        start = np.concatenate([self.linear_values, list(candidate.params.values())])
        values = fit_car(self.train, self.vehicle, self.linear + params, start, max_evaluations=4)
        extended = build(self.vehicle, self.linear + params, values)
        simulated = self.simulate(extended, {"car"})
        score = self.score(simulated)
        if score < candidate.tddi_holdout:
            candidate.vehicle, candidate.tddi_holdout, candidate.simulated = extended, score, simulated
            candidate.params = {p.name: float(v) for p, v in zip(params, values[len(self.linear):])}
            candidate.linear_values = values[:len(self.linear)]

    def refit_sensor(self, candidate: Candidate) -> None:
        """Fit a sensor cause's per-channel values together with the linear parameters (the recalibration
        without them bent the car towards the faulty channels), estimate the values again on the car so
        recalibrated (channels that only looked faulty on the bent car drop out), and keep it if better."""
        cause = candidate.cause
        params = self.linear + cause.channel_parameters(candidate.params)
        start = np.concatenate([self.linear_values, list(candidate.params.values())])
        linear_values = fit_car(self.train, self.vehicle, params, start, max_evaluations=4)[:len(self.linear)]
        car = build(self.vehicle, self.linear, linear_values)
        fix = cause.estimate(self.train.measured, self.train.simulate_car([car])[0], self.train.car_channels,
                             self.train.record.rate)
        if not fix:
            return
        refitted = self.candidate(cause, fix, with_extension(car, cause.name, fix), len(fix))
        if refitted.tddi_holdout < candidate.tddi_holdout:
            candidate.params, candidate.vehicle, candidate.n_params = refitted.params, refitted.vehicle, len(fix)
            candidate.tddi_holdout, candidate.simulated = refitted.tddi_holdout, refitted.simulated
            candidate.linear_values = linear_values

    def combine(self, best: Candidate, other: Candidate) -> tuple[Vehicle, np.ndarray]:
        """The model with both causes: car causes refitted jointly from where the best one's joint fit left the
        linear parameters, others added to the car cause's model."""
        if best.cause.subsystem == other.cause.subsystem == "car":
            params = self.linear + best.cause.fit_parameters(self.vehicle) + other.cause.fit_parameters(self.vehicle)
            linear = self.linear_values if best.linear_values is None else best.linear_values
            start = np.concatenate([linear, list(best.params.values()), list(other.params.values())])
            combined = build(self.vehicle, params, fit_car(self.train, self.vehicle, params, start, max_evaluations=4))
        else:
            base, added = sorted([best, other], key=lambda c: c.cause.subsystem != "car")
            combined = added.cause.copy(added.vehicle, base.vehicle)
        return combined, self.simulate(combined, {best.cause.subsystem, other.cause.subsystem})


def _generic_extension(run: _Diagnosis, progress: Callable[[str], None]) -> Candidate | None:
    """The best generic element (a cause with ``generic`` set: the corner law as measured) fitted to a model
    that no named cause explains, with its held-out gain; None when none can be formed."""
    fitted = []
    for cause in (c for c in CAUSES.values() if c.generic):
        progress(f"generic extension {cause.name}")
        candidate = run.screen_car(cause)
        if candidate is not None:
            run.refit(candidate)  # with the linear parameters, which recalibration bent towards the law
            candidate.gain = run.gain(candidate.tddi_holdout)
            fitted.append(candidate)
    return max(fitted, key=lambda c: c.gain, default=None)


def diagnose(vehicle: Vehicle, measured: Record, holdout: Record | None = None,
             causes: tuple[str, ...] | None = None, progress: Callable[[str], None] | None = None) -> Diagnosis:
    """Diagnose what the model of ``vehicle`` gets wrong on a measured rig test (see the module docstring).

    ``causes``: names from the registry to consider (default: all that a rig test shows); ``progress(step)`` is
    told each step. A track test is diagnosed by ``rig.diagnosis.track_diagnosis.diagnose_track``.
    """
    progress = progress or (lambda step: None)
    findings = integrity_findings(measured) + (integrity_findings(holdout) if holdout is not None else [])
    errors = [f for f in findings if f["severity"] == "error"]
    if errors:
        raise RecordError("measured data failed the integrity checks: "
                          + "; ".join(f"{f['channel']}: {f['message']}" for f in errors))
    fit_record, held = (measured, holdout) if holdout is not None else split_holdout(measured)
    progress("force laws")
    clipped = tuple(f["channel"] for f in findings if f["check"] == "clipping")
    force_laws = measure_force_laws(fit_record, vehicle, clipped)  # fit data only: the held-out part judges
    run = _Diagnosis(vehicle, Experiment.from_record(fit_record, vehicle), Experiment.from_record(held, vehicle),
                     force_laws, progress)
    screens = {"car": run.screen_car, "rig": run.screen_rig, "sensor": run.screen_sensor}
    candidates = []
    for name in causes if causes is not None else causes_seen_on("rig"):
        cause = CAUSES[name]
        if cause.generic:
            continue
        progress(f"fitting {name}")
        candidate = screens[cause.subsystem](cause)
        if candidate is not None:
            candidates.append(candidate)
    car_candidates = sorted((c for c in candidates if c.cause.subsystem == "car"), key=lambda c: c.tddi_holdout)
    for screened in car_candidates[:JOINT_FITS]:
        progress(f"joint fit of {screened.effect}")  # as the cause would be fitted in practice
        run.refit(screened)
    for screened in (c for c in candidates if c.cause.subsystem == "sensor"):
        progress(f"recalibration with {screened.effect}")
        run.refit_sensor(screened)
    for c in candidates:
        c.gain = run.gain(c.tddi_holdout)
    candidates.sort(key=lambda c: c.gain - PARAMETER_PENALTY * c.n_params, reverse=True)

    chosen = [c for c in candidates[:1] if c.gain - PARAMETER_PENALTY * c.n_params >= GAIN_THRESHOLD]
    if chosen and chosen[0].cause.subsystem == "car":
        # polish the named cause with the budget a pair would get, so a second cause is judged on what it
        # adds, not on the extra fitting it brings
        progress(f"refining {chosen[0].effect}")
        run.refit(chosen[0])
        chosen[0].gain = run.gain(chosen[0].tddi_holdout)
    extended = chosen[0] if chosen else None
    extended_vehicle = extended.vehicle if extended else run.recalibrated
    extended_simulated = extended.simulated if extended else run.reference
    extended_score = extended.tddi_holdout if extended else run.reference_tddi
    floors = measurement_floor(run.test) + input_floor(run.test, run.recalibrated, run.reference[:, :run.n_car])
    floor = float(np.mean(floors))
    if chosen and extended_score > SECOND_CAUSE_FLOOR * floor:
        # a second cause only while the first leaves clearly more than measurement noise to explain; among the
        # causes that gain on their own or that the measured force laws point to (a first cause that explains
        # most of the residual dilutes the others' own gains), and only one that explains other evidence (a
        # bump stop and a progressive spring are rivals, not companions)
        progress("second cause")
        shown = {name for law in force_laws.corners.values() for shape in law.shapes for name in pointing_to(shape)}
        others = [other for other in candidates[1:]
                  if (other.gain - PARAMETER_PENALTY * other.n_params >= SECOND_CAUSE_MIN_GAIN or other.effect in shown)
                  and other.effect != chosen[0].effect
                  and not set(other.cause.evidence) & set(chosen[0].cause.evidence)]
        options = [(other, *run.combine(chosen[0], other)) for other in others[:3]]
        if options:
            other, combined, simulated = min(options, key=lambda o: run.score(o[2]))
            score = run.score(simulated)
            if (extended_score - score) / extended_score - PARAMETER_PENALTY * other.n_params >= GAIN_THRESHOLD:
                chosen.append(other)
                extended_vehicle, extended_simulated, extended_score = combined, simulated, score
    unexplained = None
    if chosen:
        verdict = "+".join(c.effect for c in chosen)
    elif run.reference_tddi <= NONE_FACTOR * floor:
        verdict = "none"
    else:
        verdict = "unexplained"
        unexplained = locate_residual(run.test, run.measured, run.reference, floors, NONE_FACTOR)
        unexplained["force_law_shapes"] = {c: law.shapes for c, law in force_laws.corners.items() if law.shapes}
        generic = _generic_extension(run, progress)
        if generic is not None:
            unexplained["generic_extension"] = generic.summary()
            if generic.gain > 0:
                extended_vehicle, extended_simulated, extended_score = (generic.vehicle, generic.simulated,
                                                                        generic.tddi_holdout)
    evidence = residual_evidence(run.test, run.reference[:, :run.n_car]) | {"force_laws": force_laws.to_json(vehicle)}
    ranked = chosen + [c for c in candidates if c not in chosen]
    compared = {label: Record(run.test.record.rate, {n: values[:, i] for i, n in enumerate(run.test.names)},
                              metadata={"model": label})
                for label, values in (("measured", run.measured), ("baseline", run.baseline),
                                      ("recalibrated", run.reference), ("extended", extended_simulated))}
    return Diagnosis(verdict, ranked, run.score(run.baseline), run.reference_tddi, extended_score, extended_vehicle,
                     run.recalibrated, findings, evidence, floor, compared, force_laws, vehicle,
                     unexplained)
