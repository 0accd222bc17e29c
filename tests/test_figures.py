"""The PNG figures as a reader sees them, read back from the matplotlib Figures the plot functions return: the
measured trace drawn last over the models, residuals under them, the time of the record a part was held out from,
axes labelled over the data's own range, titles that fit, and the size of what a panel names. Each case hides the
effect the figure must show (a burst of model error at a known time, a peak at a known time, an error that rises)
and requires the figure to show it."""

from __future__ import annotations

import dataclasses
from types import SimpleNamespace

import numpy as np
import pytest
from dyno_cases import dyno_records
from matplotlib.colors import to_rgb

from rig.signal.metrics import ChannelMetrics
from rig.causes import Shape
from rig.diagnosis.dyno.dyno_test import dyno_test
from rig.diagnosis.rig_test.force_laws import CornerLaw, ForceLaws, Slope, TyreLaw
from rig.io.record import Record
from rig.report.diagnosis_report import BEFORE_AFTER_SECONDS, plot_before_after
from rig.report.dyno_plots import plot_loops
from rig.report.force_law_report import SCALE_SHARE, plot_force_laws
from rig.report.plots import DETAIL_S, plot_convergence, plot_responses, plt
from rig.report.style import MODEL_COLORS, mpl
from rig.vehicle.vehicle_file import load_vehicle

CORNERS = ("FL", "FR", "RL", "RR")


def labelled_ticks(ax) -> list[float]:
    """The y ticks inside the axis range that carry a label, checked against their label's number."""
    fig = ax.figure
    fig.canvas.draw()
    low, high = ax.get_ylim()
    ticks = []
    for value, label in zip(ax.get_yticks(), ax.get_yticklabels()):
        if low <= value <= high and label.get_text():
            assert float(label.get_text()) == pytest.approx(value)
            ticks.append(value)
    return ticks


def history(worst: list[float]) -> list[SimpleNamespace]:
    """Iterations whose body channels' error follows ``worst`` (%), the wheels' falling below it."""
    entries = []
    for k, error in enumerate(worst):
        channels = {f"{c}/sprung_acc": ChannelMetrics.from_json({"rms_error_pct": error * (1 - 0.01 * i)})
                    for i, c in enumerate(CORNERS)}
        channels |= {f"{c}/unsprung_acc": ChannelMetrics.from_json({"rms_error_pct": 11.0 - k}) for c in CORNERS}
        entries.append(SimpleNamespace(iteration=k, gain=1.0, worst_rms_error_pct=error, channels=channels))
    return entries


@pytest.mark.parametrize("target", [1.0, None])
def test_convergence_labels_the_errors_own_range_and_says_that_the_error_rose(target):
    """The demo's first iteration: the worst channel from 13.3 % up to 16.5 %, the target 1 %. A log axis labelled
    only at decades left 10-20 % without a label; the figure must label the range the worst channel is in and say
    that its error rose, and which iteration was best."""
    worst = [13.3, 13.2, 14.5, 15.6, 16.5]
    reason = "stopped: three iterations improved less than 1 %; best iteration 1, worst channel 13.2 % RMS error " \
             "against a target of 1 % (missed)"
    fig = plot_convergence(history(worst), target, reason)
    ax = fig.axes[0]
    ticks = labelled_ticks(ax)
    assert any(10 < t < 20 for t in ticks) and len(ticks) >= 2
    assert ax.get_ylim()[1] > max(worst) and ax.get_ylim()[0] < min([*worst, target or 99])
    title = ax.get_title().replace("\n", " ")
    box = ax.title.get_window_extent(fig.canvas.get_renderer())
    assert fig.bbox.x0 <= box.x0 and box.x1 <= fig.bbox.x1  # a long stop reason wraps inside the figure
    assert title.startswith(reason) and "rose from 13.3 % (iteration 0) to 16.5 % (iteration 4)" in title
    assert "best 13.2 % at iteration 1" in title
    plt.close(fig)


def test_a_long_run_shows_a_readable_window_around_its_peak_under_the_whole_run():
    """28 s of broadband response at 512 Hz is solid ink at 1.9 inches a row: the time histories show DETAIL_S
    around the largest body acceleration (hidden at 17.3 s on RR), under a row with the whole run and that window."""
    rate, rng = 512.0, np.random.default_rng(1)
    n = int(28 * rate)
    channels = {f"{c}/{q}": rng.standard_normal(n) for c in CORNERS for q in ("sprung_acc", "unsprung_acc")}
    channels["RR/sprung_acc"][int(17.3 * rate)] = 12.0
    record = Record(rate, channels)
    fig = plot_responses(record, "a long run")
    rows = 1 + 2
    assert len(fig.axes) == rows * len(CORNERS)
    whole = [ax for ax in fig.axes if "whole run" in ax.get_title()]
    assert len(whole) == len(CORNERS)
    for ax in whole:
        assert ax.get_xlim() == pytest.approx((0.0, record.time[-1]))
    for ax in (ax for ax in fig.axes if ax not in whole):
        low, high = ax.get_xlim()
        assert high - low == pytest.approx(DETAIL_S) and low < 17.3 < high
    assert "3.0 s of 28.0 s" in fig._suptitle.get_text()
    plt.close(fig)
    short = plot_responses(Record(rate, {n: v[:1024] for n, v in channels.items()}))
    assert len(short.axes) == 2 * len(CORNERS) and not any("whole run" in ax.get_title() for ax in short.axes)
    plt.close(short)


def test_before_after_shows_where_the_model_misses_on_the_held_out_time_with_residuals():
    """A held-out part from 20 s to 30 s of its record; the recalibrated model misses FR's travel by a burst at
    26.2 s. The figure must show FR's travel first, over the seconds round 26.2 s, on the record's time, in mm; the
    measurement drawn last (black) over both models; below it the residuals, in mm, equal to measured minus each
    model."""
    rate, rng = 200.0, np.random.default_rng(3)
    time = np.arange(int(10 * rate)) / rate
    names = [f"{c}/{q}" for c in CORNERS for q in ("sprung_acc", "susp_travel")]
    measured = {n: (0.003 if n.endswith("travel") else 1.0) * rng.standard_normal(time.size) for n in names}
    recalibrated = {n: v * 0.95 for n, v in measured.items()}
    recalibrated["FR/susp_travel"] = measured["FR/susp_travel"] + 0.02 * np.exp(-((time - 6.2) / 0.2) ** 2)
    extended = {n: v + 0.01 * np.std(v) * rng.standard_normal(v.size) for n, v in measured.items()}
    compared = {k: Record(rate, v) for k, v in (("measured", measured), ("baseline", recalibrated),
                                                 ("recalibrated", recalibrated), ("extended", extended))}
    split = SimpleNamespace(holdout=SimpleNamespace(start=20.0, end=30.0), explicit=True)
    fig = plot_before_after(SimpleNamespace(compared=compared, noise_floor=1e-4, split=split))
    top, bottom = fig.axes[0], fig.axes[1]
    assert top.get_title(loc="left").startswith("FR/susp_travel")
    low, high = top.get_xlim()
    assert 20.0 <= low < 26.2 < high <= 30.0 and high - low == pytest.approx(BEFORE_AFTER_SECONDS, abs=0.5)
    assert "[mm]" in top.get_ylabel() and bottom.get_ylabel() == "residual\n[mm]"
    last = top.get_lines()[-1]
    assert last.get_label() == "measured" and to_rgb(last.get_color()) == (0, 0, 0)
    models = {line.get_label(): line for line in top.get_lines()[:-1]}
    assert models["recalibrated model"].get_color() == mpl(MODEL_COLORS["recalibrated"])
    shown = np.isin(20.0 + time, last.get_xdata())
    residual = next(line for line in bottom.get_lines() if line.get_label() == "measured - recalibrated")
    np.testing.assert_allclose(residual.get_ydata(), 1e3 * (measured["FR/susp_travel"] - recalibrated[
        "FR/susp_travel"])[shown])
    assert "hold-out record" in fig.axes[-1].get_xlabel()
    plt.close(fig)


def _law(departure_n: float) -> CornerLaw:
    """FL's law with a straight spring and damper, its travel points off the model's line by a noise band of
    +-``departure_n`` N, and a stiffening in compression named all the same (as an over-eager detector would)."""
    x = np.linspace(-0.012, 0.012, 24)
    v = np.linspace(-0.25, 0.25, 24)
    wiggle = departure_n * np.cos(np.arange(24) * 2.1)
    rate, damping = 29000.0, 3959.0
    stiffness = [Slope(a, b, rate, 200.0) for a, b in zip(np.linspace(-0.012, 0.009, 8), np.linspace(-0.009, 0.012, 8))]
    stiffness[-1] = Slope(0.009, 0.012, rate * 1.05, 200.0)
    dampers = [Slope(a, b, damping, 50.0) for a, b in zip(np.linspace(-0.25, 0.19, 8), np.linspace(-0.19, 0.25, 8))]
    return CornerLaw("FL", stiffness, dampers, (0.0, 1.0), (0.0, 1e-4), (0.0, 1.0), 0.01,
                     [Shape.STIFFENS_IN_COMPRESSION], (x, rate * x + wiggle), (v, damping * v))


def test_force_law_panels_state_the_size_of_what_they_name_against_the_models_force():
    """A 3 N scatter about a straight 29 kN/m spring over +-12 mm, named a stiffening: the panel spans at least
    +-SCALE_SHARE of the model's force at the range's end (so 3 N is a flat band, not a curve), and its heading
    names the shape with its size and the largest departure in N and in percent of the model's force."""
    vehicle = load_vehicle("proton_x")
    law = _law(3.0)
    fig = plot_force_laws(ForceLaws({"FL": law}, {}, None, []), vehicle)
    travel = fig.axes[0]
    k = vehicle.axle("FL").suspension_rate
    low, high = travel.get_ylim()
    assert min(-low, high) >= SCALE_SHARE * k * 0.012
    heading = travel.get_title(loc="left").replace("\n", " ")
    assert heading.startswith("FL") and "stiffens in compression: end slope +5 % of the centre's" in heading
    largest = np.abs(law.travel_points[1] - k * law.travel_points[0]).max()
    assert f"largest binned departure {largest:.3g} N, {100 * largest / (k * 0.012):.2g} % of the model's k x" \
        in heading
    plt.close(fig)


def test_force_law_curves_reach_the_end_slopes_their_heading_names():
    """The binned means (a 24th of the samples each) end at +-4 mm while the fit covers +-12 mm, its last 3 mm of
    compression 50 % stiffer: the shape-free fit is drawn over the whole +-12 mm, so the stiffening the heading names
    is on the panel, 50 % of k times 3 mm at its end; solid between the binned means, faded beyond them."""
    vehicle = load_vehicle("proton_x")
    law = _law(0.0)
    k = vehicle.axle("FL").suspension_rate
    law.stiffness = [Slope(s.low, s.high, k, 200.0) for s in law.stiffness]
    law.stiffness[-1] = Slope(0.009, 0.012, 1.5 * k, 200.0)
    law.travel_points = (law.travel_points[0] / 3, k * law.travel_points[0] / 3)
    fig = plot_force_laws(ForceLaws({"FL": law}, {}, None, []), vehicle)
    lines = {line.get_label(): line for line in fig.axes[0].get_lines()}
    fitted, solid = lines["_shape-free fit, tails"], lines["shape-free fit"]
    grid, departure = fitted.get_xdata(), fitted.get_ydata()
    assert grid[0] == pytest.approx(-12.0) and grid[-1] == pytest.approx(12.0) and fitted.get_alpha() < 0.5
    assert -4.0 <= solid.get_xdata()[0] < -3.8 and 3.8 < solid.get_xdata()[-1] <= 4.0 and solid.get_alpha() is None
    assert departure[-1] == pytest.approx(0.5 * k * 0.003, rel=1e-9)
    assert np.abs(departure[grid < 9.0]).max() < 1e-9 * k
    plt.close(fig)
    law.stiffness[:4] = [Slope(s.low, s.high, k, 0.0) for s in law.stiffness[:4]]  # no sample in rebound
    fig = plot_force_laws(ForceLaws({"FL": law}, {}, None, []), vehicle)
    fitted = next(line for line in fig.axes[0].get_lines() if line.get_label() == "_shape-free fit, tails")
    assert fitted.get_xdata()[0] == pytest.approx(0.0, abs=1e-9) and fitted.get_xdata()[-1] == pytest.approx(12.0)
    plt.close(fig)


def test_a_rig_without_load_cells_gets_no_tyre_row_and_a_corner_without_one_says_so():
    """Without a tyre law at any corner (no ``tyre_force``: a rig without wheel-pan load cells) the figure has the
    laws' two rows only, not a third of empty axes; where one corner has a load cell and another not, the other's
    tyre panel says it was not measured."""
    vehicle = load_vehicle("proton_x")
    front_right = dataclasses.replace(_law(0.0), corner="FR")
    fig = plot_force_laws(ForceLaws({"FL": _law(0.0), "FR": front_right}, {}, None, []), vehicle)
    assert len(fig.axes) == 4 and fig.axes[-1].get_ylabel() == "" and "rate" in fig.axes[-1].get_xlabel()
    plt.close(fig)
    deflection = np.linspace(-0.004, 0.004, 24)
    tyre = TyreLaw("FL", (2.1e5, 1e3), (100.0, 10.0), (deflection, 2.1e5 * deflection))
    fig = plot_force_laws(ForceLaws({"FL": _law(0.0), "FR": front_right}, {"FL": tyre}, None, []), vehicle)
    assert len(fig.axes) == 6
    assert fig.axes[4].get_lines() and not fig.axes[5].get_lines()
    assert "not measured" in " ".join(t.get_text() for t in fig.axes[5].texts)
    plt.close(fig)


def test_dyno_loops_keep_long_record_names_inside_their_titles_and_draw_the_measurement_last():
    """Loop titles of records with long names stay inside the figure and apart from each other; the measured loop
    is the last line of each panel (black, over the prediction)."""
    records = dyno_records({"c_low_rebound": 3000.0, "c_high_rebound": 3000.0, "knee_rebound": 0.3,
                            "c_low_compression": 1500.0, "c_high_compression": 1500.0, "knee_compression": 0.3})[:4]
    test = dyno_test([(f"/lab/exports/2024-03-12/Fox_DPS_front_left_run003_{name}_25mm_stroke.csv", record)
                      for name, record in records])
    fig = plot_loops(test, [0.9 * run.force for run in test.runs], "a prediction")
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    frame = fig.bbox
    boxes = [ax.title.get_window_extent(renderer) for ax in fig.axes if ax.get_visible()]
    for box in boxes:
        assert frame.x0 <= box.x0 and box.x1 <= frame.x1 and box.y1 <= frame.y1
    for a, b in ((a, b) for i, a in enumerate(boxes) for b in boxes[i + 1:]):
        assert not a.overlaps(b)
    for ax in (ax for ax in fig.axes if ax.get_visible()):
        assert to_rgb(ax.get_lines()[-1].get_color()) == (0, 0, 0)
        assert "RMS difference 10.0 % of the measured" in ax.get_title()
    assert len(boxes) == 4
    plt.close(fig)
