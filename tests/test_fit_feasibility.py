"""Every fit trial is scored, none ends in a traceback: each cause's fit parameters (plain and refined forms) set at
their bounds and beyond them, on a car and on a lab bench. A trial no vehicle can be (a payload lighter than the
body, inertia off the triangle inequality, a law that diverges) scores as the worst model (the measured channels
negated), every other as its simulation. A bench's data-sheet file without ``[rig]`` takes the rig's defaults (before,
mass_error's joint fit on it ended in MuJoCo's "inertia must satisfy A + B >= C")."""

import numpy as np
import pytest

from lab_rig import lab_records
from rig.causes import CAUSES
from rig.diagnosis.core.experiment import Experiment
from rig.diagnosis.core.fitting import build
from rig.diagnosis.rig_test.synthetic import rig_test_records
from rig.io.channels import split_channel
from rig.vehicle.vehicle_file import load_vehicle, resolve_vehicle_path


def experiment(name: str, tmp_path) -> tuple[Experiment, object]:
    """A short rig test of ``name`` (a built-in vehicle; ``lab_quarter_data_sheet``: the bench's file without its
    ``[rig]`` section, as a data sheet gives masses, rates and damping only) and its vehicle."""
    if name == "lab_quarter_data_sheet":
        text = resolve_vehicle_path("lab_quarter").read_text()
        (tmp_path / "bench.toml").write_text(text[:text.index("[rig]")])
        vehicle = load_vehicle(tmp_path / "bench.toml")
    else:
        vehicle = load_vehicle(name)
    if vehicle.layout == "quarter":
        record, _, _ = lab_records(vehicle, 1, duration=3.0, holdout=1.0)
    else:
        record, _ = rig_test_records(vehicle, np.random.default_rng(1), 6.0, 2.0, 256.0)
    return Experiment.from_record(record, vehicle), vehicle


def trials(params) -> list[np.ndarray]:
    """At the low bounds, at the high ones, a span below and a span above them all."""
    low, high = np.array([p.low for p in params]), np.array([p.high for p in params])
    span = high - low
    return [low, high, low - span, high + span]


@pytest.mark.parametrize("vehicle_name", ["proton_x", "lab_quarter", "lab_quarter_data_sheet"])
def test_fit_trials_at_and_beyond_their_bounds_are_scored_never_raised(vehicle_name, tmp_path):
    test, vehicle = experiment(vehicle_name, tmp_path)
    quantities = {split_channel(n)[1] for n in test.record.names}
    fitted = infeasible = 0
    for cause in CAUSES.values():
        if cause.subsystem != "car" or cause.generic or not cause.shows_in(vehicle.layout, quantities):
            continue
        for params in (cause.fit_parameters(vehicle), cause.refined_parameters(vehicle)):
            if not params:
                continue
            vehicles = [build(vehicle, params, x) for x in trials(params)]
            for k, simulated in enumerate(test.simulate_trials(vehicles)):
                assert simulated.shape == test.measured.shape and np.all(np.isfinite(simulated)), cause.name
                scored_worst = np.array_equal(simulated, -test.measured)
                # a bench's body has no pitch or roll: every corner of its fit's box is a vehicle (a car's may not be:
                # 400 kg taken onto mounts 2 m ahead of the CG leaves the body less pitch inertia than nothing)
                assert not (scored_worst and k < 2 and vehicle.layout == "quarter"), f"{cause.name} at its bounds"
                infeasible += scored_worst
                fitted += 1
    assert fitted >= 20 and infeasible >= 1  # beyond the bounds, some trials are no vehicle (a negative bandwidth)
