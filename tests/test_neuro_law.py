"""The neuro-model paper's network ("Neuro Model for Passive Suspension of a Light Car" (paper)) and its residual
tests: unitwise Fisher scoring recovers a law, the whiteness tests hold their 99 % level on noise and fail on a
deliberately wrong model, the blended rate against its closed form, the learned law inside mj_step against its
closed form, and a quarter car whose spring and damper are laws no cause of the vocabulary is (a tanh-saturating
damper, a spring softening in rebound), simulated by an independent quarter car (tests/independent_quarter.py):
the learned law is chosen, gains most of the held-out TDDI and leaves a white residual."""

import tomllib

import numpy as np
import pytest
from independent_quarter import QuarterTruth, quarter_record
from independent_rig import Hidden, independent_records
from support.quarter import quarter_with, suspension_force

from rig import diagnose, load_vehicle
from rig.causes import with_extension
from rig.causes.neuro_law import KNOTS, REACH_MARGIN, NeuroLaw
from rig.diagnosis.rig_test.neuro_corner_law import learn_laws
from rig.diagnosis.rig_test.synthetic import event_drive
from rig.report.diagnosis_report import write_diagnosis
from rig.signal.complementary import blended_rate
from rig.signal.filters import band_pass
from rig.signal.neuro_network import train
from rig.signal.residual_tests import residual_tests
from rig.sim.simulate import Simulator
from rig.vehicle.mjcf import build_model
from rig.vehicle.vehicle_file import VehicleError, vehicle_from_dict, vehicle_to_toml

RATE = 512.0
SECTION = {"travel_linear": 28000.0, "travel_weights": [200.0, -80.0], "travel_biases": [0.5, -0.3],
           "travel_outputs": [-900.0, 300.0], "rate_linear": 3500.0, "rate_weights": [8.0], "rate_biases": [0.2],
           "rate_outputs": [-1500.0], "travel_reach": [-0.04, 0.03], "rate_reach": [-0.5, 0.6]}


def saturating(c):
    """A damper that saturates: c v0 tanh(v / v0), v0 = 0.15 m/s (no cause of the vocabulary)."""
    return lambda v: c * 0.15 * np.tanh(v / 0.15)


def softening(k):
    """A spring linear in compression that softens in rebound to at most k x0, x0 = 10 mm."""
    return lambda x: np.where(x >= 0, k * x, k * 0.01 * np.tanh(x / 0.01))


@pytest.fixture(scope="module")
def quarter_test():
    """The independent quarter car with those laws: 12 s fitted, 6 s held out, 2 % noise on every channel."""
    vehicle = load_vehicle("proton_x_quarter")
    rng = np.random.default_rng(1)
    truth = QuarterTruth.of(vehicle, softening, saturating, rng)
    records = [quarter_record(truth, event_drive(vehicle.corners, seconds, RATE, rng)[:, 0], RATE, rng)
               for seconds in (12.0, 6.0)]
    return vehicle, truth, records


def test_unitwise_fisher_scoring_recovers_a_saturating_law_and_fpe_stops_adding_units():
    rng = np.random.default_rng(0)
    x = rng.uniform(-1.0, 1.0, 3000)
    truth = 2.0 * x + 3.0 * np.tanh(4.0 * (x - 0.2))
    fit = train(x[:, None], truth + 0.05 * rng.standard_normal(x.size), ("x",), {"curve": (0,)}, (0,))
    grid = np.linspace(-1.0, 1.0, 201)
    error = fit.network.predict(grid[:, None]) - (2.0 * grid + 3.0 * np.tanh(4.0 * (grid - 0.2)))
    assert np.max(np.abs(error)) < 0.05  # of a law spanning 10
    assert 1 <= fit.order["curve"] < 6  # FPE stops: the sixth unit does not pay
    assert min(fit.orders.values()) == fit.orders[(fit.order["curve"],)]


def test_the_whiteness_tests_hold_their_level_on_noise_and_fail_on_a_deliberately_wrong_model():
    """White noise band-passed as the diagnosis compares (0.5-50 Hz, 12 s) passes at about the 99 % level (the
    paper's chi-squared limit over 20 lags, 37.6); a linear model of a law that saturates leaves a residual that
    follows its input, a network does not."""
    failures = 0
    for seed in range(30):
        rng = np.random.default_rng(seed)
        noise, other = (band_pass(rng.standard_normal(int(12 * RATE)), RATE, (0.5, 50.0)) for _ in range(2))
        tests = residual_tests("noise", noise, {"input": other}, 0, RATE, (0.5, 50.0))
        assert tests.autocorrelation.threshold == pytest.approx(37.57, abs=0.01)
        failures += not tests.white
    assert failures <= 3  # 30 x 2 tests at 1 % each: 0.6 expected
    rng = np.random.default_rng(5)
    u = rng.uniform(-1.0, 1.0, 2000)
    y = np.tanh(3.0 * u) + 0.05 * rng.standard_normal(u.size)
    wrong = train(u[:, None], y, ("u",), {"units": (0,)}, (0,), max_units=0)
    right = train(u[:, None], y, ("u",), {"units": (0,)}, (0,))
    for fit, white in ((wrong, False), (right, True)):
        tests = residual_tests("law", fit.residual, {"u": u ** 3}, fit.network.parameters, 1.0)
        assert tests.white == white, tests.describe()


def test_the_blended_rate_is_the_rate_and_far_less_noisy_than_either_part():
    t = np.arange(int(20 * RATE)) / RATE
    omega = 2 * np.pi * np.array([[0.7], [4.0], [13.0]])
    x = (0.01 * np.sin(omega * t)).sum(axis=0)
    v = (0.01 * omega * np.cos(omega * t)).sum(axis=0)
    a = (-0.01 * omega**2 * np.sin(omega * t)).sum(axis=0)
    middle = slice(int(2 * RATE), -int(2 * RATE))
    assert np.max(np.abs(blended_rate(x, a, RATE, 5.0) - v)[middle]) < 1e-3 * np.max(np.abs(v))
    rng = np.random.default_rng(0)
    noisy_x, noisy_a = x + 0.02 * np.std(x) * rng.standard_normal(t.size), a + 0.02 * np.std(a) * rng.standard_normal(
        t.size)
    blended = np.std((blended_rate(noisy_x, noisy_a, RATE) - v)[middle])
    derived = np.std((np.gradient(noisy_x) * RATE - v)[middle])
    assert blended < 0.1 * derived


def test_the_learned_law_inside_mj_step_is_its_closed_form_and_its_section_is_checked():
    """Chords of 16 knots per side: within 0.5 % of the curves' span at any point, the linear spring and damper of
    the axle taken off (the law is the corner's spring and damper)."""
    plain = quarter_with()
    sim = Simulator.create(build_model(quarter_with(neuro_law={"front": SECTION}), RATE, "ideal"))
    law = NeuroLaw(**{k: tuple(v) if isinstance(v, list) else v for k, v in SECTION.items()})
    span = float(np.ptp(law.travel_force(np.linspace(-0.05, 0.04, 50))) + np.ptp(law.rate_force(
        np.linspace(-0.6, 0.7, 50))))
    for x in (-0.045, -0.02, -0.004, 0.0, 0.006, 0.03):
        for v in (-0.6, -0.1, 0.0, 0.2, 0.7):
            force = suspension_force(sim, x, v) - suspension_force(sim, 0.0, 0.0)
            expected = float(law.travel_force(np.array(x)) + law.rate_force(np.array(v)))
            assert force == pytest.approx(expected, abs=5e-3 * span), (x, v)
    vehicle = quarter_with(neuro_law={"front": SECTION})
    again = vehicle_from_dict(tomllib.loads(vehicle_to_toml(vehicle)), "round trip")
    assert again.extensions["neuro_law"] == vehicle.extensions["neuro_law"]
    assert plain.front.damping > 0
    with pytest.raises(VehicleError, match="travel_weights, travel_biases and travel_outputs must have the same"):
        quarter_with(neuro_law={"front": {**SECTION, "travel_biases": [0.5]}})
    with pytest.raises(VehicleError, match="rate_reach must be"):
        quarter_with(neuro_law={"front": {**SECTION, "rate_reach": [0.1, 0.6]}})


def test_the_learned_law_of_a_quarter_car_no_cause_explains_is_white_and_its_curves_the_truth(quarter_test):
    vehicle, truth, (fitted, _) = quarter_test
    learned = learn_laws(fitted, vehicle)["front"]
    assert learned.tests.white, learned.tests.describe()
    x, v = np.linspace(-0.02, 0.02, 41), np.linspace(-0.5, 0.5, 41)
    spring = learned.law.travel_force(x) - truth.spring(x)
    damper = learned.law.rate_force(v) - truth.damper(v)
    assert np.max(np.abs(spring)) < 0.05 * np.ptp(truth.spring(x)), spring
    assert np.max(np.abs(damper)) < 0.05 * np.ptp(truth.damper(v)), damper


def test_the_learned_laws_of_an_independent_car_are_written_and_no_unit_is_steeper_than_a_chord():
    """The independent car with a digressive damper (12 s): trained without a bound on their slopes, units that
    explained next to nothing steepened to 3.8e9 1/m, past the vehicle file's limits, and the diagnosis could not
    simulate the learned law at all. Each unit's 10-90 % rise (2 ln 9 / slope) now spans at least a chord of the
    law as realised (KNOTS per side over REACH_MARGIN times the reach), and the laws go into a vehicle file and back."""
    vehicle = load_vehicle("proton_x")
    measured, _, _ = independent_records(vehicle, Hidden(digressive_damper=(0.1, 0.4)), 1, 12.0, 1.0)
    learned = learn_laws(measured, vehicle)
    assert set(learned) == {"front", "rear"}
    for law in (item.law for item in learned.values()):
        for group in ("travel", "rate"):
            chord = REACH_MARGIN * max(-getattr(law, f"{group}_reach")[0], getattr(law, f"{group}_reach")[1]) / KNOTS
            for weight in getattr(law, f"{group}_weights"):
                assert 2 * np.log(9.0) / abs(weight) >= chord * (1 - 1e-9), (group, weight, chord)
    written = with_extension(vehicle, "neuro_law", {axle: item.law for axle, item in learned.items()})
    again = vehicle_from_dict(tomllib.loads(vehicle_to_toml(written)), "round trip")
    assert again.extensions["neuro_law"] == written.extensions["neuro_law"]
    Simulator.create(build_model(again, RATE, "ideal"))


@pytest.mark.slow
def test_a_quarter_car_whose_laws_no_cause_is_gets_the_learned_law(quarter_test, tmp_path):
    """The acceptance case: the learned law is chosen over measured_law and every named cause on the held-out data,
    gains at least 80 % of the held-out TDDI (measured 99.7 %, against 98.8 % for measured_law) and its residual
    passes the whiteness tests; the report says so and draws them."""
    vehicle, _truth, (fitted, held) = quarter_test
    result = diagnose(vehicle, fitted, held)
    generic = result.unexplained.generic_extension
    assert generic.effect == "neuro_law", [(c.effect, c.gain) for c in result.causes[:4]]
    assert generic.gain >= 0.8 and result.extended_tddi == pytest.approx(generic.tddi_holdout)
    assert result.force_laws.learned["front"].tests.white
    write_diagnosis(result, tmp_path)
    report = (tmp_path / "report.md").read_text()
    assert "Residual tests" in report and "neuro law, front axle | yes" in report
    assert (tmp_path / "residual_tests.png").exists()
    assert "neuro_law" in (tmp_path / "vehicle_extended.toml").read_text()
