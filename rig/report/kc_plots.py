"""Plots of K&C tests (rig/sim/kc.py): they take a ``KcResult`` and return the matplotlib Figure."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")  # files only; never needs a display
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from rig.io.kc_record import FACTORS, SWEEP_UNITS, KcResult

#: quantity -> (axis label, factor from SI to the plotted unit)
PANELS = {
    "camber": ("camber [deg]", 180 / np.pi), "toe": ("toe [deg] (toe-in +)", 180 / np.pi),
    "track_change": ("track change [mm]", 1e3), "wheelbase_change": ("wheelbase change [mm]", 1e3),
    "caster": ("caster [deg]", 180 / np.pi), "kingpin": ("kingpin inclination [deg]", 180 / np.pi),
    "scrub_radius": ("scrub radius [mm]", 1e3), "trail": ("trail [mm]", 1e3),
    "motion_ratio": ("motion ratio [-]", 1.0), "wheel_rate": ("wheel rate [N/mm]", 1e-3),
    "wheel_load": ("wheel load [N]", 1.0), "travel": ("travel [mm]", 1e3),
    "compliance_steer": ("compliance steer [deg/kN]", 180 / np.pi * 1e3),
    "compliance_camber": ("compliance camber [deg/kN]", 180 / np.pi * 1e3),
    "wishbone_angle": ("lower wishbone angle [deg]", 180 / np.pi),
    "upper_wishbone_angle": ("upper wishbone angle [deg]", 180 / np.pi),
    "steering_angle": ("carrier's steering angle [deg]", 180 / np.pi),
}
_SWEEP_LABELS = {"travel": ("wheel travel [mm] (bump +)", 1e3), "roll": ("roll [deg]", 180 / np.pi),
                 "rack": ("rack travel [mm] (to the left +)", 1e3), "force": ("force at the contact patch [N]", 1.0),
                 "moment": ("moment at the contact patch [N m]", 1.0)}


def _sweep_axis(result: KcResult) -> tuple[np.ndarray, str]:
    fallback = (result.sweep_name, 1 / FACTORS[SWEEP_UNITS[result.sweep_name]])
    label, factor = _SWEEP_LABELS.get(result.sweep_name, fallback)
    return result.sweep * factor, label


def _corner_style(corner: str) -> dict:
    """Front blue, rear red; left solid, right dashed (a symmetric car draws the right over the left)."""
    return {"color": "C0" if corner[0] == "F" else "C3", "ls": "-" if corner[-1] == "L" else (0, (4, 3)),
            "lw": 1.5, "label": corner}


def plot_kc(result: KcResult) -> Figure:
    """Every curve of a K&C test against its sweep: one panel per quantity, one line per corner, and the axles'
    roll-centre heights."""
    quantities = [q for q in PANELS if any(f"{c}/{q}" in result.curves for c in result.corners)
                  and not (q == "travel" and result.sweep_name == "travel")]
    axles = [a for a in ("front", "rear") if f"{a}/roll_centre_height" in result.curves]
    count = len(quantities) + (1 if axles else 0)
    columns = 4
    rows = -(-count // columns)
    fig, axes = plt.subplots(rows, columns, figsize=(3.6 * columns, 2.6 * rows), squeeze=False)
    x, xlabel = _sweep_axis(result)
    for ax, quantity in zip(axes.flat, quantities):
        label, factor = PANELS[quantity]
        for corner in result.corners:
            ax.plot(x, result.curves[f"{corner}/{quantity}"] * factor, **_corner_style(corner))
        ax.set_ylabel(label)
    if axles:
        ax = axes.flat[len(quantities)]
        for k, axle in enumerate(axles):
            ax.plot(x, result.curves[f"{axle}/roll_centre_height"] * 1e3, color=("C0", "C3")[k], lw=1.5, label=axle)
        ax.set_ylabel("roll-centre height [mm]")
        ax.legend(fontsize=7)
    for ax in axes.flat[:count]:
        ax.grid(alpha=0.3)
        ax.set_xlabel(xlabel, fontsize=8)
    for ax in axes.flat[count:]:
        ax.set_visible(False)
    axes.flat[0].legend(fontsize=7)
    fig.suptitle(f"{result.vehicle}: K&C {result.test} test")
    fig.tight_layout()
    return fig


def plot_camber_toe(result: KcResult, corners: tuple[str, ...] = ("FL", "RL")) -> Figure:
    """Camber and toe against wheel travel (a ``travel`` test) for the left wheels (the right ones mirror them)."""
    fig, axes = plt.subplots(1, 2, figsize=(9.0, 3.6))
    x, xlabel = _sweep_axis(result)
    for ax, quantity in zip(axes, ("camber", "toe")):
        label, factor = PANELS[quantity]
        for corner in (c for c in corners if f"{c}/{quantity}" in result.curves):
            name = {"F": "front", "R": "rear"}[corner[0]]
            style = {**_corner_style(corner), "lw": 2.0, "label": f"{name} ({corner})"}
            ax.plot(x, result.curves[f"{corner}/{quantity}"] * factor, **style)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
        ax.axvline(0.0, color="0.6", lw=0.8)
        ax.legend(fontsize=8)
    fig.suptitle(f"{result.vehicle}: camber and toe in parallel wheel travel")
    fig.tight_layout()
    return fig


def plot_kc_comparison(record: KcResult, before: dict[str, np.ndarray], after: dict[str, np.ndarray],
                       title: str = "") -> Figure:
    """A K&C record against the model: per curve the measured points, the vehicle file's model (grey, dashed) and
    the extended model (the corner's colour); a row per quantity, a column per corner."""
    corners = [c for c in record.corners if any(n.startswith(f"{c}/") for n in before)]
    quantities = [q for q in PANELS if any(f"{c}/{q}" in before for c in corners)]
    fig, axes = plt.subplots(len(quantities), len(corners), figsize=(3.3 * len(corners), 2.4 * len(quantities)),
                             squeeze=False, sharex=True)
    x, xlabel = _sweep_axis(record)
    for row, quantity in enumerate(quantities):
        label, factor = PANELS[quantity]
        for column, corner in enumerate(corners):
            ax, name = axes[row, column], f"{corner}/{quantity}"
            if name not in before:
                ax.set_visible(False)
                continue
            color = _corner_style(corner)["color"]
            ax.plot(x, record.curves[name] * factor, "o", ms=3, color="0.2", label="measured")
            ax.plot(x, before[name] * factor, "--", color="0.55", lw=1.2, label="vehicle file")
            ax.plot(x, after[name] * factor, "-", color=color, lw=1.6, label="extended")
            ax.grid(alpha=0.3)
            if row == 0:
                ax.set_title(corner)
            if column == 0:
                ax.set_ylabel(label, fontsize=8)
            if row == len(quantities) - 1:
                ax.set_xlabel(xlabel, fontsize=8)
    axes[0, 0].legend(fontsize=7)
    fig.suptitle(title or f"{record.vehicle}: K&C {record.test} test, measured against the model")
    fig.tight_layout()
    return fig
