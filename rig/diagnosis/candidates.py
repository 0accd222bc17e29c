"""Candidate causes fitted on a prepared rig test: the recalibrated model, each cause screened on top of a model,
and joint fits of several causes with the linear parameters.

A ``Model`` is what the diagnosis holds at one moment: a vehicle, the causes it names, its held-out simulation
and score, and where its residual on the fit data lives (the hints that start shape-seeking causes). Screening
fits one cause's own parameters on top of a model by the strategy of its subsystem: car causes by
simulation-in-the-loop least squares (rig/diagnosis/fitting.py), rig causes on the drive -> post displacement
path, sensor causes from the model's residual, grouped as a DAQ groups channels (rig/diagnosis/sensors.py).
A joint fit refits the linear parameters together with every car cause of the model and the new one.

On a record with an actuator force (``active_force``) the force path's gain is fitted beside the linear parameters and
left out of the model they build (``Run.force_path``), unless ``force_constant_error`` is named: the road-to-body
response does not depend on the force constant, the force-to-body response scales with it, so a weak actuator must not
be soaked into the spring and damping factors. The data fix only the force constant over the overall scale of masses,
rates and damping (scaling them all by a scales the force response by 1 / a): a gain g within FORCE_SCALE_TOLERANCE
of 1 is put into that common scale (the linear factors divided by g: the same road response, the force response the
gain's), a gain beyond it is left to ``force_constant_error`` (the masses are known to a few percent, a force
constant is not).
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from typing import TypeVar

import numpy as np
from scipy.optimize import OptimizeResult

from rig.causes import CAUSES, Cause, FitParameter
from rig.causes._base import with_extension
from rig.causes.force_constant_error import SCALE_TOLERANCE as FORCE_SCALE_TOLERANCE
from rig.diagnosis.evidence import locate_residual
from rig.diagnosis.experiment import Experiment
from rig.diagnosis.fitting import Intervals, build, fit_car, fit_posts, intervals, linear_parameters
from rig.diagnosis.force_laws import ForceLaws
from rig.diagnosis.modes import pattern_peaks
from rig.diagnosis.noise import measurement_floor
from rig.diagnosis.results import Candidate, LinearFit
from rig.diagnosis.sensors import ChannelGroups, described, group_channels
from rig.diagnosis.timing import StageClock
from rig.diagnosis.validation import mean_tddi
from rig.io.channels import split_channel
from rig.vehicle.vehicle_file import Vehicle

FORCE_CONSTANT = "force_constant_error"
RESTARTS = 2        # the recalibration of a record with active_force started again at most this often...
RESTART_GAIN = 0.1  # ...while a start lowers its cost by this share (Run.fit_linear)
T, R = TypeVar("T"), TypeVar("R")

#: which part of a rig test a subsystem's causes change: the car channels or the achieved posts
AFFECTS = {"car": "car", "sensor": "car", "rig": "posts"}


@dataclass
class Model:
    """The model at one step of the diagnosis: its vehicle, the causes it names (in the order named), its held-out
    simulation and score, its linear parameters, its car channels on the fit data and the hints they give."""

    vehicle: Vehicle
    named: list[Candidate]
    simulated: np.ndarray = field(repr=False)
    score: float
    linear_values: np.ndarray = field(repr=False)
    train_simulated: np.ndarray = field(repr=False)
    hints: dict = field(repr=False)

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(c.effect for c in self.named)


def force_path_parameters(vehicle: Vehicle, train: Experiment) -> list[FitParameter]:
    """The force actuators' gains, fitted beside the linear parameters and left out of the model (module docstring),
    where the record has an actuator force; else none."""
    quantities = {split_channel(n)[1] for n in train.record.names}
    if not CAUSES[FORCE_CONSTANT].shows_in(vehicle.layout, quantities):
        return []
    return [dataclasses.replace(p, name=f"force_path_{p.name}", typical=1.0)
            for p in CAUSES[FORCE_CONSTANT].fit_parameters(vehicle)]


class Run:
    """One diagnosis's fitting: the fit and held-out experiments, the recalibrated model, screening and joint fits."""

    def __init__(self, vehicle: Vehicle, train: Experiment, test: Experiment, force_laws: ForceLaws,
                 clock: StageClock):
        self.vehicle, self.train, self.test, self.clock = vehicle, train, test, clock
        self.force_laws = force_laws
        self.measured = test.measured_all()
        self.n_car = len(test.car_channels)
        self.train_floor = measurement_floor(train)[:self.n_car]
        self.workers = len(os.sched_getaffinity(0))  # the cores this process may use
        self.baseline, _ = self.each(lambda task: task(), [self.simulate_baseline, self.recalibrate])

    def each(self, fit: Callable[[T], R], items: Sequence[T]) -> list[R]:
        """``fit`` of each of ``items`` (fits independent of each other), beside each other on the machine's cores (a
        rollout releases the interpreter's lock); the results in the order of ``items``, as one after another."""
        if self.workers < 2 or len(items) < 2:
            return [fit(item) for item in items]
        with ThreadPoolExecutor(min(self.workers, len(items))) as pool:
            return list(pool.map(fit, items))

    def simulate_baseline(self) -> np.ndarray:
        """Held-out channels of the data sheet's vehicle."""
        with self.clock.part("baseline"):
            return self.simulate(self.vehicle, None, None)

    def recalibrate(self) -> None:
        """The linear parameters fitted to the data sheet's vehicle: the recalibrated model (module docstring)."""
        with self.clock.part("linear recalibration"):
            vehicle = self.vehicle
            self.linear = linear_parameters(vehicle)
            self.force_path = force_path_parameters(vehicle, self.train)
            result = self.fit_linear()
            spread = intervals(result, self.linear + self.force_path)
            self.recalibration = LinearFit({}, dict(zip([p.name for p in self.linear], spread)), result)
            linear_values = self.linear_values(result.x, bool(self.force_path))
            self.recalibration.values = {p.name: float(x) for p, x in zip(self.linear, linear_values)}
            recalibrated = build(vehicle, self.linear, linear_values)
            reference = self.simulate(recalibrated, None, None)
            self.recalibrated = self.model(recalibrated, [], reference, linear_values)
            self.reference, self.reference_tddi = reference, self.recalibrated.score

    def fit_linear(self) -> OptimizeResult:
        """The linear factors (and the force path's gains) fitted on the fit data. Where the gains go into the common
        scale (module docstring), the fit is started again from the linear factors so divided and the gains at 1 while
        a start lowers its cost by RESTART_GAIN, at most RESTARTS times: the factors and the gains scaled together by
        a are a valley the trust region slides along slowly (only the tyre damping, which no factor scales, keeps it
        from being flat), so the first fit ends on its side (an exact bench: the gains 1.016, the suspension damping
        1.5 % high to make up for the tyre damping), where dividing by the gains leaves 16 times the noise floor."""
        params = self.linear + self.force_path
        result = fit_car(self.train, self.vehicle, params, max_evaluations=5)
        for _ in range(RESTARTS if self.force_path else 0):
            if abs(np.mean(result.x[len(self.linear):]) - 1) > FORCE_SCALE_TOLERANCE:  # force_constant_error's
                break
            start = np.concatenate([self.linear_values(result.x, True), [p.initial for p in self.force_path]])
            again = fit_car(self.train, self.vehicle, params, start, max_evaluations=5)
            if again.cost > (1 - RESTART_GAIN) * result.cost:
                break
            result = again
        return result

    def linear_values(self, x: np.ndarray, with_force_path: bool, n_linear: int | None = None) -> np.ndarray:
        """The linear factors of a fit's values ``x`` (linear first, ``n_linear`` of them where a cause owns some; the
        force-path gains last where fitted), divided by the gains' mean where it lies within FORCE_SCALE_TOLERANCE of
        1 (module docstring)."""
        linear = np.asarray(x[:len(self.linear) if n_linear is None else n_linear], float)
        gain = float(np.mean(x[-len(self.force_path):])) if with_force_path else 1.0
        return linear / gain if abs(gain - 1) <= FORCE_SCALE_TOLERANCE else linear

    def model(self, vehicle: Vehicle, named: list[Candidate], simulated: np.ndarray, linear_values: np.ndarray
              ) -> Model:
        """A model with its evidence on the fit data formed (its residual's location there: the hints)."""
        train_simulated = self.train.simulate_trials([vehicle])[0]
        where = locate_residual(self.train, self.train.measured, train_simulated, self.train_floor, 0.0)
        hints = where.to_json() | {"measured_laws": self.force_laws.measured_laws(self.vehicle),
                                   "body": self.force_laws.body,
                                   "axle_coupling": self.force_laws.axle_coupling(self.vehicle),
                                   "axle_lag_s": self.force_laws.axle_lags(),
                                   "pattern_peaks": pattern_peaks(self.train, train_simulated)}
        return Model(vehicle, named, simulated, self.score(simulated), np.asarray(linear_values), train_simulated,
                     hints)

    def simulate(self, vehicle: Vehicle, subsystems: set[str] | None, base: Model | None) -> np.ndarray:
        """Held-out channels of ``vehicle``; with ``subsystems``, only the parts their causes change are simulated
        again, the rest taken from ``base``."""
        parts = {AFFECTS[s] for s in subsystems} if subsystems is not None else {"car", "posts"}
        car = self.test.simulate_trials([vehicle])[0] if "car" in parts else base.simulated[:, :self.n_car]
        if self.test.drive is None:
            return car
        posts = self.test.simulate_posts([vehicle])[0] if "posts" in parts else base.simulated[:, self.n_car:]
        return np.hstack([car, posts])

    def score(self, simulated: np.ndarray) -> float:
        return mean_tddi(self.measured, simulated)

    @staticmethod
    def gain(score: float, on: Model) -> float:
        """Relative held-out TDDI reduction of ``score`` against the model ``on``."""
        return (on.score - score) / on.score if on.score > 0 else 0.0

    # ---- screening on top of a model, one strategy per subsystem ------------------------------------------
    def screen(self, cause: Cause, on: Model, start: dict[str, float] | None = None, evaluations: int = 5,
               refined: bool = False) -> Candidate | None:
        strategy = {"car": self.screen_car, "rig": self.screen_rig, "sensor": self.screen_sensor}[cause.subsystem]
        candidate = strategy(cause, on, start, evaluations, refined)
        if candidate is not None:
            candidate.gain, candidate.added_to = self.gain(candidate.tddi_holdout, on), on.names
        return candidate

    def screen_car(self, cause: Cause, on: Model, start: dict[str, float] | None, evaluations: int,
                   refined: bool) -> Candidate | None:
        """The cause's own parameters on the model (the joint fit with the linear ones follows for the best)."""
        params = (cause.refined_parameters if refined else cause.fit_parameters)(self.vehicle, on.hints)
        if not params:
            return None
        x0 = None if start is None else [start.get(p.name, p.initial) for p in params]
        result = fit_car(self.train, on.vehicle, params, x0, max_evaluations=evaluations)
        return self.fitted(cause, params, result, build(on.vehicle, params, result.x), on, refined=refined)

    def screen_rig(self, cause: Cause, on: Model, start: dict[str, float] | None, evaluations: int,
                   refined: bool) -> Candidate | None:
        """The rig model's parameters on the drive -> post displacement path (needs measured drives)."""
        if self.train.drive is None:
            return None
        params = cause.fit_parameters(on.vehicle)
        result = fit_posts(self.train, on.vehicle, params)
        return self.fitted(cause, params, result, build(on.vehicle, params, result.x), on)

    def screen_sensor(self, cause: Cause, on: Model, start: dict[str, float] | None, evaluations: int,
                      refined: bool) -> Candidate | None:
        """Per-channel values from the model's residual on the fit data, grouped as a DAQ groups channels."""
        groups = self.sensor_groups(cause, on.train_simulated, on.simulated[:, :self.n_car] if on.named else None)
        if not groups.groups:
            return None
        vehicle = with_extension(on.vehicle, cause.name, groups.per_channel())
        simulated = self.simulate(vehicle, {"sensor"}, on)
        return Candidate(cause.name, groups.per_channel(), vehicle, self.score(simulated), simulated,
                         n_params=groups.n_params, parameters=cause.group_parameters(groups.groups),
                         units=dict.fromkeys(groups.per_channel(), cause.unit), groups=groups.describe())

    def sensor_groups(self, cause: Cause, train_simulated: np.ndarray, test_simulated: np.ndarray | None
                      ) -> ChannelGroups:
        """A sensor cause's values on the fit data's car channels against the model's (``train_simulated``), grouped
        as a DAQ groups channels; where the model names another cause, kept only where the sensor's signature
        describes the held-out channels against the model's (``test_simulated``, None where it names none:
        rig/diagnosis/sensors.py says why)."""
        train, test = self.train, self.test
        values = dict(zip(train.car_channels, map(float, cause.channel_values(train.measured, train_simulated,
                                                                              train.record.rate))))
        if test_simulated is not None:
            values = described(cause, values, test.measured, test_simulated, test.record.rate, test.band)
        return group_channels(cause, values)

    def fitted(self, cause: Cause, params: list[FitParameter], result, vehicle: Vehicle, on: Model,
               refined: bool = False) -> Candidate:
        """A car or rig cause's candidate from its fit."""
        simulated = self.simulate(vehicle, {cause.subsystem}, on)
        return Candidate(cause.name, {p.name: float(x) for p, x in zip(params, result.x)}, vehicle,
                         self.score(simulated), simulated, n_params=len(params), parameters=params, fit=result,
                         intervals=Intervals(result, params),
                         units={p.name: p.unit for p in params},
                         refined=refined)

    # ---- joint fits ----------------------------------------------------------------------------------------
    def joint(self, on: Model, added: Candidate | None, evaluations: int = 4,
              replace: dict[str, Candidate] | None = None, linear_start: np.ndarray | None = None) -> Model:
        """The model ``on`` with ``added``: the linear parameters fitted together with every car cause (from where
        they are, or the linear ones from ``linear_start``; ``replace`` swaps named causes for other fits of theirs);
        a sensor cause estimated again on the car so fitted, a rig cause copied. The causes' parameters and
        intervals come from the joint fit."""
        named = [(replace or {}).get(c.effect, c) for c in on.named] + ([added] if added else [])
        named = [dataclasses.replace(c) for c in named]
        cars = [c for c in named if c.cause.subsystem == "car"]
        sensors = [c for c in named if c.cause.subsystem == "sensor"]
        base = self.vehicle
        for other in (c for c in named if c.cause.subsystem == "rig"):
            base = other.cause.copy(other.vehicle, base)
        force_path = [] if any(c.effect == FORCE_CONSTANT for c in cars) else self.force_path
        owned = {key for c in cars for key in c.cause.owns}
        free = np.array([p.name not in owned for p in self.linear])
        linear = [p for p, fitted in zip(self.linear, free) if fitted]
        params = linear + [p for c in cars + sensors for p in c.parameters] + force_path
        start = np.concatenate([np.asarray(on.linear_values if linear_start is None else linear_start)[free]]
                               + [list(c.params.values())[:len(c.parameters)] if c in cars
                                  else [p.initial for p in c.parameters] for c in cars + sensors]
                               + [[p.initial for p in force_path]])
        with self.clock.part("joint fit of " + " + ".join(c.effect for c in named)):
            result = fit_car(self.train, base, params, start, max_evaluations=evaluations)
        at = len(linear)
        for c in cars:
            c.params = {p.name: float(x) for p, x in zip(c.parameters, result.x[at:at + len(c.parameters)])}
            c.intervals = Intervals(result, params, at, at + len(c.parameters))
            c.units = {p.name: p.unit for p in c.parameters}
            c.fit, at = result, at + len(c.parameters)
        linear_values = np.ones(len(self.linear))  # an owned factor stays at the data sheet's 1
        linear_values[free] = self.linear_values(result.x, bool(force_path), len(linear))
        car_only = build(base, self.linear + [p for c in cars for p in c.parameters],
                         np.concatenate([linear_values] + [list(c.params.values()) for c in cars]))
        vehicle = self.with_sensors(car_only, sensors, judged=len(sensors) < len(named))  # another cause named
        subsystems = {c.cause.subsystem for c in named} | {"car"}
        simulated = self.simulate(vehicle, subsystems, on)
        return self.model(vehicle, named, simulated, linear_values)

    def from_evidence(self, candidate: Candidate, on: Model) -> Model:
        """``on`` with ``candidate``'s cause fitted jointly with the linear parameters from where the force laws put
        it (its parameters' start: a payload from the body's measured mass and CG) and from the data sheet's linear
        values: a departure the recalibration took up in other factors (a payload 1 m behind the CG as rear springs
        25 % stiffer) is fitted back to where it was measured."""
        fresh = dataclasses.replace(candidate, params={p.name: p.initial for p in candidate.parameters})
        return self.joint(on, fresh, linear_start=np.ones(len(self.linear)))

    def with_sensors(self, car: Vehicle, sensors: list[Candidate], judged: bool) -> Vehicle:
        """``car`` with each sensor cause estimated again on its residual (channels that only looked faulty on a
        car bent towards them drop out; ``judged``: the model names another cause, ``sensor_groups``)."""
        for sensor in sensors:
            groups = self.sensor_groups(sensor.cause, self.train.simulate_trials([car])[0],
                                        self.test.simulate_trials([car])[0] if judged else None)
            sensor.params, sensor.n_params = groups.per_channel(), groups.n_params
            sensor.parameters, sensor.groups = sensor.cause.group_parameters(groups.groups), groups.describe()
            sensor.units = dict.fromkeys(sensor.params, sensor.cause.unit)
            car = with_extension(car, sensor.effect, sensor.params) if sensor.params else car
        return car

    def form_intervals(self, candidates: Sequence[Candidate]) -> None:
        """Form the intervals of ``candidates`` (their fits' Jacobians at the solutions simulated beside each other,
        one per fit) and hold them as they are: the intervals a diagnosis reports."""
        one_per_fit = {id(c.fit): c for c in candidates}  # the causes of a joint fit share its Jacobian
        largest_first = sorted(one_per_fit.values(), key=lambda c: -len(c.fit.x) if c.fit is not None else 0)
        self.each(lambda c: dict(c.intervals), largest_first)
        for candidate in candidates:
            candidate.intervals = dict(candidate.intervals)

    def adopt(self, candidate: Candidate, model: Model) -> None:
        """``candidate`` takes its joint fit ``model`` (whose last named cause is its own fit) when that scores
        better on the held-out data."""
        if model.score >= candidate.tddi_holdout:
            return
        fitted = model.named[-1]
        for key in ("params", "intervals", "fit", "n_params", "parameters", "groups", "units"):
            setattr(candidate, key, getattr(fitted, key))
        candidate.vehicle, candidate.tddi_holdout, candidate.simulated = model.vehicle, model.score, model.simulated
        candidate.linear_values = model.linear_values

    def as_model(self, candidate: Candidate, on: Model, formed: bool) -> Model:
        """The model ``on`` with ``candidate`` (fitted on top of it) named; ``formed``: with its evidence on the fit
        data formed (one simulation), else without (hints and fit-data residual of ``on``)."""
        linear = on.linear_values if candidate.linear_values is None else candidate.linear_values
        named = [*on.named, candidate]
        if formed:
            return self.model(candidate.vehicle, named, candidate.simulated, linear)
        return Model(candidate.vehicle, named, candidate.simulated, candidate.tddi_holdout, np.asarray(linear),
                     on.train_simulated, on.hints)

