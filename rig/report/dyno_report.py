"""``damper.json``, the result of ``rig dyno`` (docs/contracts.md, docs/dyno.md): the chosen law, its coefficients with
their intervals, the residual, every form tried, the records as read, and, where asked, the law as written into a
vehicle file and that file's damper simulated on the dyno. Built from results; nothing here computes a fit."""

from __future__ import annotations

import math

from rig.diagnosis.dyno.damper_in_vehicle import Reproduction, WrittenDamper
from rig.diagnosis.dyno.damper_law import CONFIDENCE, DamperFit, FittedLaw, unit_of
from rig.diagnosis.dyno.dynamic_damper_fit import TRIGGER_PCT
from rig.signal.differentiate import POLYORDER

SIGN_CONVENTION = ("damper level (the rod): displacement and velocity extension positive, force positive resisting "
                   "extension (rebound in the first quadrant)")


def damper_document(fit: DamperFit, notes: tuple[str, ...] = (), plots: dict[str, str] | None = None,
                    written: WrittenDamper | None = None, written_path: str | None = None,
                    reproduced: Reproduction | None = None, simulated: dict | None = None) -> dict:
    """The ``damper.json`` document. Contract keys: ``law``, ``coefficients``, ``intervals`` ([lo, hi], 95 %; null
    for an unbounded end) and ``residual_rms_pct`` (force minus fit, RMS, in percent of the force's RMS)."""
    chosen = fit.chosen
    law = chosen.law
    best = chosen.bic
    document = {
        "law": law.name,
        "coefficients": _numbers(law.coefficients),
        "intervals": {k: [_number(lo), _number(hi)] for k, (lo, hi) in chosen.intervals.items()},
        "residual_rms_pct": round(chosen.residual_rms_pct, 4),
        "residual_tests": chosen.tests.to_json() if chosen.tests is not None else None,
        "units": {k: unit_of(k) for k in law.coefficients},
        "reference_temperature_degC": _number(law.reference_temperature),
        "confidence": CONFIDENCE,
        "sign_convention": SIGN_CONVENTION,
        "selection": {"criterion": "BIC on the effective number of samples: n_eff ln(SSR/n) + p ln(n_eff), runs "
                                   "weighted by their residual",
                      "samples": fit.samples, "effective_samples": round(fit.effective_samples, 1),
                      "dynamics": ("laws with a lag and a friction's hysteresis, and the neuro-model paper's network, "
                                   "tried: the best static law left more than "
                                   f"{TRIGGER_PCT:g} % and a residual that is not white") if fit.tried_dynamics else
                                  None},
        "forms": [_form(f, best) for f in fit.forms],
        "velocity": (f"Savitzky-Golay derivative (scipy.signal.savgol_filter, order {POLYORDER}), window per record "
                     f"minimising the expected error from the record's periodogram"),
        "records": [{"name": run.name, "rate_hz": run.rate, "samples": int(run.force.size),
                     "stroke_m": round(run.stroke, 6), "peak_velocity_m_s": round(run.peak_velocity, 5),
                     "velocity_window_samples": run.window,
                     "temperature_degC": None if run.temperature is None else
                     [round(float(run.temperature.min()), 2), round(float(run.temperature.max()), 2)]}
                    for run in fit.test.runs],
        "notes": list(notes),
        "plots": dict(plots or {}),
    }
    if written is not None:
        document["vehicle"] = _written(written, written_path, reproduced)
    if simulated is not None:
        document["simulated"] = simulated
    return document


def _form(fitted: FittedLaw, best: float) -> dict:
    tests = fitted.tests
    return {"law": fitted.law.name, "parameters": fitted.parameters,
            "residual_rms_pct": round(fitted.residual_rms_pct, 4), "bic": round(fitted.bic, 2),
            "delta_bic": round(fitted.bic - best, 2), "coefficients": _numbers(fitted.law.coefficients),
            "white": None if tests is None else tests.white,
            "residual_statistics": None if tests is None else {
                "autocorrelation": round(tests.autocorrelation.statistic, 2),
                **{f"cross_{c.name}": round(c.statistic, 2) for c in tests.cross}}}


def _written(written: WrittenDamper, path: str | None, reproduced: Reproduction | None) -> dict:
    part = {"file": path, "name": written.vehicle.name, "axle": written.axle, "motion_ratio": written.motion_ratio,
            "temperature_degC": _number(written.temperature), "sections": list(written.sections),
            "notes": list(written.notes)}
    if reproduced is not None:
        part["reproduction"] = {
            "law_rms_pct": round(reproduced.law_rms_pct, 4), "loop_rms_pct": round(reproduced.loop_rms_pct, 4),
            "runs": {name: {"law_rms_pct": round(a, 4), "loop_rms_pct": round(b, 4)}
                     for name, (a, b) in reproduced.runs.items()},
            "meaning": "the file's damper simulated on the dyno (MuJoCo) with each record's displacement: RMS "
                       "difference from the law (at the written temperature) and from the measured force, its "
                       "preload included, in percent of the RMS force"}
    return part


def _numbers(values: dict) -> dict:
    return {k: _number(v) for k, v in values.items()}


def _number(value) -> float | None:
    """A JSON number (significant digits kept), or None for a missing or unbounded value."""
    if value is None or not math.isfinite(float(value)):
        return None
    return float(f"{float(value):.8g}")
