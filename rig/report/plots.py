"""Plots a test engineer looks at first: the responses of a run per corner in time and frequency, a drive
iteration's convergence and FRF. Each function returns the matplotlib Figure; ``save_figure`` writes it."""

from __future__ import annotations

import os
import textwrap
from collections.abc import Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only; never needs a display
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.ticker import FixedLocator, FormatStrFormatter, LogLocator, MaxNLocator, NullFormatter, NullLocator

from rig.constants import ANALYSIS_BAND
from rig.io.atomic import atomic_path
from rig.io.channels import channel, sort_corners, split_channel
from rig.io.record import Record
from rig.report.style import REFERENCE_COLOR, channel_color, corner_color, display_unit, mpl
from rig.signal.psd import psd

#: Quantities of the response grid, top to bottom, with the name of their axis.
_PANELS = (("actuator_disp", "post disp."), ("road", "road"), ("sprung_acc", "sprung acc."),
           ("unsprung_acc", "unsprung acc."), ("susp_travel", "travel"), ("tyre_force", "tyre force"))
PSD_DECADES = 6  # a PSD axis shows at most this many decades below the peak
#: Frequency ticks of log axes, Hz.
HERTZ_TICKS = (0.5, 1, 2, 5, 10, 20, 50)
#: Line style per quantity where one axis holds several channels of a corner.
QUANTITY_STYLES = {"sprung_acc": "-", "unsprung_acc": "--"}


def _grid(record: Record) -> tuple[list[str], list[tuple[str, str]]]:
    corners = [c for c in sort_corners(split_channel(n)[0] for n in record.names)
               if any(channel(c, q) in record for q, _ in _PANELS)]
    return corners, [p for p in _PANELS if any(channel(c, p[0]) in record for c in corners)]


def plot_responses(record: Record, title: str = "", window: tuple[float, float] | None = None) -> plt.Figure:
    """Grid of responses (rows: quantities, columns: corners, each in its corner's colour), the drive (grey,
    thin) under the post displacement. ``window`` (s) limits the time axis: broadband signals are unreadable
    over a whole run. A record longer than LONG_S without a ``window`` is shown over DETAIL_S around its largest
    body (else first) response, under a top row with the whole run as a min/max envelope and that window shaded."""
    corners, panels = _grid(record)
    whole = window is None and record.duration > LONG_S
    if whole:
        window = detail_window(record, corners, "sprung_acc" if "sprung_acc" in dict(panels) else panels[0][0])
    rows = len(panels) + whole
    fig = plt.figure(figsize=(3.6 * len(corners), 1.9 * rows))
    grid = fig.add_gridspec(rows, len(corners), height_ratios=[1.3] * whole + [1.0] * len(panels))
    inside = slice(None)
    if window is not None:
        lo, hi = np.searchsorted(record.time, window)
        inside = slice(max(lo - 1, 0), hi + 1)
    legend_axes = None
    for col, corner in enumerate(corners):
        if whole:
            _envelope(fig.add_subplot(grid[0, col]), record, corner, dict(panels), window)
        first = None
        for row, (quantity, label) in enumerate(panels):
            ax = fig.add_subplot(grid[row + whole, col], sharex=first)
            first = first or ax
            legend_axes = legend_axes or ax
            unit, scale = display_unit(quantity)
            time = record.time[inside]
            if quantity == "actuator_disp" and channel(corner, "drive") in record:
                ax.plot(time, record[channel(corner, "drive")][inside] * scale, lw=0.6, color=mpl(REFERENCE_COLOR),
                        label="drive")
            name = channel(corner, quantity)
            if name in record:
                ax.plot(time, record[name][inside] * scale, lw=0.7, color=mpl(channel_color(name)), label=quantity)
            ax.grid(alpha=0.3)
            if col == 0:
                ax.set_ylabel(f"{label} [{unit}]")
            if row == 0 and not whole:
                ax.set_title(corner, color=mpl(corner_color(corner)))
            if row < len(panels) - 1:
                ax.tick_params(labelbottom=False)
        ax.set_xlabel("time [s]")
        if window:
            ax.set_xlim(*window)
    if channel(corners[0], "drive") in record:
        legend_axes.legend(loc="upper right", fontsize=7)
    detail = f"; {window[1] - window[0]:.1f} s of {record.duration:.1f} s below (shaded above)" if whole else ""
    fig.suptitle((title or f"{record.metadata.get('vehicle', '')} responses") + detail)
    return fig


#: A record longer than this (s) is plotted as a whole-run envelope above a DETAIL_S window (s): a broadband time
#: history of tens of seconds at 1.9 in per row is solid ink.
LONG_S, DETAIL_S = 6.0, 3.0
ENVELOPE_BINS = 400


def detail_window(record: Record, corners: Sequence[str], quantity: str) -> tuple[float, float]:
    """DETAIL_S (s) of ``record`` centred on the largest magnitude of ``quantity`` over ``corners``."""
    values = np.abs(np.column_stack([record[channel(c, quantity)] for c in corners if channel(c, quantity) in record]))
    peak = record.time[np.argmax(values.max(axis=1))]
    start = float(np.clip(peak - DETAIL_S / 2, record.time[0], record.time[-1] - DETAIL_S))
    return start, start + DETAIL_S


def _envelope(ax: plt.Axes, record: Record, corner: str, panels: dict[str, str], window: tuple[float, float]) -> None:
    """The whole run of the corner's body acceleration (else first quantity) as the min and max per time bin, with
    ``window`` shaded."""
    quantity = "sprung_acc" if channel(corner, "sprung_acc") in record else \
        next(q for q in panels if channel(corner, q) in record)
    unit, scale = display_unit(quantity)
    values = record[channel(corner, quantity)] * scale
    edges = np.linspace(0, values.size, min(ENVELOPE_BINS, values.size) + 1).astype(int)
    low = np.minimum.reduceat(values, edges[:-1])
    high = np.maximum.reduceat(values, edges[:-1])
    ax.fill_between(record.time[edges[:-1]], low, high, step="post", lw=0, color=mpl(channel_color(channel(corner,
                                                                                                      quantity))))
    ax.axvspan(*window, color="0.5", alpha=0.3, lw=0)
    ax.set_xlim(record.time[0], record.time[-1])
    ax.set_title(f"{corner}: whole run, {panels[quantity]} [{unit}] min/max", color=mpl(corner_color(corner)),
                 fontsize=9)
    ax.grid(alpha=0.3)


def _psd_limits(ax: plt.Axes, psds: Sequence[np.ndarray], frequency: np.ndarray, band: tuple[float, float]) -> None:
    """The y range of a log PSD axis: the decades the PSDs span inside ``band``, at most PSD_DECADES below their
    peak (a roll-off outside the band, or a drive's cut-off inside it, must not squash the band)."""
    inside = (frequency >= band[0]) & (frequency <= band[1])
    values = np.concatenate([p[inside] for p in psds])
    values = values[values > 0]
    if values.size:
        ax.set_ylim(max(values.min(), values.max() * 10.0**-PSD_DECADES) / 2, values.max() * 2)
    ax.set_xlim(band[0] / 1.2, band[1] * 1.2)
    hertz_axis(ax, band)


def hertz_axis(ax: plt.Axes, band: tuple[float, float]) -> None:
    """A log frequency axis labelled in plain Hz (0.5, 1, 2, 5, ...) over ``band``, its grid at those ticks alone; a
    log y axis beside it with minor ticks at 2 and 5 of each decade only. Eight minor lines per decade were clutter
    on a panel 1.9 in high, and their ticks took 40 % of a 20-panel figure's drawing."""
    ax.xaxis.set_major_locator(FixedLocator([t for t in HERTZ_TICKS if band[0] <= t <= band[1]]))
    ax.xaxis.set_major_formatter(FormatStrFormatter("%g"))
    ax.xaxis.set_minor_locator(NullLocator())
    if ax.get_yscale() == "log":
        ax.yaxis.set_minor_locator(LogLocator(subs=(2.0, 5.0)))


def plot_psds(record: Record, title: str = "", band: tuple[float, float] = ANALYSIS_BAND) -> plt.Figure:
    """Welch PSDs of the responses per corner (rows: quantities in their unit²/Hz, columns: corners), log axes
    over ``band`` (Hz), the y range the band's."""
    corners, panels = _grid(record)
    fig, axes = plt.subplots(len(panels), len(corners), figsize=(3.6 * len(corners), 1.9 * len(panels)),
                             sharex=True, squeeze=False)
    for col, corner in enumerate(corners):
        axes[0, col].set_title(corner, color=mpl(corner_color(corner)))
        for row, (quantity, label) in enumerate(panels):
            ax = axes[row, col]
            unit, scale = display_unit(quantity)
            name = channel(corner, quantity)
            if name in record:
                f, p = psd(record[name] * scale, record.rate)
                ax.loglog(f[1:], p[1:], lw=0.8, color=mpl(channel_color(name)))
                _psd_limits(ax, [p], f, band)
            ax.grid(alpha=0.3, which="both")
            if col == 0:
                ax.set_ylabel(f"{label}\n[({unit})²/Hz]", fontsize=8)
        axes[-1, col].set_xlabel("frequency [Hz]")
    fig.suptitle(title or "power spectral densities")
    return fig


def lay_out(fig: plt.Figure) -> None:
    """Lay ``fig`` out so that titles and labels keep apart (unless the figure has a layout of its own)."""
    if fig.get_layout_engine() is None:
        fig.tight_layout()


def save_figure(fig: plt.Figure, path: str | os.PathLike) -> None:
    """Lay out (``lay_out``), write as PNG atomically, and close ``fig``."""
    lay_out(fig)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110, format="png")
    plt.close(fig)


def plot_convergence(history: Sequence, target_error_pct: float | None = None, stop_reason: str = "",
                     title: str = "drive iteration") -> plt.Figure:
    """RMS error per channel over the iterations (``IterationRecord`` s; log axis labelled over the errors' own
    range; corner colours, sprung solid, unsprung dashed), the worst channel ringed, the best iteration marked,
    the target error dashed, and the gain below. The title says whether the worst channel's error fell or rose."""
    iterations = [h.iteration for h in history]
    worst = [h.worst_rms_error_pct for h in history]
    fig, (errors, gains) = plt.subplots(2, 1, figsize=(9, 6.5), sharex=True, gridspec_kw={"height_ratios": [3, 1]})
    shown = list(worst)
    for name in history[0].channels:
        values = [h.channels[name].rms_error_pct for h in history]
        shown += values
        errors.semilogy(iterations, values, marker="o", ms=3, lw=1.2, color=mpl(channel_color(name)), label=name,
                        ls=QUANTITY_STYLES.get(split_channel(name)[1], ":"))
    errors.semilogy(iterations, worst, "o", ms=11, mfc="none", mec="k", mew=1.2, label="worst channel")
    best = iterations[int(np.argmin(worst))]
    errors.axvline(best, color="0.4", lw=1.0, ls=":", label=f"best: iteration {best}")
    if target_error_pct is not None and target_error_pct > 0:
        errors.axhline(target_error_pct, color="k", ls="--", lw=1.2, label=f"target {target_error_pct:g} %")
        shown.append(target_error_pct)
    percent_axis(errors, shown)
    errors.set_ylabel("RMS error [%]")
    errors.xaxis.set_major_locator(MaxNLocator(integer=True))
    errors.grid(alpha=0.3, which="both")
    errors.legend(fontsize=7, ncol=3)
    trend = convergence_trend(iterations, worst)
    errors.set_title("\n".join(line for text in (stop_reason, trend) for line in textwrap.wrap(text, 100)),
                     fontsize=9, color="C3" if worst[-1] > worst[0] else "k")
    gains.plot(iterations, [h.gain for h in history], marker="o", color=mpl(REFERENCE_COLOR))
    gains.set_ylabel("gain [-]")
    gains.set_xlabel("iteration")
    gains.grid(alpha=0.3)
    fig.suptitle(title)
    fig.tight_layout()
    return fig


def convergence_trend(iterations: Sequence[int], worst: Sequence[float]) -> str:
    """The worst channel's error (%) from the first iteration to the last, in words: fell or rose, and the best."""
    if len(worst) < 2:
        return ""
    way = "rose" if worst[-1] > worst[0] else "fell"
    best = int(np.argmin(worst))
    return (f"the worst channel's RMS error {way} from {worst[0]:.3g} % (iteration {iterations[0]}) to "
            f"{worst[-1]:.3g} % (iteration {iterations[-1]}); best {worst[best]:.3g} % at iteration {iterations[best]}")


#: Mantissas of the labelled ticks of a log percent axis, densest first: a range inside one decade still gets
#: labels (12, 15), a range of several decades fewer (1, 2, 5, 10, 20, 50).
_LOG_TICKS = ((1, 1.2, 1.5, 2, 2.5, 3, 4, 5, 6, 7, 8, 9), (1, 1.5, 2, 3, 5, 7), (1, 2, 5), (1,))


def percent_axis(ax: plt.Axes, values: Sequence[float], most: int = 10) -> None:
    """A log y axis over the positive ``values`` (a margin of 15 %) with plain-number tick labels inside that
    range: at most ``most``, and at least two wherever the range allows."""
    values = np.asarray([v for v in values if v > 0 and np.isfinite(v)], float)
    if not values.size:
        return
    low, high = values.min() / 1.15, values.max() * 1.15
    ax.set_ylim(low, high)
    decades = range(int(np.floor(np.log10(low))), int(np.ceil(np.log10(high))) + 1)
    for mantissas in _LOG_TICKS:
        ticks = [m * 10.0**d for d in decades for m in mantissas if low <= m * 10.0**d <= high]
        if len(ticks) <= most:
            break
    ax.yaxis.set_major_locator(FixedLocator(ticks))
    ax.yaxis.set_major_formatter(FormatStrFormatter("%g"))  # plain numbers, not 1.3 x 10^1
    ax.yaxis.set_minor_formatter(NullFormatter())


def plot_frf(frequency: np.ndarray, h1: np.ndarray, coherence: np.ndarray, inputs: Sequence[str],
             outputs: Sequence[str], band: tuple[float, float] = ANALYSIS_BAND, title: str = "") -> plt.Figure:
    """FRFs from each input (``<corner>/drive``, m) to each output (columns): |H1| in dB re 1 output unit per
    m, phase in degrees, and the output's multiple coherence, against frequency in Hz on a log axis over
    ``band``. ``h1``: lines x outputs x inputs (SI); ``coherence``: lines x outputs. Lines take the input's
    corner colour; the output's own corner is drawn wide."""
    keep = (frequency >= band[0]) & (frequency <= band[1])
    f = frequency[keep]
    fig, axes = plt.subplots(3, len(outputs), figsize=(4.6 * len(outputs), 6.5), sharex=True, squeeze=False,
                             gridspec_kw={"height_ratios": [3, 2, 1.2]})
    for o, output in enumerate(outputs):
        corner, quantity = split_channel(output)
        unit = {"sprung_acc": "(m/s²)/m", "unsprung_acc": "(m/s²)/m"}.get(quantity, f"{quantity} SI unit/m")
        magnitude, phase, coh = axes[:, o]
        for i, source in enumerate(inputs):
            h = h1[keep, o, i]
            own = split_channel(source)[0] == corner
            style = dict(color=mpl(channel_color(source)), lw=2.0 if own else 0.9, label=f"from {source}")
            magnitude.semilogx(f, 20 * np.log10(np.maximum(np.abs(h), 1e-300)), **style)
            phase.semilogx(f, np.degrees(np.angle(h)), **style)
        coh.semilogx(f, coherence[keep, o], color=mpl(channel_color(output)), lw=1.2)
        magnitude.set_title(output, color=mpl(corner_color(corner)))
        magnitude.set_ylabel(f"|H1| [dB re 1 {unit}]", fontsize=8)
        phase.set_ylabel("phase [deg]")
        phase.set_yticks([-180, -90, 0, 90, 180])
        coh.set_ylabel("coherence [-]")
        coh.set_ylim(0, 1.05)
        coh.set_xlabel("frequency [Hz]")
        for ax in axes[:, o]:
            ax.grid(alpha=0.3, which="both")
            ax.set_xlim(*band)
            hertz_axis(ax, band)
        magnitude.legend(fontsize=9)
    fig.suptitle(title)
    fig.tight_layout()
    return fig


def plot_psd_overlay(target: np.ndarray, response: np.ndarray, rate: float, names: list[str], title: str = "",
                     band: tuple[float, float] = ANALYSIS_BAND, labels: tuple[str, str] = ("target", "response")
                     ) -> plt.Figure:
    """Target (grey, thin, on top) and response (corner colour, wide) PSDs per channel (samples x channels,
    SI), in each channel's unit²/Hz, log axes over ``band`` with the band's y range."""
    columns = min(4, len(names))
    rows = int(np.ceil(len(names) / columns))
    fig, axes = plt.subplots(rows, columns, figsize=(3.6 * columns, 2.6 * rows), squeeze=False, sharex=True)
    for i, name in enumerate(names):
        ax = axes[i // columns, i % columns]
        unit, scale = display_unit(split_channel(name)[1])
        f, response_psd = psd(response[:, i] * scale, rate)
        _, target_psd = psd(target[:, i] * scale, rate)
        ax.loglog(f[1:], response_psd[1:], lw=2.0, color=mpl(channel_color(name)), label=labels[1])
        ax.loglog(f[1:], target_psd[1:], lw=0.9, color="k", label=labels[0])
        _psd_limits(ax, [target_psd, response_psd], f, band)
        ax.set_title(name, fontsize=8)
        ax.set_ylabel(f"[({unit})²/Hz]", fontsize=7)
        ax.grid(alpha=0.3, which="both")
    for ax in axes[-1]:
        ax.set_xlabel("frequency [Hz]")
    for ax in axes.flat[len(names):]:
        ax.set_visible(False)
    axes[0, 0].legend(fontsize=7)
    fig.suptitle(title)
    return fig


class IterationPlots:
    """A drive-iteration callback that writes, after every iteration, ``convergence.png`` and
    ``psd/iteration_NN.png`` (target and response PSDs over the target's span) in ``out_dir``.

    ``target``: the edited target (samples x channels, SI) the iteration compares with; ``span``: the
    target's own samples within it; ``target_error_pct``: the error the iteration stops at.
    """

    def __init__(self, out_dir: str | os.PathLike, title: str, target: np.ndarray, span: slice, rate: float,
                 channels: list[str], target_error_pct: float | None = None):
        self.out_dir, self.title, self.target, self.span, self.rate, self.channels = \
            Path(out_dir), title, target, span, rate, list(channels)
        self.target_error_pct = target_error_pct

    def __call__(self, step) -> None:
        save_figure(plot_convergence(step.history, self.target_error_pct, title=self.title),
                    self.out_dir / "convergence.png")
        k = step.record.iteration
        save_figure(plot_psd_overlay(self.target[self.span], step.response[self.span], self.rate, self.channels,
                                     f"iteration {k}: target and response PSDs"),
                    self.out_dir / "psd" / f"iteration_{k:02d}.png")
