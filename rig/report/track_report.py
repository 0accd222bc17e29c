"""Result files of a track-test diagnosis: diagnosis.json, the extended vehicle, Markdown and PNG for people.

Order spectra per wheel (amplitude around the wheels' orders, one line per recorded speed, and the order
amplitude against speed with the model's prediction from the identified unbalance), the identified unbalance of
every wheel against its uncertainty and detection limit, what balancing would remove, and the transmissibility
check. With a rig-style diagnosis of the road part, its own report is written in ``road/``.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

from rig.diagnosis.track.track_diagnosis import TrackDiagnosis
from rig.diagnosis.track.unbalance import SPECTRUM_HALF_BAND, UnbalanceIdentification
from rig.io.atomic import write_text_atomic
from rig.io.channels import QUANTITY_UNITS, channel, split_channel
from rig.report.plots import plt, save_figure
from rig.report.style import CORNER_COLORS, mpl
from rig.vehicle.vehicle_file import vehicle_to_toml

G_M = 1e3  # g m per kg m
CORNER_COLOURS = {c: mpl(rgb) for c, rgb in CORNER_COLORS.items()}  # as the Rerun review shows them


def write_track_diagnosis(diagnosis: TrackDiagnosis, out_dir: str | os.PathLike) -> None:
    """diagnosis.json, vehicle_extended.toml, report.md, order_spectra.png, unbalance.png, transmissibility.png."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    write_text_atomic(out / "diagnosis.json", json.dumps(diagnosis.to_json(), indent=1))
    write_text_atomic(out / "vehicle_extended.toml", vehicle_to_toml(
        diagnosis.extended_vehicle, f"extended by rig diagnose on track records: verdict {diagnosis.verdict}"))
    save_figure(plot_order_spectra(diagnosis), out / "order_spectra.png")
    save_figure(plot_unbalance(diagnosis.unbalance), out / "unbalance.png")
    images = ["order_spectra.png", "unbalance.png"]
    if diagnosis.transmissibility is not None:
        save_figure(plot_transmissibility(diagnosis), out / "transmissibility.png")
        images.append("transmissibility.png")
    if diagnosis.road is not None:
        from rig.report.diagnosis_report import write_diagnosis

        write_diagnosis(diagnosis.road, out / "road")
    write_text_atomic(out / "report.md", "\n".join(_report_lines(diagnosis, images)))


def _report_lines(diagnosis: TrackDiagnosis, images: list[str]) -> list[str]:
    found = diagnosis.unbalance
    named = found.named
    headline = (f" ({named.corner}: {named.unbalance_kgm * G_M:.2f} ± {named.std_kgm * G_M:.2f} g·m at "
                f"{named.angle_deg:.1f} ± {named.std_deg:.1f}° from the mark)" if named else "")
    lines = [f"# Track diagnosis of {diagnosis.data_sheet.name}", "", f"**Verdict: {diagnosis.verdict}**{headline}", "",
             "The road under the tyres is not known, so the model is judged on what does not need it: the response "
             "locked to each wheel's measured angle (order analysis, the transputer paper), and the transmissibility "
             "from each wheel to the body.", "", "## Records", "",
             "| record | speed [m/s] | analysed [s] | " + " | ".join(f"{c} order [Hz]" for c in found.corners) + " |",
             "|---|---|---|" + "---|" * len(found.corners)]
    for label, record in _records(found):
        speed = f"{record.speed:.2f}" if record.speed is not None else "-"
        lines.append(f"| {label} | {speed} | {record.duration:.1f} | "
                     + " | ".join(f"{f:.4f}" for f in record.frequency) + " |")
    lines += ["", "## Unbalance per wheel (m e and its angle from the mark, in the rolling direction)", "",
              "| wheel | m e [g·m] | angle [°] | T² | called beyond | detection limit [g·m] | unbalanced |",
              "|---|---|---|---|---|---|---|"]
    for w in found.wheels.values():
        lines.append(f"| {w.corner} | {w.unbalance_kgm * G_M:.3f} ± {w.std_kgm * G_M:.3f} | {w.angle_deg:.1f} ± "
                     f"{min(w.std_deg, 180.0):.1f} | {w.t2:.1f} | {w.threshold:.1f} | "
                     f"{w.detection_limit_kgm * G_M:.3f} | {'yes' if w.significant else 'no'} |")
    lines += ["", f"Model check: the residual of the fit over every channel, wheel and speed has chi² / dof = "
                  f"{found.consistency:.2f} (about 1 when the model's response to an unbalance explains the order "
                  f"content)."]
    if found.holdout_chi2 is not None:
        before, after = found.holdout_chi2
        lines.append(f"Held-out record: its order content, chi² {before:.1f} before and {after:.1f} after the "
                     f"identified unbalance's prediction ({100 * (1 - after / before):.1f} % explained).")
    balancing = found.balancing()
    if balancing is not None:
        lines += ["", "## What balancing would remove", "",
                  f"A weight of {balancing['weight_kg'] * 1e3:.0f} g on the rim of {balancing['corner']} (radius "
                  f"{balancing['rim_radius_m'] * 1e3:.0f} mm) at {balancing['weight_angle_deg']:.0f}° from the mark "
                  f"cancels the unbalance and takes away this order response:", "",
                  "| speed [m/s] | order [Hz] | channel | removed (model) | measured order amplitude |",
                  "|---|---|---|---|---|"]
        for at in balancing["removed"]:
            speed = f"{at['speed']:.2f}" if at["speed"] is not None else "-"
            for name in (n for n in at["channels"] if n.startswith(balancing["corner"])):
                lines.append(f"| {speed} | {at['frequency_hz']:.3f} | {name} | {at['channels'][name]['removed']:.4g} | "
                             f"{at['channels'][name]['measured_order']:.4g} |")
    if diagnosis.transmissibility is not None:
        lines += ["", "## Transmissibility, body over wheel acceleration (model check, 0.5-20 Hz)", "",
                  "Measured against the model on a random road at the record's speed (left and right tracks "
                  "independent): the coherence-weighted RMS of the magnitude ratio, per corner: "
                  + ", ".join(f"{c} {100 * e:.1f} %" for c, e in diagnosis.transmissibility.error.items()) + "."]
    if diagnosis.road is not None:
        lines += ["", "## The road part, as a rig test on ideal posts", "",
                  f"The record carries the road, so the rig-style diagnosis ran on it with the unbalance's order "
                  f"content taken out: verdict **{diagnosis.road.verdict}** "
                  f"(report in [road/report.md](road/report.md))."]
    lines += ["", "## Limits", "",
              "- constant speed within a record (a record whose wheel speed varies by more than 2 % is refused);",
              "- the transputer paper's covariance method for the road part is not done: the road is noise to the "
              "order analysis, and the model is judged on the road only when the record carries it;",
              "- one unbalanced wheel per extended model (the vehicle file's [wheel_unbalance] names one corner); "
              "every wheel's estimate is in diagnosis.json.", ""]
    lines += [f"![{name[:-4]}]({name})" for name in images] + [""]
    return lines


def _records(found: UnbalanceIdentification):
    labelled = [(f"measured {i + 1}", r) for i, r in enumerate(found.records)]
    return labelled + ([("held out", found.holdout)] if found.holdout is not None else [])


def _own_channel(record, corner: str) -> int:
    """The channel that shows a wheel's order best: its own wheel acceleration, else any of its corner's."""
    for quantity in ("unsprung_acc", "sprung_acc", "susp_travel"):
        if channel(corner, quantity) in record.channels:
            return record.channels.index(channel(corner, quantity))
    return 0


def plot_order_spectra(diagnosis: TrackDiagnosis) -> plt.Figure:
    """Per wheel: the amplitude spectrum of its own channel around its order (one line per record, frequency in
    orders of that wheel, the other wheels' orders marked), and the order amplitude against speed, measured (with
    two standard deviations of the road's noise) and as the model predicts it from the identified unbalance."""
    found = diagnosis.unbalance
    records = _records(found)
    corners = found.corners
    fig, axes = plt.subplots(len(corners), 2, figsize=(12, 2.6 * len(corners)), squeeze=False)
    for row, corner in enumerate(corners):
        spectrum_ax, speed_ax = axes[row]
        k = _own_channel(records[0][1], corner)
        name = records[0][1].channels[k]
        for i, (label, record) in enumerate(records):
            c = record.corners.index(corner)
            order = record.spectrum_hz / record.frequency[c]
            speed = f"{record.speed:.1f} m/s" if record.speed is not None else label
            spectrum_ax.semilogy(order, record.spectrum[record.channels.index(name)], lw=0.9, color=f"C{i}",
                                 label=f"{label}, {speed}")
            for d, other in enumerate(record.corners):
                spectrum_ax.axvline(record.frequency[d] / record.frequency[c], color=CORNER_COLOURS[other],
                                    lw=1.6 if other == corner else 0.6, alpha=0.5)
        half = SPECTRUM_HALF_BAND / max(r.frequency.max() for _, r in records)
        spectrum_ax.set_xlim(1 - half, 1 + half)
        unit = QUANTITY_UNITS[split_channel(name)[1]]
        spectrum_ax.set_ylabel(f"{name}\namplitude [{unit}]", fontsize=8)
        spectrum_ax.grid(alpha=0.3, which="both")
        speeds, amplitude, spread = [], [], []
        for _label, record in records:
            c = record.corners.index(corner)
            kk = record.channels.index(name)
            speeds.append(record.speed if record.speed is not None else record.omega[c])
            amplitude.append(abs(record.coefficients[kk, c]))
            spread.append(2 * np.sqrt(2 * record.noise[kk, kk].real / record.duration / 2))
        speed_ax.errorbar(speeds, amplitude, yerr=spread, fmt="o", color=CORNER_COLOURS[corner], label="measured order")
        if diagnosis.curve is not None and diagnosis.curve.corner == corner and name in diagnosis.curve.channels:
            speed_ax.plot(diagnosis.curve.speed, diagnosis.curve.amplitude[:, diagnosis.curve.channels.index(name)],
                          color="0.3", label="model with the identified unbalance")
        speed_ax.set_ylabel(f"order amplitude [{unit}]", fontsize=8)
        speed_ax.grid(alpha=0.3)
        speed_ax.legend(fontsize=7)
    axes[0, 0].legend(fontsize=7)
    axes[-1, 0].set_xlabel("frequency in orders of the wheel (its own order at 1; lines: the wheels' orders)")
    axes[-1, 1].set_xlabel("speed [m/s]" if records[0][1].speed is not None else "wheel speed [rad/s]")
    fig.suptitle("order spectra per wheel: amplitude around the wheel's rotation order, and against speed")
    fig.tight_layout()
    return fig


def plot_unbalance(found: UnbalanceIdentification, truth: dict | None = None) -> plt.Figure:
    """Every wheel's identified unbalance m e exp(i angle) in g m, with its two-standard-deviation circle and the
    detection limit; ``truth`` (corner -> (kg m, deg)) marks known unbalances."""
    fig, ax = plt.subplots(figsize=(6, 6))
    limit = max(w.unbalance_kgm + 3 * w.std_kgm for w in found.wheels.values()) * G_M
    for w in found.wheels.values():
        u = w.unbalance_kgm * np.exp(1j * np.radians(w.angle_deg)) * G_M
        colour = CORNER_COLOURS[w.corner]
        ax.plot(u.imag, u.real, "o", color=colour, label=f"{w.corner}: {w.unbalance_kgm * G_M:.2f} g·m"
                + (" (unbalanced)" if w.significant else ""))
        ax.add_patch(plt.Circle((u.imag, u.real), 2 * w.std_kgm * G_M, color=colour, alpha=0.25))
        ax.add_patch(plt.Circle((0, 0), w.detection_limit_kgm * G_M, fill=False, ls=":", color=colour))
    for corner, (kgm, angle) in (truth or {}).items():
        u = kgm * np.exp(1j * np.radians(angle)) * G_M
        ax.plot(u.imag, u.real, "x", ms=12, color=CORNER_COLOURS[corner], label=f"{corner} true: {kgm * G_M:.2f} g·m")
    ax.set_xlim(-limit, limit)
    ax.set_ylim(-limit, limit)
    ax.set_aspect("equal")
    ax.axhline(0, color="0.6", lw=0.6)
    ax.axvline(0, color="0.6", lw=0.6)
    ax.set_xlabel("m e sin(angle) [g·m]  (angle from the mark, in the rolling direction)")
    ax.set_ylabel("m e cos(angle) [g·m]  (mark at the top: up)")
    ax.legend(fontsize=7)
    ax.set_title("identified unbalance per wheel: 2σ disc, dotted: detection limit")
    fig.tight_layout()
    return fig


def plot_transmissibility(diagnosis: TrackDiagnosis) -> plt.Figure:
    """Per corner: |body / wheel acceleration| measured and as the model gives it, and how far apart."""
    found = diagnosis.transmissibility
    corners = list(found.measured)
    fig, axes = plt.subplots(1, len(corners), figsize=(3.6 * len(corners), 3.4), squeeze=False, sharey=True)
    for ax, corner in zip(axes[0], corners):
        ax.loglog(found.frequency, np.abs(found.measured[corner]), color=CORNER_COLOURS[corner], label="measured")
        ax.loglog(found.frequency, np.abs(found.model[corner]), "k--", lw=0.9, label="model")
        ax.set_title(f"{corner}: {100 * found.error[corner]:.1f} % apart", fontsize=9)
        ax.set_xlabel("frequency [Hz]")
        ax.grid(alpha=0.3, which="both")
    axes[0, 0].set_ylabel("|body acc. / wheel acc.| [-]")
    axes[0, 0].legend(fontsize=7)
    fig.suptitle("transmissibility from wheel to body: measured and model (the road cancels out)")
    fig.tight_layout()
    return fig
