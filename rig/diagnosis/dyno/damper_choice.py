"""The choice of a damper's law from a dynamometer test: every form fitted (rig/diagnosis/dyno/damper_law.py; the forms
with dynamics where the static ones fail, rig/diagnosis/dyno/dynamic_damper_fit.py), each run weighted by how well the
most flexible laws hold it, and the laws ranked by the Bayesian information criterion on the residual's effective
number of samples."""

from __future__ import annotations

import dataclasses

import numpy as np

from rig.diagnosis.dyno.damper_law import (
    BASE_FORMS,
    MODIFIERS,
    DamperFit,
    FitData,
    FittedLaw,
    candidate_names,
    effective_samples,
    fit_law,
    fit_samples,
    summarise,
)
from rig.diagnosis.dyno.dynamic_damper_fit import dynamic_names, fit_dynamic_law, needs_dynamics
from rig.diagnosis.dyno.dyno_test import DynoTest


def fit_damper(test: DynoTest, laws: list[str] | None = None, reference_temperature: float | None = None
               ) -> DamperFit:
    """Fit ``laws`` (names as ``candidate_names`` gives them; default all) to a dyno test and rank them by
    BIC. ``reference_temperature`` (degC) defaults to the test's mean temperature.

    Each run is weighted by the inverse RMS residual that the closest of the most flexible laws (each form with
    every modifier) leaves in it (feasible generalised least squares): a run whose velocity is harder to derive
    (a triangle test's reversals, a noisy transducer) counts for less, and its errors in velocity bias the law
    less.
    """
    data = fit_samples(test, reference_temperature)
    names = laws or candidate_names(data.temperature is not None)
    flexible = [fit_law(name, data)[2] for name in _most_flexible(data)]
    data = _weighted(data, min(flexible, key=lambda residual: np.sum(residual ** 2)))
    dynamic = set(dynamic_names(True) + dynamic_names(False))
    raw = [fit_law(name, data) for name in names if name not in dynamic]
    fitted = _ranked(raw, test) if raw else []
    static = {f.law.name: f.law for f in fitted}
    wanted = [n for n in names if n in dynamic]
    if laws is None and needs_dynamics(fitted[0]):
        wanted = dynamic_names(fitted[0].law.temperature)
    if wanted:
        starts = {"digressive+preload"} | {f"{n.split('+')[0]}+preload+series" for n in wanted if "+series" in n}
        static |= {name: fit_law(name, data)[0] for name in starts - set(static)}
        raw += [fit_dynamic_law(name, test, data, static) for name in wanted]
        fitted = _ranked(raw, test)
    return DamperFit(tuple(fitted), data.force.size, fitted[0].effective_samples, test,
                     tried_dynamics=bool(wanted) and laws is None)


def _ranked(raw: list, test: DynoTest) -> list[FittedLaw]:
    """The fits summarised on the effective samples of the residual nearest to noise alone, lowest BIC first. Where
    even that residual is a model's error more than noise (a real damper no law holds), its autocorrelation would
    leave a handful of samples, on which the criterion cannot tell a law leaving 7 % from one leaving 11 %: the
    samples are then at least one per differentiator window of each run, the velocity estimates that are
    independent of each other."""
    closest = min(raw, key=lambda item: np.sum(item[2] ** 2))
    windows = sum(run.force.size / run.window for run in test.runs)
    n_eff = max(effective_samples(closest[2]), min(windows, closest[2].size))
    fitted = [summarise(law, x, residual, jacobian, test, n_eff) for law, x, residual, jacobian in raw]
    return sorted(fitted, key=lambda f: f.bic)


def _most_flexible(data: FitData) -> list[str]:
    """Each base form with every modifier the data allow."""
    modifiers = MODIFIERS if data.temperature is not None else MODIFIERS[:2]
    return ["+".join([form, *modifiers]) for form in BASE_FORMS]


def _weighted(data: FitData, residual: np.ndarray) -> FitData:
    """``data`` with each sample weighted by the inverse RMS of ``residual`` over its run."""
    rms = np.sqrt(np.bincount(data.run, residual ** 2) / np.bincount(data.run))
    return dataclasses.replace(data, weight=1.0 / np.maximum(rms, 1e-9 * rms.max())[data.run])
