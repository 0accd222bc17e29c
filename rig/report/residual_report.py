"""Residual tests as people read them (rig/signal/residual_tests.py): a Markdown table per model, and the neuro-model
paper's figure, the residual's auto-correlation and its cross-correlation with each input against the 99 % limits.
They take results; nothing here computes a test."""

from __future__ import annotations

from rig.report.plots import plt
from rig.signal.residual_tests import CONFIDENCE, LAGS, ResidualTests

MAX_ROWS = 6  # models drawn in one figure


def residual_lines(tests: list[ResidualTests], heading: str = "## Residual tests") -> list[str]:
    """A section: what the tests are, one table row per model, and one line per model that fails (where)."""
    if not tests:
        return []
    threshold = tests[0].autocorrelation.threshold
    lines = [heading, "", f"Each model's residual: its auto-correlation and its cross-correlation with each input over "
                          f"{LAGS} lags, the statistic N sum r^2 against its {CONFIDENCE:.0%} point ({threshold:.1f}); "
                          f"MSE and FPE on the samples tested (the content below 70 % of the band's top).", "",
             "| model | white | samples | rate [Hz] | MSE | FPE | auto-correlation | cross-correlation (worst input) |",
             "|---|---|---|---|---|---|---|---|"]
    for t in tests:
        worst = max(t.cross, key=lambda c: c.statistic, default=None)
        cross = f"{worst.statistic:.1f} ({worst.name})" if worst is not None else "-"
        lines.append(f"| {t.model} | {'yes' if t.white else 'no'} | {t.samples} | {t.rate:.4g} | {t.mse:.4g} | "
                     f"{t.fpe:.4g} | {t.autocorrelation.statistic:.1f} | {cross} |")
    lines += [""] + [f"- {t.describe()}" for t in tests if not t.white] + [""]
    return lines


def plot_residual_tests(tests: list[ResidualTests], title: str = "residual tests") -> plt.Figure:
    """Per model (at most MAX_ROWS), the residual's auto-correlation (left) and its cross-correlations with the
    inputs (right) against lag in ms, with the 99 % limits dashed; the statistic in each title."""
    shown = tests[:MAX_ROWS]
    fig, axes = plt.subplots(len(shown), 2, figsize=(11, 2.2 * len(shown) + 0.8), squeeze=False, sharex="col")
    for row, t in zip(axes, shown, strict=True):
        auto = t.autocorrelation
        to_ms = 1e3 / t.rate
        row[0].stem(auto.lags * to_ms, auto.values, basefmt=" ")
        row[0].set_title(f"{t.model}: auto-correlation {auto.statistic:.1f} "
                         f"({'white' if auto.white else 'not white'})", fontsize=8)
        for c in t.cross:
            row[1].plot(c.lags * to_ms, c.values, "o-", ms=3, lw=0.8,
                        label=f"{c.name} {c.statistic:.1f}{'' if c.white else ' (not white)'}")
        row[1].set_title(f"cross-correlation with the inputs (99 % point of the statistic {auto.threshold:.1f})",
                         fontsize=8)
        if t.cross:
            row[1].legend(fontsize=6, loc="upper right")
        for ax in row:
            ax.axhline(auto.limit, color="r", ls="--", lw=0.8)
            ax.axhline(-auto.limit, color="r", ls="--", lw=0.8)
            ax.axhline(0.0, color="0.5", lw=0.5)
            ax.grid(alpha=0.3)
        row[0].set_ylabel("correlation [-]")
    for ax in axes[-1]:
        ax.set_xlabel("lag [ms]")
    more = f" (the first {MAX_ROWS} of {len(tests)})" if len(tests) > MAX_ROWS else ""
    fig.suptitle(f"{title}{more}: {CONFIDENCE:.0%} limits dashed", fontsize=10)
    fig.tight_layout()
    return fig
