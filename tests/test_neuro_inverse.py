"""Drive estimation by the neuro form (controllers/neuro_inverse.py: Eq 5.1 through the servo with a learned
suspension force) and the choice among the inverse models by their held-out checks (controllers/inverse_choice.py):
a linear car's spring and damper learned from its drives, the command line's summary with the residual tests, and
the independent large-event case (tests/drive_estimation_case.py) within the 10 % asked."""

import json

import numpy as np
import pytest

from controllers.drive_estimation import drive_errors, estimate_drive
from controllers.neuro_inverse import fit_neuro_inverse
from rig.cli.main import main
from rig.io.files import write_record
from rig.io.record import Record
from rig.signal.filters import band_limited_noise
from rig.sim.replay import replay
from rig.vehicle.vehicle_file import load_vehicle

RATE = 512.0


def rig_test(vehicle, seconds: float, seed: int) -> Record:
    drive = band_limited_noise(seconds, RATE, (0.5, 30.0), 0.004, 4, seed=seed, slope=1.0)
    return replay(vehicle, Record(RATE, {f"{c}/drive": drive[:, i] for i, c in enumerate(vehicle.corners)})).record


@pytest.fixture(scope="module")
def linear_car():
    vehicle = load_vehicle("proton_x")
    return vehicle, rig_test(vehicle, 24.0, 1), rig_test(vehicle, 10.0, 2)


def test_the_neuro_form_learns_a_linear_car_s_spring_and_damper_and_its_drive(linear_car):
    """Noise-free, linear: the network's linear rates come within 2 % of the data sheet's, and an unseen drive is
    recovered within 2 % (measured 1.2 %; Eq 5.1 with the data sheet's rates, 0.4 %: the network's units and power
    terms take up a little of the band's edges)."""
    vehicle, train, target = linear_car
    inverse = fit_neuro_inverse(vehicle, train, (0.5, 50.0), True)
    for axle in ("front", "rear"):
        linear = inverse.fits[axle].network.linear
        assert linear[0] == pytest.approx(vehicle.axle_named(axle).suspension_rate, rel=0.02), linear
        assert linear[1] == pytest.approx(vehicle.axle_named(axle).damping, rel=0.02), linear
    estimate = estimate_drive(vehicle, target, "neuro", train)
    assert max(drive_errors(target, estimate).values()) < 2.0
    check = estimate.checks[0]
    assert check.method == "neuro" and check.worst < 2.0 and len(check.tests) == 4


def test_estimate_drive_writes_its_summary_with_the_residual_tests(linear_car, tmp_path, capsys):
    _vehicle, train, target = linear_car
    paths = {name: tmp_path / f"{name}.csv" for name in ("train", "target")}
    write_record(paths["train"], train)
    write_record(paths["target"], target)
    out = tmp_path / "summary"
    assert main(["estimate-drive", "--vehicle", "proton_x", "--target", str(paths["target"]), "--method", "neuro",
                 "--train", str(paths["train"]), "--out", str(tmp_path / "drive.csv"), "--summary", str(out),
                 "--quiet"]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["method"] == "neuro"
    tests = summary["checks"]["neuro"]["residual_tests"]
    assert set(tests) == {f"neuro drive, {c}" for c in ("FL", "FR", "RL", "RR")}
    assert "cross_correlation" in tests["neuro drive, FL"]
    assert (out / "residual_tests.png").exists() and "held out (neuro)" in capsys.readouterr().out


@pytest.mark.slow
def test_the_independent_large_event_car_is_estimated_within_10_percent():
    """The case the issue describes (asymmetric dampers x0.6 / x1.5, a cubic spring, 1 % noise, a 60 s pink-noise
    identification run, an unseen 20 s target with six large events), simulated by the independent simulator. The
    methods' checks on the identification run's last quarter choose the neuro form (held out: 2.54 % against the
    NARX's 2.41 %; the target leaves the training), whose worst corner on the target is 6.0 % (the NARX 12.4 %,
    Eq 5.1 29.2 %, the FRF inverse 49.1 %). With the travel not measured (nor the tyre forces), the neuro form
    leaves 15.0 % and the NARX 23.5 %: there the 10 % is not met."""
    from drive_estimation_case import independent_large_event_records

    vehicle = load_vehicle("proton_x")
    train, target = independent_large_event_records(vehicle)
    estimate = estimate_drive(vehicle, target, "auto", train)
    worst = max(drive_errors(target, estimate).values())
    assert estimate.method == "neuro" and worst <= 10.0, (estimate.choice, worst)
    narx = next(c for c in estimate.checks if c.method == "narx")
    assert np.isfinite(narx.worst)


def _without(record: Record, quantities: tuple[str, ...]) -> Record:
    """The record without the channels of ``quantities``."""
    return Record(record.rate, {n: v for n, v in record.channels.items() if n.split("/")[1] not in quantities})


@pytest.mark.slow
@pytest.mark.parametrize("name, case, measured, bound", [
    ("proton_x", {}, 12.24, 13.0),
    ("proton_y", {"seed": 3, "cubic": 2.0e8, "factors": (0.5, 1.3)}, 15.86, 17.0)])
def test_without_a_travel_channel_the_independent_large_event_cars_are_estimated_from_accelerations_alone(
        name, case, measured, bound):
    """The independent large-event car (asymmetric dampers x0.6 / x1.5, cubic spring 1.5e8 N/m^3) and a second one
    (proton_y, x0.5 / x1.3, 2e8 N/m^3, other seeds), 1 % noise, with no travel and no tyre-force channel (nor the
    target's post displacement: a road target has none). The neuro form learns its spring on the travel the training
    run's post and the load balance give (controllers/travel_estimate.py): the hidden effects are the pumping of the
    asymmetric dampers, which the integrated accelerations cannot see, and their noise, which dilutes the learned
    spring. Worst corner measured 12.24 % and 15.86 % (before: the travel integrated twice, 15.0 % and 20.1 %). The
    10 % asked is not met: the noise on the wheel's acceleration alone, through Eq 5.1 with the true car, leaves
    10.4 % and 11.8 % at the worst corner (docs/drive-estimation.md)."""
    from drive_estimation_case import independent_large_event_records

    vehicle = load_vehicle(name)
    train, target = independent_large_event_records(vehicle, **case)
    estimate = estimate_drive(vehicle, _without(target, ("susp_travel", "tyre_force", "actuator_disp")), "neuro",
                              _without(train, ("susp_travel", "tyre_force")))
    worst = max(drive_errors(target, estimate).values())
    assert "estimated without a travel channel" in estimate.detail
    assert worst <= bound, (worst, measured)
