"""The force laws measured from the data, beside the model's own: the restoring force against travel and
against its rate per corner, the tyre's force against its deflection, and the body's mass properties
against the data sheet (Markdown lines and one PNG)."""

from __future__ import annotations

import numpy as np

from rig.diagnosis.force_laws import ForceLaws
from rig.io.channels import corner_axle
from rig.report.plots import plt
from rig.vehicle.vehicle_file import Vehicle


def plot_force_laws(laws: ForceLaws, model: Vehicle) -> plt.Figure | None:
    """One column per corner: the suspension force's departure from ``model``'s linear law against
    compression and against its rate (a straight law is the zero line; stiffening bends the curve up at the
    ends), the tyre force against its deflection; measured (binned means of the data) and the shape-free fit.
    None when no force law could be formed."""
    corners = [c for c in model.corners if c in laws.corners or c in laws.tyres]
    if not corners:
        return None
    fig, axes = plt.subplots(3, len(corners), figsize=(3.4 * len(corners) + 1, 9), squeeze=False)
    for column, corner in enumerate(corners):
        axle = model.axle(corner)
        law = laws.corners.get(corner)
        rows = (("travel_points", "stiffness", axle.suspension_rate, 1e3, "compression [mm]"),
                ("rate_points", "damping", axle.damping, 1.0, "compression rate [m/s]"))
        for row, (points, segments, rate, scale, label) in enumerate(rows):
            ax = axes[row, column]
            if law is not None:
                x, force = getattr(law, points)
                grid = np.linspace(x[0], x[-1], 200)
                ax.plot(x * scale, force - rate * x, "ko", ms=3, label="measured (binned)")
                fitted = law.law_at(getattr(law, segments), grid)
                if segments == "damping":  # the points hold the friction step too
                    fitted = fitted + law.friction[0] * np.sign(grid)
                ax.plot(grid * scale, fitted - rate * grid, "C3", lw=1.5, label="shape-free fit")
                learned = laws.learned.get(corner_axle(corner))
                if learned is not None:
                    curve = learned.law.travel_force if row == 0 else learned.law.rate_force
                    ax.plot(grid * scale, curve(grid) - rate * grid, "C0-.", lw=1.3, label="learned (neuro law)")
                ax.axhline(0.0, ls="--", color="0.45", lw=1.2, label="model (data sheet)")
            ax.set_xlabel(label)
            ax.grid(alpha=0.3)
        axes[0, column].set_title(corner + (": " + ", ".join(law.shapes) if law and law.shapes else ""), fontsize=8)
        tyre = laws.tyres.get(corner)
        ax = axes[2, column]
        if tyre is not None:
            deflection, force = tyre.points
            ax.plot(deflection * 1e3, force / 1e3, "ko", ms=3, label="measured (binned)")
            ax.plot(deflection * 1e3, tyre.rate[0] * deflection / 1e3, "C3", lw=1.5,
                    label=f"fit {tyre.rate[0] / 1e3:.0f} kN/m")
            ax.plot(deflection * 1e3, axle.tyre_rate * deflection / 1e3, "--", color="0.45", lw=1.2,
                    label=f"model {axle.tyre_rate / 1e3:.0f} kN/m")
            ax.legend(fontsize=6)
        ax.set_xlabel("tyre deflection, dynamic [mm]")
        ax.grid(alpha=0.3)
    for row, label in enumerate(("force - model's k x [N]", "force - model's c v [N]", "tyre force, dynamic [kN]")):
        axes[row, 0].set_ylabel(label)
    axes[0, 0].legend(fontsize=6)
    fig.suptitle("force laws measured from the data (wheel equilibrium) against the model's")
    return fig


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
    if laws.missing:
        lines += ["", "Evidence not formed:", ""] + [f"- {m}" for m in laws.missing]
    return [*lines, "", "![force laws](force_laws.png)", ""]
