"""The linearised model's frequency response (rig/diagnosis/rig_test/frequency_fit.py) against the quarter car's closed
form
and the time-domain run, and its fit against the time-domain fit on records of the independent simulator."""

import numpy as np
import pytest
from independent_rig import Car, Hidden, Simulator, independent_records, perturbed, rig_record
from support.quarter import QUARTER, quarter_with

from rig import load_vehicle
from rig.causes import CAUSES
from rig.diagnosis.core.experiment import Experiment
from rig.diagnosis.core.fitting import fit_car, intervals, linear_parameters
from rig.diagnosis.rig_test.diagnose import diagnose
from rig.diagnosis.rig_test.frequency_fit import (fit_car_frequency, frequency_response, LINEAR_NOTE, linear_response,
                                                stays_linear)
from rig.diagnosis.rig_test.synthetic import event_drive
from rig.io.record import Record
from rig.vehicle.ride_model import quarter_car_frf

RATE = 512.0


@pytest.fixture(scope="module")
def proton_x():
    return load_vehicle("proton_x")


def test_linearised_quarter_car_is_its_closed_form_transmissibility():
    """Nurhadiyanto's quarter car (eqs. 3.5, 3.6) with tyre damping: body and wheel accelerations over the post
    displacement are -w^2 times the transmissibilities, the travel the wheel's minus the body's."""
    vehicle = quarter_with(front={**QUARTER["front"], "tyre_damping": 150.0})
    names = ("sprung_acc", "unsprung_acc", "susp_travel")
    zeros = np.zeros(1024)
    record = Record(RATE, {f"FL/{q}": zeros for q in ("actuator_disp", *names)})
    experiment = Experiment.from_record(record, vehicle)
    frequency = np.array([0.5, 1.0, 1.5, 3.0, 8.0, 12.0, 20.0, 40.0])
    response = frequency_response(vehicle, experiment, frequency)[:, :, 0]
    body, wheel = quarter_car_frf(vehicle, "FL", frequency)
    w2 = (2 * np.pi * frequency) ** 2
    expected = {"FL/sprung_acc": -w2 * body, "FL/unsprung_acc": -w2 * wheel, "FL/susp_travel": wheel - body}
    for column, name in enumerate(experiment.car_channels):
        np.testing.assert_allclose(response[:, column], expected[name], rtol=1e-6, err_msg=name)


def linear_records(vehicle, hidden: Hidden, seed: int, duration: float = 20.0):
    """A record of the independent simulator's car (off by up to 3 %, ``hidden``) on drives whose events stay below
    the tyres' lift-off, and the truth car."""
    rng = np.random.default_rng(seed)
    nominal = Car.from_vehicle(vehicle)
    sim = Simulator(perturbed(nominal, rng), hidden, preload_car=nominal)
    return rig_record(sim, event_drive(vehicle.corners, duration, RATE, rng, amplitude=0.015), RATE, rng), sim


def test_linear_response_is_the_time_domain_run_where_the_car_stays_linear(proton_x):
    """The car channels from the frequency response times the posts' transform are the replay's to 0.5 % of each
    channel's rms, also on a record's first 7 s, which end with the posts moving (as a diagnosis's fit part cut from a
    longer record: 1.2 % at a rear wheel's acceleration with the response formed to twice the band's top, 0.05 % to
    the Nyquist frequency); a record on which a tyre lifts off (the independent simulator's seed-1 events) is told
    apart."""
    record, _ = linear_records(proton_x, Hidden(), 3, 10.0)
    cut = Record(record.rate, {n: v[:int(7 * record.rate)] for n, v in record.channels.items()})
    for part in (record, cut):
        experiment = Experiment.from_record(part, proton_x)
        linear, stepped = linear_response(experiment, proton_x), experiment.simulate_car([proton_x])[0]
        error = np.sqrt(np.mean((linear - stepped) ** 2, axis=0) / np.mean(stepped**2, axis=0))
        assert error.max() < 0.005, dict(zip(experiment.car_channels, error.round(4)))
        assert stays_linear(experiment, proton_x)
    lifting, _, _ = independent_records(proton_x, Hidden(), 1, 20.0, 1.0)
    assert not stays_linear(Experiment.from_record(lifting, proton_x), proton_x)


@pytest.mark.slow
def test_frequency_and_time_domain_fits_agree_within_their_intervals(proton_x):
    """Hidden tyre damping (300 N s/m) on the independent simulator's car: the recalibration's linear factors with
    the tyre damping, fitted on the frequency response and by time stepping (the same fit, the same budget), agree
    within a quarter of their 95 % intervals' half-width (0.08 measured), and the frequency fit finds the tyre
    damping within 10 %."""
    record, _ = linear_records(proton_x, Hidden(tyre_damping=300.0), 4)
    experiment = Experiment.from_record(record, proton_x)
    damping = [c for c in CAUSES.values() if c.linear and c.subsystem == "car" and not c.has_section()]
    assert len(damping) == 1  # the tyre damping: a key of the axles' tables, the one linear cause without a section
    params = linear_parameters(proton_x) + damping[0].fit_parameters(proton_x)
    by_frequency = fit_car_frequency(experiment, proton_x, params)
    by_time = fit_car(experiment, proton_x, params, max_evaluations=8)
    for p, f, t, (low, high) in zip(params, by_frequency.x, by_time.x, intervals(by_time, params)):
        assert abs(f - t) < 0.25 * (high - low) / 2, (p.name, f, t, (low, high))
    tyre = by_frequency.x[-2:]
    assert np.all(np.abs(tyre - 300.0) < 30.0), tyre


@pytest.mark.slow
def test_a_diagnosis_of_a_linear_car_fits_on_its_frequency_response_and_says_so(proton_x):
    """Hidden tyre damping (300 N s/m) on the independent simulator's car, events below lift-off: the diagnosis names
    it with its linear fits on the frequency response, says so, and its values lie within the intervals of the same
    diagnosis stepped in time (which has no such note)."""
    record, _ = linear_records(proton_x, Hidden(tyre_damping=300.0), 5, 24.0)
    causes = ("tyre_damping", "mass_error")
    by_frequency = diagnose(proton_x, record, causes=causes)
    by_time = diagnose(proton_x, record, causes=causes, frequency_domain=False)
    assert LINEAR_NOTE in by_frequency.notes and LINEAR_NOTE not in by_time.notes
    assert by_frequency.verdict == by_time.verdict == "tyre_damping"
    frequency, time = by_frequency.named[0], by_time.named[0]
    for name, (low, high) in time.intervals.items():
        assert low <= frequency.params[name] <= high, (name, frequency.params[name], (low, high))
