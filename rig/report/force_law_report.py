"""The force laws measured from the data, beside the model's own: the restoring force against travel and
against its rate per corner, the tyre's force against its deflection, and the body's mass properties
against the data sheet (Markdown lines and one PNG)."""

from __future__ import annotations

from collections.abc import Callable

import textwrap

import numpy as np

from rig.causes import Shape
from rig.diagnosis.rig_test.force_laws import CornerLaw, ForceLaws, Slope, TyreLaw
from rig.io.channels import corner_axle
from rig.report.plots import plt
from rig.vehicle.vehicle_file import Vehicle


#: The departure panels span at least this share of the model's own force at the ends of the measured range, and
#: shade it: a few newtons of scatter on a law carrying hundreds then reads as the straight law it is.
SCALE_SHARE = 0.05
HEADING_WIDTH = 52  # characters per line of a panel's heading
TAIL_ALPHA = 0.35   # opacity of the curves beyond the binned means
_ROWS = (("travel_points", "stiffness", "suspension_rate", 1e3, "compression [mm]", "k x"),
         ("rate_points", "damping", "damping", 1.0, "compression rate [m/s]", "c v"))


def plot_force_laws(laws: ForceLaws, model: Vehicle) -> plt.Figure | None:
    """One column per corner: the suspension force's departure from ``model``'s linear law against
    compression and against its rate (a straight law is the zero line; stiffening bends the curve up at the
    ends) over a band of +-SCALE_SHARE of the model's force, each panel naming the shapes found in it with their
    size and the largest departure in newtons and in percent of the model's force; the tyre force against its
    deflection where a load cell measured it (no such row on a rig without them); measured (binned means of the
    data) and the shape-free fit. None when no force law could be formed."""
    corners = [c for c in model.corners if c in laws.corners or c in laws.tyres]
    if not corners:
        return None
    rows = 3 if laws.tyres else 2
    fig, axes = plt.subplots(rows, len(corners), figsize=(3.6 * len(corners) + 1, 3.2 * rows - 0.1), squeeze=False)
    for column, corner in enumerate(corners):
        law = laws.corners.get(corner)
        for row, spec in enumerate(_ROWS):
            ax = axes[row, column]
            heading = [corner] if row == 0 else []
            if law is not None:
                learned = laws.learned.get(corner_axle(corner))
                heading += _departure_panel(ax, law, getattr(model.axle(corner), spec[2]), spec, _row_shapes(law, row),
                                            None if learned is None else (learned.law.travel_force if row == 0
                                                                          else learned.law.rate_force))
            ax.set_title("\n".join(heading), fontsize=7, loc="left")
            ax.set_xlabel(spec[4])
            ax.grid(alpha=0.3)
        if laws.tyres:
            _tyre_panel(axes[2, column], laws.tyres.get(corner), model.axle(corner))
    labels = ("force - model's k x [N]", "force - model's c v [N]", "tyre force, dynamic [kN]")
    for row, label in enumerate(labels[:rows]):
        axes[row, 0].set_ylabel(label)
    axes[0, 0].legend(fontsize=6, loc="lower left")
    fig.suptitle("force laws measured from the data (wheel equilibrium) against the model's")
    return fig


def _departure_panel(ax: plt.Axes, law: CornerLaw, rate: float, spec: tuple, shapes: list[str],
                     learned: Callable[[np.ndarray], np.ndarray] | None = None) -> list[str]:
    """The measured departure from the model's linear law (``rate``: N/m or N s/m) against travel or its rate,
    with the law ``learned`` by the neuro-model paper's networks where there is one; the panel's heading:
    ``shapes`` and the largest departure, wrapped. The curves span the range the fit covers (the 0.5 and 99.5 %
    quantiles), where the end slopes the heading names lie, less a side no sample reached (its segments' slopes
    borrowed, their error zero); beyond the binned means (each a 24th of the samples) they are faded: a few percent
    of the samples decide them there."""
    points, segments, _, scale, _, term = spec
    x, force = getattr(law, points)
    fitted_segments = getattr(law, segments)
    measured = [s for s in fitted_segments if s.error > 0] or fitted_segments
    grid = np.linspace(measured[0].low, measured[-1].high, 200)
    departure = force - rate * x
    fitted = law.law_at(fitted_segments, grid)
    if segments == "damping":  # the points hold the friction step too
        fitted = fitted + law.friction[0] * np.sign(grid)
    cone = SCALE_SHARE * rate * np.abs(grid)
    ax.fill_between(grid * scale, -cone, cone, color="0.85", lw=0, label=f"±{100 * SCALE_SHARE:g} % of the model's "
                                                                          f"{term}")
    ax.axhline(0.0, ls="--", color="0.45", lw=1.2, label="model (data sheet)")
    inner = (grid >= x[0]) & (grid <= x[-1])
    curves = [(fitted - rate * grid, "C3", 1.5, "shape-free fit")] + (
        [(learned(grid) - rate * grid, "C0-.", 1.3, "learned (neuro law)")] if learned is not None else [])
    for curve, style, width, label in curves:  # each curve's departure from the model's law
        ax.plot(grid * scale, curve, style, lw=width, alpha=TAIL_ALPHA, label=f"_{label}, tails")
        ax.plot(grid[inner] * scale, curve[inner], style, lw=width, label=label)
    ax.plot(x * scale, departure, "ko", ms=3, label="measured (binned)")
    reach = max(np.abs(departure).max(), np.abs(curves[0][0]).max(), cone.max()) * 1.15
    ax.set_ylim(-reach, reach)
    largest = np.abs(departure).max()
    share = largest / max(np.abs(rate * x).max(), 1e-12)
    lines = [*shapes, f"largest binned departure {largest:.3g} N, {100 * share:.2g} % of the model's {term}"]
    return [wrapped for line in lines for wrapped in textwrap.wrap(line, HEADING_WIDTH)]


def _row_shapes(law: CornerLaw, row: int) -> list[str]:
    """The shapes found in a corner's law that the panel of ``row`` shows (0: travel, 1: rate), each with its
    size: a slope's change in percent of the centre slope and in standard errors, a step, a lag, a coupling."""
    n = len(law.stiffness) // 2
    k, c = law.stiffness, law.damping
    sizes = {Shape.STIFFENS_IN_COMPRESSION: (0, _slope_change(k[n], k[-1])),
             Shape.SOFTENS_IN_COMPRESSION: (0, _slope_change(k[n], k[-1])),
             Shape.STIFFENS_IN_REBOUND: (0, _slope_change(k[n - 1], k[0])),
             Shape.SOFTENS_IN_REBOUND: (0, _slope_change(k[n - 1], k[0])),
             Shape.STIFFENS_BOTH_WAYS: (0, f"{_slope_change(k[n - 1], k[0])} and {_slope_change(k[n], k[-1])}"),
             Shape.COUPLED: (0, f"{law.coupling[0]:.0f} ± {law.coupling[1]:.0f} N/m"),
             Shape.ASYMMETRIC_DAMPING: (1, f"{c[n - 1].value:.0f} (rebound) / {c[n].value:.0f} (compression) N s/m "
                                           "at low speed"),
             Shape.PROGRESSIVE_DAMPING: (1, f"{_slope_change(c[n - 1], c[0])} and {_slope_change(c[n], c[-1])}"),
             Shape.DIGRESSIVE_DAMPING: (1, f"{_slope_change(c[n - 1], c[0])} and {_slope_change(c[n], c[-1])}"),
             Shape.FRICTION_STEP: (1, f"{law.friction[0]:.0f} ± {law.friction[1]:.0f} N"),
             Shape.FORCE_LAGS: (1, f"{1e3 * law.lag_s[0]:.1f} ± {1e3 * law.lag_s[1]:.1f} ms")}
    return [f"{shape}: {sizes[shape][1]}" for shape in law.shapes if shape in sizes and sizes[shape][0] == row]


def _slope_change(centre: Slope, end: Slope) -> str:
    """An end slope against the centre one: percent and standard errors."""
    sigma = (end.value - centre.value) / max(np.hypot(centre.error, end.error), 1e-12)
    return f"end slope {100 * (end.value / centre.value - 1):+.0f} % of the centre's ({sigma:+.1f} σ)"


def _tyre_panel(ax: plt.Axes, tyre: TyreLaw | None, axle) -> None:
    """The tyre's dynamic force against its deflection: measured, fitted and the model's rate; where no load cell
    measured it, a note that says so."""
    if tyre is None:
        ax.text(0.5, 0.5, "no tyre_force in the record:\nnot measured at this corner", ha="center", va="center",
                fontsize=7, color="0.4", transform=ax.transAxes)
    else:
        deflection, force = tyre.points
        ax.plot(deflection * 1e3, force / 1e3, "ko", ms=3, label="measured (binned)")
        ax.plot(deflection * 1e3, tyre.rate[0] * deflection / 1e3, "C3", lw=1.5,
                label=f"fit {tyre.rate[0] / 1e3:.0f} kN/m")
        ax.plot(deflection * 1e3, axle.tyre_rate * deflection / 1e3, "--", color="0.45", lw=1.2,
                label=f"model {axle.tyre_rate / 1e3:.0f} kN/m")
        ax.legend(fontsize=6)
    ax.set_xlabel("tyre deflection, dynamic [mm]")
    ax.grid(alpha=0.3)


def force_law_lines(laws: ForceLaws, model: Vehicle) -> list[str]:
    """Markdown: the named shapes per corner, the tyres, the body's mass properties against the data sheet,
    the departures from it and the evidence that could not be formed."""
    lines = ["## Force laws measured from the data", "",
             "The suspension force at each corner follows from the wheel's equilibrium (tyre load and wheel "
             "acceleration), fitted without a model form; a shape is named only when the data resolve it.", "",
             "| corner | shape | centre rate [N/m] | model rate | low-speed damping [N s/m] | model damping | "
             "friction step [N] | force lag [ms] | left-right coupling [N/m] |",
             "|---|---|---|---|---|---|---|---|---|"]
    for corner, law in laws.corners.items():
        axle = model.axle(corner)
        n = len(law.stiffness) // 2
        lines.append(f"| {corner} | {', '.join(law.shapes) or 'linear'} | {law.stiffness[n].value:.0f} "
                     f"± {law.stiffness[n].error:.0f} | {axle.suspension_rate:.0f} | {law.damping[n].value:.0f} "
                     f"± {law.damping[n].error:.0f} | {axle.damping:.0f} | {law.friction[0]:.1f} "
                     f"± {law.friction[1]:.1f} | {1e3 * law.lag_s[0]:.2f} ± {1e3 * law.lag_s[1]:.2f} "
                     f"| {law.coupling[0]:.0f} ± {law.coupling[1]:.0f} |")
    if laws.tyres:
        lines += ["", "| tyre | rate [N/m] | model | damping [N s/m] | model |", "|---|---|---|---|---|"]
        for corner, tyre in laws.tyres.items():
            axle = model.axle(corner)
            lines.append(f"| {corner} | {tyre.rate[0]:.0f} ± {tyre.rate[1]:.0f} | {axle.tyre_rate:.0f} | "
                         f"{tyre.damping[0]:.0f} ± {tyre.damping[1]:.0f} | {axle.tyre_damping:.0f} |")
    if laws.body is not None:
        body = laws.body
        lines += ["", "| body | measured | data sheet |", "|---|---|---|",
                  f"| sprung mass [kg] | {body.mass[0]:.1f} ± {body.mass[1]:.2g} | {model.sprung_mass:.1f} |",
                  f"| CG x from the data sheet's [m] | {body.cg_x[0]:+.3f} ± {body.cg_x[1]:.1g} | 0 |",
                  f"| CG y from the data sheet's [m] | {body.cg_y[0]:+.3f} ± {body.cg_y[1]:.1g} | 0 |",
                  f"| pitch inertia [kg m²] | {body.pitch_inertia[0]:.0f} ± {body.pitch_inertia[1]:.2g} | "
                  f"{model.pitch_inertia:.0f} |",
                  f"| roll inertia [kg m²] | {body.roll_inertia[0]:.0f} ± {body.roll_inertia[1]:.2g} | "
                  f"{model.roll_inertia:.0f} |"]
    departures = laws.departures(model)
    if departures:
        lines += ["", "Departures from the data sheet beyond its usual few percent:", ""]
        lines += [f"- {d.what}: {d.measured:.4g} ± {d.error:.2g}, data sheet {d.data_sheet:.4g}"
                  + (f" (points to {', '.join(d.suggests)})" if d.suggests else "") for d in departures]
    if laws.assumed:
        lines += ["", "Taken from the data sheet:", ""] + [f"- {a}" for a in laws.assumed]
    if laws.missing:
        lines += ["", "Evidence not formed:", ""] + [f"- {m}" for m in laws.missing]
    return [*lines, "", "![force laws](force_laws.png)", ""]
