"""What the diagnosis's speed rests on must not change a result: a batch of variants simulates each as it runs alone,
an experiment looks a vehicle it simulated up instead of simulating it again, a car on measured posts steps coarser
only where its modes and elements allow and then gives what the default step gives, a fit that updates its Jacobian
by secants still finds the truth and states its intervals from differences (simulated only when read: a superseded
fit never pays for them), a fit given Jacobian columns simulates only the others, a fit's start runs in one batch with
the Jacobian there and ends as one run at a time would, fits run beside each other give what they give one after
another (the slow test: a whole diagnosis both ways, its reported intervals formed), and the corner laws are learned
once, whichever thread asks first."""

import dataclasses
import threading
import time
from types import SimpleNamespace

import numpy as np
import pytest

from scipy.optimize import OptimizeResult

import rig.diagnosis.rig_test.candidates as candidates
from rig.causes import CAUSES, scale_axle, with_extension
from rig.diagnosis.rig_test.candidates import LINEAR, known_columns
from rig.diagnosis.rig_test.diagnose import diagnose
from rig.diagnosis.core.timing import StageClock
from rig.diagnosis.core.experiment import Experiment
from rig.diagnosis.core.fitting import Intervals, fit_car, intervals, linear_parameters
from rig.diagnosis.rig_test.synthetic import hidden_cause_records, rig_test_records
from rig.diagnosis.core.validation import mean_tddi
from rig.sim.step_size import COARSE_TIMESTEP, fit_timestep
from rig.vehicle.mjcf import MAX_TIMESTEP, build_model
from rig.vehicle.vehicle_file import load_vehicle


@pytest.fixture(scope="module")
def proton_x():
    return load_vehicle("proton_x")


def test_a_batch_of_variants_is_each_run_alone_and_a_vehicle_run_again_is_looked_up(proton_x):
    measured, _, _ = hidden_cause_records(proton_x, "none", 5, 6.0, 3.0)
    softer = scale_axle(proton_x, "front", spring_rate=0.9)
    heavier = dataclasses.replace(proton_x, sprung_mass=proton_x.sprung_mass * 1.05)
    batch = Experiment.from_record(measured, proton_x)
    together = batch.simulate_car([softer, heavier])
    alone = [Experiment.from_record(measured, proton_x).simulate_car([v])[0] for v in (softer, heavier)]
    for a, b in zip(together, alone):
        np.testing.assert_array_equal(a, b)
    assert not np.allclose(together[0], together[1])  # the variants differ: the batch did not run one model twice
    again = batch.simulate_car([heavier, dataclasses.replace(softer)])  # equal vehicles, other objects
    assert again[0] is together[1] and again[1] is together[0]
    assert not again[0].flags.writeable


def test_a_car_on_measured_posts_steps_coarser_only_where_its_modes_and_elements_allow(proton_x):
    """proton_x's fastest mode (wheel hop, 75 rad/s) allows one step a sample at 512 Hz, and its car channels then
    miss the default step's by a TDDI of 4e-9 (asserted at 1e-7, a 2 % noise floor is 4e-5); a linkage car's
    bushings (2000 rad/s), servo posts and a cause sized to the default step keep 1 ms."""
    assert fit_timestep(proton_x, 512.0) == COARSE_TIMESTEP
    assert build_model(proton_x, 512.0, "ideal", longest=COARSE_TIMESTEP).steps_per_sample == 1
    assert fit_timestep(load_vehicle("fs_car"), 512.0) == MAX_TIMESTEP
    assert build_model(proton_x, 512.0, "servo", longest=COARSE_TIMESTEP).steps_per_sample == 2
    stop = CAUSES["bump_stop"].values(0.01, 4e6)
    stopped = with_extension(proton_x, "bump_stop", {"front": stop, "rear": stop})
    assert build_model(stopped, 512.0, "ideal", longest=COARSE_TIMESTEP).steps_per_sample == 2
    measured, _, _ = hidden_cause_records(proton_x, "none", 5, 6.0, 3.0)
    fine = Experiment.from_record(measured, proton_x).simulate_car([proton_x])[0]
    coarse = Experiment.from_record(measured, proton_x, longest=COARSE_TIMESTEP).simulate_car([proton_x])[0]
    assert mean_tddi(fine, coarse) < 1e-7


def test_a_fit_with_secant_updates_finds_the_truth_and_states_intervals_from_differences(proton_x):
    """Front springs 8 % stiffer and rear damping 10 % lower are found within 0.5 %, each inside its interval, and
    the intervals come from a Jacobian formed by differences at the solution (a secant update's would differ)."""
    truth = scale_axle(scale_axle(proton_x, "front", spring_rate=1.08, parasitic_rate=1.08), "rear", damping=0.9)
    measured, _ = rig_test_records(truth, np.random.default_rng(6), 8.0, 3.0)
    experiment = Experiment.from_record(measured, proton_x)
    params = [p for p in linear_parameters(proton_x) if p.name in ("front_spring_rate", "rear_damping")]
    result = fit_car(experiment, proton_x, params, max_evaluations=5)
    np.testing.assert_allclose(result.x, [1.08, 0.9], rtol=5e-3)
    again = fit_car(experiment, proton_x, params, result.x, max_evaluations=1)  # differences at the solution
    np.testing.assert_allclose(result.jac, again.jac, rtol=1e-9)


def test_the_jacobian_at_a_fits_solution_is_simulated_when_its_intervals_are_first_read(proton_x, monkeypatch):
    """A fit ends without simulating its Jacobian at the solution; reading its intervals simulates it once (one
    variant per parameter, the residual at the solution the fit's own) and gives what the intervals of that Jacobian
    are, a part of them for a part."""
    truth = scale_axle(proton_x, "front", spring_rate=1.05, parasitic_rate=1.05)
    measured, _ = rig_test_records(truth, np.random.default_rng(6), 8.0, 3.0)
    experiment = Experiment.from_record(measured, proton_x)
    params = [p for p in linear_parameters(proton_x) if p.name in ("front_spring_rate", "front_damping")]
    result = fit_car(experiment, proton_x, params, max_evaluations=3)
    simulated = []
    real = experiment.simulate_trials
    monkeypatch.setattr(experiment, "simulate_trials", lambda vehicles: simulated.append(len(vehicles)) or
                        real(vehicles))
    spread = Intervals(result, params, 1)
    assert simulated == [] and len(spread) == 1
    assert dict(spread) == {"front_damping": intervals(result, params)[1]}
    assert simulated == [len(params)]  # the shifted variants in one batch, the residual at the solution kept
    formed = len(simulated)
    assert dict(Intervals(result, params)) == dict(zip(["front_spring_rate", "front_damping"],
                                                       intervals(result, params)))
    assert len(simulated) == formed  # formed once


def test_a_fit_takes_the_jacobian_columns_it_is_given_and_simulates_only_the_others(proton_x, monkeypatch):
    """Given the start's spring column (from a fit that formed it there), a fit simulates the damping's alone and
    ends where the fit that simulated both ends, bit for bit; a joint fit takes the linear factors' columns that
    earlier fits formed at the same values, never a cause's."""
    truth = scale_axle(proton_x, "front", spring_rate=1.06, parasitic_rate=1.06, damping=0.92)
    measured, _ = rig_test_records(truth, np.random.default_rng(7), 8.0, 3.0)
    experiment = Experiment.from_record(measured, proton_x)
    params = [p for p in linear_parameters(proton_x) if p.name in ("front_spring_rate", "front_damping")]
    at_start = fit_car(experiment, proton_x, params, max_evaluations=1).held_jacobian  # differences at the start
    plain = fit_car(experiment, proton_x, params, max_evaluations=4)
    batches = []
    real = experiment.simulate_trials
    monkeypatch.setattr(experiment, "simulate_trials", lambda vehicles: batches.append(len(vehicles)) or
                        real(vehicles))
    given = fit_car(experiment, proton_x, params, max_evaluations=4, known={0: at_start[:, 0]})
    np.testing.assert_array_equal(given.x, plain.x)
    assert batches[0] == 2  # the start and the damping's variant: the spring's column was given

    fit = OptimizeResult(x=np.array([1.02, 0.97, 1.5]), held_jacobian=np.arange(9.0).reshape(3, 3),
                         parameter_keys=[(LINEAR, "front_spring_rate"), (LINEAR, "front_damping"), ("stop", "gap")])
    keys = [(LINEAR, "front_damping"), (LINEAR, "front_spring_rate"), ("stop", "gap")]
    known = known_columns(keys, np.array([0.97, 1.02, 1.5]), [None, fit], {"stop"})
    assert sorted(known) == [0, 1] and list(known[0]) == [1.0, 4.0, 7.0]  # a polish: the stop's own is simulated
    assert known_columns(keys, np.array([0.97, 1.01, 1.5]), [fit], {"stop"}) == {}  # the spring moved on
    assert known_columns([*keys, ("spring", "cubic")], np.array([0.97, 1.02, 1.5, 0.0]), [fit],
                         {"stop", "spring"}) == {}  # a car cause added: its effect moves the columns
    fit["jac"] = -fit.held_jacobian  # formed by differences at the solution: preferred
    assert list(known_columns(keys, np.array([0.97, 1.02, 1.5]), [fit], {"stop"})[0]) == [-1.0, -4.0, -7.0]


def test_a_fit_simulates_its_start_and_the_jacobian_there_in_one_batch_and_ends_as_one_run_at_a_time(
        proton_x, monkeypatch):
    """The fit's first point and the variants whose differences form the Jacobian there run in one batch (the fit asks
    for that Jacobian next: the cores run the variants beside the point), and the fit ends bit for bit where one whose
    every vehicle runs alone ends: values, residual and Jacobian held."""
    truth = scale_axle(proton_x, "rear", spring_rate=1.05, parasitic_rate=1.05, damping=0.93)
    measured, _ = rig_test_records(truth, np.random.default_rng(8), 8.0, 3.0)
    params = [p for p in linear_parameters(proton_x) if p.name in ("rear_spring_rate", "rear_damping", "sprung_mass")]
    batched = Experiment.from_record(measured, proton_x)
    batches = []
    real = batched.simulate_trials
    monkeypatch.setattr(batched, "simulate_trials", lambda vehicles: batches.append(len(vehicles)) or real(vehicles))
    together = fit_car(batched, proton_x, params, max_evaluations=4)
    assert batches[0] == 1 + len(params) and batches[1:] == [1] * (len(batches) - 1)

    alone = Experiment.from_record(measured, proton_x)
    one = alone.simulate_trials
    monkeypatch.setattr(alone, "simulate_trials", lambda vehicles: [one([v])[0] for v in vehicles])
    apart = fit_car(alone, proton_x, params, max_evaluations=4)
    np.testing.assert_array_equal(together.x, apart.x)
    np.testing.assert_array_equal(together.fun, apart.fun)
    assert together.held_jacobian is not None
    np.testing.assert_array_equal(together.held_jacobian, apart.held_jacobian)


@pytest.mark.slow
def test_fits_beside_each_other_give_what_they_give_one_after_another(proton_x, monkeypatch):
    measured, holdout, _ = hidden_cause_records(proton_x, "damper_asymmetry", 4, 12.0, 6.0)
    causes = ("damper_asymmetry", "bump_stop", "sensor_gain")
    beside = diagnose(proton_x, measured, holdout, causes=causes)
    monkeypatch.setattr(candidates.os, "sched_getaffinity", lambda pid: {0})
    alone = diagnose(proton_x, measured, holdout, causes=causes)
    assert beside.verdict == alone.verdict == ("damper_asymmetry",)
    assert (beside.recalibrated_tddi, beside.extended_tddi) == (alone.recalibrated_tddi, alone.extended_tddi)
    assert [(c.effect, c.params, c.tddi_holdout, c.intervals) for c in beside.causes] == \
        [(c.effect, c.params, c.tddi_holdout, c.intervals) for c in alone.causes]
    assert all(type(c.intervals) is dict for c in beside.causes)  # formed before the diagnosis returned


def test_the_corner_laws_are_learned_once_whichever_thread_asks_first(monkeypatch):
    """Run.learned_laws: asked on two threads at once (two generic elements screened beside each other, both fitted on
    the learned laws), the training runs once and both get its laws; the second asker waits for the first."""
    trained = []

    def slow_training(record, vehicle, saturated, band):
        trained.append(threading.get_ident())
        time.sleep(0.2)
        return {"front": object()}

    monkeypatch.setattr(candidates, "learn_laws", slow_training)
    run = object.__new__(candidates.Run)  # the method reads only these
    run.force_laws = SimpleNamespace(learned={}, saturated=())
    run.train, run.test, run.vehicle = SimpleNamespace(record=None), SimpleNamespace(band=(0.5, 50.0)), None
    run.clock, run._learning, run._learned = StageClock(), threading.Lock(), False
    got = []
    threads = [threading.Thread(target=lambda: got.append(run.learned_laws())) for _ in range(2)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert len(trained) == 1
    assert got[0] is got[1] is run.force_laws.learned
    assert [t.stage for t in run.clock.times] == ["learned laws"]

