"""Result files of a validation: validation.json for tools, PSD overlays and pattern FRFs for people."""

from __future__ import annotations

import json
import os
import re
from pathlib import Path

import numpy as np

from rig.diagnosis.core.validation import ValidationReport
from rig.io.atomic import write_text_atomic
from rig.io.channels import split_channel
from rig.report.plots import hertz_axis, plot_psd_overlay, plt, save_figure
from rig.report.style import channel_color, index_text, mpl
from rig.signal.discrepancy import Discrepancy

#: Rows of the pattern FRF figure: one quantity each, with its unit per m of post pattern.
PATTERN_ROWS = (("sprung_acc", "body acc. [(m/s²)/m]"), ("unsprung_acc", "wheel acc. [(m/s²)/m]"),
                ("susp_travel", "travel [m/m]"), ("sprung_disp", "body disp. [m/m]"),
                ("unsprung_disp", "wheel disp. [m/m]"), ("tyre_force", "tyre force [N/m]"))
COHERENCE_FLOOR = 0.8  # below it the measured FRF is noise as much as response: its band is greyed


def write_validation(report: ValidationReport, out_dir: str | os.PathLike, ran: str | None = None) -> None:
    """validation.json (TDDI and RMS error % per channel), report.md (what ran, whether it passed, what next), PSD
    overlays and heave/pitch/roll/warp FRFs."""
    out = Path(out_dir)
    write_text_atomic(out / "validation.json", json.dumps(report.to_json(), indent=1))
    write_text_atomic(out / "report.md", "\n".join(report_lines(report, ran)))
    names = report.measured.names
    save_figure(plot_psd_overlay(np.column_stack([report.measured[n] for n in names]),
                                 np.column_stack([report.simulated[n] for n in names]), report.measured.rate, names,
                                 f"{report.vehicle}: measured and simulated PSDs", report.band_hz,
                                 ("measured", "simulated")), out / "psd_overlay.png")
    save_figure(plot_pattern_frfs(report), out / "pattern_frfs.png")


def report_lines(report: ValidationReport, ran: str | None = None) -> list[str]:
    """report.md: the command, the verdict, the notes, each channel's score and the figures."""
    worst = sorted(report.channels.items(), key=lambda kv: -kv[1].tddi)
    return [f"# Validation of {report.vehicle}", "", *([f"Run: `{ran}`", ""] if ran else []),
            f"**{report.verdict()}**", "", *[f"- {note}" for note in report.notes], "", "## What to do next", "",
            f"- {next_step(report, ran)}", "",
            f"Compared in {report.band_hz[0]:.3g}-{report.band_hz[1]:.3g} Hz, worst first:", "",
            "| channel | TDDI | RMS error [%] |", "|---|---|---|",
            *[f"| {name} | {score.tddi:.4g} | {score.rms_error_pct:.2f} |" for name, score in worst], "",
            "![PSDs](psd_overlay.png)", "", "![pattern FRFs](pattern_frfs.png)", ""]


def indices_line(indices: Discrepancy) -> str:
    """Forsén's measures of a test in one line (rig/signal/discrepancy.py)."""
    return (f"Forsén's indices: TDDI {indices.tddi:.4g} (eq. 7), {indices.tddi_measured:.4g} against the measured "
            f"variance (eq. 8); ride {index_text(indices.ride)}, payload {index_text(indices.payload)}, fatigue "
            f"{index_text(indices.fatigue)} (positive: the model responds less)")


def next_step(report: ValidationReport, ran: str | None = None) -> str:
    """What the verdict asks of the user; with ``ran`` (this validation's command), the command to run next."""
    if report.passed:
        return "the model stands on this record: iterate drives on it (`rig iterate --vehicle V --target T --out DIR`)"
    diagnose = "rig diagnose --vehicle V --measured M --out diagnosis"
    if ran:
        diagnose = re.sub(r" --out \S+", "", ran.replace("rig validate", "rig diagnose", 1)) + " --out diagnosis"
    return f"name what the model gets wrong and extend it: `{diagnose}`"


def _grey_low_coherence(ax: plt.Axes, frequency: np.ndarray, coherence: np.ndarray) -> None:
    """Grey the bands where the measured coherence is below COHERENCE_FLOOR."""
    low = coherence < COHERENCE_FLOOR
    edges = np.flatnonzero(np.diff(np.concatenate([[0], low.astype(int), [0]])))
    for start, stop in zip(edges[::2], edges[1::2]):
        ax.axvspan(frequency[start], frequency[min(stop, frequency.size - 1)], color="0.85", zorder=0, lw=0)


def plot_pattern_frfs(report: ValidationReport) -> plt.Figure:
    """|response / input| for the heave, pitch, roll and warp patterns (columns; then a record's actuator forces,
    per N), one quantity per row,
    every corner in its colour: measured solid, simulated dashed; bands where a measured response's coherence
    with the patterns is below COHERENCE_FLOOR are greyed."""
    frequency = report.pattern_frequency
    keep = (frequency >= report.band_hz[0]) & (frequency <= report.band_hz[1])
    rows = [(q, label) for q, label in PATTERN_ROWS if any(split_channel(n)[1] == q for n in report.car_channels)]
    patterns = report.pattern_names
    fig, axes = plt.subplots(len(rows), len(patterns), figsize=(3.75 * max(len(patterns), 2), 2.8 * len(rows) + 0.8),
                             sharex=True, squeeze=False)
    for r, (quantity, label) in enumerate(rows):
        indices = [i for i, n in enumerate(report.car_channels) if split_channel(n)[1] == quantity]
        for p, pattern in enumerate(patterns):
            ax = axes[r, p]
            if report.pattern_coherence is not None:
                worst = report.pattern_coherence[keep][:, indices].min(axis=1)
                _grey_low_coherence(ax, frequency[keep], worst)
            for i in indices:
                color = mpl(channel_color(report.car_channels[i]))
                ax.loglog(frequency[keep], np.abs(report.pattern_measured[keep, i, p]), lw=1.2, color=color,
                          label=f"{split_channel(report.car_channels[i])[0]} measured")
                ax.loglog(frequency[keep], np.abs(report.pattern_simulated[keep, i, p]), "--", lw=1.0, color=color,
                          label=f"{split_channel(report.car_channels[i])[0]} simulated")
            ax.grid(alpha=0.3, which="both")
            hertz_axis(ax, report.band_hz)
            if r == 0:
                ax.set_title(f"{pattern} input" + (" (per N)" if "/" in pattern else ""))
        axes[r, 0].set_ylabel(label)
        axes[r, -1].legend(fontsize=6, ncol=2, loc="lower right")
    for ax in axes[-1]:
        ax.set_xlabel("frequency [Hz]")
    fig.suptitle(f"FRFs by post input pattern, per quantity: measured solid, simulated dashed;\ngrey: measured "
                 f"coherence below {COHERENCE_FLOOR:g}")
    return fig
