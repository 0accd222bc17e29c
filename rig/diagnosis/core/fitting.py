"""Simulation-in-the-loop least squares of vehicle parameters on a measured rig test.

SciPy's trust-region ``least_squares`` over batched rollouts of vehicle variants (one rollout gives the whole
finite-difference Jacobian). The Jacobian is formed by differences at the start and updated by Broyden's rank-one
secant rule along each step taken, in the parameters scaled by their typical sizes (SciPy's own Broyden solvers are
for square systems, not bounded least squares), and formed by differences again at the solution for the confidence
intervals: a few-step fit simulates its Jacobian twice instead of at every step. That second Jacobian is simulated
when the intervals are first read (``FitResult``, ``Intervals``): a fit that a later fit supersedes never pays for it.
The first point's differences are simulated in one batch with the point itself (the fit asks for them next), so that
the cores run them beside its run. A fit that starts where an earlier fit of the same model ended may take the columns
it formed there (``known``: the linear factors' of a polish, a cause's richer form or a sensor cause's joint fit,
rig/diagnosis/rig_test/candidates.py ``known_columns``) and simulate only the others.
``mujoco.sysid`` fits MjSpec fields through its own rollouts, while these are vehicle-file parameters that the
builder turns into tendons, actuators and bodies on a settled initial state, so the loop is written here. The fits
return SciPy's ``OptimizeResult``; ``intervals`` turns its Jacobian into confidence intervals of the parameters (the
residual samples are band-limited, so they count as the 2 B T independent values a band of B Hz holds over T s per
channel, not as one per sample).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Iterator, Mapping

import numpy as np
from scipy.optimize import OptimizeResult, least_squares
from scipy.stats import t as student

from rig.elements.air_spring import AirSpring
from rig.causes import FitParameter, axles_of, scale_axle
from rig.diagnosis.core.experiment import Experiment
from rig.vehicle.vehicle_file import Vehicle


#: a data sheet's sprung mass is weighed: off by at most this share; beyond it the body carries something the data
#: sheet does not (a payload), mass_error's to name with its mass and place
MASS_TOLERANCE = 0.05


def linear_parameters(vehicle: Vehicle) -> list[FitParameter]:
    """Scale factors of the data-sheet values a real car misses by a few percent: sprung mass (within
    MASS_TOLERANCE), and per axle spring (with parasitic) rate, damping, tyre rate and unsprung mass. An axle on air
    springs has no spring rate to scale (its springs' force is their gas law's; ``air_spring_law`` fits that): a factor
    that changes nothing would leave every interval of a fit undetermined."""
    params = [FitParameter("sprung_mass", 1.0, 1 - MASS_TOLERANCE, 1 + MASS_TOLERANCE,
                           lambda v, f: dataclasses.replace(v, sprung_mass=v.sprung_mass * f))]
    for axle in axles_of(vehicle):
        if not isinstance(vehicle.axle_named(axle).law, AirSpring):
            params.append(FitParameter(f"{axle}_spring_rate", 1.0, 0.8, 1.25,
                                       lambda v, f, a=axle: scale_axle(v, a, spring_rate=f, parasitic_rate=f)))
        params += [
            FitParameter(f"{axle}_damping", 1.0, 0.7, 1.4, lambda v, f, a=axle: scale_axle(v, a, damping=f)),
            FitParameter(f"{axle}_tyre_rate", 1.0, 0.8, 1.25, lambda v, f, a=axle: scale_axle(v, a, tyre_rate=f)),
            FitParameter(f"{axle}_unsprung_mass", 1.0, 0.8, 1.25,
                         lambda v, f, a=axle: scale_axle(v, a, unsprung_mass=f)),
        ]
    return params


def build(vehicle: Vehicle, params: list[FitParameter], values: np.ndarray) -> Vehicle:
    """``vehicle`` with each parameter applied at its value, in order."""
    for p, value in zip(params, values):
        vehicle = p.apply(vehicle, float(value))
    return vehicle


def residual_stride(rate: float, top: float) -> int:
    """Every how many samples a fit compares: about four per period of the band's top (two at 512 Hz, 50 Hz)."""
    return max(1, int(rate // (4 * top)))


class FitResult(OptimizeResult):
    """SciPy's ``OptimizeResult`` whose ``jac``, the Jacobian at the solution, is formed by ``jacobian()`` when first
    read."""

    def __init__(self, result: OptimizeResult, jacobian: Callable[[], np.ndarray] | None = None):
        super().__init__(result)
        if jacobian is not None:
            del self["jac"]
            self._jacobian = jacobian

    def __getattr__(self, name: str):
        if name == "jac" and "jac" not in self:
            self["jac"] = self.pop("_jacobian")()
        return super().__getattr__(name)


class Intervals(Mapping):
    """95 % confidence intervals of the parameters ``params[start:stop]`` of a fit over ``params`` (``intervals``),
    formed when first read: name -> (low, high); each divided by ``divided`` where its value was (a gain put into the
    common scale: rig/diagnosis/rig_test/candidates.py ``Run.into_scale``)."""

    def __init__(self, result: OptimizeResult, params: list[FitParameter], start: int = 0, stop: int | None = None,
                 divided: np.ndarray | None = None):
        self._result, self._params, self._span = result, params, slice(start, stop)
        self._divided = np.ones(len(params[self._span])) if divided is None else divided
        self._formed: dict[str, tuple[float, float]] | None = None

    def _values(self) -> dict[str, tuple[float, float]]:
        if self._formed is None:
            spread = intervals(self._result, self._params)[self._span]
            self._formed = {p.name: (float(low / d), float(high / d)) for p, (low, high), d in
                            zip(self._params[self._span], spread, self._divided)}
        return self._formed

    def __getitem__(self, name: str) -> tuple[float, float]:
        return self._values()[name]

    def unconverged(self) -> list[str]:
        """The parameters that the Gauss-Newton step from the solution (``newton_step``) takes out of their interval:
        a fit stopped by its budget before it converged (a converged fit's step is within its noise)."""
        stepped = (self._result.x + newton_step(self._result, self._params))[self._span] / self._divided
        return [name for (name, (low, high)), x in zip(self._values().items(), stepped) if not low <= x <= high]

    def __iter__(self) -> Iterator[str]:
        return iter(self._values())

    def __len__(self) -> int:
        return len(self._params[self._span])


def newton_step(result: OptimizeResult, params: list[FitParameter]) -> np.ndarray:
    """The Gauss-Newton step from a fit's solution, on its Jacobian there (``result.jac``), in the parameters scaled
    by their typical sizes as ``fit_car`` takes them, held within their bounds."""
    sizes = np.array([p.typical or p.high - p.low for p in params])
    step = np.linalg.lstsq(np.atleast_2d(result.jac) * sizes, -result.fun, rcond=None)[0] * sizes
    low, high = np.array([p.low for p in params]), np.array([p.high for p in params])
    return np.clip(result.x + step, low, high) - result.x


def fit_space(params: list[FitParameter], start: np.ndarray | None = None
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """A car fit's start (``start``, else each parameter's initial value) inside its bounds, the bounds, and each
    parameter's typical size (its scale in the fit)."""
    low, high = np.array([p.low for p in params]), np.array([p.high for p in params])
    x0 = np.array([p.initial for p in params]) if start is None else np.asarray(start, float)
    return np.clip(x0, low, high), low, high, np.array([p.typical or p.high - p.low for p in params])


def car_residuals(experiment: Experiment) -> Callable[[np.ndarray], np.ndarray]:
    """The residual a car fit minimises, of simulated car channels (samples x channels): each channel's error over
    its measured rms, at the residual stride, flattened."""
    scale = np.sqrt(np.mean(experiment.measured**2, axis=0))
    stride = residual_stride(experiment.record.rate, experiment.band[1])
    return lambda simulated: ((simulated - experiment.measured) / scale)[::stride].ravel()


def fit_car(experiment: Experiment, vehicle: Vehicle, params: list[FitParameter], start: np.ndarray | None = None,
            max_evaluations: int = 8, known: Mapping[int, np.ndarray] | None = None,
            simulate: Callable[[list[Vehicle]], list[np.ndarray]] | None = None) -> FitResult:
    """Fit ``params`` to the car channels of ``experiment`` (car on the measured posts); ``.x`` holds the values,
    ``.jac`` the Jacobian at them (formed by differences when first read), ``.held_jacobian`` the one the fit held
    there (by differences or Broyden's update; None where it held none there). ``known``: columns of the Jacobian at the
    start that are known already (parameter index -> column, from other fits at the same values), not simulated
    again. ``simulate``: the compared car channels of trial vehicles (default: their rollouts,
    ``Experiment.simulate_trials``; rig/diagnosis/rig_test/frequency_fit.py gives a linear car's frequency
    response instead)."""
    known = dict(known or {})
    x0, low, high, sizes = fit_space(params, start)
    steps = 0.01 * sizes
    residuals_of = car_residuals(experiment)
    last: dict = {}
    ahead: dict = {}  # the residuals at the first point's shifted points, simulated beside it

    def shifted(x, skip=()):  # parameter index -> the point whose difference forms that column of the Jacobian at x
        points = {}
        for i in (i for i in range(len(x)) if i not in skip):
            y = x.copy()
            y[i] = y[i] + steps[i] if y[i] + steps[i] <= high[i] else y[i] - steps[i]
            points[i] = y
        return points

    def residuals(points):
        trials = simulate or experiment.simulate_trials  # looked up when simulated (a test may watch it)
        return [residuals_of(run) for run in trials([build(vehicle, params, y) for y in points])]

    def fun(x):
        if last.get("x") is None or not np.array_equal(last["x"], x):
            # the fit asks for the Jacobian at its first point next: its columns run in the same batch, on the cores
            # beside the point's own run instead of after it
            around = {} if last else shifted(x, known)
            r, *columns = residuals([x, *around.values()])
            if around:
                ahead.update(x=x.copy(), columns=dict(zip(around, columns)))
            last.update(x=x.copy(), r=r)
        return last["r"]

    def differences(x, base=None, skip=()):  # base: the residual at x, where known; skip: columns not simulated
        base = fun(x) if base is None else base
        J = np.zeros((base.size, len(x)))
        points = shifted(x, skip)
        done = ahead["columns"] if ahead and np.array_equal(ahead["x"], x) else {}
        missing = [i for i in points if i not in done]
        if missing:
            done = {**done, **dict(zip(missing, residuals([points[i] for i in missing])))}
        for i, y in points.items():
            J[:, i] = (done[i] - base) / (y[i] - x[i])
        return J

    secant: dict = {}

    def jac(x):
        if not secant:
            J = differences(x, skip=known)
            for i, column in known.items():
                J[:, i] = column
            secant.update(x=x.copy(), r=fun(x), J=J, exact=not known)
        elif not np.array_equal(x, secant["x"]):  # Broyden's update along the step taken, in the scaled parameters
            r = fun(x)
            step = (x - secant["x"]) / sizes
            J = secant["J"] + np.outer(r - secant["r"] - secant["J"] @ (step * sizes), step / sizes) / (step @ step)
            secant.update(x=x.copy(), r=r, J=J, exact=False)
        return secant["J"]

    result = least_squares(fun, x0, jac=jac, bounds=(low, high), x_scale=sizes, max_nfev=max_evaluations,
                           method="trf", ftol=1e-4, xtol=1e-4)
    held = bool(secant) and np.array_equal(secant["x"], result.x)
    exact = held and secant["exact"]  # else differences at the solution
    result = FitResult(result, None if exact else lambda x=result.x, r=result.fun: differences(x, r))
    result.held_jacobian = secant["J"] if held else None
    result.independent = independent_samples(experiment, experiment.measured.shape[1])
    return result


def fit_posts(experiment: Experiment, vehicle: Vehicle, params: list[FitParameter]) -> OptimizeResult:
    """Fit ``params`` so that the rig model's achieved post displacement follows the measured one under
    the measured drives; ``.x`` holds the values."""
    scale = np.sqrt(np.mean(experiment.measured_posts**2, axis=0))
    stride = residual_stride(experiment.record.rate, experiment.band[1])

    def fun(x):
        simulated = experiment.simulate_post_trials([build(vehicle, params, x)])[0]
        return ((simulated - experiment.measured_posts) / scale)[::stride].ravel()

    span = [p.high - p.low for p in params]
    result = least_squares(fun, [p.initial for p in params], bounds=([p.low for p in params], [p.high for p in params]),
                           x_scale=[p.typical or s for p, s in zip(params, span)],
                           diff_step=[p.relative_step or 0.01 for p in params], max_nfev=20)
    result.independent = independent_samples(experiment, experiment.measured_posts.shape[1])
    return result


def independent_samples(experiment: Experiment, channels: int) -> float:
    """How many independent values the compared channels hold: 2 B T per channel for a band of B Hz over T s."""
    low, high = experiment.band
    return 2 * (high - low) * experiment.compared_seconds * channels


def intervals(result: OptimizeResult, params: list[FitParameter], confidence: float = 0.95
              ) -> list[tuple[float, float]]:
    """Confidence intervals of fitted parameters (in the order of ``params``) from the optimiser's Jacobian at its
    solution: covariance s^2 (J^T J)^-1, s^2 the residual variance per independent value (``result.independent``),
    Student's t. A parameter the data do not determine (a singular direction) gets an infinite interval; a parameter
    at a bound is reported as it is (the interval is then only a local statement)."""
    jacobian, residual = np.atleast_2d(result.jac), result.fun
    samples = residual.size
    independent = min(float(getattr(result, "independent", samples)), samples)
    dof = max(1.0, independent - len(params))
    variance = float(residual @ residual) / samples * independent / dof  # per-sample power, counted per value
    normal = jacobian.T @ jacobian * independent / samples
    try:
        covariance = variance * np.linalg.inv(normal)
        spread = np.sqrt(np.clip(np.diag(covariance), 0.0, None))
    except np.linalg.LinAlgError:
        spread = np.full(len(params), np.inf)
    half = student.ppf(0.5 + confidence / 2, dof) * spread
    return [(float(x - h), float(x + h)) for x, h in zip(result.x, half)]
