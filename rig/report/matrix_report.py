"""Result files of a test matrix (rig/diagnosis/track/test_matrix.py): matrix.json for tools; for people, the verdict
chart
(per case, each channel's model TDDI against the repeats' scatter) and per case the band of the repeats with the
model in it, one channel per quantity: the one furthest outside, or closest to leaving."""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

from rig.diagnosis.track.scatter import CaseScatter
from rig.diagnosis.track.test_matrix import MatrixResult
from rig.io.atomic import write_text_atomic
from rig.io.channels import split_channel
from rig.report.plots import plt, save_figure
from rig.report.style import channel_color, display_unit, mpl

INSIDE, OUTSIDE = (0.15, 0.55, 0.25), (0.80, 0.15, 0.12)
BAND_COLOR = (0.75, 0.75, 0.75)
ZOOM_S = 2.0  # s of a run shown beside it, where the model leaves the band furthest


def write_matrix(result: MatrixResult, out_dir: str | os.PathLike) -> list[str]:
    """matrix.json, verdicts.png and band_<n>.png per case; the names of the files written."""
    out = Path(out_dir)
    write_text_atomic(out / "matrix.json", json.dumps(result.to_json(), indent=1))
    save_figure(plot_verdicts(result), out / "verdicts.png")
    written = ["matrix.json", "verdicts.png"]
    for number, case in enumerate(result.cases, 1):
        save_figure(plot_band(case), out / f"band_{number}.png")
        written.append(f"band_{number}.png")
    return written


def plot_verdicts(result: MatrixResult) -> plt.Figure:
    """Per case (a row), each channel's scatter (the repeats' mean TDDI over their pairs, a bar up to the largest
    pair's) and the model's mean TDDI against the repeats (a dot: green inside the scatter, red outside)."""
    height = 2.8 * len(result.cases) + 1.3
    fig, axes = plt.subplots(len(result.cases), 1, figsize=(12, height), squeeze=False)
    for ax, case in zip(axes[:, 0], result.cases):
        x = np.arange(len(case.names))
        scatter = np.array([case.channels[n].scatter for n in case.names])
        worst = np.array([case.channels[n].scatter_max for n in case.names])
        model = np.array([case.channels[n].model for n in case.names])
        ax.bar(x, scatter, color=BAND_COLOR, label="repeats' scatter (mean TDDI of their pairs)")
        ax.errorbar(x, scatter, yerr=[np.zeros_like(worst), worst - scatter], fmt="none", ecolor="0.4", capsize=2,
                    lw=0.8, label="largest pair")
        inside = model <= scatter
        ax.scatter(x[inside], model[inside], color=INSIDE, zorder=3, s=18, label="model: inside")
        ax.scatter(x[~inside], model[~inside], color=OUTSIDE, zorder=3, s=18, label="model: outside")
        ax.set_yscale("log")
        ax.set_xticks(x, case.names, rotation=70, fontsize=6)
        ax.set_ylabel("TDDI (eq. 7)")
        ax.set_title(f"{case.label}: {len(case.outside)} of {len(case.names)} channels outside the scatter of "
                     f"{case.repeats.shape[0]} repeats", fontsize=9)
        ax.grid(alpha=0.3, axis="y", which="both")
    handles, labels = axes[0, 0].get_legend_handles_labels()
    fig.suptitle(f"{result.vehicle} against the scatter of repeated runs ({result.repeats_of})")
    fig.tight_layout(rect=(0, 0.35 / height, 1, 1))  # the legend below
    fig.legend(handles, labels, fontsize=7, loc="lower center", ncol=4, bbox_to_anchor=(0.5, 0.005))
    return fig


def band_channels(case: CaseScatter) -> list[str]:
    """One channel per quantity: the one whose model lies furthest beyond its scatter (model over scatter)."""
    chosen: dict[str, str] = {}
    for name in case.names:
        quantity = split_channel(name)[1]
        ratio = case.channels[name].model / max(case.channels[name].scatter, 1e-300)
        best = chosen.get(quantity)
        if best is None or ratio > case.channels[best].model / max(case.channels[best].scatter, 1e-300):
            chosen[quantity] = name
    return list(chosen.values())


def zoom_window(case: CaseScatter, name: str, seconds: float = ZOOM_S) -> slice:
    """``seconds`` of the run around where the model's channel lies furthest outside the repeats' band (or, inside it
    throughout, furthest from the band's middle)."""
    k = case.names.index(name)
    model, low, high = case.model[:, k], case.low[:, k], case.high[:, k]
    beyond = np.maximum(low - model, model - high)
    where = int(np.argmax(beyond if np.max(beyond) > 0 else np.abs(model - (low + high) / 2)))
    width = min(int(seconds * case.rate), model.size)
    start = int(np.clip(where - width // 2, 0, model.size - width))
    return slice(start, start + width)


def plot_band(case: CaseScatter) -> plt.Figure:
    """For ``band_channels``: the repeats' band (their envelope at each sample: dark grey, edged, so that a narrow
    band still shows) and the model's run (a line in the corner's colour, drawn over it) over the whole run (left)
    and over ZOOM_S s where the model leaves the band furthest (right, where the band's width shows); each row says
    the verdict."""
    names = band_channels(case)
    time = np.arange(case.model.shape[0]) / case.rate
    fig, axes = plt.subplots(len(names), 2, figsize=(13, 2.2 * len(names) + 0.8), squeeze=False,
                             gridspec_kw={"width_ratios": (2, 1)})
    for row, name in zip(axes, names):
        k = case.names.index(name)
        unit, scale = display_unit(split_channel(name)[1])
        color = mpl(channel_color(name)) if split_channel(name)[0] in case_corners(case) else (0.1, 0.1, 0.1)
        zoom = zoom_window(case, name)
        for ax, part in zip(row, (slice(None), zoom)):
            ax.plot(time[part], scale * case.model[part, k], lw=0.9, color=color, label="model")
            ax.fill_between(time[part], scale * case.low[part, k], scale * case.high[part, k], color="0.15",
                            alpha=0.55, lw=0.5, edgecolor="0.15", label=f"band of {case.repeats.shape[0]} repeats")
            ax.grid(alpha=0.3)
        row[0].axvspan(time[zoom.start], time[zoom.stop - 1], color="0.85", zorder=0, lw=0)
        score = case.channels[name]
        row[0].set_title(f"{name}: model {'inside' if score.inside else 'outside'} the scatter (TDDI {score.model:.3g} "
                         f"against the repeats, their scatter {score.scatter:.3g})", fontsize=8,
                         color=INSIDE if score.inside else OUTSIDE)
        row[1].set_title(f"the {ZOOM_S:g} s shaded on the left", fontsize=8)
        row[0].set_ylabel(f"[{unit}]")
    axes[0, 1].legend(fontsize=7, loc="upper right")
    for ax in axes[-1]:
        ax.set_xlabel("time [s]")
    fig.suptitle(f"{case.label}: the repeats' band and the model (analysis band)")
    return fig


def case_corners(case: CaseScatter) -> set[str]:
    """The corners among the case's channels (not ``cab``)."""
    return {split_channel(n)[0] for n in case.names if split_channel(n)[0] != "cab"}
