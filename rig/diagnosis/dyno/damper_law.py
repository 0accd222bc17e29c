"""Damper force laws fitted to a dynamometer test: the forms, their least-squares fits with confidence
intervals, and the choice among them by an information criterion.

At the damper (dyno) level, v the rod's extension rate (m/s) and F the force, positive resisting extension (N),
so rebound lies in the first quadrant. Base forms:

    linear                F = c v
    asymmetric            F = c_rebound v (v > 0), c_compression v (v < 0)
    quadratic             F = c0 v + cn v|v|   ("Neuro Model for Passive Suspension of a Light Car" (paper): C0 + Cn v)
    quadratic_asymmetric  the same with its own c0, cn in rebound and in compression
    digressive            per direction the slope c_low up to the knee speed, c_high beyond

and modifiers, each a parameter more:

    +preload      F = ... - preload: a constant force pushing the rod out (the gas pressure on the rod), N
    +series       the damper in series with a stiffness series_rate (N/m): it moves at v - (dF/dt)/series_rate,
                  so the force lags the velocity (hysteresis loops); fitted as an equation error, with the force's
                  measured rate
    +temperature  every coefficient of the base form scales by 1 + temperature_drift (T - T_ref), 1/degC

Every combination is fitted (``scipy.optimize.least_squares``, trust-region reflective; a digressive knee starts
from the best of a grid, where the rest is linear). Each coefficient has a 95 % interval from the Jacobian at the
optimum, ``cov = s^2 (J^T J)^-1``, widened by the residual's autocorrelation (the samples are not independent:
the effective number of samples is n / (1 + 2 sum rho_k)). The law is chosen by the Bayesian information
criterion on that effective number, ``n_eff ln(SSR / n) + p ln(n_eff)``: a parameter must pay for itself.
Written here: the forms and their fits (the choice among them: rig/diagnosis/dyno/damper_choice.py); the optimiser is
SciPy's.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from itertools import product

import numpy as np
from scipy import optimize, stats

from rig.diagnosis.dyno.damper_dynamics import friction_shape, lagged
from rig.diagnosis.dyno.dyno_test import DynoError, DynoRun, DynoTest
from rig.signal.neuro_network import unit
from rig.signal.residual_tests import ResidualTests, residual_tests

UNITS = {"c": "N s/m", "c_rebound": "N s/m", "c_compression": "N s/m", "c0": "N s/m", "cn": "N s^2/m^2",
         "c0_rebound": "N s/m", "cn_rebound": "N s^2/m^2", "c0_compression": "N s/m", "cn_compression": "N s^2/m^2",
         "c_low_rebound": "N s/m", "c_high_rebound": "N s/m", "knee_rebound": "m/s", "c_low_compression": "N s/m",
         "c_high_compression": "N s/m", "knee_compression": "m/s", "preload": "N", "series_rate": "N/m",
         "temperature_drift": "1/degC", "lag_time": "s", "friction": "N", "friction_reach": "m",
         "gas_rate": "N/m"}
NEURO_UNITS = {"w": "s/m", "b": "-", "a": "N"}  # a neuro law's unit j: w<j>, b<j>, a<j>
BASE_FORMS = ("linear", "asymmetric", "quadratic", "quadratic_asymmetric", "digressive")
MODIFIERS = ("preload", "series", "temperature")
DYNAMIC = ("lag", "hysteresis")  # damper_dynamics.py, fitted by dynamic_damper_fit.py
POSITIVE = ("lag_time", "friction_reach")  # fitted as they are, used as their magnitude
CONFIDENCE = 0.95
SAMPLES_PER_WINDOW = 100000  # samples fitted per differentiator window
KNEE_GRID = np.linspace(0.1, 0.8, 8)  # knee candidates, as fractions of each direction's peak speed


def _ramp(v: np.ndarray, knee: float) -> np.ndarray:
    """Speed beyond a knee in each direction's own sense (knee > 0: rebound side, < 0: compression side)."""
    return np.maximum(v - knee, 0.0) if knee > 0 else np.minimum(v - knee, 0.0)


def _base_force(form: str, p: dict[str, float], v: np.ndarray) -> np.ndarray:
    """F of a base form at extension rate ``v`` (m/s), N."""
    rebound = v > 0
    if form == "linear":
        return p["c"] * v
    if form == "asymmetric":
        return np.where(rebound, p["c_rebound"], p["c_compression"]) * v
    if form == "quadratic":
        return p["c0"] * v + p["cn"] * v * np.abs(v)
    if form == "quadratic_asymmetric":
        return np.where(rebound, p["c0_rebound"] * v + p["cn_rebound"] * v * v,
                        p["c0_compression"] * v - p["cn_compression"] * v * v)
    if form == "digressive":
        return (np.where(rebound, p["c_low_rebound"], p["c_low_compression"]) * v
                + (p["c_high_rebound"] - p["c_low_rebound"]) * _ramp(v, p["knee_rebound"])
                + (p["c_high_compression"] - p["c_low_compression"]) * _ramp(v, -p["knee_compression"]))
    if form == "neuro":
        units = range(1, sum(k.startswith("w") for k in p) + 1)
        return p["c"] * v + sum(p[f"a{j}"] * (unit(p[f"w{j}"] * v + p[f"b{j}"]) - unit(p[f"b{j}"])) for j in units)
    raise ValueError(f"unknown damper law form '{form}' (known: {', '.join(BASE_FORMS)}, neuro)")


def unit_of(key: str) -> str:
    """The unit of a coefficient (SI)."""
    return UNITS.get(key) or NEURO_UNITS[key[0]]


def base_parameters(form: str) -> tuple[str, ...]:
    """The coefficient names of a base form, in fitting order."""
    return {"linear": ("c",), "asymmetric": ("c_rebound", "c_compression"), "quadratic": ("c0", "cn"),
            "quadratic_asymmetric": ("c0_rebound", "cn_rebound", "c0_compression", "cn_compression"),
            "digressive": ("c_low_rebound", "c_high_rebound", "knee_rebound", "c_low_compression",
                           "c_high_compression", "knee_compression")}[form]


@dataclass(frozen=True)
class DamperLaw:
    """A damper force law: a base form, its modifiers and their coefficients (SI, see ``UNITS``);
    ``reference_temperature`` (degC) is where the temperature drift is zero."""

    form: str
    coefficients: dict[str, float]
    preload: bool = False
    series: bool = False
    temperature: bool = False
    reference_temperature: float | None = None
    lag: bool = False
    hysteresis: bool = False

    @property
    def name(self) -> str:
        """``form`` and its modifiers: ``digressive+preload+temperature``."""
        return "+".join([self.form] + [m for m in MODIFIERS + DYNAMIC if getattr(self, m)])

    @property
    def dynamic(self) -> bool:
        """Whether the force depends on the run's history (a lag, a friction's hysteresis)."""
        return self.lag or self.hysteresis

    def base_force(self, velocity: np.ndarray, temperature: float | None = None) -> np.ndarray:
        """The force (N) at damper velocity ``velocity`` (m/s), without preload or compliance, at ``temperature``
        (degC; the reference temperature when None)."""
        force = _base_force(self.form, self.coefficients, np.asarray(velocity, dtype=float))
        return force * self.temperature_scale(temperature)

    def temperature_scale(self, temperature) -> np.ndarray | float:
        """Factor on the base form's coefficients at ``temperature`` (degC; None: the reference)."""
        if not self.temperature or temperature is None:
            return 1.0
        return 1.0 + self.coefficients["temperature_drift"] * (np.asarray(temperature) - self.reference_temperature)

    def force(self, velocity: np.ndarray, force_rate: np.ndarray | None = None,
              temperature: np.ndarray | None = None) -> np.ndarray:
        """The law's force (N) at rod velocity (m/s), with the force's rate (N/s) for a series compliance and
        the temperature (degC) for a drift."""
        velocity = np.asarray(velocity, dtype=float)
        if self.series:
            velocity = velocity - np.asarray(force_rate) / self.coefficients["series_rate"]
        force = self.base_force(velocity, temperature)
        return force - self.coefficients["preload"] if self.preload else force

    def along(self, run: DynoRun, force_rate: np.ndarray | None = None, temperature=None) -> np.ndarray:
        """The law's force (N) along a run: its velocity and displacement, the force's rate (``force_rate``, N/s;
        default the run's own) and the temperature (degC; default the run's), the lag and the hysteresis through
        the run's history."""
        rate_of_force = run.force_rate if force_rate is None else force_rate
        heat = run.temperature if temperature is None else temperature
        preload = self.coefficients["preload"] if self.preload else 0.0
        force = self.force(run.velocity, rate_of_force, heat if self.temperature else None) + preload
        if self.lag:
            force = lagged(force, run.rate, self.coefficients["lag_time"])
        if self.hysteresis:
            force = force + self.coefficients["friction"] * friction_shape(
                run.displacement, run.velocity, self.coefficients["friction_reach"]) \
                + self.coefficients["gas_rate"] * run.displacement
        return force - preload


@dataclass(frozen=True)
class FittedLaw:
    """A law fitted to a dyno test: 95 % ``intervals`` per coefficient, the residual's RMS in percent of the
    force's RMS, the information criterion (lower is better), the number of parameters and the residual (force
    minus fit, N, every sample of the test, run after run)."""

    law: DamperLaw
    intervals: dict[str, tuple[float, float]]
    residual_rms_pct: float
    bic: float
    parameters: int
    residual: np.ndarray = field(repr=False)
    effective_samples: float = 0.0
    tests: ResidualTests | None = None  # the residual's whiteness (rig/signal/residual_tests.py)


@dataclass(frozen=True)
class DamperFit:
    """Every form fitted to a test, best (lowest BIC) first; ``samples`` and ``effective_samples`` (after the
    residual's autocorrelation) are what the intervals and the criterion used."""

    forms: tuple[FittedLaw, ...]
    samples: int
    effective_samples: float
    test: DynoTest = field(repr=False)
    tried_dynamics: bool = False  # the laws with dynamics were fitted because the static ones failed

    @property
    def chosen(self) -> FittedLaw:
        return self.forms[0]

    def form(self, name: str) -> FittedLaw:
        """The fit of the law called ``name`` (e.g. ``quadratic+preload``)."""
        for fitted in self.forms:
            if fitted.law.name == name:
                return fitted
        raise KeyError(f"no law '{name}' was fitted (fitted: {', '.join(f.law.name for f in self.forms)})")


@dataclass(frozen=True)
class FitData:
    velocity: np.ndarray
    force: np.ndarray
    force_rate: np.ndarray
    temperature: np.ndarray | None
    reference_temperature: float | None
    run: np.ndarray                # index of each sample's run
    weight: np.ndarray | None = None  # per sample: 1 / the RMS residual of its run (None: unweighted)


def candidate_names(temperature: bool) -> list[str]:
    """Every law the fit tries: each base form with each combination of modifiers."""
    modifiers = MODIFIERS if temperature else MODIFIERS[:2]
    names = []
    for form, flags in product(BASE_FORMS, product((False, True), repeat=len(modifiers))):
        names.append("+".join([form] + [m for m, on in zip(modifiers, flags, strict=True) if on]))
    return names


def fit_samples(test: DynoTest, reference_temperature: float | None) -> FitData:
    """The samples fitted: every run's, thinned to ``SAMPLES_PER_WINDOW`` per differentiator window (the velocity
    is smooth over a window; more samples would only repeat it)."""
    picks = [slice(None, None, max(1, run.window // SAMPLES_PER_WINDOW)) for run in test.runs]

    def joined(quantity: str) -> np.ndarray:
        return np.concatenate([getattr(run, quantity)[pick] for run, pick in zip(test.runs, picks, strict=True)])

    temperature = joined("temperature") if test.has_temperature else None
    if temperature is not None and reference_temperature is None:
        reference_temperature = float(np.mean(temperature))
    run = np.concatenate([np.full(run.force[pick].size, i) for i, (run, pick) in
                          enumerate(zip(test.runs, picks, strict=True))])
    return FitData(joined("velocity"), joined("force"), joined("force_rate"), temperature, reference_temperature,
                 run)


def effective_samples(residual: np.ndarray) -> float:
    """n / (1 + 2 sum rho_k), the sum over the residual's autocorrelation up to its first lag below 0.05."""
    n = residual.size
    centred = residual - residual.mean()
    spectrum = np.fft.rfft(centred, 2 * n)
    correlation = np.fft.irfft(spectrum * np.conj(spectrum))[:n]
    rho = correlation / correlation[0]
    below = np.flatnonzero(rho[1:] < 0.05)
    lags = below[0] if below.size else n - 1
    return float(n / max(1.0 + 2.0 * rho[1:lags + 1].sum(), 1.0))


def _split_name(name: str) -> tuple[str, set[str]]:
    form, *modifiers = name.split("+")
    unknown = [m for m in modifiers if m not in MODIFIERS]
    if form not in BASE_FORMS or unknown:
        raise DynoError(f"unknown damper law '{name}': a form ({', '.join(BASE_FORMS)}) and modifiers "
                         f"+{', +'.join(MODIFIERS)}")
    return form, set(modifiers)


def fit_law(name: str, data: FitData) -> tuple[DamperLaw, np.ndarray, np.ndarray, np.ndarray]:
    """Least squares of one law: the law, its parameter vector, (weighted) residual and Jacobian at the optimum.

    Levenberg-Marquardt (MINPACK) without bounds: a knee is used as its magnitude, and a series compliance is
    fitted as the square of a parameter, ``1 / series_rate = q^2``, so that it cannot turn negative.
    """
    form, modifiers = _split_name(name)
    if "temperature" in modifiers and data.temperature is None:
        raise DynoError(f"law '{name}' needs damper/temperature in every record")
    names = list(base_parameters(form)) + [m for m in MODIFIERS if m in modifiers]
    start = _start(form, modifiers, data)

    def make(x: np.ndarray) -> DamperLaw:
        values = dict(zip(names, x, strict=True))
        for knee in ("knee_rebound", "knee_compression"):
            if knee in values:
                values[knee] = abs(values[knee])
        if "series" in modifiers:
            values["series_rate"] = 1.0 / max(values.pop("series") ** 2, 1e-300)
        if "temperature" in modifiers:
            values["temperature_drift"] = values.pop("temperature")
        return DamperLaw(form, values, "preload" in modifiers, "series" in modifiers, "temperature" in modifiers,
                         data.reference_temperature if "temperature" in modifiers else None)

    weight = 1.0 if data.weight is None else data.weight

    def residual(x: np.ndarray) -> np.ndarray:
        return (make(x).force(data.velocity, data.force_rate, data.temperature) - data.force) * weight

    result = optimize.least_squares(residual, start, x_scale="jac", method="lm")
    return make(result.x), result.x, result.fun, result.jac


def _start(form: str, modifiers: set[str], data: FitData) -> np.ndarray:
    """Initial parameters: the base form (and preload) by linear least squares, a digressive knee from a grid,
    a small compliance (a 1 ms lag) and no drift."""
    v, force = data.velocity, data.force
    columns, knees = linear_columns(form, v, force, "preload" in modifiers)
    if form == "digressive":
        peak_r, peak_c = max(v.max(), 1e-6), max(-v.min(), 1e-6)
        knees = min(((kr * peak_r, kc * peak_c) for kr in KNEE_GRID for kc in KNEE_GRID),
                    key=lambda k: _ssr(columns(k), force))
    coefficients = np.linalg.lstsq(columns(knees), force, rcond=None)[0]
    start = _base_start(form, coefficients, knees)
    if "preload" in modifiers:
        start.append(-coefficients[-1])
    if "series" in modifiers:
        slope = max(np.dot(v, force) / np.dot(v, v), 1.0)
        start.append(np.sqrt(1e-3 / slope))
    if "temperature" in modifiers:
        start.append(0.0)
    return np.array(start, float)


def linear_columns(form: str, v: np.ndarray, force: np.ndarray, preload: bool
                    ) -> tuple[Callable[[tuple[float, float]], np.ndarray], tuple[float, float]]:
    """The design matrix of a base form given its knees (where it is linear in the rest), and default knees."""
    rebound, compression = np.maximum(v, 0.0), np.minimum(v, 0.0)

    def columns(knees: tuple[float, float]) -> np.ndarray:
        cols = {"linear": [v], "asymmetric": [rebound, compression], "quadratic": [v, v * np.abs(v)],
                "quadratic_asymmetric": [rebound, rebound ** 2, compression, -compression ** 2],
                "digressive": [rebound, _ramp(v, knees[0]), compression, _ramp(v, -knees[1])]}[form]
        return np.column_stack(cols + ([np.ones_like(v)] if preload else []))

    return columns, (0.3 * max(v.max(), 1e-6), 0.3 * max(-v.min(), 1e-6))


def _base_start(form: str, coefficients: np.ndarray, knees: tuple[float, float]) -> list[float]:
    """The base form's parameters from the linear coefficients (digressive: slopes from slope changes)."""
    if form != "digressive":
        return list(coefficients[:len(base_parameters(form))])
    low_r, change_r, low_c, change_c = coefficients[:4]
    return [low_r, low_r + change_r, knees[0], low_c, low_c + change_c, knees[1]]


def _ssr(columns: np.ndarray, force: np.ndarray) -> float:
    solution, residual, *_ = np.linalg.lstsq(columns, force, rcond=None)
    return float(residual[0]) if residual.size else float(np.sum((columns @ solution - force) ** 2))


def summarise(law: DamperLaw, x: np.ndarray, residual: np.ndarray, jacobian: np.ndarray, test: DynoTest,
               n_eff: float) -> FittedLaw:
    """Intervals from the Jacobian of the weighted fit (widened for correlated samples), BIC, and the RMS residual
    over every sample of the test in percent of the force's RMS."""
    n, p = residual.size, x.size
    ssr = float(np.sum(residual ** 2))
    variance = ssr / max(n - p, 1) * n / n_eff
    covariance = np.linalg.pinv(jacobian.T @ jacobian) * variance
    errors = np.sqrt(np.clip(np.diag(covariance), 0.0, None))
    half = stats.t.ppf(0.5 + CONFIDENCE / 2, max(n_eff - p, 1)) * errors
    intervals = {}
    for key, value, width in zip(law.coefficients, x, half, strict=True):
        if key == "series_rate":  # fitted as q, 1 / rate = q^2: the q interval mapped (inf: no upper bound)
            q = abs(value)
            intervals[key] = (float(1.0 / (q + width) ** 2), float(1.0 / (q - width) ** 2) if q > width else np.inf)
        else:
            value = abs(value) if key.startswith("knee") or key in POSITIVE else value
            intervals[key] = (float(value - width), float(value + width))
    force = test.joined("force")
    everywhere = force - np.concatenate([law.along(run) for run in test.runs])
    rms = 100.0 * np.sqrt(np.mean(everywhere ** 2) / np.mean(force ** 2))
    bic = n_eff * np.log(ssr / n) + p * np.log(n_eff)
    return FittedLaw(law, intervals, float(rms), float(bic), p, everywhere, n_eff, _tests(law, everywhere, test, p))


def _tests(law: DamperLaw, residual: np.ndarray, test: DynoTest, parameters: int) -> ResidualTests | None:
    """The residual's whiteness against the rod's velocity and displacement, run by run end to end, at every sample
    (the force is measured as it is; only the velocity is smoothed); None where the test holds too few samples."""
    try:
        return residual_tests(law.name, residual, {"velocity": test.joined("velocity"),
                                                   "displacement": test.joined("displacement")},
                              parameters, test.runs[0].rate)
    except ValueError:
        return None
