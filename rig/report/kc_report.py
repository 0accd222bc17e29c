"""The report of a diagnosis on K&C records (``rig diagnose`` on ``# test: kc`` records): diagnosis.json,
vehicle_extended.toml, report.md and a figure per record (measured against the model per corner). It takes the
finished ``KcDiagnosis`` (rig/diagnosis/kc/kinematic_diagnosis.py) and never simulates."""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

from rig.diagnosis.kc.kinematic_diagnosis import P_VALUE, KcDiagnosis
from rig.io.atomic import write_text_atomic
from rig.sim.kc import COMPLIANCE_TESTS
from rig.report.kc_plots import plot_kc_comparison
from rig.report.plots import save_figure
from rig.vehicle.vehicle_file import vehicle_to_toml

LENGTHS = ("track_change", "wheelbase_change")
NO_BUSHINGS = ("The vehicle file gives no bushing tables on the measured axles, so the compliance records fit no "
               "rate: give [<axle>.bushings.<joint>] tables to start from.")


def figure_name(k: int, test: str) -> str:
    return f"kc_{k + 1}_{test}.png"


def write_kc_diagnosis(diagnosis: KcDiagnosis, out_dir: str | os.PathLike) -> None:
    """diagnosis.json, vehicle_extended.toml, report.md and the figures."""
    out = Path(out_dir)
    write_text_atomic(out / "diagnosis.json", json.dumps(diagnosis.to_json(), indent=1))
    write_text_atomic(out / "vehicle_extended.toml", vehicle_to_toml(
        diagnosis.extended_vehicle, f"extended by rig diagnose on K&C records: verdict {diagnosis.verdict}"))
    for k, (record, before, after) in enumerate(zip(diagnosis.records, diagnosis.before, diagnosis.after)):
        save_figure(plot_kc_comparison(record, before, after), out / figure_name(k, record.test))
    write_text_atomic(out / "report.md", "\n".join(report_lines(diagnosis)))


def report_lines(diagnosis: KcDiagnosis) -> list[str]:
    """report.md."""
    tests = ", ".join(r.test for r in diagnosis.records)
    lines = [f"# K&C diagnosis of {diagnosis.extended_vehicle.name}", "", f"**Verdict: {diagnosis.verdict}**", "",
             f"Records: {tests} tests of {', '.join(dict.fromkeys(c for r in diagnosis.records for c in r.corners))}.",
             f"A cause is named when its fit gains significantly over the vehicle file (F test, p < {P_VALUE:g}) and "
             f"a parameter moved beyond its interval at that level.", ""]
    lines += _hardpoint_lines(diagnosis) + _bushing_lines(diagnosis) + _residual_lines(diagnosis)
    lines += ["## Measured against the model", ""]
    lines += [f"![{r.test}]({figure_name(k, r.test)})" for k, r in enumerate(diagnosis.records)] + [""]
    return lines


def _hardpoint_lines(diagnosis: KcDiagnosis) -> list[str]:
    finding = diagnosis.hardpoints
    if finding is None:
        return []
    fit = finding.fit
    scope = "each corner its own (the records show a left-right difference" if finding.per_corner else \
        "both corners of an axle alike (the records show no significant left-right difference"
    if finding.left_right is not None:
        scope += f": F {finding.left_right.f_statistic:.3g}, p {finding.left_right.p_value:.3g})"
    else:
        scope += ")"
    lines = ["## Hardpoints (travel, roll and steer records)", "",
             f"Fitted {scope}; against the vehicle file F {finding.significance.f_statistic:.3g}, p "
             f"{finding.significance.p_value:.3g}. The extended vehicle moves the points with a moved coordinate (all "
             f"their fitted coordinates); the others stay where the table puts them.", "",
             "| coordinate | offset [mm] | 95 % interval [mm] | moved |", "|---|---|---|---|"]
    for c, n, f, i in zip(fit.free, fit.nominal, fit.fitted, fit.interval):
        interval = f"+-{i * 1e3:.3f}" if np.isfinite(i) else "not identifiable"
        lines.append(f"| {c.name} | {(f - n) * 1e3:+.3f} | {interval} | {'yes' if c.name in finding.moved else ''} |")
    lines.append("")
    if finding.aliases:
        lines += ["What the curves cannot tell apart:", ""] + [f"- {a.sentence()}" for a in finding.aliases] + [""]
    if finding.screened_out:
        lines += [f"Left to the fitted coordinates (the curves move with them or not at all): "
                  f"{', '.join(finding.screened_out)}.", ""]
    return lines


def _bushing_lines(diagnosis: KcDiagnosis) -> list[str]:
    finding = diagnosis.bushings
    if finding is None:
        if any(r.test in COMPLIANCE_TESTS for r in diagnosis.records):
            return ["## Bushings", "", NO_BUSHINGS, ""]
        return []
    fit = finding.fit
    lines = ["## Bushings (lateral, longitudinal and aligning records)", "",
             f"Against the vehicle file F {finding.significance.f_statistic:.3g}, p "
             f"{finding.significance.p_value:.3g}. The extended vehicle takes the moved rates; the others keep the "
             f"file's (within their interval at the verdict's level, or on an axle whose curves gain nothing "
             f"significant).", "",
             "| rate | file | fitted | 95 % interval | moved |", "|---|---|---|---|---|"]
    for r, n, v, x in zip(fit.free, fit.nominal, fit.fitted, fit.factor):
        interval = f"{v / x:.4g} .. {v * x:.4g}" if np.isfinite(x) else "not identifiable"
        lines.append(f"| {r.name} [{r.unit}] | {n:.4g} | {v:.4g} | {interval} | "
                     f"{'yes' if r.name in finding.moved else ''} |")
    lines.append("")
    if finding.screened_out:
        lines += [f"Rates these tests cannot identify apart from the fitted ones: {', '.join(finding.screened_out)}.",
                  ""]
    return lines


def _residual_lines(diagnosis: KcDiagnosis) -> list[str]:
    lines = ["## Residual per corner and curve (RMS, measured minus model)", "",
             "| test | corner | curve | vehicle file | extended |", "|---|---|---|---|---|"]
    for name, values in diagnosis.residuals().items():
        test, corner, quantity = name.split("/")
        scale, unit = (1e3, "mm") if quantity in LENGTHS else (180 / np.pi, "deg")
        lines.append(f"| {test} | {corner} | {quantity} | {values['before'] * scale:.4f} {unit} | "
                     f"{values['after'] * scale:.4f} {unit} |")
    return [*lines, ""]
