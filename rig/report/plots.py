"""Plots a test engineer looks at first: the responses of a run per corner, in time and frequency, as PNG."""

from __future__ import annotations

import os
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only; never needs a display
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.ticker import FormatStrFormatter, MaxNLocator
from scipy.signal import welch

from rig.io.atomic import atomic_path
from rig.io.channels import CORNERS, channel
from rig.io.record import Record

#: (quantity, axis label, scale from SI)
_PANELS = (
    ("actuator_disp", "post disp. [mm]", 1e3),
    ("road", "road [mm]", 1e3),
    ("sprung_acc", "sprung acc. [m/s²]", 1.0),
    ("unsprung_acc", "unsprung acc. [m/s²]", 1.0),
    ("susp_travel", "travel [mm]", 1e3),
    ("tyre_force", "tyre force [kN]", 1e-3),
)


def plot_responses(record: Record, path: str | os.PathLike, title: str = "",
                   window: tuple[float, float] | None = None) -> None:
    """Grid of responses (rows: quantities, columns: corners), drive overlaid on post displacement.

    ``window`` (s) limits the time axis: broadband signals are unreadable over a whole run.
    """
    corners = [c for c in CORNERS if any(channel(c, q) in record for q, _, _ in _PANELS)]
    panels = [p for p in _PANELS if any(channel(c, p[0]) in record for c in corners)]
    fig, axes = plt.subplots(len(panels), len(corners), figsize=(3.6 * len(corners), 1.9 * len(panels)),
                             sharex=True, squeeze=False)
    time = record.time
    for col, corner in enumerate(corners):
        axes[0, col].set_title(corner)
        for row, (quantity, label, scale) in enumerate(panels):
            ax = axes[row, col]
            if quantity == "actuator_disp" and channel(corner, "drive") in record:
                ax.plot(time, record[channel(corner, "drive")] * scale, lw=0.6, color="0.6", label="drive")
            name = channel(corner, quantity)
            if name in record:
                ax.plot(time, record[name] * scale, lw=0.6, color="C0", label=quantity)
            ax.grid(alpha=0.3)
            if col == 0:
                ax.set_ylabel(label)
        axes[-1, col].set_xlabel("time [s]")
        if window:
            axes[-1, col].set_xlim(*window)
    if channel(corners[0], "drive") in record:
        axes[0, 0].legend(loc="upper right", fontsize=7)
    fig.suptitle(title or f"{record.metadata.get('vehicle', '')} responses")
    save_figure(fig, path)


def plot_psds(record: Record, path: str | os.PathLike, title: str = "",
              band: tuple[float, float] = (0.3, 60.0)) -> None:
    """Welch PSDs of the responses per corner (rows: quantities, columns: corners), log scales."""
    corners = [c for c in CORNERS if any(channel(c, q) in record for q, _, _ in _PANELS)]
    panels = [p for p in _PANELS if any(channel(c, p[0]) in record for c in corners)]
    fig, axes = plt.subplots(len(panels), len(corners), figsize=(3.6 * len(corners), 1.9 * len(panels)),
                             sharex=True, squeeze=False)
    segment = int(min(record.n_samples, 8 * record.rate))
    for col, corner in enumerate(corners):
        axes[0, col].set_title(corner)
        for row, (quantity, label, scale) in enumerate(panels):
            ax = axes[row, col]
            name = channel(corner, quantity)
            if name in record:
                f, p = welch(record[name] * scale, record.rate, nperseg=segment)
                keep = (f >= band[0]) & (f <= band[1])
                ax.loglog(f[keep], p[keep], lw=0.8)
                if p[keep].max() > 0:  # six decades: out-of-band roll-off would flatten the band itself
                    ax.set_ylim(p[keep].max() * 1e-6, p[keep].max() * 3)
            ax.grid(alpha=0.3, which="both")
            if col == 0:
                ax.set_ylabel(f"PSD of {label.split(' [')[0]}")
        axes[-1, col].set_xlabel("frequency [Hz]")
    fig.suptitle(title or "power spectral densities (units² / Hz, axis units as in the time plot)")
    save_figure(fig, path)


def save_figure(fig: plt.Figure, path: str | os.PathLike) -> None:
    """Lay out, write as PNG atomically, and close ``fig``."""
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110, format="png")
    plt.close(fig)


def plot_convergence(history: list[dict], path: str | os.PathLike, title: str = "drive iteration") -> None:
    """RMS error per channel and the gain over the iterations (log error axis)."""
    iterations = [h["iteration"] for h in history]
    fig, (errors, gains) = plt.subplots(2, 1, figsize=(8, 6), sharex=True, gridspec_kw={"height_ratios": [3, 1]})
    for name in history[0]["channels"]:
        errors.semilogy(iterations, [h["channels"][name]["rms_error_pct"] for h in history], marker="o", ms=3,
                        lw=1, label=name)
    errors.semilogy(iterations, [h["worst_rms_error_pct"] for h in history], color="k", lw=2, label="worst")
    errors.set_ylabel("RMS error [%]")
    errors.yaxis.set_major_formatter(FormatStrFormatter("%g"))  # plain numbers, not 1.3 x 10^1
    errors.yaxis.set_minor_formatter(FormatStrFormatter("%g"))
    errors.xaxis.set_major_locator(MaxNLocator(integer=True))
    errors.grid(alpha=0.3, which="both")
    errors.legend(fontsize=7, ncol=3)
    gains.plot(iterations, [h["gain"] for h in history], marker="o", color="C3")
    gains.set_ylabel("gain")
    gains.set_xlabel("iteration")
    gains.grid(alpha=0.3)
    fig.suptitle(title)
    save_figure(fig, path)


def plot_psd_overlay(target: np.ndarray, response: np.ndarray, rate: float, names: list[str],
                     path: str | os.PathLike, title: str = "") -> None:
    """Target and response PSDs per channel (samples x channels arrays), log scales."""
    columns = min(4, len(names))
    rows = int(np.ceil(len(names) / columns))
    fig, axes = plt.subplots(rows, columns, figsize=(3.4 * columns, 2.4 * rows), squeeze=False, sharex=True)
    segment = int(min(target.shape[0], 8 * rate))
    for i, name in enumerate(names):
        ax = axes[i // columns, i % columns]
        for values, label, style in ((target[:, i], "target", "-"), (response[:, i], "response", "--")):
            f, p = welch(values, rate, nperseg=segment)
            keep = (f > 0.2) & (f < 80)
            ax.loglog(f[keep], p[keep], style, lw=0.9, label=label)
        ax.set_title(name, fontsize=8)
        ax.grid(alpha=0.3, which="both")
    for ax in axes[-1]:
        ax.set_xlabel("frequency [Hz]")
    for ax in axes.flat[len(names):]:
        ax.set_visible(False)
    axes[0, 0].legend(fontsize=7)
    fig.suptitle(title)
    save_figure(fig, path)


class IterationPlots:
    """A drive-iteration callback that draws, after every iteration, ``convergence.png`` and
    ``psd/iteration_NN.png`` (target and response PSDs over the target's span) in ``out_dir``.

    ``target``: the edited target (samples x channels, SI) the iteration compares with; ``span``: the
    target's own samples within it.
    """

    def __init__(self, out_dir: str | os.PathLike, title: str, target: np.ndarray, span: slice, rate: float,
                 channels: list[str]):
        self.out_dir, self.title, self.target, self.span, self.rate, self.channels = \
            Path(out_dir), title, target, span, rate, list(channels)

    def __call__(self, step) -> None:
        plot_convergence([h.to_json() for h in step.history], self.out_dir / "convergence.png", self.title)
        k = step.record.iteration
        plot_psd_overlay(self.target[self.span], step.response[self.span], self.rate, self.channels,
                         self.out_dir / "psd" / f"iteration_{k:02d}.png", f"iteration {k}: target and response PSDs")
