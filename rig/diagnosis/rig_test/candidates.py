"""Candidate causes fitted on a prepared rig test: the recalibrated model, each cause screened on top of a model,
and joint fits of several causes with the linear parameters.

A ``Model`` is what the diagnosis holds at one moment: a vehicle, the causes it names, its held-out simulation
and score, and where its residual on the fit data lives (the hints that start shape-seeking causes). Screening
fits one cause's own parameters on top of a model by the strategy of its subsystem: car causes by
simulation-in-the-loop least squares (rig/diagnosis/core/fitting.py), rig causes on the drive -> post displacement
path, sensor causes from the model's residual, grouped as a DAQ groups channels (rig/diagnosis/rig_test/sensors.py).
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
import threading
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from typing import TypeVar

import numpy as np
from scipy.optimize import OptimizeResult

from rig.causes import CAUSES, Cause, FitParameter, Shape, with_extension
from rig.causes.force_constant_error import CAUSE as FORCE_CONSTANT_CAUSE
from rig.causes.force_constant_error import SCALE_TOLERANCE as FORCE_SCALE_TOLERANCE
from rig.diagnosis.rig_test.evidence import locate_residual
from rig.diagnosis.core.experiment import Experiment
from rig.diagnosis.core.fitting import (MASS_TOLERANCE, Intervals, build, fit_car, fit_posts, intervals,
                                       linear_parameters)
from rig.diagnosis.rig_test.force_laws import ForceLaws
from rig.diagnosis.rig_test.frequency_fit import fit_car_frequency, stays_linear
from rig.diagnosis.rig_test.input_chain import InputChain
from rig.diagnosis.rig_test.modes import pattern_peaks
from rig.diagnosis.rig_test.neuro_corner_law import LearnedLaw, learn_laws
from rig.diagnosis.core.noise import measurement_floor
from rig.diagnosis.rig_test.diagnosis_results import Candidate, LinearFit
from rig.diagnosis.rig_test.sensors import ChannelGroups, described, group_channels
from rig.diagnosis.core.timing import StageClock
from rig.diagnosis.core.validation import mean_tddi
from rig.io.channels import split_channel
from rig.vehicle.vehicle_file import Vehicle

FORCE_CONSTANT = FORCE_CONSTANT_CAUSE.name
LINEAR = "linear"   # the owner of the linear parameters and the force path's gains in a fit's keys
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

    @property
    def found(self) -> list[Candidate]:
        """The causes the selection named, after those of the input channels corrected first (``checked_first``)."""
        return [c for c in self.named if not c.checked_first]


def known_columns(keys: list[tuple[str, str]], start: np.ndarray, fits: list, cars: set[str]) -> dict[int, np.ndarray]:
    """The columns of a joint fit's Jacobian at ``start`` (its parameters named by ``keys``: owner and name) for the
    linear factors and the force path's gains, from the first of ``fits`` (earlier fits of the same experiment, their
    ``parameter_keys`` set) that ended at the same linear values with every car cause of the new fit (``cars``) in
    its model: parameter index -> column. A fit's Jacobian at its solution is the one formed there by differences
    where it was (for its intervals), else the one it held (``held_jacobian``). So a polish, a cause's richer form and
    a sensor cause take the columns of the fit they build on; a car cause added to a model does not: its own effect
    moves those columns (taking them from the recalibration, the truck's driveline mounts, started 2 Hz off, ended
    with a damping 36 % high, where the fit that simulated them ends 4.7 % high; the rebound stop's gain fell from
    0.755 to 0.725 with its screening's columns too), and neither does a cause fitted from the measured evidence (it
    starts at the data sheet's values)."""
    linear = [i for i, key in enumerate(keys) if key[0] == LINEAR]
    for fit in (f for f in fits if f is not None and f.get("parameter_keys") is not None):
        jacobian = fit["jac"] if "jac" in fit else fit.get("held_jacobian")
        where = {key: i for i, key in enumerate(fit["parameter_keys"])}
        owners = {owner for owner, _ in where}
        if jacobian is None or not cars <= owners or not all(
                keys[i] in where and fit.x[where[keys[i]]] == start[i] for i in linear):
            continue
        return {i: jacobian[:, where[keys[i]]] for i in linear}
    return {}


def force_path_parameters(vehicle: Vehicle, train: Experiment, hints: dict) -> list[FitParameter]:
    """The force actuators' gains, fitted beside the linear parameters and left out of the model (module docstring),
    where the record has an actuator force; else none."""
    quantities = {split_channel(n)[1] for n in train.record.names}
    if not CAUSES[FORCE_CONSTANT].shows_in(vehicle.layout, quantities):
        return []
    return [dataclasses.replace(p, name=f"force_path_{p.name}", typical=abs(p.initial))
            for p in CAUSES[FORCE_CONSTANT].fit_parameters(vehicle, hints)]


class Run:
    """One diagnosis's fitting: the fit and held-out experiments, the recalibrated model, screening and joint fits."""

    def __init__(self, vehicle: Vehicle, train: Experiment, test: Experiment, force_laws: ForceLaws,
                 clock: StageClock, inputs: InputChain | None = None, frequency_domain: bool = True):
        self.vehicle, self.train, self.test, self.clock = vehicle, train, test, clock
        self.frequency_domain = frequency_domain  # linear fits on the car's frequency response where it stays linear
        self.force_laws, self.inputs = force_laws, inputs
        self.input_hints = {} if inputs is None else {
            "input_gains": inputs.gains, "gross_inputs": tuple(n for n in inputs.gains if inputs.gross(n))}
        self.measured = test.measured_all()
        self.n_car = len(test.car_channels)
        self.train_floor = measurement_floor(train)[:self.n_car]
        self.workers = len(os.sched_getaffinity(0))  # the cores this process may use
        self._learning, self._learned = threading.Lock(), False
        self.baseline, _ = self.each(lambda task: task(), [self.simulate_baseline, self.recalibrate])
        baseline = self.score(self.baseline)
        for corrected in self.recalibrated.named:  # each one's gain: the data sheet's model with it alone
            alone = self.score(self.simulate(build(self.vehicle, corrected.parameters,
                                                   list(corrected.params.values())), None, None))
            corrected.gain = (baseline - alone) / baseline if baseline > 0 else 0.0

    def each(self, fit: Callable[[T], R], items: Sequence[T]) -> list[R]:
        """``fit`` of each of ``items`` (fits independent of each other), beside each other on the machine's cores (a
        rollout releases the interpreter's lock); the results in the order of ``items``, as one after another."""
        if self.workers < 2 or len(items) < 2:
            return [fit(item) for item in items]
        with ThreadPoolExecutor(min(self.workers, len(items))) as pool:
            return list(pool.map(fit, items))

    def learned_laws(self) -> dict[str, LearnedLaw]:
        """The corner laws learned per axle from the fit data (rig/diagnosis/rig_test/neuro_corner_law.py), kept as
        ``force_laws.learned``: trained once, on whichever thread asks first; a thread that asks meanwhile waits."""
        with self._learning:
            if not self._learned:
                with self.clock.part("learned laws"):
                    laws = self.force_laws
                    laws.learned = laws.learned or learn_laws(self.train.record, self.vehicle, laws.saturated,
                                                              self.test.band)
                self._learned = True
            return self.force_laws.learned

    def simulate_baseline(self) -> np.ndarray:
        """Held-out channels of the data sheet's vehicle (refused where it cannot be simulated: the user's to mend)."""
        with self.clock.part("baseline"):
            return self.test.simulate(self.vehicle)

    def recalibrate(self) -> None:
        """The linear parameters fitted to the data sheet's vehicle: the recalibrated model (module docstring), with
        the input channels' gross faults corrected and fitted beside them (``corrected_inputs``)."""
        with self.clock.part("linear recalibration"):
            vehicle = self.vehicle
            self.linear = linear_parameters(vehicle)
            corrections = self.corrected_inputs()
            corrected = [p for _, own in corrections for p in own]
            named_force = any("active_force" in cause.input_quantities for cause, _ in corrections)
            self.force_path = [] if named_force else force_path_parameters(vehicle, self.train, self.input_hints)
            params = self.linear + corrected + self.force_path
            forces = self.force_gains(params, corrections)
            self.car_linear = self.frequency_domain and not forces.size and not corrected \
                and stays_linear(self.train, vehicle)
            result = self.fit_linear(params, forces)
            result.parameter_keys = [(LINEAR, p.name) for p in self.linear] + [
                (c.name, p.name) for c, own in corrections for p in own] + [(LINEAR, p.name) for p in self.force_path]
            spread = intervals(result, params)
            self.recalibration = LinearFit({}, dict(zip([p.name for p in self.linear], spread)), result)
            x, scale = self.into_scale(result.x, forces)
            linear_values = x[:len(self.linear)]
            self.recalibration.values = {p.name: float(v) for p, v in zip(self.linear, linear_values)}
            at, named = len(self.linear), []
            for cause, own in corrections:
                span = slice(at, at + len(own))
                named.append(Candidate(cause.name, {p.name: float(v) for p, v in zip(own, x[span])}, vehicle, 0.0,
                                       None, n_params=len(own), parameters=own, fit=result,
                                       intervals=Intervals(result, params, span.start, span.stop, scale[span]),
                                       units={p.name: p.unit for p in own}, checked_first=True))
                at += len(own)
            recalibrated = build(vehicle, self.linear + corrected, x[:len(self.linear) + len(corrected)])
            reference = self.simulate(recalibrated, None, None)
            self.recalibrated = self.model(recalibrated, named, reference, linear_values)
            for candidate in named:
                candidate.vehicle, candidate.simulated = recalibrated, reference
                candidate.tddi_holdout = self.recalibrated.score
            self.reference, self.reference_tddi = reference, self.recalibrated.score

    def shown(self, linear_values: np.ndarray | None = None) -> set[Shape]:
        """The force laws' shapes and departures from the data sheet, and the sprung mass's where the recalibration
        (or the fit that left the linear factors at ``linear_values``: a model's) stopped at its tolerance (a payload
        the body's equilibrium could not show: no channel for it)."""
        mass = self.recalibration.values["sprung_mass"] if linear_values is None else \
            dict(zip((p.name for p in self.linear), linear_values))["sprung_mass"]
        at_bound = abs(mass - 1) >= MASS_TOLERANCE - 1e-3
        return self.force_laws.shown(self.vehicle) | ({Shape.SPRUNG_MASS} if at_bound else set())

    def corrected_inputs(self) -> list[tuple[Cause, list[FitParameter]]]:
        """The causes of the input channels the input chain found grossly wrong (reversed, or off by more than
        threefold: rig/diagnosis/rig_test/input_chain.py), with their parameters started there: no recalibration takes
        such a
        fault up, so it is corrected before the recalibration and named (a cause ``checked_first``)."""
        gross = self.input_hints.get("gross_inputs", ())
        if not gross:
            return []
        hints = self.input_hints | {"input_gains": {n: g for n, g in self.input_hints["input_gains"].items()
                                                    if n in gross}}
        causes = [c for c in CAUSES.values() if set(c.input_quantities) & {split_channel(n)[1] for n in gross}]
        found = [(c, [p for p in c.fit_parameters(self.vehicle, hints) if p.initial != 1.0]) for c in causes]
        return [(c, params) for c, params in found if params]

    def force_gains(self, params: list[FitParameter], corrections: list[tuple[Cause, list[FitParameter]]]
                    ) -> np.ndarray:
        """Where among ``params`` the force actuators' gains are: the force path's, or a force corrected first."""
        forces = {id(p) for cause, own in corrections if "active_force" in cause.input_quantities for p in own}
        forces |= {id(p) for p in self.force_path}
        return np.array([i for i, p in enumerate(params) if id(p) in forces], int)

    def into_scale(self, x: np.ndarray, forces: np.ndarray, n_linear: int | None = None
                   ) -> tuple[np.ndarray, np.ndarray]:
        """A fit's values with the force gains' common size put into the common scale of masses, rates and damping
        where it lies within FORCE_SCALE_TOLERANCE of 1 (module docstring): the linear factors (the first
        ``n_linear``, all by default) divided by it, the force path's gains set to 1, a corrected force's factor to its
        sign; and the factor each value was divided by (for its interval)."""
        divided = np.ones(len(x))
        gain = float(np.mean(np.abs(x[forces]))) if forces.size else 1.0
        if abs(gain - 1) <= FORCE_SCALE_TOLERANCE:
            divided[:len(self.linear) if n_linear is None else n_linear] = divided[forces] = gain
        return x / divided, divided

    def fit_linear(self, params: list[FitParameter], forces: np.ndarray) -> OptimizeResult:
        """The linear factors, the corrected inputs' parameters and the force path's gains (``params``) fitted on the
        fit data; on a record with an actuator force, started again from where a fit ended, its force gains put into
        the common scale (``into_scale``), while a start lowers its cost by RESTART_GAIN, at most RESTARTS times:
        the factors and the gains scaled together by a are a valley the trust region slides along slowly (only the
        tyre damping, which no factor scales, keeps it from being flat), so the first fit ends on its side (an exact
        bench: the gains 1.016, the suspension damping 1.5 % high to make up for the tyre damping), where dividing by
        the gains leaves 16 times the noise floor. A reversed force corrected first lies in the same valley: its fit
        ended at -1.016, and the tyre damping the valley's side wants (1.7 % high) was named as a second cause."""
        fit = fit_car_frequency if self.car_linear else fit_car
        result = fit(self.train, self.vehicle, params, max_evaluations=5)
        for _ in range(RESTARTS if forces.size else 0):
            start, divided = self.into_scale(result.x, forces)
            if np.all(divided == 1):  # the gains are force_constant_error's, not the scale's
                break
            again = fit(self.train, self.vehicle, params, start, max_evaluations=5)
            if again.cost > (1 - RESTART_GAIN) * result.cost:
                break
            result = again
        return result

    def model(self, vehicle: Vehicle, named: list[Candidate], simulated: np.ndarray, linear_values: np.ndarray
              ) -> Model:
        """A model with its evidence on the fit data formed (its residual's location there: the hints)."""
        train_simulated = self.train.simulate_trials([vehicle])[0]
        where = locate_residual(self.train, self.train.measured, train_simulated, self.train_floor, 0.0)
        hints = where.to_json() | self.input_hints | {"measured_laws": self.force_laws.measured_laws(self.vehicle),
                                                     "sprung_mass_factor": self.recalibration.values["sprung_mass"],
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
        posts = self.test.simulate_post_trials([vehicle])[0] if "posts" in parts else base.simulated[:, self.n_car:]
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
        fit = fit_car_frequency if self.on_frequency_response(on, [cause]) else fit_car
        result = fit(self.train, on.vehicle, params, x0, max_evaluations=evaluations)
        return self.fitted(cause, params, result, build(on.vehicle, params, result.x), on, refined=refined)

    def on_frequency_response(self, on: Model, causes: Sequence[Cause]) -> bool:
        """Whether a fit of ``causes`` on the model ``on`` runs on the car's frequency response
        (rig/diagnosis/rig_test/frequency_fit.py): where asked for and the recalibration's car stays linear on the fit
        data, for the first round's fits (on the recalibrated model) of causes of the car that keep it linear."""
        return self.car_linear and on is self.recalibrated and all(c.subsystem == "car" and c.linear for c in causes)

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
        rig/diagnosis/rig_test/sensors.py says why)."""
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
        keys = [(LINEAR, p.name) for p in linear] + [(c.effect, p.name) for c in cars + sensors for p in c.parameters] \
            + [(LINEAR, p.name) for p in force_path]
        known = known_columns(keys, start, [c.fit for c in named] + [self.recalibration.result],
                              {c.effect for c in cars})
        fit = fit_car_frequency if self.on_frequency_response(on, [c.cause for c in named]) else fit_car
        with self.clock.part("joint fit of " + " + ".join(c.effect for c in named)):
            result = fit(self.train, base, params, start, max_evaluations=evaluations, known=known)
        result.parameter_keys = keys
        at = len(linear)
        for c in cars:
            c.params = {p.name: float(x) for p, x in zip(c.parameters, result.x[at:at + len(c.parameters)])}
            c.intervals = Intervals(result, params, at, at + len(c.parameters))
            c.units = {p.name: p.unit for p in c.parameters}
            c.fit, at = result, at + len(c.parameters)
        linear_values = np.ones(len(self.linear))  # an owned factor stays at the data sheet's 1
        forces = np.arange(len(params) - len(force_path), len(params))
        linear_values[free] = self.into_scale(result.x, forces, len(linear))[0][:len(linear)]
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

