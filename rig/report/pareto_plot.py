"""The comfort / road-holding plot: passive damper settings as a curve, controllers placed on it (PNG)."""

from __future__ import annotations

from collections.abc import Sequence

from rig.envs.pareto import FrontPoint
from rig.report.plots import plt


def plot_pareto(front: Sequence[FrontPoint], controllers: dict[str, dict[str, float]], title: str = "",
                highlight: str | None = None) -> plt.Figure:
    """Tyre load RMS over static (x) against ISO 2631 a_w (y) for the passive settings and each controller
    (name -> metrics); ``highlight`` names the controller drawn larger."""
    ordered = sorted(front, key=lambda p: p.scale)
    fig, ax = plt.subplots(figsize=(7.5, 5.5))
    load = [p.metrics["tyre_load_rms"] for p in ordered]
    comfort = [p.metrics["a_w"] for p in ordered]
    ax.plot(load, comfort, "o-", color="0.35", label="passive damper, scaled")
    for p in ordered:
        ax.annotate(f"{p.scale:g}", (p.metrics["tyre_load_rms"], p.metrics["a_w"]), textcoords="offset points",
                    xytext=(5, 4), fontsize=8, color="0.35")
    markers = "s^vD<>ph*"
    for i, (name, m) in enumerate(controllers.items()):
        big = name == highlight
        ax.plot(m["tyre_load_rms"], m["a_w"], markers[i % len(markers)], markersize=11 if big else 8,
                label=name + (f" ({m['power_w']:.0f} W)" if m.get("power_w", 0) > 0 else ""),
                markeredgecolor="k" if big else None)
    ax.set_xlabel("dynamic tyre load RMS / static load (worst corner) [-]")
    ax.set_ylabel("ISO 2631-1 a_w, body [m/s²] (worst corner)")
    ax.set_title(title or "comfort vs road holding")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    fig.tight_layout()
    return fig
