"""Damper laws with a lag and the forces of the rod's path (rig/diagnosis/dyno/damper_dynamics.py) fitted to a dyno
test,
and the neuro-model paper's network as a damper law of its own ("Neuro Model for Passive Suspension of a Light Car"
(paper)).

A law ``<form>+preload[+series|+temperature][+lag][+hysteresis]`` is its base form's force (through a series
stiffness, or lagged by ``lag_time`` s), less the preload, plus a Dahl friction of ``friction`` (N) turning over
``friction_reach`` (m) and a gas spring of ``gas_rate`` (N/m). It is fitted by output error where it has a lag (the
force simulated along each run from its start; a series stiffness stays an equation error in the force's measured
rate), by SciPy's trust-region least squares (``least_squares``, at most ITERATIONS steps) on every coefficient at
once, each run weighted as ``fit_damper`` weights it. The start: for each lag and reach of a grid (LAG_GRID,
REACH_GRID) the base form's columns (its knees those of its static fit; with a series stiffness, the static law
through it), lagged run by run, with a constant, the friction's shape and the displacement, solved by linear least
squares; the best of the grid.

The form ``neuro`` is the paper's damper network on the rod's velocity, F = c v + sum_j a_j [f(w_j v + b_j) - f(b_j)]
(coefficients ``c``, ``w<j>`` s/m, ``b<j>``, ``a<j>`` N): trained by the paper's unitwise Fisher scoring, its units
chosen by FPE (rig/signal/neuro_network.py), on the force less the path's forces of the best grid point, observed as
the law is (lagged run by run, at the samples the differentiator's window leaves independent), and then refined with
the lag and the path's forces like the other forms.

These laws are tried where the static ones fail (``needs_dynamics``): the best of them leaves more than
TRIGGER_PCT of the force's RMS and a residual that is not white.
"""

from __future__ import annotations

import numpy as np
from scipy import optimize

from rig.diagnosis.dyno.damper_dynamics import friction_shape, lagged
from rig.diagnosis.dyno.damper_law import (
    BASE_FORMS,
    DamperLaw,
    FittedLaw,
    FitData,
    base_parameters,
    linear_columns,
)
from rig.diagnosis.dyno.dyno_test import DynoError, DynoTest
from rig.signal.neuro_network import train

LAG_GRID = np.geomspace(0.002, 0.08, 11)      # s
REACH_GRID = np.geomspace(2e-4, 5e-3, 6)      # m
TRIGGER_PCT = 3.0
NEURO_UNITS = 4
COMBINATIONS = ("lag", "hysteresis", "lag+hysteresis", "series+hysteresis")
ITERATIONS = 40   # trust-region steps at most (each one simulation, and one per parameter for its Jacobian)


def dynamic_names(temperature: bool) -> list[str]:
    """The laws with dynamics: every base form with a preload and a lag, the path's forces or both, or a series
    stiffness with the path's forces (and the drift where the records carry a temperature); the neuro form with a
    preload, alone and with a lag, the path's forces or both."""
    drift = "+temperature" if temperature else ""
    names = []
    for form in BASE_FORMS:
        names += [f"{form}+preload{drift}+{combo}" for combo in COMBINATIONS if "series" not in combo]
        names.append(f"{form}+preload+series{drift}+hysteresis")
    return names + ["neuro+preload"] + [f"neuro+preload+{c}" for c in COMBINATIONS if "series" not in c]


def needs_dynamics(best: FittedLaw) -> bool:
    """Whether the best static law fails: more than TRIGGER_PCT of the force's RMS left, and not white."""
    return best.residual_rms_pct > TRIGGER_PCT and best.tests is not None and not best.tests.white


def fit_dynamic_law(name: str, test: DynoTest, data: FitData, static: dict[str, DamperLaw]
                    ) -> tuple[DamperLaw, np.ndarray, np.ndarray, np.ndarray]:
    """Least squares of one law with dynamics (module docstring): the law, its parameter vector, (weighted) residual
    and Jacobian at the optimum. ``static``: the static fits by name, whose knees start a digressive form's."""
    form, *modifiers = name.split("+")
    known = {"preload", "series", "temperature", "lag", "hysteresis"}
    if (form not in (*BASE_FORMS, "neuro") or "preload" not in modifiers or set(modifiers) - known
            or {"series", "lag"} <= set(modifiers) or (form == "neuro" and {"series", "temperature"} & set(modifiers))):
        raise DynoError(f"unknown damper law '{name}' (known: {', '.join(dynamic_names(True))})")
    temperature = "temperature" in modifiers
    if temperature and data.temperature is None:
        raise DynoError(f"law '{name}' needs damper/temperature in every record")
    flags = {"series": "series" in modifiers, "lag": "lag" in modifiers, "hysteresis": "hysteresis" in modifiers}
    weight = np.ones_like(data.force) if data.weight is None else data.weight
    runs = [np.flatnonzero(data.run == i) for i in range(len(test.runs))]
    if any(index.size != run.force.size for index, run in zip(runs, test.runs, strict=True)):
        raise DynoError(f"law '{name}' is simulated along every sample of a run: a run was thinned")
    start = _grid_start(form, flags, temperature, test, data, weight, runs, static)
    keys = list(start)

    def make(x: np.ndarray) -> DamperLaw:
        values = dict(zip(keys, map(float, x), strict=True))
        if "series" in values:  # fitted as q, 1 / series_rate = q^2, as the static laws fit it
            values["series_rate"] = 1.0 / max(values.pop("series") ** 2, 1e-300)
            values = {k: values.pop(k) for k in [*keys[:keys.index("series")], "series_rate",
                                                 *keys[keys.index("series") + 1:]]}
        for key in ("lag_time", "friction_reach"):
            if key in values:
                values[key] = abs(values[key])
        for key in (k for k in values if k.startswith("knee")):
            values[key] = abs(values[key])
        return DamperLaw(form, values, True, flags["series"], temperature,
                         data.reference_temperature if temperature else None, flags["lag"], flags["hysteresis"])

    def residual(x: np.ndarray) -> np.ndarray:
        law = make(x)
        return np.concatenate([law.along(run) for run in test.runs]) * weight - data.force * weight

    x0 = np.array(list(start.values()))
    result = optimize.least_squares(residual, x0, x_scale="jac", method="trf", max_nfev=ITERATIONS)
    return make(result.x), result.x, result.fun, result.jac


def _grid_start(form: str, flags: dict[str, bool], temperature: bool, test: DynoTest, data: FitData,
                weight: np.ndarray, runs: list[np.ndarray], static: dict[str, DamperLaw]) -> dict[str, float]:
    """The start of every coefficient at the best lag and reach of the grid (module docstring)."""
    taus = LAG_GRID if flags["lag"] else [0.0]
    reaches = REACH_GRID if flags["hysteresis"] else [np.inf]
    if flags["series"]:  # the static law through its series stiffness: one column, its scale fitted
        through = static[f"{form}+preload+series"]
        raw = (np.concatenate([through.along(run) for run in test.runs]) + through.coefficients["preload"])[:, None]
    else:
        columns_of, knees = linear_columns("digressive" if form == "neuro" else form, data.velocity, data.force,
                                            False)
        reference = static.get("digressive+preload")
        if reference is not None and form in ("digressive", "neuro"):
            knees = (reference.coefficients["knee_rebound"], reference.coefficients["knee_compression"])
        raw = columns_of(knees)
    displacement = np.concatenate([run.displacement for run in test.runs])
    best = None
    for tau in taus:
        lagged_columns = _lagged_columns(raw, test, runs, tau)
        for reach in reaches:
            extra = [np.ones_like(data.force)]
            if np.isfinite(reach):
                extra += [np.concatenate([friction_shape(run.displacement, run.velocity, reach) for run in test.runs]),
                          displacement]
            design = np.column_stack([lagged_columns, *extra]) * weight[:, None]
            solution, *_ = np.linalg.lstsq(design, data.force * weight, rcond=None)
            ssr = float(np.sum((design @ solution - data.force * weight) ** 2))
            if best is None or ssr < best[0]:
                best = (ssr, tau, reach, solution)
    _, tau, reach, solution = best
    n_base = raw.shape[1]
    path = (float(solution[n_base + 1]), float(solution[n_base + 2])) if np.isfinite(reach) else (0.0, 0.0)
    preload = float(-solution[n_base])
    if form == "neuro":
        start = _neuro_start(test, data, runs, tau, reach, path, preload)
    elif flags["series"]:
        start = {k: v * (solution[0] if k in base_parameters(form) else 1.0) for k, v in through.coefficients.items()
                 if k not in ("preload", "series_rate")}
        start["series"] = float(np.sqrt(1.0 / through.coefficients["series_rate"]))
    else:
        start = _form_start(form, solution[:n_base], knees)
    start["preload"] = preload
    if flags["series"]:
        start["series"] = start.pop("series")
    if temperature:
        start["temperature_drift"] = 0.0
    if flags["lag"]:
        start["lag_time"] = float(tau)
    if flags["hysteresis"]:
        start.update(friction=path[0], friction_reach=float(reach), gas_rate=path[1])
    return start


def _lagged_columns(columns: np.ndarray, test: DynoTest, runs: list[np.ndarray], tau: float) -> np.ndarray:
    """Each column lagged by ``tau`` run by run."""
    if tau <= 0:
        return columns
    out = np.empty_like(columns)
    for run, index in zip(test.runs, runs, strict=True):
        out[index] = np.column_stack([lagged(columns[index, k], run.rate, tau) for k in range(columns.shape[1])])
    return out


def _form_start(form: str, coefficients: np.ndarray, knees: tuple[float, float]) -> dict[str, float]:
    """A base form's coefficients from its linear columns' solution (a digressive form's slopes from the slope
    changes at its knees)."""
    names = base_parameters(form)
    if form != "digressive":
        return dict(zip(names, map(float, coefficients), strict=True))
    low_r, change_r, low_c, change_c = map(float, coefficients)
    return dict(zip(names, (low_r, low_r + change_r, knees[0], low_c, low_c + change_c, knees[1]), strict=True))


def _neuro_start(test: DynoTest, data: FitData, runs: list[np.ndarray], tau: float, reach: float,
                 path: tuple[float, float], preload: float) -> dict[str, float]:
    """The damper network trained by unitwise Fisher scoring on the force less the path's forces and with the preload
    back, observed lagged by ``tau`` run by run at the samples the differentiator's window leaves independent."""
    target = data.force + preload
    if np.isfinite(reach):
        target = target - np.concatenate([path[0] * friction_shape(r.displacement, r.velocity, reach)
                                          + path[1] * r.displacement for r in test.runs])
    picks = np.concatenate([index[::max(1, run.window // 2)] for run, index in zip(test.runs, runs, strict=True)])

    def observe(columns: np.ndarray) -> np.ndarray:
        return _lagged_columns(columns, test, runs, tau)[picks]

    fit = train(data.velocity[:, None], target[picks], ("velocity",), {"damper": (0,)}, (0,), observe, NEURO_UNITS)
    net = fit.network
    start = {"c": float(net.linear[0])}
    for j, (w, b, a) in enumerate(zip(net.weights, net.biases, net.outputs, strict=True), 1):
        start.update({f"w{j}": float(w[0]), f"b{j}": float(b), f"a{j}": float(a)})
    return start
