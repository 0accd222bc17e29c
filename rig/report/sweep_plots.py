"""Plots of a finished sweep (PNG): response surfaces, the comfort / road-holding Pareto front, PSD scatter bands."""

from __future__ import annotations


import numpy as np

from rig.io.channels import QUANTITY_UNITS, split_channel
from rig.report.plots import plt
from rig.sweep.design import SPEED
from rig.sweep.results import BAND_PERCENTILES, PsdBand, SweepResult, column_unit, pareto_mask

SURFACE_METRICS = (("a_w", "a_w [m/s²]"), ("tyre_load_rms", "tyre load RMS / static [-]"),
                   ("travel_rms", "travel RMS [m]"))


def _key_label(key: str) -> str:
    """A varied key with its unit: ``front.damping [N s/m]``."""
    unit = column_unit(key)
    return f"{key} [{unit}]" if unit else key


def plot_response_surfaces(result: SweepResult, title: str = "") -> plt.Figure:
    """Each ride metric over the varied keys: a line over one key, over the first two filled contours (a grid) or
    coloured points (samples), histograms when no key varies."""
    values = result.design.values
    varied = [k for j, k in enumerate(result.design.keys) if np.ptp(values[:, j]) > 0]
    fig, axes = plt.subplots(1, len(SURFACE_METRICS), figsize=(5.2 * len(SURFACE_METRICS), 4.4))
    for ax, (name, label) in zip(axes, SURFACE_METRICS):
        z = result.column(name)
        if not varied:
            ax.hist(z, bins=max(5, int(np.sqrt(z.size))), color="0.5")
            ax.set_xlabel(label)
            ax.set_ylabel("points")
        elif len(varied) == 1:
            x = result.column(varied[0])
            order = np.argsort(x)
            ax.plot(x[order], z[order], "o-", color="C0")
            ax.set_xlabel(_key_label(varied[0]))
            ax.set_ylabel(label)
        else:
            x, y = result.column(varied[0]), result.column(varied[1])
            if result.design.kind == "grid":
                filled = ax.tricontourf(x, y, z, levels=12, cmap="viridis")
                ax.plot(x, y, "k.", markersize=3)
            else:  # scattered samples: the points themselves, no surface drawn between them
                filled = ax.scatter(x, y, c=z, cmap="viridis", s=30, edgecolors="k", linewidths=0.3)
            fig.colorbar(filled, ax=ax, label=label)
            ax.set_xlabel(_key_label(varied[0]))
            ax.set_ylabel(_key_label(varied[1]))
            if len(varied) > 2:
                ax.set_title(f"over {varied[0]}, {varied[1]}; {', '.join(varied[2:])} mixed in", fontsize=8)
        ax.grid(alpha=0.3)
    fig.suptitle(title or "sweep: response surfaces")
    fig.tight_layout()
    return fig


def plot_sweep_pareto(result: SweepResult, title: str = "") -> plt.Figure:
    """a_w against tyre load RMS for every point, the Pareto front (neither can improve without the other
    getting worse) joined and each front point labelled with its key values. Speed is a condition, not a
    design choice: a grid over a few speeds gets one front per speed."""
    load, comfort = result.column("tyre_load_rms"), result.column("a_w")
    speeds = np.unique(result.column(SPEED)) if SPEED in result.design.keys else np.array([np.nan])
    groups = [np.ones(load.size, bool)] if speeds.size > 8 or np.isnan(speeds[0]) else \
        [result.column(SPEED) == v for v in speeds]
    fig, ax = plt.subplots(figsize=(7.5, 5.5))
    for g, members in enumerate(groups):
        front = np.zeros(load.size, bool)
        front[members] = pareto_mask(load[members], comfort[members])
        color = f"C{g % 10}"
        label = "" if len(groups) == 1 else f" at {speeds[g]:g} m/s"
        ax.plot(load[members & ~front], comfort[members & ~front], "o", color=color, alpha=0.35,
                label="design points" + label)
        order = np.flatnonzero(front)[np.argsort(load[front])]
        ax.plot(load[order], comfort[order], "o-", color=color, label="Pareto front" + label)
        for i in order:
            text = ", ".join(f"{k.split('.')[-1]} {result.design.values[i, j]:.4g}"
                             for j, k in enumerate(result.design.keys) if k != SPEED or len(groups) == 1)
            ax.annotate(text, (load[i], comfort[i]), textcoords="offset points", xytext=(5, 4), fontsize=7, color=color)
    ax.set_xlabel("dynamic tyre load RMS / static load (worst corner) [-]")
    ax.set_ylabel("ISO 2631-1 a_w, body [m/s²] (worst corner)")
    ax.set_title(title or "comfort vs road holding")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def plot_psd_band(band: PsdBand, measured: dict[str, tuple[np.ndarray, np.ndarray]] | None = None,
                  title: str = "") -> plt.Figure:
    """Each channel's PSD scatter band (5-95 %, median) over the points, with the measured PSD (frequency,
    PSD per channel name) drawn over it where given."""
    n = len(band.channels)
    columns = min(4, n)
    rows = -(-n // columns)
    fig, axes = plt.subplots(rows, columns, figsize=(4.2 * columns, 3.2 * rows), squeeze=False)
    low, _, high = BAND_PERCENTILES
    for ax, c, name in zip(axes.flat, range(n), band.channels):
        ax.fill_between(band.frequency, band.low[c], band.high[c], color="C0", alpha=0.3,
                        label=f"simulated {low:g}-{high:g} %")
        ax.plot(band.frequency, band.median[c], color="C0", lw=1, label="simulated median")
        if measured and name in measured:
            f, p = measured[name]
            ax.plot(f, p, color="k", lw=0.9, label="measured")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(name, fontsize=9)
        ax.set_xlabel("frequency [Hz]")
        ax.set_ylabel(f"PSD [({QUANTITY_UNITS.get(split_channel(name)[1], 'SI')})²/Hz]", fontsize=8)
        ax.grid(alpha=0.3, which="both")
    for ax in list(axes.flat)[n:]:
        ax.axis("off")
    axes.flat[0].legend(fontsize=7)
    fig.suptitle(title or "Monte-Carlo scatter band of the PSDs")
    fig.tight_layout()
    return fig
