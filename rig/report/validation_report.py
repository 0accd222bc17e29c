"""Result files of a validation: validation.json for tools, PSD overlays and pattern FRFs for people."""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

from rig.diagnosis.validation import PATTERNS, ValidationReport
from rig.io.atomic import write_text_atomic
from rig.report.plots import plot_psd_overlay, plt, save_figure


def write_validation(report: ValidationReport, out_dir: str | os.PathLike) -> None:
    """validation.json (TDDI and RMS error % per channel), PSD overlays and heave/pitch/roll/warp FRFs."""
    out = Path(out_dir)
    write_text_atomic(out / "validation.json", json.dumps(report.to_json(), indent=1))
    names = report.measured.names
    plot_psd_overlay(np.column_stack([report.measured[n] for n in names]),
                     np.column_stack([report.simulated[n] for n in names]), report.measured.rate, names,
                     out / "psd_overlay.png", f"{report.vehicle}: measured (target) and simulated (response) PSDs")
    _plot_pattern_frfs(report, out / "pattern_frfs.png")


def _plot_pattern_frfs(report: ValidationReport, path: Path) -> None:
    frequency = report.pattern_frequency
    keep = (frequency > report.band_hz[0]) & (frequency < report.band_hz[1])
    fig, axes = plt.subplots(1, 4, figsize=(15, 3.8), sharey=True)
    for p, (pattern, ax) in enumerate(zip(PATTERNS, axes)):
        for i, name in enumerate(report.car_channels):
            line, = ax.loglog(frequency[keep], np.abs(report.pattern_measured[keep, i, p]), lw=1, label=name)
            ax.loglog(frequency[keep], np.abs(report.pattern_simulated[keep, i, p]), "--", lw=1, color=line.get_color())
        ax.set_title(f"{pattern} input")
        ax.set_xlabel("frequency [Hz]")
        ax.grid(alpha=0.3, which="both")
    axes[0].set_ylabel("|response / post pattern| (SI per m)")
    axes[-1].legend(fontsize=6, ncol=2)
    fig.suptitle("FRFs by post input pattern: measured (solid), simulated (dashed)")
    save_figure(fig, path)
