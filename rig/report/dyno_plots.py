"""Plots of a damper dynamometer test: force against velocity with the fitted law and its residual, and each run's
force-displacement loop beside a prediction (the fit, or a vehicle file's damper simulated on the dyno). They take
results (rig/diagnosis/dyno/damper_law.py, rig/sim/dyno.py) and return matplotlib Figures; the caller saves them."""

from __future__ import annotations

import math
import textwrap
from pathlib import Path

import numpy as np

from rig.diagnosis.dyno.damper_law import DamperFit
from rig.diagnosis.dyno.dyno_test import DynoTest
from rig.report.plots import plt

MAX_POINTS = 4000  # measured points drawn per run (thinned evenly beyond)


def plot_force_velocity(fit: DamperFit, temperatures: tuple[float, ...] = ()) -> plt.Figure:
    """Measured force against rod velocity (one colour per run), the chosen law at its reference temperature (and
    at ``temperatures``, degC, for a drifting law; preload included, no compliance; a friction at its full force,
    in the direction of motion, and the gas spring at mid stroke), and below, the residual (force minus fit)
    against velocity."""
    chosen = fit.chosen
    law = chosen.law
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 7.5), sharex=True, gridspec_kw={"height_ratios": [3, 1.3]})
    start = 0
    for i, run in enumerate(fit.test.runs):
        pick = slice(None, None, max(1, run.force.size // MAX_POINTS))
        colour = plt.cm.viridis(i / max(len(fit.test.runs) - 1, 1))
        top.plot(run.velocity[pick], run.force[pick] / 1e3, ".", ms=1.5, color=colour, label=Path(run.name).name)
        residual = chosen.residual[start:start + run.force.size]
        bottom.plot(run.velocity[pick], residual[pick], ".", ms=1.5, color=colour)
        start += run.force.size
    speed = max(run.peak_velocity for run in fit.test.runs)
    grid = np.linspace(-speed, speed, 401)
    middle = float(np.mean(fit.test.joined("displacement")))
    reference = f" at {law.reference_temperature:.1f} degC" if law.temperature else ""
    top.plot(grid, _steady_force(law, grid, middle) / 1e3, "r-", lw=2.0, label=f"fit: {law.name}{reference}")
    for temperature in temperatures if law.temperature else ():
        top.plot(grid, _steady_force(law, grid, middle, temperature) / 1e3, "r--", lw=1.0,
                 label=f"fit at {temperature:.1f} degC")
    top.axhline(0.0, color="0.6", lw=0.8)
    top.axvline(0.0, color="0.6", lw=0.8)
    top.set_ylabel("force, positive resisting extension [kN]")
    series = "\n(series compliance: the fit uses the force's rate; the curve leaves it out)" if law.series else ""
    top.set_title(f"damper force against velocity: {law.name}, residual {chosen.residual_rms_pct:.2f} % of RMS "
                  f"force{series}", fontsize=9)
    top.legend(fontsize=7, markerscale=5, ncol=2)
    top.grid(alpha=0.3)
    bottom.axhline(0.0, color="r", lw=1.0)
    bottom.set_xlabel("rod velocity, extension (rebound) positive [m/s]")
    bottom.set_ylabel("force - fit [N]")
    bottom.grid(alpha=0.3)
    fig.tight_layout()
    return fig


def _steady_force(law, velocity: np.ndarray, displacement: float, temperature: float | None = None) -> np.ndarray:
    """The law's force (N) at a steady ``velocity`` (m/s) through ``displacement`` (m): its base form less the
    preload, and for a hysteresis law the friction turned over to its full force against the motion and the gas
    spring's rate there."""
    force = law.base_force(velocity, temperature) - (law.coefficients["preload"] if law.preload else 0.0)
    if law.hysteresis:
        force = force + law.coefficients["friction"] * np.sign(velocity) + law.coefficients["gas_rate"] * displacement
    return force


TITLE_NAME = 36  # characters of a record's name a loop's title shows (the middle elided beyond)


def plot_loops(test: DynoTest, predictions: list[np.ndarray], label: str, title: str = "") -> plt.Figure:
    """Each run's force against displacement: ``predictions`` (one force array per run, N, labelled ``label``,
    red, dashed), the measured loop over it (black, thin, drawn last) and their difference (grey) on the same
    axes; each title the record's name and, below it, its peak speed and the RMS difference."""
    n = len(test.runs)
    columns = min(3, n)
    rows = math.ceil(n / columns)
    fig, axes = plt.subplots(rows, columns, figsize=(4.2 * columns, 3.5 * rows), squeeze=False)
    for ax, run, predicted in zip(axes.flat, test.runs, predictions, strict=False):
        x = run.displacement * 1e3
        ax.plot(x, (run.force - predicted) / 1e3, "-", color="0.6", lw=0.5)
        ax.plot(x, predicted / 1e3, "r--", lw=1.0)
        ax.plot(x, run.force / 1e3, "k-", lw=0.6)
        rms = 100 * np.sqrt(np.mean((run.force - predicted) ** 2) / np.mean(run.force ** 2))
        ax.set_title(f"{_short(Path(run.name).name)}\nup to {run.peak_velocity:.2f} m/s; RMS difference {rms:.1f} % "
                     "of the measured", fontsize=8)
        ax.grid(alpha=0.3)
    for ax in axes.flat[n:]:
        ax.set_visible(False)
    for ax in axes[-1]:
        ax.set_xlabel("displacement, extension positive [mm]")
    for ax in axes[:, 0]:
        ax.set_ylabel("force [kN]")
    legend = textwrap.fill(f"{label} (red, dashed), measured over it (black), their difference (grey)",
                           width=45 * columns)  # the figure's width in characters at this size
    fig.suptitle(f"{title or 'force-displacement loops'}\n{legend}", fontsize=10)
    fig.tight_layout()
    return fig


def _short(name: str) -> str:
    """``name`` in at most TITLE_NAME characters, its middle elided."""
    if len(name) <= TITLE_NAME:
        return name
    keep = TITLE_NAME - 3
    return name[:keep - keep // 2] + "..." + name[-(keep // 2):]
