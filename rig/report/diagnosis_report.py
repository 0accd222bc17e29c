"""Result files of a diagnosis: diagnosis.json for tools, the extended vehicle file, Markdown and PNG for people."""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

from rig.causes import CAUSES
from rig.diagnosis.diagnose import GAIN_THRESHOLD, Diagnosis
from rig.io.atomic import write_text_atomic
from rig.report.force_law_report import force_law_lines, plot_force_laws
from rig.report.plots import plt, save_figure
from rig.vehicle.vehicle_file import vehicle_to_toml


def write_diagnosis(diagnosis: Diagnosis, out_dir: str | os.PathLike) -> None:
    """diagnosis.json, vehicle_extended.toml, report.md and its plots."""
    out = Path(out_dir)
    write_text_atomic(out / "diagnosis.json", json.dumps(diagnosis.to_json(), indent=1))
    comment = (f"extended by rig diagnose: verdict {diagnosis.verdict}; held-out TDDI {diagnosis.baseline_tddi:.4g} "
               f"(baseline) -> {diagnosis.recalibrated_tddi:.4g} (recalibrated) -> {diagnosis.extended_tddi:.4g}")
    write_text_atomic(out / "vehicle_extended.toml", vehicle_to_toml(diagnosis.extended_vehicle, comment))
    records = diagnosis.compared
    measured, recalibrated, extended = (np.column_stack(list(records[k].channels.values()))
                                        for k in ("measured", "recalibrated", "extended"))
    _plot_before_after(measured, recalibrated, extended, records["measured"].names, records["measured"].rate,
                       out / "before_after.png")
    _plot_evidence(diagnosis.evidence, out / "evidence.png")
    _plot_ranking(diagnosis, out / "ranking.png")
    drawn = plot_force_laws(diagnosis.force_laws, diagnosis.data_sheet, out / "force_laws.png")
    lines = [f"# Diagnosis of {diagnosis.recalibrated_vehicle.name}", "",
             f"**Verdict: {diagnosis.verdict}**", "",
             "| model | held-out TDDI |", "|---|---|",
             f"| baseline (data sheet) | {diagnosis.baseline_tddi:.4g} |",
             f"| recalibrated (rates, damping, mass) | {diagnosis.recalibrated_tddi:.4g} |",
             f"| extended ({diagnosis.verdict}) | {diagnosis.extended_tddi:.4g} |",
             f"| noise floor (measured on this record) | {diagnosis.noise_floor:.4g} |", "",
             *_unexplained_lines(diagnosis.unexplained),
             "## Candidates (gain: relative held-out TDDI reduction against the recalibrated model)", "",
             "| cause | subsystem | what it means | gain | held-out TDDI | parameters |", "|---|---|---|---|---|---|"]
    for c in diagnosis.causes:
        params = ", ".join(f"{k} = {v:.4g}" for k, v in c.params.items())
        meaning = c.cause.meaning.replace("|", "\\|")  # a law may hold |v|: not a column in Markdown
        lines.append(f"| {c.effect} | {c.cause.subsystem} | {meaning} | {c.gain:.3f} | {c.tddi_holdout:.4g} "
                     f"| {params} |")
    if diagnosis.named:
        lines += ["", "How the named cause shows in the evidence: " + "; ".join(
            f"{c.effect}: {c.cause.signature}" for c in diagnosis.named) + "."]
    laws = force_law_lines(diagnosis.force_laws, diagnosis.data_sheet)
    lines += ["", *(laws if drawn else laws[:-2])]
    lines += ["", "## Data integrity", ""] + ([f"- {f['channel']}: {f['message']}" for f in diagnosis.findings]
                                              or ["- no findings"])
    lines += ["", "![before and after](before_after.png)", "", "![evidence](evidence.png)", "",
              "![ranking](ranking.png)", ""]
    write_text_atomic(out / "report.md", "\n".join(lines))


def _unexplained_lines(where: dict | None) -> list[str]:
    """Where the residual lives, when no cause explains it."""
    if where is None:
        return []
    amplitude = where["amplitude_dependence"]
    reading = ("about the same at every amplitude: a linear model error" if abs(amplitude - 1) < 0.3 else
               "growing with amplitude: a nonlinearity" if amplitude > 1 else
               "largest at small amplitude: friction or play")
    return ["## Unexplained: where the residual lives", "",
            "The recalibrated model is wrong beyond the noise floor and no cause of the registry explains it.", "",
            f"- channels: {', '.join(where['channels'])}",
            f"- band: {where['band_hz'][0]:.1f}-{where['band_hz'][1]:.1f} Hz (10-90 % of the residual power), "
            f"peak at {where['peak_hz']:.2f} Hz",
            f"- residual share in the loudest third of the record over the quietest: {amplitude:.2f} ({reading})",
            *[f"- the measured force law at {corner}: {', '.join(shapes)}"
              for corner, shapes in where.get("force_law_shapes", {}).items()],
            *_generic_lines(where.get("generic_extension")), ""]


def _generic_lines(generic: dict | None) -> list[str]:
    """The generic element that extends the model when no cause explains it."""
    if generic is None:
        return []
    used = ("the extended model carries it (vehicle_extended.toml)" if generic["gain"] > 0
            else "it does not improve the held-out fit, so the model is not extended")
    return [f"- generic extension `{generic['effect']}` ({CAUSES[generic['effect']].meaning}): held-out gain "
            f"{generic['gain']:.3f}, TDDI {generic['tddi_holdout']:.4g}; {used}"]


def _plot_before_after(measured, recalibrated, extended, names, rate, path) -> None:
    worst = np.argsort([-np.mean((measured[:, i] - recalibrated[:, i]) ** 2) / np.mean(measured[:, i] ** 2)
                        for i in range(len(names))])[:4]
    window = slice(int(measured.shape[0] * 0.4), int(measured.shape[0] * 0.4) + int(3 * rate))
    time = np.arange(measured.shape[0])[window] / rate
    fig, axes = plt.subplots(len(worst), 1, figsize=(11, 2.3 * len(worst)), sharex=True, squeeze=False)
    for ax, i in zip(axes[:, 0], worst):
        ax.plot(time, measured[window, i], "k", lw=1, label="measured")
        ax.plot(time, recalibrated[window, i], lw=0.9, label="recalibrated model")
        ax.plot(time, extended[window, i], "--", lw=0.9, label="extended model")
        ax.set_ylabel(names[i], fontsize=8)
        ax.grid(alpha=0.3)
    axes[0, 0].legend(fontsize=7, ncol=3)
    axes[-1, 0].set_xlabel("held-out time [s]")
    fig.suptitle("held-out data: the channels the recalibrated model misses most")
    save_figure(fig, path)


def _plot_evidence(evidence: dict, path) -> None:
    fig, axes = plt.subplots(1, 3, figsize=(14, 3.6))
    for key, ax, label in (("residual_vs_travel", axes[0], "compression [m]"),
                           ("residual_vs_travel_rate", axes[1], "compression rate [m/s]")):
        if key in evidence:
            ax.plot(evidence[key]["x"], evidence[key]["residual"], "o-")
        ax.axhline(0, color="0.5", lw=0.8)
        ax.set_xlabel(label)
        ax.set_ylabel("mean residual body acc. [m/s²]")
        ax.grid(alpha=0.3)
    gains = evidence.get("channel_gain", {})
    delays = evidence.get("channel_delay_s", {})
    axes[2].bar(range(len(gains)), [g - 1 for g in gains.values()], label="gain - 1")
    axes[2].bar(range(len(delays)), [d * 100 for d in delays.values()], alpha=0.5, label="delay x 100 [s]")
    axes[2].set_xticks(range(len(gains)), list(gains), rotation=90, fontsize=6)
    axes[2].legend(fontsize=7)
    axes[2].set_title("per-channel calibration and timing")
    fig.suptitle("evidence from the recalibrated model's held-out residual")
    save_figure(fig, path)


def _plot_ranking(diagnosis: Diagnosis, path) -> None:
    fig, ax = plt.subplots(figsize=(8, 3.5))
    ax.barh([c.effect for c in diagnosis.causes][::-1], [c.gain for c in diagnosis.causes][::-1])
    ax.axvline(GAIN_THRESHOLD, color="C3", lw=1, label="threshold to name a cause")
    ax.set_xlabel("held-out gain")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    save_figure(fig, path)
