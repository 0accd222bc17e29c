"""Result files of a diagnosis: diagnosis.json for tools, the extended vehicle file, Markdown and PNG for people.
Everything is written from the typed ``Diagnosis``; nothing is read back from the JSON to present."""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

from rig.diagnosis.rig_test.diagnose import GAIN_THRESHOLD, NONE_FACTOR, Diagnosis
from rig.diagnosis.rig_test.diagnosis_results import Candidate, Unexplained
from rig.io.atomic import write_text_atomic
from rig.io.channels import split_channel
from rig.report.force_law_report import force_law_lines, plot_force_laws
from rig.report.plots import plt, save_figure
from rig.report.residual_report import plot_residual_tests, residual_lines
from rig.report.style import MODEL_COLORS, channel_color, display_unit, index_text, mpl, value_text
from rig.signal.discrepancy import Discrepancy, discrepancy
from rig.vehicle.vehicle_file import vehicle_to_toml


def write_diagnosis(diagnosis: Diagnosis, out_dir: str | os.PathLike, ran: str | None = None) -> None:
    """diagnosis.json, vehicle_extended.toml, report.md and its plots; ``ran``: the command that ran (report.md says
    what it answers and what to do next)."""
    out = Path(out_dir)
    indices = held_out_indices(diagnosis)
    write_text_atomic(out / "diagnosis.json", json.dumps(
        diagnosis.to_json() | {"indices": {label: index.to_json() for label, index in indices.items()}}, indent=1))
    write_text_atomic(out / "vehicle_extended.toml",
                      vehicle_to_toml(diagnosis.extended_vehicle, toml_comment(diagnosis)))
    save_figure(plot_before_after(diagnosis), out / "before_after.png")
    save_figure(plot_evidence(diagnosis), out / "evidence.png")
    save_figure(plot_ranking(diagnosis), out / "ranking.png")
    laws = plot_force_laws(diagnosis.force_laws, diagnosis.data_sheet)
    if laws is not None:
        save_figure(laws, out / "force_laws.png")
    tested = residual_models(diagnosis)
    if tested:
        save_figure(plot_residual_tests(tested, "residual tests: the learned laws and the extended model"),
                    out / "residual_tests.png")
    write_text_atomic(out / "report.md", "\n".join(report_lines(diagnosis, indices, laws is not None, ran, out)))


def residual_models(diagnosis: Diagnosis) -> list:
    """The residual tests a diagnosis reports: each learned law's, then the extended model's per channel."""
    return [law.tests for law in diagnosis.force_laws.learned.values()] + list(diagnosis.residual_tests)


def toml_comment(diagnosis: Diagnosis) -> str:
    """The extended vehicle file's header: what extended it, on which test, and how well (nothing of the records'
    own headers: a rig diagnosis's model is not a track test's)."""
    return (f"extended by rig diagnose on a rig test: verdict {diagnosis.verdict}\n"
            f"held-out TDDI {diagnosis.baseline_tddi:.4g} (baseline) -> {diagnosis.recalibrated_tddi:.4g} "
            f"(recalibrated) -> {diagnosis.extended_tddi:.4g} (extended); noise floor {diagnosis.noise_floor:.3g}")


def report_lines(diagnosis: Diagnosis, indices: dict[str, Discrepancy], force_law_plot: bool, ran: str | None = None,
                 out: Path = Path("diagnosis")) -> list[str]:
    """report.md; ``indices``: the diagnosis's ``held_out_indices``."""
    lines = [f"# Diagnosis of {diagnosis.recalibrated_vehicle.name}", "",
             *([f"Run: `{ran}`", ""] if ran else []), f"**Verdict: {diagnosis.verdict}**", "",
             *_verdict_lines(diagnosis), "", "## What to do next", "", *next_steps(diagnosis, out), "",
             "| model | held-out TDDI |", "|---|---|",
             f"| baseline (data sheet) | {diagnosis.baseline_tddi:.4g} |",
             f"| recalibrated (rates, damping, mass) | {diagnosis.recalibrated_tddi:.4g} |",
             f"| extended ({diagnosis.verdict}) | {diagnosis.extended_tddi:.4g} |",
             f"| noise floor (measured on this record) | {diagnosis.noise_floor:.4g} |",
             f"| detection limit ({NONE_FACTOR:g} x the floor) | {diagnosis.detection_limit.tddi_holdout:.4g} |", "",
             *_indices_lines(indices), *_input_chain_lines(diagnosis), *_recalibration_lines(diagnosis),
             *_named_lines(diagnosis), *_unexplained_lines(diagnosis.unexplained),
             *_step_lines(diagnosis), *_candidate_lines(diagnosis), *_phase_lines(diagnosis)]
    laws = force_law_lines(diagnosis.force_laws, diagnosis.data_sheet)
    lines += [*(laws if force_law_plot else laws[:-2])]
    lines += residual_lines(residual_models(diagnosis), "## Residual tests (the neuro-model paper's)")
    if residual_models(diagnosis):
        lines += ["![residual tests](residual_tests.png)", ""]
    lines += ["## Data integrity", ""] + ([f"- {f.channel}: {f.message}" for f in diagnosis.findings]
                                         or ["- no findings"])
    lines += ["", "![before and after](before_after.png)", "", "![evidence](evidence.png)", "",
              "![ranking](ranking.png)", ""]
    return lines


def held_out_indices(diagnosis: Diagnosis) -> dict[str, Discrepancy]:
    """Forsén's measures (rig/signal/discrepancy.py) of each model's held-out channels against the measured ones."""
    measured = diagnosis.compared["measured"]
    names = measured.names
    values = np.column_stack([measured[n] for n in names])
    return {label: discrepancy(values, np.column_stack([record[n] for n in names]), names, measured.rate)
            for label, record in diagnosis.compared.items() if label != "measured"}


def _indices_lines(indices: dict[str, Discrepancy]) -> list[str]:
    """The held-out indices per model (per channel in diagnosis.json)."""
    lines = ["## Forsén's measures on the held-out part", "",
             "TDDI of eq. 7 (the headline) and against the measured variance (eq. 8); the ride, payload and fatigue "
             "discrepancy indices (eqs. 10-13: (measured - model) / measured of the cab's and the frame's ISO 2631-1 "
             "Wk-weighted RMS and of the rainflow damage; positive: the model responds less). Per channel in "
             "diagnosis.json.", "", "| model | TDDI (eq. 7) | TDDI (eq. 8) | ride | payload | fatigue |",
             "|---|---|---|---|---|---|"]
    lines += [f"| {label} | {x.tddi:.4g} | {x.tddi_measured:.4g} | {index_text(x.ride)} | {index_text(x.payload)} | "
              f"{index_text(x.fatigue)} |" for label, x in indices.items()]
    return [*lines, ""]


def _verdict_lines(diagnosis: Diagnosis) -> list[str]:
    """What the verdict rests on, and what a reader must know about this record."""
    lines = [f"- {note}" for note in diagnosis.notes]
    lines += [f"- shortfall: {s.text()}" for s in diagnosis.shortfalls]
    for c in diagnosis.named:
        if c.plausibility:
            lines.append(f"- {c.effect}: {c.plausibility} (named all the same: no car cause matches its signature)")
        if c.checked_first:
            lines.append(f"- {c.effect}: an input channel's fault the records show before any model is fitted "
                         f"({_parameter_text(c)}): corrected first, then fitted with the recalibration")
        lines += [f"- {statement}" for statement in c.alike.values()]
    limit = diagnosis.detection_limit.tddi_holdout
    if str(diagnosis.verdict) == "none":
        lines.append(f"- `none`: the recalibrated model's held-out TDDI ({diagnosis.recalibrated_tddi:.3g}) is "
                     + ("within the detection limit" if diagnosis.recalibrated_tddi <= limit
                        else "beyond the detection limit, but this record is too short to judge a discrepancy no "
                             "cause explains") + f" ({limit:.3g})")
    return lines


def next_steps(diagnosis: Diagnosis, out: Path) -> list[str]:
    """What the verdict asks of the user, with the commands to run (``out``: where the diagnosis was written)."""
    extended = out / "vehicle_extended.toml"
    steps = []
    channels = [c for c in diagnosis.named if c.cause.keyed_by_channel or c.cause.input_quantities]
    for c in channels:
        steps.append(f"- mend the measurement chain, then measure again or read the record through a channel map that "
                     f"corrects it (`scale = ...` per channel; a negative scale reverses a polarity): {c.effect} "
                     f"{_parameter_text(c)}")
    if diagnosis.named:
        steps.append(f"- the extended model is `{extended}`: check it on a record it was not fitted to (`rig validate "
                     f"--vehicle {extended} --measured OTHER`), and iterate drives on it (`rig iterate --vehicle "
                     f"{extended} --target T --out iteration`)")
    for c in diagnosis.named:
        steps += [f"- {statement}" for statement in c.alike.values()]
    if diagnosis.unexplained is not None:
        steps.append("- no cause of the vocabulary explains what is left (below: where it lives); a test that excites "
                     "it alone (a sine sweep in its band, a static load step) narrows it down")
    if str(diagnosis.verdict) == "none":
        steps.append(f"- the recalibrated data sheet stands (`{extended}`, its factors below): use it as the model")
    if not diagnosis.detection_limit.judged:
        steps.append(f"- record a longer test: {diagnosis.detection_limit.reason}")
    return steps


def _input_chain_lines(diagnosis: Diagnosis) -> list[str]:
    """Each input channel's gain on the responses, found from the records against the data sheet's model."""
    if diagnosis.inputs is None:
        return []
    return ["## The input channels, checked first", "",
            "Each input's gain on the measured responses, by least squares of the responses on the data sheet's model "
            "moved by each input alone (95 % intervals; the data sheet's own errors move a gain by a few percent, a "
            f"lightly damped resonance by more; the inputs so weighted explain {100 * diagnosis.inputs.explained:.1f} "
            "% of the responses' variance):", "", *[f"- {line}" for line in diagnosis.inputs.lines()], ""]


def _recalibration_lines(diagnosis: Diagnosis) -> list[str]:
    """The recalibration's factors with their intervals, and why a recalibration that scores worse than the data
    sheet is kept."""
    lines = ["## Recalibration", "", "Scale factors of the data sheet's values fitted on the fit part "
             "(95 % confidence intervals from the fit's Jacobian):", "", "| parameter | factor | 95 % interval |",
             "|---|---|---|"]
    fit = diagnosis.recalibration
    lines += [f"| {name} | {value:.4f} | {_interval(fit.intervals.get(name), '-')} |"
              for name, value in fit.values.items()]
    if diagnosis.recalibrated_tddi > diagnosis.baseline_tddi:
        lines += ["", f"The recalibrated model scores worse on the held-out part than the data sheet "
                  f"({diagnosis.baseline_tddi:.4g} -> {diagnosis.recalibrated_tddi:.4g}). The factors are fitted on "
                  "the fit part only: a structural discrepancy there bends them towards what it does (a linear spring "
                  "and damper standing in for a nonlinear law), and on held-out data with other amplitudes the bent "
                  "values miss. The causes are judged against the recalibrated model all the same, so that a few "
                  "percent of data-sheet error is never taken for a cause."]
    return [*lines, ""]


def _interval(interval: tuple[float, float] | None, unit: str) -> str:
    if interval is None:
        return ""
    low, high = interval
    suffix = "" if unit in ("-", "") else f" {unit}"
    return "not determined" if not np.isfinite(low) else f"{low:.4g} .. {high:.4g}{suffix}"


def _parameter_text(c: Candidate) -> str:
    """Parameters with units and 95 % intervals (each value to the precision its interval supports), as one table
    cell."""
    parts = []
    for name, value in c.params.items():
        unit = c.units.get(name, "-")
        interval = c.intervals.get(name)
        reversed_channel = value < 0 and unit == "-" and (c.cause.keyed_by_channel or c.cause.input_quantities)
        parts.append(f"{name} = {value_text(value, unit, interval)}" + (": polarity reversed" if reversed_channel
                                                                        else ""))
    return ", ".join(parts)


def _named_lines(diagnosis: Diagnosis) -> list[str]:
    if not diagnosis.named:
        return []
    lines = ["## Causes named", "", "In the order named; each gain is what the cause takes off the held-out TDDI "
             "of the model it was added to, its share in the final model what the final model loses without it "
             "(parameters with 95 % confidence intervals).", "",
             "| cause | added to | gain | share in the final model | held-out TDDI | parameters |",
             "|---|---|---|---|---|---|"]
    for c in diagnosis.named:
        added_to = " + ".join(c.added_to) or "recalibrated"
        share = "" if c.own_gain is None else f"{c.own_gain:.3f}"
        lines.append(f"| {c.effect}{' (richer form)' if c.refined else ''} | {added_to} | {c.gain:.3f} | {share} "
                     f"| {c.tddi_holdout:.4g} | {_parameter_text(c)} |")
    lines += ["", "How the named causes show in the evidence: " + "; ".join(
        f"{c.effect}: {c.cause.signature}" for c in diagnosis.named) + ".", ""]
    return lines


def _unexplained_lines(where: Unexplained | None) -> list[str]:
    """Where the residual lives, when no cause explains it."""
    if where is None:
        return []
    place = where.where
    amplitude = place.amplitude_dependence or 1.0
    reading = ("about the same at every amplitude: a linear model error" if abs(amplitude - 1) < 0.3 else
               "growing with amplitude: a nonlinearity" if amplitude > 1 else
               "largest at small amplitude: friction or play")
    lines = ["## Unexplained: where the residual lives", "",
             f"The model leaves a held-out TDDI of {where.tddi_holdout:.4g}, {where.floor_multiple:.1f} times the "
             f"noise floor, that no cause of the registry explains.", ""]
    if place.channels:
        lines += [f"- channels: {', '.join(place.channels)}",
                  f"- band: {place.band_hz[0]:.1f}-{place.band_hz[1]:.1f} Hz (10-90 % of the residual power), "
                  f"peak at {place.peak_hz:.2f} Hz",
                  f"- residual share in the loudest third of the record over the quietest: {amplitude:.2f} ({reading})"]
    lines += [f"- the measured force law at {corner}: {', '.join(shapes)}"
              for corner, shapes in where.force_law_shapes.items()]
    lines += _generic_lines(where)
    return [*lines, ""]


def _generic_lines(where: Unexplained) -> list[str]:
    """The generic element fitted in the named causes' place, and whether the extended model carries it."""
    generic = where.generic_extension
    if generic is None:
        return []
    if where.generic_carried:
        used = "the extended model carries it (vehicle_extended.toml)"
    elif generic.gain <= 0:
        used = "it does not improve the held-out fit, so no model carries it"
    else:
        used = (f"the extended model keeps the named causes, which leave {where.tddi_holdout:.4g}: the generic element "
                f"would have to leave {GAIN_THRESHOLD:.0%} less to take their place")
    return [f"- generic extension `{generic.effect}` ({generic.cause.meaning}): held-out gain "
            f"{generic.gain:.3f}, TDDI {generic.tddi_holdout:.4g}; {used}"]


def _step_lines(diagnosis: Diagnosis) -> list[str]:
    """The evidence formed again after each named cause."""
    if not diagnosis.steps:
        return []
    lines = ["## What each named cause leaves", ""]
    for step in diagnosis.steps:
        lines.append(f"- with {' + '.join(step.named)}: held-out TDDI {step.tddi_holdout:.4g}, the residual "
                     f"{step.where.text(most=4)}")
    return [*lines, ""]


def _candidate_lines(diagnosis: Diagnosis) -> list[str]:
    lines = ["## Candidates", "", "Gain: relative held-out TDDI reduction against the model the cause was fitted on "
             f"(named when, less {0.01:g} per parameter, it clears {GAIN_THRESHOLD:g}).", "",
             "| cause | subsystem | what it means | gain | held-out TDDI | parameters | why not named |",
             "|---|---|---|---|---|---|---|"]
    names = diagnosis.verdict.causes
    for c in diagnosis.causes:
        meaning = c.cause.meaning.replace("|", "\\|")  # a law may hold |v|: not a column in Markdown
        why = "named" if c.effect in names else (c.why_not or "")
        if c.plausibility and c.plausibility not in why:
            why = f"{why}; {c.plausibility}" if why else c.plausibility
        params = _parameter_text(c).replace("|", "\\|")
        lines.append(f"| {c.effect} | {c.cause.subsystem} | {meaning} | {c.gain:.3f} | {c.tddi_holdout:.4g} "
                     f"| {params} | {why} |")
    return [*lines, ""]


def _phase_lines(diagnosis: Diagnosis) -> list[str]:
    """The residual's phase against frequency, per body and wheel accelerometer: the delay line that fits it and how
    much of it that line explains (a sensor's delay: nearly all; a car's lag: a curve the line misses)."""
    curves = [c for c in diagnosis.evidence.phase.values() if split_channel(c.channel)[1] != "susp_travel"]
    if not curves:
        return []
    lines = ["## Phase of the measurement against the recalibrated model", "",
             "A time shift's phase is a line through zero (-2 pi f tau); a damper acting through a compliance lags "
             "along a curve that follows the series stiffness.", "", "| channel | delay that fits best [ms] | "
             "share the line explains |", "|---|---|---|"]
    lines += [f"| {c.channel} | {1e3 * c.delay_s:.2f} | {c.linearity:.2f} |" for c in curves]
    return [*lines, ""]


#: before_after.png: the channels shown, the seconds of each, and the noise band's half-width in RMS of the noise.
BEFORE_AFTER_CHANNELS, BEFORE_AFTER_SECONDS, NOISE_SIGMAS = 4, 3.0, 2.0


def plot_before_after(diagnosis: Diagnosis) -> plt.Figure:
    """The channels the recalibrated model misses most on the held-out part, each over the BEFORE_AFTER_SECONDS
    where it misses most (times of the record the part was held out from): the recalibrated and extended models
    with the measurement over them (black, thin, drawn last), in the channel's display unit; below each, the
    residuals (measured minus each model) over the band noise alone would leave (+-2 RMS from the noise floor)."""
    records = diagnosis.compared
    measured, recalibrated, extended = (np.column_stack(list(records[k].channels.values()))
                                        for k in ("measured", "recalibrated", "extended"))
    names, rate = records["measured"].names, records["measured"].rate
    power = np.mean(measured**2, axis=0)
    miss = {m: np.mean((measured - simulated) ** 2, axis=0) / power
            for m, simulated in (("recalibrated", recalibrated), ("extended", extended))}
    worst = np.argsort(-miss["recalibrated"])[:BEFORE_AFTER_CHANNELS]
    part = diagnosis.split.holdout
    time = part.start + np.arange(measured.shape[0]) / rate
    fig = plt.figure(figsize=(11, 3.3 * len(worst)), layout="constrained")
    panes = [sub.subplots(2, 1, sharex=True, gridspec_kw={"height_ratios": [2.2, 1.0]})
             for sub in np.atleast_1d(fig.subfigures(len(worst), 1, hspace=0.03))]
    for (top, bottom), i in zip(panes, worst, strict=True):
        unit, scale = display_unit(split_channel(names[i])[1])
        shown = _where_missed(measured[:, i] - recalibrated[:, i], rate)
        residuals = {m: (measured[shown, i] - s[shown, i]) * scale
                     for m, s in (("recalibrated", recalibrated), ("extended", extended))}
        for model, simulated in (("recalibrated", recalibrated), ("extended", extended)):
            top.plot(time[shown], simulated[shown, i] * scale, color=mpl(MODEL_COLORS[model]), lw=1.4,
                     label=f"{model} model")
            bottom.plot(time[shown], residuals[model], color=mpl(MODEL_COLORS[model]), lw=1.1,
                        label=f"measured - {model}")
        top.plot(time[shown], measured[shown, i] * scale, "k", lw=0.9, label="measured", zorder=3)
        band = NOISE_SIGMAS * np.sqrt(2 * diagnosis.noise_floor * power[i]) * scale
        bottom.axhspan(-band, band, color="0.6", alpha=0.35, lw=0, label=f"noise, ±{NOISE_SIGMAS:g} RMS")
        top.set_title(f"{names[i]}: RMS miss over the held-out part {100 * np.sqrt(miss['recalibrated'][i]):.1f} % "
                      f"(recalibrated) -> {100 * np.sqrt(miss['extended'][i]):.1f} % (extended) of the measured RMS",
                      fontsize=9, loc="left")
        top.set_ylabel(f"{split_channel(names[i])[1]}\n[{unit}]", fontsize=8)
        bottom.set_ylabel(f"residual\n[{unit}]", fontsize=8)
        for ax in (top, bottom):
            ax.grid(alpha=0.3)
    for ax in panes[0]:
        ax.legend(fontsize=7, ncol=3, loc="upper right")
    record = "hold-out record" if diagnosis.split.explicit else "measured record"
    panes[-1][1].set_xlabel(f"time in the {record} [s]")
    fig.suptitle(f"held-out part, {part.start:.1f}-{part.end:.1f} s: the channels the recalibrated model misses "
                 f"most, {BEFORE_AFTER_SECONDS:g} s of each where it misses most")
    return fig


def _where_missed(residual: np.ndarray, rate: float) -> slice:
    """The BEFORE_AFTER_SECONDS (samples) where ``residual`` has the most energy."""
    width = min(residual.size, int(round(BEFORE_AFTER_SECONDS * rate)))
    energy = np.convolve(residual**2, np.ones(width), mode="valid")
    start = int(np.argmax(energy))
    return slice(start, start + width)


def plot_evidence(diagnosis: Diagnosis) -> plt.Figure:
    """The recalibrated model's held-out residual: against travel and its rate, per-channel gain and delay (each on
    its own axis), and the body accelerometers' phase against frequency with their best delay lines."""
    evidence = diagnosis.evidence
    fig, axes = plt.subplot_mosaic([["travel", "rate"], ["gain", "phase"], ["delay", "phase"]], figsize=(13, 9.5),
                                   height_ratios=[1.2, 1.0, 1.0])
    for binned, ax, label, scale in ((evidence.residual_vs_travel, axes["travel"], "compression [mm]", 1e3),
                                     (evidence.residual_vs_travel_rate, axes["rate"], "compression rate [m/s]", 1.0)):
        if binned is not None:
            ax.plot(np.asarray(binned.x) * scale, binned.residual, "o-")
        ax.axhline(0, color="0.5", lw=0.8)
        ax.set_xlabel(label)
        ax.set_ylabel("mean residual body acc. [m/s²]")
        ax.grid(alpha=0.3)
    names = list(evidence.channel_gain)
    position = np.arange(len(names))
    for key, values, label, colour in (("gain", [100 * (evidence.channel_gain[n] - 1) for n in names],
                                        "gain - 1, measured / model [%]", "C0"),
                                       ("delay", [1e3 * evidence.channel_delay_s[n] for n in names],
                                        "delay of the measurement [ms]", "C1")):
        ax = axes[key]
        ax.bar(position, values, 0.7, color=colour)
        ax.axhline(0, color="0.5", lw=0.8)
        ax.set_ylabel(label, fontsize=8)
        ax.set_xticks(position, names if key == "delay" else [], rotation=90, fontsize=6)
        ax.grid(alpha=0.3, axis="y")
    axes["gain"].set_title("per-channel calibration and timing", fontsize=9)
    _plot_phase(axes["phase"], evidence)
    fig.suptitle("evidence from the recalibrated model's held-out residual")
    return fig


def _plot_phase(ax, evidence) -> None:
    body = [c for c in evidence.phase.values() if split_channel(c.channel)[1] == "sprung_acc"]
    for curve in body:
        shown = curve.weight > 0
        colour = mpl(channel_color(curve.channel))
        ax.plot(curve.frequency[shown], np.degrees(curve.phase[shown]), ".", ms=3, color=colour,
                label=f"{curve.channel} ({1e3 * curve.delay_s:.1f} ms line explains {curve.linearity:.2f})")
        ax.plot(curve.frequency, np.degrees(-2 * np.pi * curve.frequency * curve.delay_s), "-", lw=0.8, color=colour)
    ax.axhline(0, color="0.5", lw=0.8)
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("phase, measured against model [deg]")
    ax.set_title("body accelerometers: a delay is a line, a car's lag a curve", fontsize=9)
    ax.legend(fontsize=6)
    ax.grid(alpha=0.3)


def plot_ranking(diagnosis: Diagnosis) -> plt.Figure:
    """Every candidate's gain against the naming threshold; the named marked, and each cause past the threshold
    that is not named labelled with why."""
    causes = diagnosis.causes[::-1]
    names = set(diagnosis.verdict.causes)
    fig, ax = plt.subplots(figsize=(11, 0.45 * len(causes) + 1.6))
    colours = ["C2" if c.effect in names else "C0" for c in causes]
    ax.barh([c.effect for c in causes], [c.gain for c in causes], color=colours)
    ax.axvline(GAIN_THRESHOLD, color="C3", lw=1, label=f"threshold to name a cause ({GAIN_THRESHOLD:g} + 0.01 per "
                                                       f"parameter)")
    for row, c in enumerate(causes):
        text = "named" + (f" (on top of {' + '.join(c.added_to)})" if c.added_to else "") if c.effect in names \
            else (_short(c.why_not) if c.gain >= GAIN_THRESHOLD and c.why_not else "")
        if text:
            ax.text(max(c.gain, 0) + 0.01, row, text, va="center", fontsize=7)
    ax.set_xlim(min(0.0, min(c.gain for c in causes) - 0.05) if causes else 0.0, 1.6)
    ax.set_xlabel("held-out gain (relative TDDI reduction on the model the cause was fitted to)")
    ax.set_title("candidates (green: named)", fontsize=9)
    ax.legend(fontsize=7, loc="lower right")
    ax.grid(alpha=0.3)
    return fig


def _short(why: str, limit: int = 70) -> str:
    first = why.split(":")[0]
    return first if len(first) <= limit else first[:limit - 3] + "..."
